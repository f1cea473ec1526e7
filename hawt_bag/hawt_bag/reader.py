"""Read a ROS 2 MCAP bag: what it holds (`BagInfo`) and its messages in log-time order.

Only the `mcap` library: no ROS needed. Every failure to read the file is a
`BagError` naming it (missing, not MCAP, truncated or never finished).
"""
import os
import struct
from dataclasses import dataclass
from datetime import datetime, timezone
from pathlib import Path
from typing import Iterable, Iterator, Optional

from mcap.exceptions import McapError
from mcap.reader import NonSeekingReader, SeekingReader
from mcap.records import Schema, Statistics
from mcap.summary import Summary

from .errors import BagError, UnfinishedBagError, not_a_file
from .qos_profiles import QosOffer, parse_offered_qos

__all__ = ["PUBLISHER", "BagInfo", "BagMessage", "BagReader", "TopicInfo"]

PUBLISHER = "publisher"
"""Channel metadata key: who published the channel's messages (the recorder writes one channel per topic and
publishing node, named by its fully qualified name, or ``gid <hex>`` if the graph did not name it). Bags written
otherwise (from arrays, or recorded before hawt recorded publishers) have one channel per topic without it."""

_MAGIC = b"\x89MCAP0\r\n"
_FAULTS = (McapError, struct.error, EOFError, ValueError, KeyError, OSError, MemoryError)
"""What the mcap library raises on a damaged file."""


@dataclass(frozen=True)
class TopicInfo:
    """One topic of a bag, all its channels together.

    ``publishers`` holds ``(publisher, count)`` of each channel that names its publisher (`PUBLISHER`), and
    ``offers`` the QoS offered by the publishers of every channel.
    """

    topic: str
    type: str
    count: int
    offers: tuple[QosOffer, ...]
    type_hash: str
    encoding: str
    publishers: tuple[tuple[str, int], ...] = ()


@dataclass(frozen=True)
class BagInfo:
    """The summary of a bag, as ``ros2 bag info`` shows it.

    Times are integer nanoseconds of the messages' log times; ``compression`` is the
    set of chunk compressions used (``zstd``, ``lz4`` or ``none``).
    """

    path: Path
    size: int
    profile: str
    library: str
    start: int
    end: int
    message_count: int
    chunk_count: int
    compression: tuple[str, ...]
    topics: tuple[TopicInfo, ...]

    @property
    def duration(self) -> float:
        """end − start [s] (0 for an empty bag)."""
        return (self.end - self.start) * 1e-9

    def text(self) -> str:
        """The report of ``hawt bag info``: file, size, duration, start/end, then one line per topic."""
        def stamp(ns: int) -> str:
            moment = datetime.fromtimestamp(ns * 1e-9, timezone.utc)
            return f"{moment:%b %d %Y %H:%M:%S}.{ns % 1_000_000_000:09d} UTC ({ns // 1_000_000_000}.{ns % 1_000_000_000:09d})"

        lines = [
            f"Files:             {self.path}",
            f"Bag size:          {_human_size(self.size)}",
            "Storage id:        mcap",
            f"Profile:           {self.profile or '(none)'} (written by {self.library or 'unknown'})",
            f"Duration:          {self.duration:.9f}s",
            f"Start:             {stamp(self.start) if self.message_count else '-'}",
            f"End:               {stamp(self.end) if self.message_count else '-'}",
            f"Messages:          {self.message_count}",
            f"Chunks:            {self.chunk_count} ({', '.join(self.compression) or 'none'})",
            "Topic information:",
        ]
        width = max((len(t.topic) for t in self.topics), default=0)
        for topic in self.topics:
            qos = ", ".join(sorted({f"{q.reliability}/{q.durability}" for q in topic.offers})) or "unknown"
            publishers = ", ".join(f"{name} ({count})" for name, count in topic.publishers)
            lines.append(f"  Topic: {topic.topic:<{width}} | Type: {topic.type} | Count: {topic.count} | "
                         f"Serialization Format: {topic.encoding} | QoS: {qos}"
                         + (f" | Publishers: {publishers}" if publishers else ""))
        return "\n".join(lines)


def _human_size(size: int) -> str:
    for unit in ("B", "KiB", "MiB", "GiB"):
        if size < 1024 or unit == "GiB":
            return f"{size:.1f} {unit}" if unit != "B" else f"{size} B"
        size /= 1024
    return f"{size} B"


@dataclass(frozen=True)
class BagMessage:
    """One message: topic, type ``pkg/msg/Type``, times [ns], per-channel sequence, CDR bytes and its channel's
    publisher ("" if the channel does not name one)."""

    topic: str
    type: str
    log_time: int
    publish_time: int
    sequence: int
    data: bytes
    publisher: str = ""


