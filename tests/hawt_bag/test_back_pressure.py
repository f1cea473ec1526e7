"""A recorded lockstep run is complete, from its first step, at any pace of its recorder (/recorder/progress).

The recorder of a running ``hawt launch baseline --record`` is stopped (SIGSTOP, as a starved process
would be): the plant must stop within its ``recorder_window`` of what the recorder has written,
say so, and go on when the recorder does, leaving a bag that ``hawt bag verify`` finds complete.
With ``--record-optional``, a recorder that stays stopped past ``recorder_timeout`` is given up with a
recorder event (also logged: the recorder it is about may never take it), and the run still completes;
without it the plant waits for the recorder however long it takes (tests/hawt_faults/test_recorder_loss.py).
"""
import re

import psutil
import pytest
from launched_graph import LaunchedGraph

from hawt_bag.verification import verify_bag

pytestmark = pytest.mark.ros

WINDOW = 1.0
HELD = re.compile(r"t=([\d.]+) s: waiting for the recorder, which has written \S+ up to t=([\d.]+) s")
PROGRESS = re.compile(r"\bt=([\d.]+) s \(")


def _recorder(graph: LaunchedGraph) -> psutil.Process:
    children = psutil.Process(graph.process.pid).children(recursive=True)
    return next(child for child in children if any(part.endswith("hawt_bag/record") for part in child.cmdline()))


def _launch(bag, duration: float, timeout: float, window: float, optional: bool) -> LaunchedGraph:
    return LaunchedGraph(["baseline", "namespace:=bp", f"duration:={duration:g}", "-p", "plant.report_period:=0.1",
                          "-p", f"plant.recorder_window:={window:g}", "-p", f"plant.recorder_timeout:={timeout:g}",
                          "--record", str(bag), *(["--record-optional"] if optional else [])])


def _run_stopping_the_recorder(bag, duration: float, timeout: float, at: str, until: str,
                               window: float = WINDOW, optional: bool = False) -> tuple[list, list, list]:
    """Run the graph, stop its recorder once the plant prints ``at``, let it go on once the plant prints ``until``
    (a line after the stop: a busy machine's recorder may have held the plant before; for an optional recorder, a
    line printed before the stop counts too: the plant gives an optional recorder up once, and a busy machine's may
    have been given up at its slow start); the lines printed up to the stop, those printed while the recorder was
    stopped, and all."""
    with _launch(bag, duration, timeout, window, optional) as graph:
        graph.wait_for_line(at)
        recorder = _recorder(graph)
        recorder.suspend()
        stopped = len(graph.lines)
        graph.wait_for_line(until, after=0 if optional else stopped)
        printed = len(graph.lines)
        recorder.resume()
        assert graph.finish() == 0, graph.tail()
    return graph.lines[:stopped], graph.lines[stopped:printed], graph.lines


def test_a_stopped_recorder_holds_the_plant_within_its_window_and_the_bag_is_complete(tmp_path):
    bag = tmp_path / "held.mcap"
    before, stopped, _ = _run_stopping_the_recorder(bag, 10, 600, "t=3.0 s (", "waiting for the recorder")
    held_at, written = (float(x) for x in HELD.search("".join(stopped)).groups())
    assert 3.0 <= held_at and held_at - written <= WINDOW + 0.02, "held more than one step past the window (and "\
        "the 0.01 s of the printed times)"
    while_held = [float(m.group(1)) for line in before + stopped if (m := PROGRESS.search(line))]
    assert max(while_held) <= held_at, "the plant stepped past the step it held"
    verification = verify_bag(bag)
    assert verification.ok, verification.text()
    loads = next(topic for topic in verification.topics if topic.coverage.topic == "/bp/plant/blade_loads")
    assert loads.coverage.ranges == ((0, 999),)


def test_the_plant_finishes_only_once_the_recorder_has_written_its_last_step(tmp_path):
    """A window longer than the run never holds it, but the end waits: stopping the graph loses no backlog."""
    bag = tmp_path / "end.mcap"
    _, stopped, _ = _run_stopping_the_recorder(bag, 5, 600, "t=1.0 s (", "the last step: waiting for the recorder",
                                               window=10)
    assert any("t=5.0 s (" in line for line in stopped), "the plant ran to its end while the recorder was stopped"
    verification = verify_bag(bag)
    assert verification.ok, verification.text()
    ranges = {topic.coverage.topic: topic.coverage.ranges for topic in verification.topics}
    assert ranges["/bp/plant/blade_loads"] == ranges["/bp/control/pitch_command"] == ((0, 499),), verification.text()


def test_an_optional_recorder_stopped_for_good_is_given_up_with_an_event_and_the_run_completes(tmp_path):
    *_, lines = _run_stopping_the_recorder(tmp_path / "given_up.mcap", 8, 2, "t=2.0 s (",
                                           "going on without waiting for it", optional=True)
    # The recorder event is published and logged: the recorder it is about, given up, may never take it. A busy
    # machine may add warnings of its own (a fresh-clone CI run printed two; which the other was, it did not show).
    output = "".join(lines)
    reported = "".join(line for line in lines if "[WARN]" in line or "[ERROR]" in line)
    assert output.count("recorder: the recorder has written nothing more of plant/blade_loads for 2 s") == 1, reported
    assert "[ERROR]" not in output, reported
    assert "finished 800 steps" in output

