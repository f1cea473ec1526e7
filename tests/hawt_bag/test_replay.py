"""hawt replay on real graphs: recorded timing at rate 1, and step replay through the example relay."""
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest
from hawt_msgs.msg import BladeLoads
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message

from hawt_analysis.synthetic_run import synthetic_channels
from hawt_bag.column_writing import TopicData, write_topics
from hawt_bag.reader import BagReader
from hawt_bag.topic_columns import read_topic_columns
from hawt_bag.writer import BagWriter

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ros_helpers import wait_for_file  # noqa: E402

pytestmark = pytest.mark.ros

GRAPH = """\
launch:
- node:
    pkg: hawt_tools
    exec: {executable}
    name: {name}
    namespace: t
    param:
{parameters}    remap:
{remaps}"""


def _graph(folder: Path, executable: str, name: str, parameters: dict, remaps: dict) -> Path:
    path = folder / f"{name}.yaml"
    path.write_text(GRAPH.format(
        executable=executable, name=name,
        parameters="".join(f"    - {{name: {k}, value: {v}}}\n" for k, v in parameters.items()),
        remaps="".join(f"    - {{from: {k}, to: {v}}}\n" for k, v in remaps.items())))
    return path


class _Arrivals:
    """Subscribes the probe to a topic and keeps (time of publication [s], serialized message) of each arrival: the
    publisher's source timestamp, not this process's time of arrival, which a busy machine delays as much as the
    replay's (a fresh-clone CI run timed 0.92 s from the first arrival to the last of a replay of 1.18 s). Also keeps
    the first message of each step: a step replay sends a step again when its answer is late, and a relay answers
    each copy.

    A replayer that has ended has had its messages acknowledged, but the probe's thread may not have taken the last
    ones yet: wait for them (``wait_for``) before reading ``items``.
    """

    def __init__(self, probe, topic: str) -> None:
        self.probe = probe
        self.lock = threading.Lock()
        self.items = []
        self.first_of_step = {}  # step: the first serialized message of that step
        self.subscription = probe.node.create_subscription(
            BladeLoads, topic, self._arrived, QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE),
            raw=True)

    def _arrived(self, data: bytes, info) -> None:
        with self.lock:
            self.items.append((info["source_timestamp"] * 1e-9, data))
            self.first_of_step.setdefault(deserialize_message(data, BladeLoads).step, data)

    def wait_matched(self, timeout: float = 30.0) -> None:
        self.probe.wait_until(lambda: self.subscription.get_publisher_count() >= 1,
                              "match of the probe's subscription", timeout=timeout)

    def wait_for(self, count: int, timeout: float = 30.0) -> None:
        """Return once ``count`` messages have arrived; fail after ``timeout`` s."""
        self.probe.wait_until(lambda: len(self.items) >= count, f"{count} messages", timeout=timeout)

    def first_of_each_step(self, count: int, timeout: float = 30.0) -> list:
        """The first message of each of the steps 0 … ``count`` - 1, in step order, once they have arrived."""
        self.probe.wait_until(lambda: len(self.first_of_step) >= count, f"{count} steps", timeout=timeout)
        assert sorted(self.first_of_step) == list(range(count)), f"steps arrived: {sorted(self.first_of_step)}"
        return [self.first_of_step[step] for step in range(count)]


def test_replay_at_rate_one_keeps_the_recorded_spacing(processes, probe, tmp_path):
    """Messages recorded 20 ms apart are published about 20 ms apart (loose bound; figures in bench_bag.py)."""
    bag = tmp_path / "timed.mcap"
    n, period = 60, 20_000_000
    channels = synthetic_channels(duration=(n - 1) * period * 1e-9, sample_rate=1e9 / period)
    columns = {"step": np.arange(n, dtype=np.uint64), "azimuth": channels["azimuth"],
               "root_moment_oop": channels["root_moment_oop"]}
    with BagWriter(bag) as writer:
        write_topics(writer, [TopicData("/timed/loads", "hawt_msgs/msg/BladeLoads", columns,
                                        5_000_000_000 + period * np.arange(n))])
    arrivals = _Arrivals(probe, "/timed/loads")
    replay = processes.hawt("replay", str(bag), "--wait-for-subscribers")
    out, err = replay.communicate(timeout=60)
    assert replay.returncode == 0, err
    assert f"replayed {n} messages" in out and "warning" not in err  # nobody else publishes /timed/loads
    arrivals.wait_for(n)
    times = np.array([t for t, _ in arrivals.items])
    assert times.size == n
    spacing = np.diff(times)
    assert np.median(spacing) == pytest.approx(period * 1e-9, abs=0.004)
    assert times[-1] - times[0] == pytest.approx((n - 1) * period * 1e-9, abs=0.25)
    # late on a busy machine, perhaps, but never early: each message at or after its recorded offset from the first
    assert np.all(times - times[0] >= period * 1e-9 * np.arange(n) - 0.001)


