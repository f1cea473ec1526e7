"""The bag library without ROS: what BagWriter puts in a file, what BagReader gives back, and recovery."""

import numpy as np
import pytest
import yaml
from mcap.reader import make_reader
from rosbags.rosbag2.storage_mcap import get_qos

from hawt_bag.column_writing import TopicData, write_topics
from hawt_bag.errors import BagError
from hawt_bag.interface_files import schema_text, type_hash
from hawt_bag.qos_profiles import QosOffer, offered_qos_yaml, parse_offered_qos
from hawt_bag.reader import BagReader
from hawt_bag.recover import recover_bag
from hawt_bag.writer import BagWriter

RELIABLE = QosOffer(history="unknown", depth=0, reliability="reliable", durability="volatile")


def _loads(n: int, start: int = 0, step_ns: int = 10_000_000) -> TopicData:
    steps = np.arange(n, dtype=np.uint64)
    return TopicData("/wt1/plant/blade_loads", "hawt_msgs/msg/BladeLoads",
                     {"step": steps, "azimuth": 0.1 * steps, "root_moment_oop": np.outer(steps, [1.0, 2.0, 3.0])},
                     start + step_ns * steps.astype(np.int64))


def test_bag_has_the_ros2_profile_schemas_with_dependencies_and_channel_metadata(tmp_path):
    """Profile ros2, schema pkg/msg/Type in ros2msg with each dependency after 80 '=' and 'MSG: pkg/Type',
    cdr channels with offered_qos_profiles (readable by rosbags) and the type hash of the .json."""
    path = tmp_path / "a.mcap"
    with BagWriter(path) as writer:
        channel = writer.add_topic("/wt1/plant/blade_loads", "hawt_msgs/msg/BladeLoads", [RELIABLE])
        writer.write(channel, 1, b"\x00\x01\x00\x00" + bytes(64))
    with open(path, "rb") as stream:
        reader = make_reader(stream)
        assert reader.get_header().profile == "ros2"
        summary = reader.get_summary()
    (schema,) = summary.schemas.values()
    (channel,) = summary.channels.values()
    text = schema.data.decode()
    assert (schema.name, schema.encoding, channel.message_encoding) == ("hawt_msgs/msg/BladeLoads", "ros2msg", "cdr")
    assert f"\n{'=' * 80}\nMSG: std_msgs/Header\n" in text and f"\n{'=' * 80}\nMSG: builtin_interfaces/Time\n" in text
    assert text == schema_text("hawt_msgs/msg/BladeLoads")
    assert channel.metadata["topic_type_hash"] == type_hash("hawt_msgs/msg/BladeLoads")
    assert channel.metadata["topic_type_hash"].startswith("RIHS01_")
    (qos,) = get_qos(b"".join(len(s).to_bytes(4, "little") + s for s in (
        b"offered_qos_profiles", channel.metadata["offered_qos_profiles"].encode())))
    assert (qos.reliability.name, qos.durability.name, qos.depth) == ("RELIABLE", "VOLATILE", 0)
    assert all(index.compression == "zstd" for index in summary.chunk_indexes)
    assert summary.statistics.channel_message_counts == {channel.id: 1}


def test_offered_qos_yaml_is_rosbag2s_version_9_text():
    """The exact YAML::Dump layout rosbag2 9 writes; version 8 integer enums read back the same."""
    text = offered_qos_yaml([RELIABLE])
    assert text == ("- history: unknown\n  depth: 0\n  reliability: reliable\n  durability: volatile\n"
                    "  deadline:\n    sec: 9223372036\n    nsec: 854775807\n"
                    "  lifespan:\n    sec: 9223372036\n    nsec: 854775807\n  liveliness: automatic\n"
                    "  liveliness_lease_duration:\n    sec: 9223372036\n    nsec: 854775807\n"
                    "  avoid_ros_namespace_conventions: false")
    assert offered_qos_yaml([]) == "[]"
    assert parse_offered_qos(text) == [RELIABLE]
    version_8 = yaml.safe_dump([{"history": 3, "depth": 0, "reliability": 1, "durability": 2,
                                 "deadline": {"sec": 9223372036, "nsec": 854775807},
                                 "lifespan": {"sec": 9223372036, "nsec": 854775807}, "liveliness": 1,
                                 "liveliness_lease_duration": {"sec": 9223372036, "nsec": 854775807},
                                 "avoid_ros_namespace_conventions": False}])
    assert parse_offered_qos(version_8) == [RELIABLE]


