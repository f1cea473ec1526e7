"""A topic of a bag as numpy columns: the fast path from a recorded run to analysis arrays.

For an indexed MCAP (chunked, with message indexes: what `BagWriter` and rosbag2 write)
each chunk holding the topic is read and decompressed once (once for all of them when
`read_topics_columns` reads several topics); the topic's messages are located through
its message index, their headers and CDR bytes gathered with numpy,
and the fields decoded by `cdr_columns` — no Python work per message. Files without
indexes are read message by message through the mcap reader.

A topic recorded from several publishers has a channel for each (`reader.PUBLISHER`); its
columns hold every channel's messages, and ``publisher`` says whose each row is.
"""
import struct
from dataclasses import dataclass
from typing import Iterable, Mapping, Optional

import lz4.frame
import numpy as np
import zstandard
from mcap.records import ChunkIndex, Schema

from .cdr_columns import decode_columns
from .errors import BagError
from .msg_definition import parse_schema, short_type_name
from .reader import PUBLISHER, BagReader

__all__ = ["TopicColumns", "read_topic_columns", "read_topics_columns"]

_CHUNK = struct.Struct("<BQQQQI")
"""Chunk record: opcode, record length, message start/end time, uncompressed size, CRC."""
_MESSAGE_HEADER = 31
"""Opcode (1) + record length (8) + channel id (2) + sequence (4) + log time (8) + publish time (8)."""


@dataclass(frozen=True)
class TopicColumns:
    """A topic's messages in log-time order (equal times in file order).

    Attributes
    ----------
    topic, type : str
    log_time, publish_time : numpy.ndarray of int64, shape (n,)
        [ns].
    sequence : numpy.ndarray of uint32, shape (n,)
        Per channel: each publisher's messages are counted apart.
    fields : Mapping[str, numpy.ndarray]
        Field path → values, one row per message (see `cdr_columns.decode_columns`).
    publisher : numpy.ndarray of str, shape (n,)
        The publisher of each message's channel ("" where the channel names none).
    """

    topic: str
    type: str
    log_time: np.ndarray
    publish_time: np.ndarray
    sequence: np.ndarray
    fields: Mapping[str, np.ndarray]
    publisher: np.ndarray

    def __len__(self) -> int:
        return int(self.log_time.size)

    def stamp(self) -> np.ndarray:
        """``header.stamp`` [s] as float64, shape (n,) (BagError if the type has no header)."""
        if "header.stamp.sec" not in self.fields:
            raise BagError(f"{self.topic}: {self.type} has no header.stamp")
        return self.fields["header.stamp.sec"].astype(np.float64) + 1e-9 * self.fields["header.stamp.nanosec"]


def _decompress(compression: str, data: bytes, size: int) -> bytes:
    if compression == "":
        return data
    if compression == "zstd":
        return zstandard.ZstdDecompressor().decompress(data, max_output_size=size)
    if compression == "lz4":
        return lz4.frame.decompress(data)
    raise BagError(f"chunk compression {compression!r} is not supported")


def _chunk_records(file, index: ChunkIndex) -> np.ndarray:
    file.seek(index.chunk_start_offset)
    raw = file.read(index.chunk_length)
    _, _, _, _, size, _ = _CHUNK.unpack_from(raw, 0)
    pos = _CHUNK.size
    (name_length,) = struct.unpack_from("<I", raw, pos)
    compression = raw[pos + 4:pos + 4 + name_length].decode()
    pos += 4 + name_length
    (records_length,) = struct.unpack_from("<Q", raw, pos)
    records = raw[pos + 8:pos + 8 + records_length]
    return np.frombuffer(_decompress(compression, records, size), dtype=np.uint8)


def _message_offsets(file, offset: int) -> np.ndarray:
    """Offsets into the uncompressed chunk of a channel's messages, from its MessageIndex record."""
    file.seek(offset)
    opcode, length = struct.unpack("<BQ", file.read(9))
    body = file.read(length)
    (entries_length,) = struct.unpack_from("<I", body, 2)
    entries = np.frombuffer(body, dtype=[("log_time", "<u8"), ("offset", "<u8")], count=entries_length // 16,
                            offset=6)
    return np.sort(entries["offset"].astype(np.int64))


def _u64(records: np.ndarray, positions: np.ndarray) -> np.ndarray:
    return records[positions[:, None] + np.arange(8)].view("<u8")[:, 0]


def _publishers(reader: BagReader, channel: np.ndarray) -> np.ndarray:
    """The publisher of each row from its channel id ("" where the channel names none)."""
    ids, inverse = np.unique(channel, return_inverse=True)
    names = [reader.summary.channels[int(i)].metadata.get(PUBLISHER, "") for i in ids]
    return np.asarray(names, dtype=str)[inverse]


