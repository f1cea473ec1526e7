"""hawt launch runs real node graphs: separate processes that talk, composed runs, clean stops and failures."""
import json
import math
import re
import signal
import subprocess
import tempfile
import time
from pathlib import Path

import psutil
import pytest
from launched_graph import LaunchedGraph

from hawt_bag.reader import BagReader

pytestmark = pytest.mark.ros

GRAPH = """\
launch:
- arg: {{name: record_file}}
- node:
    pkg: hawt_tools
    exec: pulse_source
    name: source
    namespace: t
    param:
    - {{name: rate_hz, value: 100.0}}
    - {{name: wait_for_subscribers, value: 1}}
    remap:
    - {{from: out, to: loads}}
- node:
    pkg: hawt_tools
    exec: relay
    name: relay
    namespace: t
    param:
    - {{name: gain, value: 2.0}}
{relay_extra}    remap:
    - {{from: in, to: loads}}
    - {{from: out, to: relayed}}
- node:
    pkg: hawt_tools
    exec: counter_sink
    name: sink
    namespace: t
    on_exit: shutdown
    param:
    - {{name: record_file, value: $(var record_file)}}
    remap:
    - {{from: in, to: relayed}}
"""


def _graph(folder: Path, relay_extra: str = "") -> Path:
    path = folder / "graph.yaml"
    path.write_text(GRAPH.format(relay_extra=relay_extra))
    return path


def _received(record: Path) -> dict:
    return {int(step): values for step, values in json.loads(record.read_text()).items()}


def _source_moment(step: int, blade: int, rate_hz: float = 100.0, rotor_speed: float = 1.267) -> float:
    """Blade moment the pulse source sends at a step (its documented 1P pattern)."""
    azimuth = (rotor_speed / rate_hz * step) % (2 * math.pi)
    return 1.0e6 * (1.0 + 0.2 * math.cos(azimuth + 2 * math.pi * blade / 3))


def _launch(hawt_cli, graph: Path, record: Path, *options: str, timeout: float = 60.0):
    return subprocess.run([*hawt_cli, "launch", str(graph), f"record_file:={record}", *options],
                          capture_output=True, text=True, timeout=timeout)


