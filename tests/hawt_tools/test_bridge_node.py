"""``hawt bridge`` on the ROS graph (hawt_tools.bridge_launch, hawt_tools.bridge_node), driven by hawt's own DISCON host.

The host (hawt_controllers.discon.library, ctypes) loads libhawt_discon.so and calls it with the measurements of a
``hawt run`` of the same graph on hawt's plant (18 m/s, shear 0.2: the blades' loads have a 1P), replayed call by
call; the bridge is ``hawt bridge GRAPH --file F`` in a child process, its graph real ROS processes in lockstep.
The reference is the in-process bridge (``--in-process``) on the same calls.
"""
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import psutil
import pytest

from discon_host import bridge_file, graph, host, inputs, listening, start_bridge
from hawt_controllers.discon.library import DisconFailure
from hawt_tools.in_process import build_run

pytestmark = pytest.mark.ros

STEPS = 400
"""Calls per run: 4 s at the graphs' 100 Hz."""


def _outputs(name: str, steps: int) -> tuple:
    """The graph ``name`` in process on hawt's plant: its description and the outputs of its first ``steps`` steps."""
    run = build_run(graph(name))
    outputs = []
    for _ in range(steps):
        outputs.append(run.output)
        run.step()
    return run.description, outputs


def _drive(path: Path, description, outputs, individual: bool, pause=None) -> list:
    """The host's demands for each of ``outputs`` (then its last call); ``pause(k)`` runs before call k if given."""
    library = host(path, description, individual)
    demands = []
    for k, output in enumerate(outputs):
        if pause is not None:
            pause(k)
        demands.append(library.step(inputs(output)))
    library.close()
    return demands


def _bridged(folder: Path, name: str, outputs, description, individual: bool, in_process: bool, extra: str = "",
             options=(), pause=None) -> tuple:
    """``hawt bridge GRAPH --file F OPTIONS [--in-process]`` driven through ``outputs``: the demands, the bridge's
    exit code and output."""
    path = bridge_file(folder, name, extra, "in-process" if in_process else "ros-graph")
    bridge = listening(start_bridge(path, in_process, name, *options))
    try:
        demands = _drive(path, description, outputs, individual, pause)
        out, err = bridge.communicate(timeout=120)
    finally:
        if bridge.poll() is None:
            bridge.send_signal(signal.SIGINT)
            bridge.communicate(timeout=60)
    return demands, bridge.returncode, out, err


def _commands(demands) -> np.ndarray:
    """Pitch of each blade and generator torque of each call, as the library wrote them (float32)."""
    return np.array([[*d.pitch, d.generator_torque] for d in demands], dtype=np.float32)


@pytest.fixture(scope="module")
def baseline(tmp_path_factory):
    """The baseline graph bridged on the ROS graph (recorded) and in process, on the same STEPS calls."""
    folder = tmp_path_factory.mktemp("bridge_baseline")
    description, outputs = _outputs("baseline", STEPS)
    bag = folder / "bridged.mcap"
    ros = _bridged(folder, "baseline", outputs, description, False, False, options=("namespace:=brb", "--record",
                                                                                      str(bag)))
    in_process = _bridged(folder, "baseline", outputs, description, False, True)
    return {"ros": ros, "in_process": in_process, "bag": bag}


def test_the_ros_graph_answers_every_call_as_the_in_process_bridge_bit_for_bit(baseline):
    """Pitch of every blade and torque at every call: the lockstep graph's equal the in-process engine's to the
    bit (the engines are bit-identical, docs/architecture.md §5)."""
    ros, in_process = _commands(baseline["ros"][0]), _commands(baseline["in_process"][0])
    assert ros.shape == (STEPS, 4)
    assert np.array_equal(ros, in_process), np.argwhere(ros != in_process)[:5]


def test_the_last_call_ends_the_graph_cleanly(baseline):
    """Status -1 ends the bridge plant node and, through it, the graph: exit 0, every step answered."""
    _, code, out, err = baseline["ros"]
    assert code == 0, out[-3000:] + err[-3000:]
    assert f"finished {STEPS} steps" in out and "/brb/plant finished" in out
    assert "the simulator's last call ended the graph" in out