class BagReader:
    """An open bag. Use as a context manager, or call `close`.

    Raises
    ------
    BagError
        ``"<path>: no such file"`` (or ``"a folder; …"``), ``"<path>: not an MCAP file"``, or
        ``"<path>: truncated or unfinished MCAP (…); hawt bag recover <path> rescues its chunks"``
        (an `UnfinishedBagError`).
    """

    def __init__(self, path: os.PathLike) -> None:
        self.path = Path(path)
        if not self.path.is_file():
            raise not_a_file(self.path)
        self._file = open(self.path, "rb")
        try:
            if self._file.read(len(_MAGIC)) != _MAGIC:
                raise BagError(f"{self.path}: not an MCAP file (no MCAP magic at the start)")
            self._file.seek(0)
            self._reader = SeekingReader(self._file)
            self._header = self._reader.get_header()
            summary = self._reader.get_summary()
            self._has_summary = summary is not None and summary.statistics is not None
            self._summary = summary or self._scan_summary()
        except BagError:
            self._file.close()
            raise
        except _FAULTS as error:
            self._file.close()
            raise UnfinishedBagError(f"{self.path}: truncated or unfinished MCAP ({_one_line(error)}); "
                                     f"'hawt bag recover {self.path}' rescues its complete chunks") from None

    def _scan_summary(self) -> Summary:
        """A summary built by reading the whole file (a finished file written without one)."""
        self._file.seek(0)
        summary = Summary()
        counts: dict[int, int] = {}
        times = []
        for schema, channel, message in NonSeekingReader(self._file).iter_messages(log_time_order=False):
            summary.channels[channel.id] = channel
            if schema is not None:
                summary.schemas[schema.id] = schema
            counts[channel.id] = counts.get(channel.id, 0) + 1
            times.append(message.log_time)
        summary.statistics = Statistics(
            attachment_count=0, channel_count=len(summary.channels), channel_message_counts=counts,
            chunk_count=0, message_count=len(times), message_end_time=max(times, default=0),
            message_start_time=min(times, default=0), metadata_count=0, schema_count=len(summary.schemas))
        return summary

    def __enter__(self) -> "BagReader":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        self._file.close()

    @property
    def summary(self) -> Summary:
        """The MCAP summary (channels, schemas, statistics, chunk indexes)."""
        return self._summary

    @property
    def has_summary(self) -> bool:
        """Whether the file has its own summary section with statistics (False: `summary` was built by scanning)."""
        return self._has_summary

    @property
    def file(self):
        """The open binary file (for readers that seek into chunks themselves)."""
        return self._file

    def schema(self, topic: str) -> Schema:
        """The schema of a topic's channel (BagError naming the topic if the bag lacks it)."""
        for channel in self._summary.channels.values():
            if channel.topic == topic:
                schema = self._summary.schemas.get(channel.schema_id)
                if schema is None:
                    raise BagError(f"{self.path}: topic {topic} has no schema")
                return schema
        raise BagError(f"{self.path}: no topic {topic} (topics: {', '.join(self.topic_names()) or 'none'})")

    def topic_names(self) -> list[str]:
        """Topics of the bag, sorted."""
        return sorted({channel.topic for channel in self._summary.channels.values()})

    def info(self) -> BagInfo:
        """What ``hawt bag info`` prints."""
        stats = self._summary.statistics
        counts = stats.channel_message_counts if stats else {}
        topics = []
        for name in self.topic_names():
            channels = [c for c in self._summary.channels.values() if c.topic == name]
            schema = self._summary.schemas.get(channels[0].schema_id)
            offers = [o for c in channels for o in parse_offered_qos(c.metadata.get("offered_qos_profiles", ""))]
            publishers = tuple((c.metadata[PUBLISHER], counts.get(c.id, 0)) for c in channels
                               if PUBLISHER in c.metadata)
            topics.append(TopicInfo(name, schema.name if schema else "", sum(counts.get(c.id, 0) for c in channels),
                                    tuple(offers), channels[0].metadata.get("topic_type_hash", ""),
                                    channels[0].message_encoding, publishers))
        compression = sorted({index.compression or "none" for index in self._summary.chunk_indexes})
        return BagInfo(self.path, self.path.stat().st_size, self._header.profile, self._header.library,
                       stats.message_start_time if stats else 0, stats.message_end_time if stats else 0,
                       stats.message_count if stats else 0, len(self._summary.chunk_indexes),
                       tuple(compression), tuple(topics))

    def messages(self, topics: Optional[Iterable[str]] = None, start: Optional[int] = None,
                 end: Optional[int] = None) -> Iterator[BagMessage]:
        """Messages in log-time order (equal times in file order), optionally filtered.

        Parameters
        ----------
        topics : iterable of str, optional
            Only these topics (all if None).
        start, end : int, optional
            Log-time bounds [ns] of the half-open range ``[start, end)``.
        """
        selected = None if topics is None else list(topics)
        try:
            for schema, channel, message in self._reader.iter_messages(
                    topics=selected, starting_at=start, ending_before=end, log_time_order=True):
                yield BagMessage(channel.topic, schema.name if schema else "", message.log_time,
                                 message.publish_time, message.sequence, message.data,
                                 channel.metadata.get(PUBLISHER, ""))
        except _FAULTS as error:
            raise BagError(f"{self.path}: damaged data ({_one_line(error)})") from None


def _one_line(error: BaseException) -> str:
    text = str(error).strip().splitlines()
    return f"{type(error).__name__}: {text[0]}" if text else type(error).__name__
