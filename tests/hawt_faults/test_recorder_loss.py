"""A recorder lost in a recorded lockstep run loses no step: it is an ERROR event at once, and it is respawned.

``hawt launch --record`` starts the recorder again on the bag's next part; the plant holds within its
``recorder_window`` until the new recorder has caught up, the new recorder gets back the steps the dead one
had not written from the publishers' transient-local history, and the launcher joins the parts into the bag
named on the command line. With ``--record-optional`` the recorder is not respawned, and the run ends in an
error naming what was lost.
"""
import psutil
import pytest
from hawt_msgs.msg import ControlEvent
from launched_graph import LaunchedGraph

from hawt_bag.verification import verify_bag
from hawt_faults.fault_runs import read_recording

pytestmark = pytest.mark.ros


def _kill_the_recorder(graph: LaunchedGraph) -> None:
    children = psutil.Process(graph.process.pid).children(recursive=True)
    next(child for child in children if any(part.endswith("hawt_bag/record") for part in child.cmdline())).kill()


def test_a_killed_recorder_is_respawned_and_the_bag_has_every_step(tmp_path):
    bag = tmp_path / "run.mcap"
    with LaunchedGraph(["baseline", "namespace:=lost", "duration:=30", "-p", "plant.report_period:=1",
                        "--record", str(bag)]) as graph:
        graph.wait_for_line("t=3.0 s (")
        _kill_the_recorder(graph)
        graph.wait_for_line("respawning it on")
        assert graph.finish() == 0, graph.tail()
    assert sorted(path.name for path in tmp_path.iterdir()) == ["run.mcap"], "the parts were not joined"
    verification = verify_bag(bag)
    assert verification.ok, verification.text()
    ranges = {topic.coverage.topic: topic.coverage.ranges for topic in verification.topics}
    for topic in ("plant/blade_loads", "plant/state", "control/pitch_command", "control/collective"):
        assert ranges[f"/lost/{topic}"] == ((0, 2999),), verification.text()
    recording = read_recording(bag, "lost")
    (lost,) = recording.events_of("recorder_lost")
    assert lost["level"] == ControlEvent.ERROR and lost["step"] >= 300
    assert f"the recorder of {bag} died (killed by SIGKILL); respawned on {tmp_path / 'run.part2.mcap'}" \
           in lost["detail"]
    assert recording.events_of("finished")


def test_an_optional_recorder_that_dies_is_not_respawned_and_the_run_ends_in_an_error(tmp_path):
    bag = tmp_path / "optional.mcap"
    with LaunchedGraph(["baseline", "namespace:=optional", "duration:=20", "-p", "plant.report_period:=1",
                        "-p", "plant.recorder_timeout:=1", "--record", str(bag), "--record-optional"]) as graph:
        graph.wait_for_line("t=3.0 s (")
        _kill_the_recorder(graph)
        assert graph.finish() == 1, graph.tail()
    output = "".join(graph.lines)
    assert "died (killed by SIGKILL); recording stops here (--record-optional)" in output
    assert "finished 2000 steps" in output and "respawning" not in output
    assert output.rstrip().splitlines()[-1] == (f"hawt launch: the recorder of {bag} died (killed by SIGKILL); "
                                                "recording stops here (--record-optional)")
