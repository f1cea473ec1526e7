"""libhawt_discon.so and hawt_tools.discon_bridge: a graph as a DISCON library, driven by hawt's own DISCON host.

The host is hawt_controllers.discon.library (ctypes, float32 swap array, a private loaded copy per instance);
the bridge is a separate process (``python -m hawt_tools.discon_bridge --in-process FILE``), as it is beside
OpenFAST. The bridge on the ROS graph (its default) is tests/hawt_tools/test_bridge_node.py's; the faults found at the
first call, before a graph starts, are checked here on both.
"""
import os
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from discon_host import bridge_file as _bridge_file
from discon_host import graph as _graph
from discon_host import host, inputs as _inputs
from discon_host import listening as _listening
from discon_host import start_bridge as _start_bridge
from hawt_controllers.discon.library import DisconFailure, DisconLibrary
from hawt_tools.discon_bridge import MISSING_FIELDS, BridgeError, bridge_library, measurements, read_bridge_file
from hawt_tools.in_process import RunRecord, build_run

STEPS = 600
"""Calls per run: 6 s at the graphs' 100 Hz."""


def _host(path: Path, run, individual: bool = False) -> DisconLibrary:
    return host(path, run.description, individual)


class _Replay:
    """A plant model that returns given outputs one by one (the in-process reference on the host's inputs)."""

    def __init__(self, outputs):
        self.outputs = iter(outputs)

    def step(self, pitch, torque):
        return next(self.outputs)


@pytest.fixture(scope="module", params=["baseline", "ipc"])
def bridged(request, tmp_path_factory):
    """``hawt run GRAPH`` (in process, 18 m/s sheared) for STEPS steps, then the same measurements through the
    library and the bridge: the run's outputs and commands, the host's demands and what the library sent."""
    name = request.param
    run = build_run(_graph(name))
    book, outputs = RunRecord(), []
    for _ in range(STEPS):
        outputs.append(run.output)
        run.step(book)
    folder = tmp_path_factory.mktemp(name)
    path = _bridge_file(folder, name)
    bridge = _start_bridge(path)
    host = _host(path, run, individual=name == "ipc")
    demands, sent = [], []
    for output in outputs:
        demands.append(host.step(_inputs(output)))
        sent.append(host.swap[:129].copy())
    host.close()
    out, err = bridge.communicate(timeout=60)
    return {"name": name, "run": run, "outputs": outputs, "commands": book.rows["control/pitch_command"],
            "demands": demands, "sent": sent, "bridge": (bridge.returncode, out, err)}


def test_the_bridge_ends_cleanly_at_the_last_call(bridged):
    """Status -1 ends the bridge's run: exit 0, every call answered (STEPS and the last)."""
    code, out, err = bridged["bridge"]
    assert code == 0, err
    assert f"finished {STEPS + 1} DISCON calls" in out


def test_commands_equal_the_graph_in_process_on_the_same_measurements_bit_for_bit(bridged):
    """The graph stepped in process on the float32 measurements the library sent gives, rounded to float32, the
    library's demands bit for bit: pitch per blade, collective and torque."""
    blades = bridged["run"].description.blades
    seen = [measurements(swap, blades) for swap in bridged["sent"]]
    reference = build_run(_graph(bridged["name"]), plant=lambda values, progress: (
        _turbine(values), _Replay(seen[1:] + seen[-1:]), seen[0]))
    book = RunRecord()
    for _ in range(STEPS):
        reference.step(book)
    for k, (row, demand) in enumerate(zip(book.rows["control/pitch_command"], bridged["demands"])):
        pitch = np.asarray(row["pitch"], dtype=np.float32)
        assert np.array_equal(np.asarray(demand.pitch, dtype=np.float32), pitch), k
        assert np.float32(demand.collective) == np.float32(np.mean(row["pitch"])), k
        assert np.float32(demand.generator_torque) == np.float32(row["generator_torque"]), k


def _turbine(values):
    from hawt_plant.turbine import nrel_5mw, turbine_from

    return turbine_from(values["turbine_file"]) if values["turbine_file"] else nrel_5mw()


