"""hawt record, launch --record and bag recover on real node graphs: what was published is what the bag holds."""
import re
import signal
import sys
import time
from pathlib import Path

import hawt_msgs.msg
import numpy as np
import pytest
from mcap.reader import make_reader
from mcap.stream_reader import StreamReader, breakup_chunk
from mcap.records import Chunk, Message
from mcap_ros2.decoder import DecoderFactory
from rclpy.duration import Duration
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message

from hawt_bag.errors import BagError
from message_samples import MESSAGE_TYPES, filled
from hawt_bag.reader import BagReader
from hawt_bag.topic_columns import read_topic_columns
from hawt_core.topics import RECORDER_PROGRESS

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ros_helpers import HERE, wait_for_file  # noqa: E402
from ros_probe import ProbeNode  # noqa: E402

pytestmark = pytest.mark.ros

SOURCE_GRAPH = """\
launch:
- node:
    pkg: hawt_tools
    exec: pulse_source
    name: source
    namespace: t
    param:
    - {{name: rate_hz, value: {rate}}}
    - {{name: count, value: {count}}}
    - {{name: wait_for_subscribers, value: {subscribers}}}
    remap:
    - {{from: out, to: loads}}
"""


def _fields(message, kind) -> dict:
    """Any decoder's message of hawt_msgs type ``kind`` as a dict of plain Python values (header flattened)."""
    values = {}
    for name, type_name in kind.get_fields_and_field_types().items():
        value = getattr(message, name)
        if type_name == "std_msgs/Header":
            values.update(sec=int(value.stamp.sec), nanosec=int(value.stamp.nanosec), frame_id=str(value.frame_id))
        elif type_name.startswith("sequence"):
            element = type_name[len("sequence<"):-1]
            values[name] = [{"double": float, "string": str}.get(element, int)(v) for v in value]
        else:
            values[name] = {"double": float, "string": str}.get(type_name, int)(value)
    return values


def test_recorded_bag_of_every_message_type_decodes_with_independent_readers(processes, tmp_path):
    """Every hawt_msgs type published by a node process is in the bag, counted by bag info and decoded
    identically by mcap_ros2, rosbags and rclpy (nested std_msgs/Header included)."""
    count = 25
    bag = tmp_path / "every.mcap"
    recorder = processes.hawt("record", "-o", str(bag), "--regex", "^/every/")
    wait_for_file(bag, recorder)
    publisher = processes.start([sys.executable, str(HERE / "every_type_publisher.py"), str(count), "1"])
    assert publisher.wait(timeout=60) == 0, publisher.communicate()
    code, out, err = processes.stop(recorder)
    assert code == 0, err

    info = processes.hawt("bag", "info", str(bag))
    text = info.communicate(timeout=30)[0]
    for name in MESSAGE_TYPES:
        assert re.search(rf"Topic: /every/{name} +\| Type: hawt_msgs/msg/{name} \| Count: {count} \|", text), text

    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore
    kinds = {f"/every/{name}": getattr(hawt_msgs.msg, name) for name in MESSAGE_TYPES}
    decoded = {decoder: {topic: [] for topic in kinds} for decoder in ("rosbags", "mcap_ros2", "rclpy")}
    with AnyReader([bag], default_typestore=get_typestore(Stores.EMPTY)) as reader:
        for connection, _, raw in reader.messages():
            decoded["rosbags"][connection.topic].append(
                _fields(reader.deserialize(raw, connection.msgtype), kinds[connection.topic]))
    with open(bag, "rb") as stream:
        for _, channel, message, ros_msg in make_reader(stream, decoder_factories=[DecoderFactory()]) \
                .iter_decoded_messages():
            kind = kinds[channel.topic]
            decoded["mcap_ros2"][channel.topic].append(_fields(ros_msg, kind))
            decoded["rclpy"][channel.topic].append(_fields(deserialize_message(message.data, kind), kind))
    for topic, kind in kinds.items():
        expected = [_fields(filled(kind, i), kind) for i in range(count)]
        for decoder, messages in decoded.items():
            assert messages[topic] == expected, f"{decoder} decoding of {topic}"