def test_step_replay_through_the_relay_gives_exactly_the_recorded_relayed_messages(processes, probe, tmp_path):
    """A source -> relay run is recorded; replaying its loads step by step through a new relay yields the
    recorded relayed messages, every field bit for bit, in step order."""
    count = 80
    recorded = tmp_path / "run.mcap"
    relay_graph = _graph(tmp_path, "relay", "relay", {"gain": 2.5}, {"in": "loads", "out": "relayed"})
    source_graph = _graph(tmp_path, "pulse_source", "source",
                          {"rate_hz": 100.0, "count": count, "wait_for_subscribers": 2}, {"out": "loads"})
    relay = processes.hawt("launch", str(relay_graph))
    recorder = processes.hawt("record", "-o", str(recorded), "--topics", "/t/loads", "/t/relayed")
    wait_for_file(recorded, recorder)
    probe.wait_subscribed("/t/relayed", "hawt_recorder")
    source = processes.hawt("launch", str(source_graph))
    assert source.wait(timeout=60) == 0, source.communicate()
    code, _, err = processes.stop(recorder)
    assert code == 0, err
    processes.stop(relay)

    arrivals = _Arrivals(probe, "/t/relayed")  # before the relay: it then knows this reader by its first answer
    relay = processes.hawt("launch", str(relay_graph))
    arrivals.wait_matched()
    replay = processes.hawt("replay", str(recorded), "--topics", "/t/loads", "--step-trigger", "/t/relayed")
    out, err = replay.communicate(timeout=120)
    assert replay.returncode == 0, err
    assert f"in {count} steps" in out
    payload = arrivals.first_of_each_step(count)
    processes.stop(relay)

    with BagReader(recorded) as reader:
        expected = read_topic_columns(reader, "/t/relayed").fields
    replayed = tmp_path / "replayed.mcap"
    with BagWriter(replayed) as writer:
        channel = writer.add_topic("/t/relayed", "hawt_msgs/msg/BladeLoads")
        for time_ns, data in enumerate(payload):
            writer.write(channel, time_ns, data)
    with BagReader(replayed) as reader:
        got = read_topic_columns(reader, "/t/relayed").fields
    assert expected["step"].tolist() == list(range(count))
    assert set(got) == set(expected)
    for name, values in expected.items():
        assert values.dtype == got[name].dtype and values.tobytes() == got[name].tobytes(), name


def test_paused_replay_plays_one_message_per_play_next_and_resumes_on_the_parameter(processes, probe, tmp_path):
    """--start-paused: nothing flows; each std_msgs/Empty on /hawt_player/play_next releases one message;
    setting the player's 'paused' parameter to false plays the rest."""
    from rclpy.parameter import Parameter
    from rclpy.parameter_client import AsyncParameterClient
    from std_msgs.msg import Empty

    bag, n = tmp_path / "paused.mcap", 20
    with BagWriter(bag) as writer:
        write_topics(writer, [TopicData("/paused/loads", "hawt_msgs/msg/BladeLoads",
                                        {"step": np.arange(n, dtype=np.uint64)}, 10_000_000 * np.arange(n))])
    arrivals = _Arrivals(probe, "/paused/loads")
    next_publisher = probe.node.create_publisher(Empty, "/hawt_player/play_next", 10)
    replay = processes.hawt("replay", str(bag), "--start-paused", "--wait-for-subscribers")
    arrivals.wait_matched()
    probe.wait_until(lambda: next_publisher.get_subscription_count() >= 1, "the player's play_next subscription",
                     timeout=30)
    time.sleep(1.0)
    assert arrivals.items == []
    for _ in range(3):
        next_publisher.publish(Empty())
    arrivals.wait_for(3)
    assert len(arrivals.items) == 3
    client = AsyncParameterClient(probe.node, "hawt_player")
    assert client.wait_for_services(timeout_sec=30)
    future = client.set_parameters([Parameter("paused", value=False)])
    out, err = replay.communicate(timeout=60)
    assert replay.returncode == 0, err
    assert future.result().results[0].successful
    arrivals.wait_for(n)
    assert len(arrivals.items) == n


def test_a_replay_into_a_topic_a_running_graph_publishes_says_so_in_one_warning(processes, probe, tmp_path):
    """The probe publishes /mixed/loads itself (a running graph's plant): the replay still runs, and says on stderr,
    once, that its messages mix with that node's."""
    bag = tmp_path / "mixed.mcap"
    n, period = 60, 20_000_000
    columns = {"step": np.arange(n, dtype=np.uint64)}
    with BagWriter(bag) as writer:
        write_topics(writer, [TopicData("/mixed/loads", "hawt_msgs/msg/BladeLoads", columns,
                                        5_000_000_000 + period * np.arange(n))])
    live = probe.node.create_publisher(BladeLoads, "/mixed/loads", 10)
    arrivals = _Arrivals(probe, "/mixed/loads")
    replay = processes.hawt("replay", str(bag), "--wait-for-subscribers")
    out, err = replay.communicate(timeout=60)
    assert replay.returncode == 0, err
    assert f"replayed {n} messages" in out and arrivals.items
    assert err.splitlines() == ["hawt replay: warning: /mixed/loads is also published by /bag_test_probe: the "
                                "replayed messages mix with that graph's own (in it and in any recording of it)"]
    probe.node.destroy_publisher(live)