def _start(hawt_cli, graph: Path, record: Path, *options: str) -> subprocess.Popen:
    return subprocess.Popen([*hawt_cli, "launch", str(graph), f"record_file:={record}", *options],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _wait_for_children(process: subprocess.Popen, count: int, timeout: float = 20.0) -> list:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        children = psutil.Process(process.pid).children(recursive=True)
        if len(children) >= count:
            return children
        time.sleep(0.1)
    raise AssertionError(f"the launcher started {len(children)} processes, expected {count}")


def _wait_for_file(path: Path, timeout: float = 20.0) -> None:
    deadline = time.monotonic() + timeout
    while not path.exists() and time.monotonic() < deadline:
        time.sleep(0.1)


def test_three_nodes_in_separate_processes_exchange_messages(hawt_cli, tmp_path):
    """source -> relay -> sink, each its own process: the sink receives the source's pattern scaled by the relay."""
    record = tmp_path / "received.json"
    # The run ends when the sink has 150 messages (on_exit: shutdown), not after a wall-clock time.
    result = _launch(hawt_cli, _graph(tmp_path), record, "-p", "sink.expect:=150")
    assert result.returncode == 0, result.stderr
    for label in ("/t/source", "/t/relay", "/t/sink"):
        assert f"[{label}]" in result.stdout
    received = _received(record)
    assert len(received) > 100
    for step, values in received.items():
        assert values == pytest.approx([2.0 * _source_moment(step, blade) for blade in range(3)], rel=1e-12)


def test_composed_run_gives_the_same_messages(hawt_cli, tmp_path):
    """The same graph in one process on one executor delivers what separate processes do: the source's pattern
    scaled by the relay, at every step the sink receives. (Which steps those are depends on when the relay
    discovered the sink, on a busy machine hundreds of steps apart between two runs.)"""
    separate, composed = tmp_path / "separate.json", tmp_path / "composed.json"
    assert _launch(hawt_cli, _graph(tmp_path), separate, "-p", "sink.expect:=300").returncode == 0
    result = _launch(hawt_cli, _graph(tmp_path), composed, "-p", "sink.expect:=300", "--composed")
    assert result.returncode == 0, result.stderr
    for received in (_received(separate), _received(composed)):
        assert len(received) >= 300
        for step, values in received.items():
            assert values == pytest.approx([2.0 * _source_moment(step, blade) for blade in range(3)], rel=1e-12), step


def test_sigint_stops_every_node_and_leaves_no_process(tmp_path):
    """Ctrl-C on the launcher, once the sink has messages, stops all three node processes and it exits 0."""
    record = tmp_path / "received.json"
    with LaunchedGraph([str(_graph(tmp_path)), f"record_file:={record}"]) as graph:
        graph.wait_for_line("received ")  # the sink's report of what it has, once it has something
        children = psutil.Process(graph.process.pid).children(recursive=True)
        graph.process.send_signal(signal.SIGINT)
        assert graph.finish(timeout=30) == 0, graph.tail()
    assert len(children) == 3
    assert not [c.pid for c in children if c.is_running() and c.status() != psutil.STATUS_ZOMBIE]
    assert _received(record), "the sink wrote what it received on its way out"


def test_a_node_that_dies_is_named_and_the_launch_fails(hawt_cli, tmp_path):
    """A node killed mid-run: the launcher names it, stops the others and exits 1."""
    launcher = _start(hawt_cli, _graph(tmp_path), tmp_path / "received.json")
    children = _wait_for_children(launcher, 3)
    time.sleep(1.5)
    relay = next(c for c in children if "__node:=relay" in " ".join(c.cmdline()))
    relay.kill()
    out, err = launcher.communicate(timeout=30)
    assert launcher.returncode == 1
    assert err.strip().splitlines()[-1] == "hawt launch: node /t/relay died unexpectedly (killed by SIGKILL)"
    assert not [c.pid for c in children if c.is_running() and c.status() != psutil.STATUS_ZOMBIE]


def test_a_node_failing_at_start_is_named(hawt_cli, tmp_path):
    """A relay given a number for its string label fails to start: exit 1, named.

    Through its ros_args, which the check before start does not read (-p relay.label:=3 is refused before start,
    tests/hawt_tools/test_parameter_check.py).
    """
    graph = _graph(tmp_path, relay_extra='    ros_args: "-p label:=3"\n')
    result = _launch(hawt_cli, graph, tmp_path / "r.json", "--duration", "20")
    assert result.returncode == 1
    assert "hawt launch: node /t/relay died unexpectedly (exit code 1)" in result.stderr


def test_a_graph_with_a_typo_is_refused_before_anything_starts(hawt_cli, tmp_path):
    """'remaps' instead of 'remap': exit 2, one line naming file, line and key, no node output, no record."""
    graph = tmp_path / "graph.yaml"
    graph.write_text(GRAPH.format(relay_extra="").replace("    remap:\n    - {from: in", "    remaps:\n    - {from: in"))
    record = tmp_path / "received.json"
    result = _launch(hawt_cli, graph, record, "--duration", "5")
    assert result.returncode == 2
    assert result.stderr == f"hawt launch: {graph}:20: unknown key 'remaps' in node (did you mean 'remap'?)\n"
    assert result.stdout == "" and not record.exists()


def test_a_graph_naming_a_missing_executable_is_refused(hawt_cli, tmp_path):
    """exec: rely (a typo) is found before start, with the executables the package has."""
    graph = tmp_path / "graph.yaml"
    graph.write_text(GRAPH.format(relay_extra="").replace("exec: relay", "exec: rely"))
    result = _launch(hawt_cli, graph, tmp_path / "r.json")
    assert result.returncode == 2
    assert result.stderr.endswith(":13: node 'relay': package 'hawt_tools' has no executable 'rely' "
                                  "(did you mean 'relay'?)\n")


def test_an_executable_action_runs_its_program_under_hawt_launch_only(hawt_cli, tmp_path):
    """A program that is no package's node runs only by an explicit 'executable' action, in its own process beside
    the nodes; the engines that run nodes in one process refuse the graph before anything starts."""
    graph = _graph(tmp_path)
    graph.write_text(graph.read_text() + "- executable: {cmd: 'touch $(var record_file).marker', name: marker}\n")
    record = tmp_path / "received.json"
    result = _launch(hawt_cli, graph, record, "-p", "sink.expect:=50")
    assert result.returncode == 0, result.stderr
    assert Path(f"{record}.marker").exists() and "[hawt launch] program marker finished" in result.stdout
    refusal = f"{graph}:33: the 'executable' action 'marker' runs only under hawt launch (separate processes), not"
    composed = _launch(hawt_cli, graph, tmp_path / "composed.json", "--composed")
    in_process = subprocess.run([*hawt_cli, "run", str(graph), f"record_file:={tmp_path / 'run.json'}"],
                                capture_output=True, text=True, timeout=60)
    assert (composed.returncode, composed.stderr) == (2, f"hawt launch: {refusal} --composed\n")
    assert (in_process.returncode, in_process.stderr) == (2, f"hawt run: {refusal} in one process (hawt run, "
                                                             "campaigns)\n")


def test_parameters_from_a_file_wildcards_and_overrides_reach_the_node(hawt_cli, tmp_path):
    """'/**' sets the label, the node entry sets gain 3, and -p relay.gain:=4.0 wins over both."""
    (tmp_path / "relay.yaml").write_text("/**:\n  ros__parameters:\n    label: wildcard\n"
                                         "/**/relay:\n  ros__parameters:\n    gain: 3.0\n")
    graph = _graph(tmp_path, relay_extra="    - {from: relay.yaml}\n")
    record = tmp_path / "received.json"
    # The run ends when the sink has 5 messages (on_exit: shutdown), not after a wall-clock time.
    result = _launch(hawt_cli, graph, record, "-p", "sink.expect:=5")
    assert result.returncode == 0
    assert "gain=3.0 label='wildcard'" in result.stdout
    result = _launch(hawt_cli, graph, record, "-p", "sink.expect:=5", "-p", "relay.gain:=4.0")
    assert "gain=4.0 label='wildcard'" in result.stdout
    step, values = next(iter(_received(record).items()))
    assert values[0] == pytest.approx(4.0 * _source_moment(step, 0))


def test_an_override_of_a_node_not_in_the_graph_is_refused(hawt_cli, tmp_path):
    """-p rellay.gain:=2 names the nodes that exist."""
    result = _launch(hawt_cli, _graph(tmp_path), tmp_path / "r.json", "-p", "rellay.gain:=2")
    assert result.returncode == 2
    assert "no node named 'rellay' in the graph (nodes: /t/source, /t/relay, /t/sink)" in result.stderr


def test_a_respawned_node_comes_back(tmp_path):
    """respawn: true brings a killed relay back and the sink keeps receiving."""
    record = tmp_path / "received.json"
    graph = _graph(tmp_path)
    graph.write_text(graph.read_text().replace("    name: relay\n", "    name: relay\n    respawn: true\n"))
    with LaunchedGraph([str(graph), f"record_file:={record}"]) as launched:
        launched.wait_for_line("received ")  # the sink has messages through the first relay
        relay = next(c for c in psutil.Process(launched.process.pid).children(recursive=True)
                     if "__node:=relay" in " ".join(c.cmdline()))
        relay.kill()
        launched.wait_for_line("respawning in 0 s (respawn 1)")
        respawned = len(launched.lines)
        launched.wait_for_line("gain=2.0", after=respawned)  # the new relay is up
        up = len(launched.lines)
        launched.wait_for_line("received ", after=up)
        killed_at = max(_steps_reported(launched.lines[:respawned]))
        launched.wait_until(lambda: max(_steps_reported(launched.lines[up:]), default=0) > killed_at + 100,
                            "the sink receiving after the relay came back")
        launched.process.send_signal(signal.SIGINT)
        assert launched.finish(timeout=30) == 0, launched.tail()
    output = "".join(launched.lines)
    assert "/t/relay ended (killed by SIGKILL); respawning in 0 s (respawn 1)" in output
    assert output.count("gain=2.0") == 2
    assert max(_received(record)) > killed_at + 100, "the sink received messages after the relay came back"


def _steps_reported(lines) -> list:
    """The last step of each of the sink's 'received N messages, steps A..B' reports."""
    return [int(m.group(1)) for line in lines if (m := re.search(r"received \d+ messages, steps \d+\.\.(\d+)", line))]


def test_hawt_list_shows_the_running_nodes_and_topics_with_types(hawt_cli, tmp_path):
    """While a graph runs, hawt list names its three nodes and its topics with their types."""
    launcher = _start(hawt_cli, _graph(tmp_path), tmp_path / "r.json")  # runs until the SIGINT below
    try:
        _wait_for_children(launcher, 3)
        while launcher.poll() is None:  # until discovery has found the three nodes (slow on a busy machine)
            listing = subprocess.run([*hawt_cli, "list"], capture_output=True, text=True, timeout=60)
            if listing.returncode != 0 or listing.stdout.startswith("nodes (3):"):
                break
    finally:
        launcher.send_signal(signal.SIGINT)
        launcher.communicate(timeout=30)
    assert listing.returncode == 0, listing.stderr
    lines = listing.stdout.splitlines()
    assert lines[:4] == ["nodes (3):", "  /t/relay", "  /t/sink", "  /t/source"]
    assert any(line.split()[:2] == ["/t/loads", "hawt_msgs/msg/BladeLoads"] and "(1 pub, 1 sub)" in line
               for line in lines)
    assert any(line.split()[:2] == ["/t/relayed", "hawt_msgs/msg/BladeLoads"] for line in lines)


def test_a_launcher_killed_with_sigkill_leaves_no_node_a_finished_bag_and_no_folder_after_the_next_launch(
        hawt_cli, tmp_path):
    """kill -9 of hawt launch --record: every node and the recorder see their parent gone and stop, the recorder
    finishing its bag; the parameter folder the killed launcher could not remove goes with the next launch."""
    bag = tmp_path / "killed.mcap"
    launcher = _start(hawt_cli, _graph(tmp_path), tmp_path / "r.json", "--record", str(bag))
    children = _wait_for_children(launcher, 4)  # three nodes and the recorder
    folder = next(Path(tempfile.gettempdir()).glob(f"hawt_launch_{launcher.pid}_*"))
    launcher.kill()
    launcher.wait()
    psutil.wait_procs(children, timeout=60)
    assert not [c.pid for c in children if c.is_running() and c.status() != psutil.STATUS_ZOMBIE]
    with BagReader(bag) as reader:
        assert reader.has_summary, "the bag has its summary: the recorder finished it"
    # (a launch of another test running beside this one may already have removed it: any next launch does)
    assert _launch(hawt_cli, _graph(tmp_path), tmp_path / "again.json", "-p", "sink.expect:=5").returncode == 0
    assert not folder.exists()