def test_sigkill_loses_at_most_the_open_chunk_and_sigterm_finishes_the_bag(processes, probe, tmp_path):
    """Two recorders of one source: after SIGKILL the bag is unreadable until recovered, and the recovered
    bag holds every message of the complete chunks, without gaps; after SIGTERM the bag has its summary."""
    killed, terminated = tmp_path / "killed.mcap", tmp_path / "terminated.mcap"
    recorders = {}
    for path, name in ((killed, "rec_kill"), (terminated, "rec_term")):
        recorders[path] = processes.hawt("record", "-o", str(path), "--topics", "/t/loads", "--node-name", name,
                                         "--chunk-size", "4000", "--chunk-interval", "0.2")
    graph = tmp_path / "source.yaml"
    graph.write_text(SOURCE_GRAPH.format(rate=200.0, count=0, subscribers=2))
    for path in recorders:
        wait_for_file(path, recorders[path])
    source = processes.hawt("launch", str(graph))
    for name in ("rec_kill", "rec_term"):
        probe.wait_subscribed("/t/loads", name)
    seen = []  # the probe counts what the recorders are sent: a condition, not a clock
    probe.node.create_subscription(hawt_msgs.msg.BladeLoads, "/t/loads", seen.append, 1000)
    probe.wait_until(lambda: len(seen) >= 500, "500 messages on /t/loads")
    processes.stop(recorders[killed], signal.SIGKILL)
    code, _, err = processes.stop(recorders[terminated], signal.SIGTERM)
    processes.stop(source)
    assert code == 0, err

    with BagReader(terminated) as reader:
        summary_count = reader.info().message_count
        assert summary_count == sum(1 for _ in reader.messages()) > 200

    with pytest.raises(BagError, match="unfinished MCAP.*hawt bag recover"):
        BagReader(killed)
    in_complete_chunks = 0
    with open(killed, "rb") as stream:
        try:
            for record in StreamReader(stream, emit_chunks=True).records:
                if isinstance(record, Chunk):
                    in_complete_chunks += sum(isinstance(r, Message) for r in breakup_chunk(record))
        except Exception:  # noqa: BLE001 - the cut-off end of the file
            pass
    result = processes.hawt("bag", "recover", str(killed))
    out, err = result.communicate(timeout=60)
    assert result.returncode == 0, err
    with BagReader(tmp_path / "killed.recovered.mcap") as reader:
        steps = read_topic_columns(reader, "/t/loads").fields["step"]
    assert steps.size == in_complete_chunks > 100
    assert np.array_equal(steps, np.arange(steps[0], steps[0] + steps.size))


def test_a_stopped_recorder_first_takes_everything_queued_for_it(processes, probe, tmp_path):
    """Six topics of 3000 messages each, sent as fast as this process can to a recorder that writes each in a chunk
    of its own (slow: rclpy's executor hands it one message in a few hundred µs): it is stopped (SIGINT) as soon as
    its subscriptions have acknowledged the last, with thousands still to take and write. The bag holds all 18 000,
    in order. (A lockstep plant may be its recorder_window ahead when a wall-clock --duration stops a graph; a drain
    limited to 1 s once cut the last 488 steps of such a run.) 3000 per topic stay under Fast DDS's 5000 samples
    per reader, so all are acknowledged without the recorder taking any (beyond it, acknowledgements come only as
    fast as it takes); on a busy machine the test waits as long as the recorder goes on writing, and fails if it
    writes nothing for a minute."""
    count, topics = 3000, [f"/backlog/t{k}" for k in range(6)]
    bag = tmp_path / "backlog.mcap"
    recorder = processes.hawt("record", "-o", str(bag), "--regex", "^/backlog/", "--chunk-size", "1")
    wait_for_file(bag, recorder)
    written = []  # the recorder's count of messages written, from its progress
    probe.node.create_subscription(hawt_msgs.msg.RecorderProgress, RECORDER_PROGRESS,
                                   lambda message: written.append(sum(message.counts)), 1)
    reliable = QoSProfile(depth=count, reliability=ReliabilityPolicy.RELIABLE)
    publishers = [probe.node.create_publisher(hawt_msgs.msg.BladeLoads, topic, reliable) for topic in topics]
    probe.wait_until(lambda: all(p.get_subscription_count() == 1 for p in publishers), "the recorder's subscriptions",
                     alive=recorder)
    for step in range(count):
        for publisher in publishers:
            publisher.publish(hawt_msgs.msg.BladeLoads(step=step))
    writing = (None, time.monotonic())  # the recorder's last count, and since when it has had it
    while not all(publisher.wait_for_all_acked(Duration(seconds=0.1)) for publisher in publishers):
        probe.spin(0.01)
        if written and written[-1] != writing[0]:
            writing = (written[-1], time.monotonic())
        assert recorder.poll() is None, "the recorder ended before it had every message"
        assert time.monotonic() - writing[1] < 60, f"the recorder wrote nothing for 60 s ({writing[0]} written)"
    code, out, err = processes.stop(recorder, timeout=120)
    assert code == 0, err
    assert f"recorded {len(topics) * count} messages on {len(topics)} topics" in out, out
    with BagReader(bag) as reader:
        for topic in topics:
            assert np.array_equal(read_topic_columns(reader, topic).fields["step"], np.arange(count)), topic


