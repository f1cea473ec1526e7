"""Vectorised CDR: columns decode what rclpy serialized, and encode what rclpy deserializes."""
import random
import sys
from pathlib import Path

import hawt_msgs.msg
import numpy as np
import pytest
from rclpy.serialization import deserialize_message, serialize_message

from hawt_bag.cdr_columns import FieldReader, decode_columns, encode_messages
from hawt_bag.errors import BagError
from message_samples import MESSAGE_TYPES, filled
from hawt_bag.interface_files import schema_text
from hawt_bag.msg_definition import parse_msg, parse_schema
from hawt_bag.reader import BagReader
from hawt_bag.topic_columns import read_topic_columns
from hawt_bag.writer import BagWriter

sys.path.insert(0, str(Path(__file__).resolve().parent))


def _definitions(name: str):
    return parse_schema(schema_text(f"hawt_msgs/msg/{name}"), f"hawt_msgs/msg/{name}")


def _packed(messages: list[bytes]):
    lengths = np.array([len(m) for m in messages])
    return np.frombuffer(b"".join(messages), np.uint8), np.cumsum(lengths) - lengths, lengths


def _expected(kind, messages, path: str):
    head, _, rest = path.partition(".")
    values = [getattr(m, head) for m in messages]
    for part in rest.split(".") if rest else ():
        values = [getattr(v, part) for v in values]
    return values


@pytest.mark.parametrize("name", MESSAGE_TYPES)
def test_columns_equal_rclpy_fields_for_every_hawt_message(name):
    """Messages with strings of varying length (several layouts) decode field by field like rclpy."""
    kind = getattr(hawt_msgs.msg, name)
    messages = [filled(kind, i) for i in range(40)]
    columns = decode_columns(_definitions(name), f"hawt_msgs/{name}", *_packed([serialize_message(m)
                                                                                for m in messages]))
    assert "header.stamp.sec" in columns and "header.frame_id" in columns
    for path, values in columns.items():
        expected = _expected(kind, messages, path)
        if values.ndim == 2:
            assert np.array_equal(values, np.array([list(v) for v in expected])), path
        else:
            assert values.tolist() == list(expected), path


def _has_string_arrays(name: str) -> bool:
    return "sequence<string>" in getattr(hawt_msgs.msg, name).get_fields_and_field_types().values()


@pytest.mark.parametrize("name", [n for n in MESSAGE_TYPES if not _has_string_arrays(n)])
def test_encoded_columns_deserialize_with_rclpy(name):
    """encode_messages is the inverse of decode_columns: rclpy reads back every field.

    Types with string arrays (ControllerSwitch) are left out: their strings are not columns.
    """
    kind = getattr(hawt_msgs.msg, name)
    messages = [filled(kind, i) for i in range(15)]
    definitions = _definitions(name)
    columns = decode_columns(definitions, f"hawt_msgs/{name}", *_packed([serialize_message(m) for m in messages]))
    encoded = encode_messages(definitions, f"hawt_msgs/{name}", columns, len(messages))
    assert [deserialize_message(data, kind) for data in encoded] == messages


def test_fixed_arrays_and_empty_sequences_have_their_shape():
    """T[N] gives N columns, an empty sequence gives zero columns; nothing is read past the message."""
    definitions = {"p/M": parse_msg("uint8 a\nfloat64[2] b\nfloat32[] c\nint16 d", "p/M")}
    data = (b"\x00\x01\x00\x00" + b"\x07" + bytes(7) + np.array([1.5, -2.0]).tobytes() + bytes(4)
            + np.int16(-3).tobytes())
    columns = decode_columns(definitions, "p/M", *_packed([data, data]))
    assert columns["a"].tolist() == [7, 7] and columns["d"].tolist() == [-3, -3]
    assert columns["b"].tolist() == [[1.5, -2.0]] * 2 and columns["c"].shape == (2, 0)


def test_truncated_message_is_named():
    """A message cut inside a length prefix raises BagError naming the field."""
    definitions = _definitions("ControlEvent")
    data = serialize_message(filled(hawt_msgs.msg.ControlEvent, 0))[:30]
    with pytest.raises(BagError, match=r"hawt_msgs/ControlEvent\.\w+: "):
        decode_columns(definitions, "hawt_msgs/ControlEvent", *_packed([data]))


def test_field_reader_reads_the_step_of_single_messages():
    """FieldReader gives one field of each message, layouts changing with the header's frame id."""
    kind = hawt_msgs.msg.PitchCommand
    read = FieldReader(_definitions("PitchCommand"), "hawt_msgs/PitchCommand", "step")
    assert [read(serialize_message(filled(kind, i))) for i in range(10)] == list(range(10))


def test_topic_columns_of_a_chunked_bag_equal_decoding_message_by_message(tmp_path):
    """The indexed fast path (chunks, message indexes, interleaved topics) gives the rows in log-time order."""
    path = tmp_path / "a.mcap"
    kind = hawt_msgs.msg.BladeLoads
    messages = [filled(kind, i) for i in range(300)]
    rng = random.Random(1)
    times = sorted(rng.randrange(10**9) for _ in messages)
    with BagWriter(path, chunk_size=3000) as writer:
        loads = writer.add_topic("/loads", "hawt_msgs/msg/BladeLoads")
        other = writer.add_topic("/other", "hawt_msgs/msg/ControlEvent")
        for t, message in zip(times, messages):
            writer.write(loads, t, serialize_message(message))
            writer.write(other, t, serialize_message(filled(hawt_msgs.msg.ControlEvent, t % 7)))
    with BagReader(path) as reader:
        columns = read_topic_columns(reader, "/loads", ("step", "pitch", "header.stamp"))
        assert reader.info().chunk_count > 10
    assert columns.log_time.tolist() == times
    assert columns.fields["step"].tolist() == list(range(300))
    assert np.array_equal(columns.fields["pitch"], np.array([list(m.pitch) for m in messages]))
    assert np.allclose(columns.stamp(), [m.header.stamp.sec + 1e-9 * m.header.stamp.nanosec for m in messages])
    assert set(columns.fields) == {"step", "pitch", "header.stamp.sec", "header.stamp.nanosec"}