def test_writer_refuses_to_overwrite_a_bag(tmp_path):
    """An existing path is never overwritten."""
    path = tmp_path / "a.mcap"
    path.write_bytes(b"precious")
    with pytest.raises(BagError, match=f"{path}: exists; refusing to overwrite"):
        BagWriter(path)
    assert path.read_bytes() == b"precious"


def test_messages_come_in_log_time_order_with_ties_in_written_order_and_filters(tmp_path):
    """Two topics written out of order come back sorted by log time; equal times keep their written order;
    topic and [start, end) filters apply."""
    path = tmp_path / "a.mcap"
    with BagWriter(path, chunk_size=200) as writer:
        a = writer.add_topic("/a", "std_msgs/msg/Float64")
        b = writer.add_topic("/b", "std_msgs/msg/Float64")
        for time_ns, channel, label in ((30, a, 0), (10, b, 1), (20, a, 2), (20, b, 3), (20, a, 4), (5, b, 5)):
            writer.write(channel, time_ns, b"\x00\x01\x00\x00" + np.float64(label).tobytes())
    with BagReader(path) as reader:
        order = [int(np.frombuffer(m.data[4:], np.float64)[0]) for m in reader.messages()]
        only_a = [m.log_time for m in reader.messages(topics=["/a"])]
        window = [m.log_time for m in reader.messages(start=10, end=30)]
        info = reader.info()
    assert order == [5, 1, 2, 3, 4, 0]
    assert only_a == [20, 20, 30]
    assert window == [10, 20, 20, 20]
    assert (info.message_count, info.start, info.end) == (6, 5, 30)
    assert {t.topic: t.count for t in info.topics} == {"/a": 3, "/b": 3}


def test_unfinished_bag_is_refused_and_recover_keeps_every_complete_chunk(tmp_path):
    """A writer that never finished (killed) leaves only complete chunks on disk: the reader refuses the
    file naming recover, and recover rewrites exactly the messages of those chunks."""
    path = tmp_path / "killed.mcap"
    writer = BagWriter(path, chunk_size=2000)
    channel = writer.add_topic("/x", "std_msgs/msg/Float64")
    for i in range(500):
        writer.write(channel, i, b"\x00\x01\x00\x00" + np.float64(i).tobytes())
    written_chunks = path.stat().st_size
    with pytest.raises(BagError, match=rf"{path}: truncated or unfinished MCAP .*hawt bag recover {path}"):
        BagReader(path)
    result = recover_bag(path)
    with BagReader(result.output) as reader:
        values = [int(np.frombuffer(m.data[4:], np.float64)[0]) for m in reader.messages()]
    assert written_chunks > 0 and 400 < len(values) < 500
    assert values == list(range(len(values)))
    assert result.counts == {"/x": len(values)}
    with pytest.raises(BagError, match="exists; refusing to overwrite"):
        recover_bag(path)


@pytest.mark.parametrize("content, message", [
    (b"", "not an MCAP file"),
    (b"hello, not a bag", "not an MCAP file"),
    (None, "no such file"),
])
def test_reader_names_the_file_of_a_bad_bag(tmp_path, content, message):
    """Empty, foreign or missing files give a one-line BagError naming the file."""
    path = tmp_path / "bad.mcap"
    if content is not None:
        path.write_bytes(content)
    with pytest.raises(BagError, match=f"^{path}: {message}"):
        BagReader(path)


def test_truncated_bag_is_refused(tmp_path):
    """A finished bag cut short loses its footer: refused, naming recover."""
    path = tmp_path / "a.mcap"
    with BagWriter(path) as writer:
        write_topics(writer, [_loads(300)])
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    with pytest.raises(BagError, match="truncated or unfinished MCAP"):
        BagReader(path)