def test_the_recorded_bag_has_every_step(baseline):
    """``--record``: the bag is finished and plant/blade_loads, plant/state and control/pitch_command hold every
    answered call's step, 0 to STEPS - 1, without a gap (a step the plant sent again is recorded again, the same)."""
    from hawt_bag.verification import verify_bag

    verification = verify_bag(baseline["bag"])
    assert verification.ok, verification.text()
    coverage = {check.coverage.topic.split("/", 2)[-1]: check.coverage for check in verification.topics}
    for topic in ("plant/blade_loads", "plant/state", "control/pitch_command"):
        assert (coverage[topic].first, coverage[topic].last, coverage[topic].gaps) == (0, STEPS - 1, ()), topic


@pytest.fixture(scope="module")
def switched(tmp_path_factory):
    """The switching graph bridged on the ROS graph, paused at call 200 for one ``hawt switch --activate ipc_h1``;
    then the in-process bridge with that switch in the manager's schedule at the step the switch answered, on the
    same calls."""
    folder = tmp_path_factory.mktemp("bridge_switch")
    description, outputs = _outputs("switching", STEPS)
    answers = []

    def switch(k: int) -> None:
        if k == 200:  # the graph waits in lockstep for call 200: the switch lands at a known step
            answers.append(subprocess.run([sys.executable, "-m", "hawt_tools.cli", "switch", "--activate", "ipc_h1",
                                           "--namespace", "brs"], capture_output=True, text=True, timeout=120))

    ros = _bridged(folder, "switching", outputs, description, True, False, options=("namespace:=brs",), pause=switch)
    (answer,) = answers
    found = re.search(r"at step (\d+)", answer.stdout)
    assert answer.returncode == 0 and found, answer.stdout + answer.stderr
    step = int(found.group(1))
    in_process = _bridged(folder, "switching", outputs, description, True, True,
                          options=(f"schedule:=['{step} +ipc_h1']",))
    return {"ros": ros, "in_process": in_process, "step": step, "answer": answer.stdout}


def test_a_live_switch_during_a_bridged_run_acts_at_the_step_it_answers(switched):
    """``hawt switch --activate ipc_h1`` while a simulator drives the graph: collective pitch (all blades alike) until
    the step the switch answered, the blades apart from then on (the 1P controller ramps in), and every command
    equal to the in-process bridge's with that switch scheduled at that step, to the bit."""
    ros, in_process, step = _commands(switched["ros"][0]), _commands(switched["in_process"][0]), switched["step"]
    assert switched["ros"][1] == 0, switched["ros"][2][-3000:]
    assert 200 <= step < STEPS - 100, switched["answer"]
    spread = np.ptp(ros[:, :3], axis=1)
    assert np.all(spread[:step] == 0)
    assert np.all(spread[step + 10:] > 0)
    assert np.array_equal(ros, in_process), np.argwhere(ros != in_process)[:5]


def test_a_graph_killed_mid_run_makes_the_library_fail_within_its_timeout(tmp_path):
    """SIGKILL of ``hawt bridge`` (its launcher) after 50 calls: its nodes stop by themselves (parent watchdog), the
    bridge plant node's end closes the connection, and a call of the library fails with its message within the
    file's timeout (5 s) of the kill, not hanging (the calls right after the kill may still be answered, by nodes
    that have not seen it yet); no node process is left behind."""
    description, outputs = _outputs("baseline", 1)
    path = bridge_file(tmp_path, "baseline")
    bridge = listening(start_bridge(path, False, "baseline", "namespace:=brk"))
    library = host(path, description)
    for _ in range(50):
        library.step(inputs(outputs[0]))
    nodes = psutil.Process(bridge.pid).children(recursive=True)
    bridge.kill()
    killed = time.monotonic()
    with pytest.raises(DisconFailure, match=r"hawt bridge on .* (is gone|did not answer within 5 s)"):
        while time.monotonic() - killed < 60:
            library.step(inputs(outputs[0]))
    assert time.monotonic() - killed < 5.0 + 1.0
    bridge.communicate(timeout=60)
    _, alive = psutil.wait_procs(nodes, timeout=60)
    for process in alive:
        process.kill()
    assert not alive, [p.pid for p in alive]