def test_commands_equal_hawt_run_to_float32_precision(bridged):
    """Against ``hawt run`` on the float64 measurements: the same commands but for the float32 rounding of the
    swap array (inputs and outputs), which the controllers' filters carry on: within 1e-6 rad and 1e-5 relative."""
    commands, demands = bridged["commands"], bridged["demands"]
    pitch = np.array([c["pitch"] for c in commands])
    torque = np.array([c["generator_torque"] for c in commands])
    assert np.max(np.abs(np.array([d.pitch for d in demands]) - pitch)) < 1e-6
    assert np.max(np.abs(np.array([d.generator_torque for d in demands]) - torque) / np.abs(torque)) < 1e-5
    if bridged["name"] == "ipc":
        assert np.ptp(pitch, axis=1).max() > np.radians(0.1), "the ipc graph pitches the blades apart"


def test_fields_the_interface_lacks_are_nan():
    """The plant output of a call has NaN exactly where the DISCON interface has no record."""
    swap = np.arange(1, 130, dtype=np.float32)
    output = measurements(swap, 3)
    for name in MISSING_FIELDS:
        assert np.isnan(getattr(output, name)), name
    assert output.rotor_speed == 21 and list(output.root_moment_oop) == [30, 31, 32]
    assert list(output.pitch) == [4, 33, 34] and list(output.root_moment_ip) == [69, 70, 71]


@pytest.fixture(scope="module")
def steady():
    """The baseline graph built in process, not stepped, and its first output: the description and measurements a
    host sends (each test reads them, none steps the run)."""
    run = build_run(_graph("baseline"))
    return run, run.output


def test_a_bridge_killed_mid_run_makes_the_library_fail_with_a_message(steady, tmp_path):
    """SIGKILL of the bridge after 50 calls: the next call fails (aviFAIL < 0) naming the gone bridge, and the swap
    array holds the safe commands: the last pitch one step towards feather, the last torque held."""
    run, output = steady
    path = _bridge_file(tmp_path)
    bridge = _start_bridge(path)
    host = _host(path, run)
    for _ in range(50):
        last = host.step(_inputs(output))
    bridge.kill()
    bridge.wait()
    with pytest.raises(DisconFailure, match="hawt bridge on .* is gone"):
        host.step(_inputs(output))
    rate, dt = run.turbine.pitch_actuator.max_rate, run.description.dt
    assert np.allclose(host.swap[41:44], np.float32(last.pitch[0] + rate * dt), rtol=0, atol=1e-6)
    assert host.swap[46] == np.float32(last.generator_torque)


def test_a_bridge_that_stops_answering_makes_the_library_fail_after_the_timeout(steady, tmp_path):
    """A stopped bridge (SIGSTOP) does not answer: the call returns after the file's timeout with aviFAIL < 0.
    (The first call, which builds the graph, has the start timeout.)"""
    run, output = steady
    path = _bridge_file(tmp_path)
    path.write_text(path.read_text().replace("timeout = 5", "timeout = 0.5"))
    bridge = _listening(_start_bridge(path))
    host = _host(path, run)
    try:
        host.step(_inputs(output))
        os.kill(bridge.pid, signal.SIGSTOP)
        with pytest.raises(DisconFailure, match="did not answer within 0.5 s"):
            host.step(_inputs(output))
    finally:
        bridge.kill()
        bridge.wait()


def test_no_bridge_listening_is_a_failure_not_a_hang(steady, tmp_path):
    """Without a bridge the first call fails after the timeout, saying where it looked and how to start one."""
    run, output = steady
    path = _bridge_file(tmp_path)
    path.write_text(path.read_text() + "start_timeout = 0.2\n")
    with pytest.raises(DisconFailure, match="no hawt bridge answers on .*bridge.sock within 0.2 s"):
        _host(path, run).step(_inputs(output))


@pytest.mark.parametrize("text, message", [
    ("graph = baseline\n", "no socket = PATH line"),
    ("socket = /tmp/x.sock\ngraph = baseline\ntimeout = soon\n", "timeout: expected seconds > 0, found soon"),
    ("socket = /tmp/x.sock\ngraph = baseline\nstart_timeout = -1\n", "start_timeout: expected seconds > 0, found -1"),
])
def test_a_bad_bridge_file_is_one_line_on_both_sides(steady, tmp_path, text, message):
    """The library fails with the file's fault; the bridge refuses the same file with one line and exit 2."""
    run, output = steady
    path = tmp_path / "bridge.txt"
    path.write_text(text)
    with pytest.raises(DisconFailure, match=message):
        _host(path, run).step(_inputs(output))
    bridge = _start_bridge(path, in_process=False)  # the default engine, the ROS graph: the file is read first
    _, err = bridge.communicate(timeout=60)
    assert bridge.returncode == 2
    assert err.count("\n") == 1 and message in err