def _indexed(reader: BagReader, channel_ids: Mapping[str, set[int]]) -> dict:
    """Topic → (buffer, starts, lengths, log, publish, sequence, publisher) in file order via chunk and message
    indexes.

    Each chunk holding any of the topics is read and decompressed once.
    """
    parts = {topic: ([], [], [], [], [], [], []) for topic in channel_ids}
    base = dict.fromkeys(channel_ids, 0)
    for index in sorted(reader.summary.chunk_indexes, key=lambda c: c.chunk_start_offset):
        wanted = {topic: [i for i in index.message_index_offsets if i in ids] for topic, ids in channel_ids.items()}
        wanted = {topic: ids for topic, ids in wanted.items() if ids}
        if not wanted:
            continue
        records = _chunk_records(reader.file, index)
        for topic, ids in wanted.items():
            buffers, starts, lengths, logs, publishes, sequences, channels = parts[topic]
            offsets = np.sort(np.concatenate([_message_offsets(reader.file, index.message_index_offsets[i])
                                              for i in ids]))
            record_length = _u64(records, offsets + 1)
            channels.append(records[offsets[:, None] + 9 + np.arange(2)].view("<u2")[:, 0])
            sequences.append(records[offsets[:, None] + 11 + np.arange(4)].view("<u4")[:, 0])
            logs.append(_u64(records, offsets + 15))
            publishes.append(_u64(records, offsets + 23))
            size = (record_length - 22).astype(np.int64)
            first = offsets + _MESSAGE_HEADER
            packed = np.cumsum(size) - size
            buffers.append(records[np.repeat(first - packed, size) + np.arange(int(size.sum()))])
            starts.append(packed + base[topic])
            lengths.append(size)
            base[topic] += int(size.sum())
    loaded = dict.fromkeys(parts)
    for topic, columns in parts.items():
        if columns[0]:
            *arrays, channels = (np.concatenate(column) for column in columns)
            loaded[topic] = (*arrays, _publishers(reader, channels))
    return loaded


def _scanned(reader: BagReader, topic: str):
    """The same as `_indexed`, message by message (files without message indexes)."""
    messages = list(reader.messages(topics=[topic]))
    if not messages:
        return None
    size = np.array([len(m.data) for m in messages], dtype=np.int64)
    buffer = np.frombuffer(b"".join(m.data for m in messages), dtype=np.uint8)
    return (buffer, np.cumsum(size) - size, size, np.array([m.log_time for m in messages], dtype=np.uint64),
            np.array([m.publish_time for m in messages], dtype=np.uint64),
            np.array([m.sequence for m in messages], dtype=np.uint32), np.array([m.publisher for m in messages]))


def read_topic_columns(reader: BagReader, topic: str, fields: Optional[Iterable[str]] = None) -> TopicColumns:
    """Read one topic's messages into numpy columns.

    Parameters
    ----------
    reader : BagReader
    topic : str
        Absolute topic name.
    fields : iterable of str, optional
        Field paths or prefixes to decode (all if None), e.g. ``("header.stamp", "step", "pitch")``.

    Raises
    ------
    BagError
        Naming the bag and topic if the bag lacks it, or the field at fault if a
        message cannot be decoded.
    """
    return read_topics_columns(reader, [topic], fields)[topic]


def read_topics_columns(reader: BagReader, topics: Iterable[str],
                        fields: Optional[Iterable[str]] = None) -> dict[str, TopicColumns]:
    """Read several topics into numpy columns, each chunk decompressed once for all of them.

    Parameters
    ----------
    reader : BagReader
    topics : iterable of str
        Absolute topic names.
    fields : iterable of str, optional
        Field paths or prefixes to decode in every topic (all if None).

    Returns
    -------
    dict
        Topic → `TopicColumns`, as `read_topic_columns` gives them.

    Raises
    ------
    BagError
        As `read_topic_columns`.
    """
    topics = list(topics)
    schemas = {topic: reader.schema(topic) for topic in topics}
    fields = None if fields is None else tuple(fields)
    channel_ids = {topic: {c.id for c in reader.summary.channels.values() if c.topic == topic} for topic in topics}
    indexed = {topic: ids for topic, ids in channel_ids.items()
               if any(ids & set(c.message_index_offsets) for c in reader.summary.chunk_indexes)}
    try:
        loaded = _indexed(reader, indexed)
        loaded.update({topic: _scanned(reader, topic) for topic in topics if topic not in indexed})
    except (struct.error, IndexError, ValueError, zstandard.ZstdError) as error:
        raise BagError(f"{reader.path}: damaged chunk while reading {', '.join(topics)} ({error})") from None
    return {topic: _columns(reader, topic, schemas[topic], loaded[topic], fields) for topic in topics}


def _columns(reader: BagReader, topic: str, schema: Schema, loaded: Optional[tuple],
             fields: Optional[tuple[str, ...]]) -> TopicColumns:
    """Decode one topic's gathered messages (`_indexed` / `_scanned`) in log-time order."""
    root = short_type_name(schema.name)
    definitions = parse_schema(schema.data.decode(), schema.name)
    if loaded is None:
        empty = np.zeros(0, dtype=np.int64)
        return TopicColumns(topic, schema.name, empty, empty, empty.astype(np.uint32), {}, empty.astype(str))
    buffer, starts, lengths, log, publish, sequence, publisher = loaded
    order = np.argsort(log, kind="stable")
    try:
        columns = decode_columns(definitions, root, buffer, starts[order], lengths[order], fields)
    except BagError as error:
        raise BagError(f"{reader.path}: {topic}: {error}") from None
    return TopicColumns(topic, schema.name, log[order].astype(np.int64), publish[order].astype(np.int64),
                        sequence[order], columns, publisher[order])