def _record_two_senders(processes, probe, bag, topic: str, second_name: str, offers: tuple, first_readers: int):
    """``hawt record`` of ``topic`` while the probe's node and a second node (``second_name``) publish 50 messages
    each on it (even and odd steps), with the QoS ``offers`` (the probe's, the second's); the second publisher is
    made once the recorder reads the first, and the run goes on once the recorder reads it too (the first then has
    ``first_readers``). The bag's channels' publishers and the topic's columns."""
    recorder = processes.hawt("record", "-o", str(bag), "--topics", topic)
    wait_for_file(bag, recorder)
    second = ProbeNode(second_name, background=True)
    try:
        first = probe.node.create_publisher(hawt_msgs.msg.BladeLoads, topic, offers[0])
        probe.wait_until(lambda: first.get_subscription_count() == 1, "the recorder's subscription", alive=recorder)
        late = second.node.create_publisher(hawt_msgs.msg.BladeLoads, topic, offers[1])
        probe.wait_until(lambda: late.get_subscription_count() == 1 and first.get_subscription_count() == first_readers,
                         "the recorder reading both publishers", alive=recorder)
        for step in range(50):
            first.publish(hawt_msgs.msg.BladeLoads(step=2 * step))
            late.publish(hawt_msgs.msg.BladeLoads(step=2 * step + 1))
        for publisher in (first, late):
            assert publisher.wait_for_all_acked(Duration(seconds=60)), publisher.topic_name
        code, _, err = processes.stop(recorder)  # while both nodes are in the graph
    finally:
        second.close()
    assert code == 0, err
    with BagReader(bag) as reader:
        named = sorted(c.metadata["publisher"] for c in reader.summary.channels.values() if c.topic == topic)
        return named, read_topic_columns(reader, topic, ("step",))


def test_a_topic_of_two_publishing_nodes_is_recorded_in_a_channel_each_and_reads_whole(processes, probe, tmp_path):
    """Two nodes publish on one topic, 50 messages each (even steps and odd steps): the bag has a channel for each,
    named by the node's fully qualified name, and read_topic_columns reads the topic whole, each message with its
    publisher."""
    reliable = QoSProfile(depth=50, reliability=ReliabilityPolicy.RELIABLE)
    named, columns = _record_two_senders(processes, probe, tmp_path / "two.mcap", "/two/loads", "second_sender",
                                         (reliable, reliable), first_readers=1)
    assert named == ["/bag_test_probe", "/second_sender"]
    steps = columns.fields["step"]
    assert np.array_equal(np.sort(steps), np.arange(100))
    assert np.array_equal(steps[columns.publisher == "/bag_test_probe"], np.arange(0, 100, 2))
    assert np.array_equal(steps[columns.publisher == "/second_sender"], np.arange(1, 100, 2))


def test_a_publisher_the_subscription_cannot_match_is_recorded_through_a_second_one_each_message_once(
        processes, probe, tmp_path):
    """The topic's first publisher offers transient local, so the recorder subscribes transient local; a volatile
    publisher (an intruder, a probe) that joins later cannot match that subscription. Its messages come through a
    second subscription, which matches both publishers: every message of both is in the bag, and once."""
    latched = QoSProfile(depth=50, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    volatile = QoSProfile(depth=50, reliability=ReliabilityPolicy.RELIABLE)
    _, columns = _record_two_senders(processes, probe, tmp_path / "late.mcap", "/late/loads", "volatile_sender",
                                     (latched, volatile), first_readers=2)
    assert np.array_equal(np.sort(columns.fields["step"]), np.arange(100))
    assert np.array_equal(columns.fields["step"][columns.publisher == "/volatile_sender"], np.arange(1, 100, 2))


def test_launch_record_starts_the_recorder_first_and_stops_it_last(hawt_cli, tmp_path):
    """hawt launch --record: the bag is complete and holds the last message the graph's sink received."""
    import json
    import subprocess

    from hawt_bag.reader import BagReader
    bag, received = tmp_path / "run.mcap", tmp_path / "received.json"
    graph = Path(__file__).resolve().parents[2] / "hawt_tools" / "launch" / "example.yaml"
    result = subprocess.run([*hawt_cli, "launch", str(graph), f"record_file:={received}", "--duration", "5",
                             "--record", str(bag)], capture_output=True, text=True, timeout=90)
    assert result.returncode == 0, result.stderr
    last = max(int(step) for step in json.loads(received.read_text()))
    with BagReader(bag) as reader:
        steps = read_topic_columns(reader, "/wt1/relayed", ("step",)).fields["step"]
    assert last in steps
    again = subprocess.run([*hawt_cli, "launch", str(graph), "--duration", "1", "--record", str(bag)],
                           capture_output=True, text=True, timeout=60)
    assert again.returncode == 2 and again.stderr.count("\n") == 1 and f"{bag}: exists" in again.stderr