@pytest.mark.parametrize("in_process", [True, False], ids=["in_process", "ros_graph"])
@pytest.mark.parametrize("extra, message", [
    ("parameters = cpc.no_such_gain:=1\n", "no_such_gain"),
    ("arguments = wind_speed:=fast\n", "wind_speed"),
    ("parameters = plant.faults:=['grid_loss at=1']\n",
     "plant.faults: the simulator is the plant: inject faults there"),
])
def test_a_graph_error_is_one_line_exit_2_and_the_library_fails_with_it(steady, tmp_path, extra, message, in_process):
    """A graph the bridge cannot build: the bridge says why in one line and exits 2; the library's first call fails
    with the same line. On either engine: the ROS graph's is checked before it starts."""
    run, output = steady
    path = _bridge_file(tmp_path, "baseline", extra)
    bridge = _start_bridge(path, in_process)
    with pytest.raises(DisconFailure, match=message) as failure:
        _host(path, run).step(_inputs(output))
    _, err = bridge.communicate(timeout=60)
    assert bridge.returncode == 2
    last = err.strip().splitlines()[-1]
    assert last.startswith("hawt bridge: ") and message in last
    assert last[len("hawt bridge: "):] in str(failure.value)


def test_read_bridge_file_names_the_line_of_an_unknown_key(tmp_path):
    """An unknown key is refused with the file and line."""
    path = tmp_path / "b.txt"
    path.write_text("socket = /tmp/s\ngraph = baseline\nsocke = x\n")
    with pytest.raises(BridgeError, match=r"b.txt:3: expected KEY = VALUE"):
        read_bridge_file(path)


def test_a_library_older_than_its_source_is_never_used(tmp_path):
    """bridge_library refuses a library whose stamp is not its source's digest, and one not built."""
    import shutil

    built = bridge_library()
    root = built.parents[2]
    source = tmp_path / "hawt_tools" / "discon_bridge" / "hawt_discon.c"
    source.parent.mkdir(parents=True)
    shutil.copy(root / "hawt_tools" / "discon_bridge" / "hawt_discon.c", source)
    with pytest.raises(BridgeError, match="not built"):
        bridge_library(tmp_path)
    (tmp_path / "ros2_ws" / "lib").mkdir(parents=True)
    for name in ("libhawt_discon.so", ".hawt-discon"):
        shutil.copy(built.parent / name, tmp_path / "ros2_ws" / "lib" / name)
    assert bridge_library(tmp_path) == tmp_path / "ros2_ws" / "lib" / "libhawt_discon.so"
    source.write_text(source.read_text() + "/* changed */\n")
    with pytest.raises(BridgeError, match="built from another version of hawt_tools/discon_bridge/hawt_discon.c"):
        bridge_library(tmp_path)


def test_hawt_bridge_serves_the_command_lines_graph_and_records_every_call(steady, tmp_path):
    """``hawt bridge ipc NAME:=VALUE --file F --record B --in-process``: a file with only a socket serves the command
    line's graph; at the last call the bag holds one plant/blade_loads and one control/pitch_command per answered
    call."""
    from hawt_bag.plant_run import load_plant_run
    from hawt_bag.reader import BagReader

    run, output = steady
    path = tmp_path / "bridge.txt"
    path.write_text(f"socket = {tmp_path / 'b.sock'}\n")
    bag = tmp_path / "bridged.mcap"
    bridge = subprocess.Popen([sys.executable, "-m", "hawt_tools.cli", "bridge", "ipc", "wind_speed:=18", "--file",
                               str(path), "--record", str(bag), "--in-process"], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True)
    _listening(bridge)
    host = _host(path, run, individual=True)
    for _ in range(200):
        host.step(_inputs(output))
    host.close()
    out, err = bridge.communicate(timeout=60)
    assert bridge.returncode == 0, err
    assert "finished 201 DISCON calls" in out and str(bag) in out
    with BagReader(bag) as reader:
        recorded = load_plant_run(reader)
    assert list(recorded.steps) == list(range(200))
    assert {topic.rsplit("/", 2)[-2] + "/" + topic.rsplit("/", 1)[-1]: n for topic, n in recorded.counts.items()
            if "events" not in topic} == {"plant/blade_loads": 200, "plant/state": 200, "control/pitch_command": 200}
    # what the simulator does not measure (NaN at every step) is left out of the analysis, and said so
    (unmeasured,) = [line for line in recorded.warnings if "not measured" in line]
    assert "tower_base_fa_moment" in unmeasured and "aero_torque" in unmeasured
    assert "tower_base_fa_moment" not in recorded.channels and "generator_torque" in recorded.channels


