"""A recorded lockstep run is complete, from its first step, at any pace of its recorder (/recorder/progress).

The recorder of a running ``hawt launch ipc --record`` is stopped (SIGSTOP, as a starved process
would be): the plant must stop within its ``recorder_window`` of what the recorder has written,
say so, and go on when the recorder does, leaving a bag that ``hawt bag verify`` finds complete.
A recorder that stays stopped past ``recorder_timeout`` is given up with a recorder event (also logged:
the recorder it is about may never take it), and the run still completes.
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


def _launch(bag, duration: float, timeout: float) -> LaunchedGraph:
    return LaunchedGraph(["ipc", "namespace:=bp", f"duration:={duration:g}", "-p", "plant.report_period:=0.1",
                          "-p", f"plant.recorder_window:={WINDOW:g}", "-p", f"plant.recorder_timeout:={timeout:g}",
                          "--record", str(bag)])


def _run_stopping_the_recorder(bag, duration: float, timeout: float, at: str, until: str) -> tuple[LaunchedGraph, int]:
    """Run the graph, stop its recorder once the plant prints ``at``, let it go on once the plant prints ``until``;
    the graph and how many lines it had printed by then."""
    with _launch(bag, duration, timeout) as graph:
        graph.wait_for_line(at)
        recorder = _recorder(graph)
        recorder.suspend()
        graph.wait_for_line(until)
        printed = len(graph.lines)
        recorder.resume()
        assert graph.finish() == 0, graph.tail()
    return graph, printed


def test_a_stopped_recorder_holds_the_plant_within_its_window_and_the_bag_is_complete(tmp_path):
    bag = tmp_path / "held.mcap"
    graph, held_lines = _run_stopping_the_recorder(bag, 20, 600, "t=3.0 s (", "waiting for the recorder")
    held_at, written = (float(x) for x in HELD.search("".join(graph.lines)).groups())
    assert 3.0 <= held_at and held_at - written <= WINDOW + 0.02, "held more than one step past the window (and "\
        "the 0.01 s of the printed times)"
    while_held = [float(m.group(1)) for line in graph.lines[:held_lines] if (m := PROGRESS.search(line))]
    assert max(while_held) <= held_at, "the plant stepped past the step it held"
    verification = verify_bag(bag)
    assert verification.ok, verification.text()
    loads = next(topic for topic in verification.topics if topic.coverage.topic == "/bp/plant/blade_loads")
    assert loads.coverage.ranges == ((0, 1999),)


def test_a_recorder_stopped_for_good_is_given_up_with_an_event_and_the_run_completes(tmp_path):
    graph, _ = _run_stopping_the_recorder(tmp_path / "given_up.mcap", 8, 2, "t=2.0 s (",
                                          "going on without waiting for it")
    # The recorder event is published and logged: the recorder it is about, given up, may never take it.
    output = "".join(graph.lines)
    assert output.count("[WARN]") == 1 and "recorder: the recorder has written nothing more of plant/blade_loads " \
        "for 2 s" in output
    assert "finished 800 steps" in output

