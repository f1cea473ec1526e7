"""Rescue a bag whose writer never finished (killed, full disk): ``hawt bag recover``.

The file is read from the start, record by record (`mcap.stream_reader.StreamReader`,
chunk CRCs checked), until the first record that is cut off or damaged; the schemas,
channels and messages read so far are written into a new, complete bag (summary,
statistics, indexes). Since `BagWriter` writes each chunk whole as it fills, what is
lost is the chunk being filled at the kill and anything after a damaged record.
"""
import os
import struct
import zlib
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

from mcap.exceptions import McapError
from mcap.records import Channel, Header, Message, Schema
from mcap.stream_reader import StreamReader
from mcap.writer import Writer

from .errors import BagError

__all__ = ["Recovery", "recover_bag", "recovered_path"]


@dataclass(frozen=True)
class Recovery:
    """What `recover_bag` wrote: the output, messages per topic, and why reading stopped."""

    source: Path
    output: Path
    counts: dict[str, int]
    stopped: str

    @property
    def message_count(self) -> int:
        return sum(self.counts.values())

    def text(self) -> str:
        topics = ", ".join(f"{topic} {count}" for topic, count in sorted(self.counts.items())) or "none"
        return (f"recovered {self.message_count} messages into {self.output} ({topics}); "
                f"reading {self.source} stopped at: {self.stopped}")


def recovered_path(path: os.PathLike) -> Path:
    """``run.mcap`` → ``run.recovered.mcap`` beside it."""
    path = Path(path)
    return path.with_name(f"{path.stem}.recovered{path.suffix or '.mcap'}")


def recover_bag(path: os.PathLike, output: Optional[os.PathLike] = None) -> Recovery:
    """Write every readable message of ``path`` into a new complete bag.

    Parameters
    ----------
    path : path-like
        The damaged or unfinished bag.
    output : path-like, optional
        The new file (default `recovered_path`); an existing file is refused.

    Raises
    ------
    BagError
        If ``path`` is missing or not MCAP, or ``output`` exists.
    """
    path = Path(path)
    output = Path(output) if output is not None else recovered_path(path)
    if not path.is_file():
        raise BagError(f"{path}: no such file")
    with open(path, "rb") as source:
        if source.read(8) != b"\x89MCAP0\r\n":
            raise BagError(f"{path}: not an MCAP file (no MCAP magic at the start)")
    try:
        target = open(output, "xb")
    except FileExistsError:
        raise BagError(f"{output}: exists; refusing to overwrite it (give another -o)") from None
    counts: dict[str, int] = {}
    with open(path, "rb") as source, target:
        writer: Optional[Writer] = None
        schemas: dict[int, int] = {}
        channels: dict[int, int] = {}
        topics: dict[int, str] = {}
        stopped = "end of file"
        try:
            for record in StreamReader(source, validate_crcs=True).records:
                if isinstance(record, Header):
                    writer = Writer(target)
                    writer.start(profile=record.profile, library=record.library)
                elif writer is None:
                    break
                elif isinstance(record, Schema) and record.id not in schemas:
                    schemas[record.id] = writer.register_schema(record.name, record.encoding, record.data)
                elif isinstance(record, Channel) and record.id not in channels:
                    channels[record.id] = writer.register_channel(
                        record.topic, record.message_encoding, schemas.get(record.schema_id, 0), record.metadata)
                    topics[record.id] = record.topic
                elif isinstance(record, Message) and record.channel_id in channels:
                    writer.add_message(channels[record.channel_id], record.log_time, record.data,
                                       record.publish_time, record.sequence)
                    topic = topics[record.channel_id]
                    counts[topic] = counts.get(topic, 0) + 1
        except (McapError, struct.error, EOFError, ValueError, zlib.error, MemoryError) as error:
            stopped = f"{type(error).__name__}: {str(error).splitlines()[0] if str(error) else 'damaged record'}"
        if writer is not None:
            writer.finish()
    if writer is None:
        output.unlink()
        raise BagError(f"{path}: nothing readable (no MCAP header record at the start)")
    return Recovery(path, output, counts, stopped)