def test_individual_pitch_for_a_simulator_that_pitches_collectively_fails_with_a_message(steady, tmp_path):
    """The ipc graph behind a host with record 28 = 0: the first step whose blades' commands differ fails the library
    with the reason (set Ptch_Cntrl = 1), and the bridge exits 2."""
    run, output = steady
    path = _bridge_file(tmp_path, "ipc")
    bridge = _start_bridge(path)
    host = _host(path, run, individual=False)
    with pytest.raises(DisconFailure, match="pitches collectively: set record 28"):
        for _ in range(STEPS):
            host.step(_inputs(output))
    _, err = bridge.communicate(timeout=60)
    assert bridge.returncode == 2 and "Ptch_Cntrl = 1" in err.strip().splitlines()[-1]



def test_a_simulator_that_goes_away_before_its_last_call_ends_the_bridge_with_exit_1(steady, tmp_path):
    """A simulator that closes the socket without its last call (killed): the bridge says so in one line and exits
    1; it does not wait on. The simulator here is a plain socket speaking the library's messages."""
    import socket as sockets

    from hawt_controllers.discon.library import Record
    from hawt_tools.discon_bridge import REPLY, REQUEST

    run, output = steady
    swap = np.zeros(129, dtype=np.float32)
    for record, value in ((Record.DT, run.description.dt), (Record.BLADES, 3), (Record.ROTOR_SPEED, output.rotor_speed),
                          (Record.GENERATOR_SPEED, output.generator_speed),
                          (Record.GENERATOR_TORQUE, output.generator_torque), (Record.PITCH_1, output.pitch[0]),
                          (Record.PITCH_2, output.pitch[1]), (Record.PITCH_3, output.pitch[2])):
        swap[record - 1] = value
    path = _bridge_file(tmp_path)
    bridge = _listening(_start_bridge(path))
    with sockets.socket(sockets.AF_UNIX, sockets.SOCK_SEQPACKET) as simulator:
        simulator.connect(str(tmp_path / "bridge.sock"))
        for status in (0, 1):
            simulator.sendall(REQUEST.pack(b"HWB1", status, *swap, str(path).encode()))
            magic, fail, *_ = REPLY.unpack(simulator.recv(REPLY.size))
            assert (magic, fail) == (b"HWR1", 0)
    _, err = bridge.communicate(timeout=60)
    assert bridge.returncode == 1
    assert err.strip().splitlines()[-1] == ("hawt bridge: the simulator closed the connection after 2 calls, before "
                                            "its last call")



@pytest.mark.parametrize("in_process", [True, False], ids=["in_process", "ros_graph"])
def test_a_simulator_of_another_turbine_is_refused_at_its_first_call(steady, tmp_path, in_process):
    """Generator speed 50 times the rotor's (the graph's NREL 5 MW has 97): the first call fails naming both, and
    the bridge exits 2, on either engine (the ROS graph's before it starts)."""
    from dataclasses import replace

    run, output = steady
    path = _bridge_file(tmp_path)
    bridge = _start_bridge(path, in_process)
    with pytest.raises(DisconFailure, match="generator speed is 50 times its rotor speed .* gearbox ratio 97"):
        _host(path, run).step(replace(_inputs(output), generator_speed=50 * output.rotor_speed))
    bridge.communicate(timeout=60)
    assert bridge.returncode == 2
