"""hawt launch SIGKILLed mid-run: its node processes and its recorder see their parent gone and stop as on SIGTERM,
so nothing is left running and the bag is finished, with every step it holds from step 0 on."""
import psutil
import pytest
from launched_graph import LaunchedGraph

from hawt_bag.verification import verify_bag

pytestmark = pytest.mark.ros


def test_a_killed_launcher_leaves_no_process_and_a_finished_bag(tmp_path):
    bag = tmp_path / "orphaned.mcap"
    with LaunchedGraph(["ipc", "namespace:=orphaned", "duration:=600", "-p", "plant.report_period:=1",
                        "--record", str(bag)]) as graph:
        graph.wait_for_line("t=5.0 s (")
        children = psutil.Process(graph.process.pid).children(recursive=True)
        graph.process.kill()
        _, alive = psutil.wait_procs(children, timeout=60)
    assert len(children) >= 6 and not alive, [process.cmdline() for process in alive]
    verification = verify_bag(bag)
    assert verification.ok, verification.text()
    loads = next(topic for topic in verification.topics if topic.coverage.topic == "/orphaned/plant/blade_loads")
    # The recorder may be up to recorder_window (5 s) behind the plant when the launcher dies; what it has is
    # complete from step 0.
    assert loads.coverage.ranges[0][0] == 0 and loads.coverage.ranges[-1][1] >= 100
