"""Rescue a bag whose writer never finished (killed, full disk) or whose bytes were damaged: ``hawt bag recover``.

The file is read from the start, record by record, up to its data end record; the
schemas, channels and messages read are written into a new, complete bag (summary,
statistics, indexes). The `mcap` library parses each record and checks each chunk's CRC
(`mcap.stream_reader.breakup_chunk`). Its `StreamReader` ends at the first damaged
record, so the framing is done here, by hand, on a memory map of the file: a record is
*damaged* if its length runs past the end of the file, its opcode is not one of MCAP's,
its fields do not fill its length exactly, or, a chunk, its compression is unknown or it
does not decompress or match its CRC. (The `mcap` writer writes neither private records
nor fields beyond its version's, so this strictness only costs a skipped span on a bag
from another writer, and it keeps a damaged length that happens to be plausible from
silently swallowing the records after it.)

From a damaged record the file is scanned byte by byte for the next *restart point*: a
chunk with a consistent header whose CRC is present and matches, or the data end record
where the footer (if intact) places it. Reading goes on there, and the bytes skipped are
reported as a `DamagedSpan`: the messages lost per topic, as the message indexes of the
skipped chunks list them, and the log times of the messages kept on either side. With
no restart point after the damage (a writer killed while writing a chunk leaves a cut-off
last record), reading stops there. Since `BagWriter` writes each chunk whole as it
fills, a killed writer loses the chunk being filled and damage the chunks it hits.

A message whose channel record was lost (the chunk holding it damaged) is kept if the
file's summary repeats that channel, and skipped and counted otherwise.
"""
import dataclasses
import io
import mmap
import os
import struct
import zlib
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

from mcap.data_stream import ReadDataStream
from mcap.exceptions import EndOfFile, McapError
from mcap.opcode import Opcode
from mcap.records import (Attachment, AttachmentIndex, Channel, Chunk, ChunkIndex, DataEnd, Footer, Header, McapRecord,
                          Message, MessageIndex, Metadata, MetadataIndex, Schema, Statistics, SummaryOffset)
from mcap.stream_reader import breakup_chunk
from mcap.writer import Writer
from zstandard import ZstdError

from .errors import BagError, not_a_file

__all__ = ["DamagedSpan", "Recovery", "recover_bag", "recovered_path"]

_MAGIC = b"\x89MCAP0\r\n"
_DATA_END = struct.pack("<BQ", Opcode.DATA_END, 4)
"""Opcode and length of the data end record (its body: a 4-byte CRC)."""
_FOOTER_SIZE = 9 + 20
_RECORDS = {Opcode.ATTACHMENT: Attachment, Opcode.ATTACHMENT_INDEX: AttachmentIndex, Opcode.CHANNEL: Channel,
            Opcode.CHUNK: Chunk, Opcode.CHUNK_INDEX: ChunkIndex, Opcode.DATA_END: DataEnd, Opcode.FOOTER: Footer,
            Opcode.HEADER: Header, Opcode.MESSAGE: Message, Opcode.MESSAGE_INDEX: MessageIndex,
            Opcode.METADATA: Metadata, Opcode.METADATA_INDEX: MetadataIndex, Opcode.SCHEMA: Schema,
            Opcode.STATISTICS: Statistics, Opcode.SUMMARY_OFFSET: SummaryOffset}
"""The `mcap` record class that reads each opcode's fields."""
_DAMAGE = (McapError, struct.error, EOFError, ValueError, zlib.error, ZstdError, RuntimeError, MemoryError)
"""What a damaged record raises: mcap's errors, struct's, and zlib's, zstandard's and lz4's (RuntimeError)."""


@dataclass(frozen=True)
class DamagedSpan:
    """Bytes ``start``-``end`` of the source, skipped from a damaged record to the next restart point.

    ``lost`` is the messages per topic the message indexes of the skipped chunks list (None if
    the records there could not all be framed); ``before`` and ``after`` the log times [ns] of
    the messages kept just before and just after (None at the start or end).
    """

    start: int
    end: int
    reason: str
    lost: Optional[dict[str, int]]
    before: Optional[int]
    after: Optional[int]

    def text(self) -> str:
        lost = (", ".join(f"{topic} {count}" for topic, count in sorted(self.lost.items())) or "no message"
                if self.lost is not None else "an unknown number of messages (message indexes unreadable)")
        before = ("no message kept before it" if self.before is None
                  else f"last message kept before it at log time {self.before / 1e9:.3f} s")
        after = "none after it" if self.after is None else f"first after it at log time {self.after / 1e9:.3f} s"
        return f"skipped damaged bytes {self.start}-{self.end} ({self.reason}): lost {lost}; {before}, {after}"


@dataclass(frozen=True)
class Recovery:
    """What `recover_bag` wrote: the output, messages per topic, the damaged spans it skipped, and why it stopped.

    ``orphans`` counts the messages skipped because their channel record was lost.
    """

    source: Path
    output: Path
    counts: dict[str, int]
    stopped: str
    spans: tuple[DamagedSpan, ...]
    orphans: int

    @property
    def message_count(self) -> int:
        return sum(self.counts.values())

    def text(self) -> str:
        topics = ", ".join(f"{topic} {count}" for topic, count in sorted(self.counts.items())) or "none"
        lines = [f"recovered {self.message_count} messages into {self.output} ({topics}); "
                 f"reading {self.source} stopped at: {self.stopped}"]
        lines += [span.text() for span in self.spans]
        if self.orphans:
            lines.append(f"skipped {self.orphans} messages whose channel record was lost")
        return "\n".join(lines)


def recovered_path(path: os.PathLike) -> Path:
    """``run.mcap`` → ``run.recovered.mcap`` beside it."""
    path = Path(path)
    return path.with_name(f"{path.stem}.recovered{path.suffix or '.mcap'}")


class _Exact(io.BytesIO):
    """One record's bytes, refusing a read past their end (mcap's `ReadDataStream` accepts short reads)."""

    def read(self, size: Optional[int] = -1) -> bytes:
        data = super().read(size)
        if size is not None and 0 <= size != len(data):
            raise EndOfFile()
        return data


def _reason(error: Exception) -> str:
    text = str(error).splitlines()[0] if str(error) else ""
    return f"{type(error).__name__}: {text}" if text else type(error).__name__


def _chunk_header_fits(data: mmap.mmap, offset: int, length: int) -> bool:
    """Whether the chunk at ``offset`` has a known compression and field sizes adding up to ``length``."""
    if length < 40:
        return False
    at = offset + 9 + 28  # opcode, length; start and end time, uncompressed size, CRC
    (name_length,) = struct.unpack_from("<I", data, at)
    if name_length > 4:
        return False
    (records_length,) = struct.unpack_from("<Q", data, at + 4 + name_length)
    return (data[at + 4:at + 4 + name_length] in (b"", b"zstd", b"lz4")
            and 28 + 4 + name_length + 8 + records_length == length)


def _record(data: mmap.mmap, offset: int) -> tuple[McapRecord, list[McapRecord], int]:
    """The record at ``offset``, the records it holds (a chunk's, CRC checked; else itself), and where the next starts.

    Raises one of `_DAMAGE` if the record is damaged.
    """
    opcode, length = struct.unpack_from("<BQ", data, offset)
    end = offset + 9 + length
    if end > len(data):
        raise McapError(f"record length {length} runs past the end of the file")
    if opcode not in _RECORDS:
        raise McapError(f"unknown opcode 0x{opcode:02x}")
    if opcode == Opcode.CHUNK and not _chunk_header_fits(data, offset, length):
        raise McapError("chunk header inconsistent with the record length")
    stream = ReadDataStream(_Exact(data[offset + 9:end]))
    record = Message.read(stream, length) if opcode == Opcode.MESSAGE else _RECORDS[opcode].read(stream)
    if stream.count != length:
        raise McapError(f"{type(record).__name__} fields end {length - stream.count} bytes before its length")
    held = breakup_chunk(record, validate_crc=True) if isinstance(record, Chunk) else [record]
    return record, held, end


def _data_end(data: mmap.mmap) -> int:
    """Where the data end record starts, as the footer places it; the file's length if the footer is damaged."""
    footer_at = len(data) - len(_MAGIC) - _FOOTER_SIZE
    try:
        footer = _record(data, footer_at)[0] if footer_at > len(_MAGIC) and data[-len(_MAGIC):] == _MAGIC else None
    except _DAMAGE:
        footer = None
    if not isinstance(footer, Footer):
        return len(data)
    at = (footer.summary_start or footer_at) - len(_DATA_END) - 4
    return at if len(_MAGIC) <= at and data[at:at + len(_DATA_END)] == _DATA_END else len(data)


def _restart(data: mmap.mmap, offset: int, data_end: int) -> Optional[int]:
    """The first restart point after ``offset``: an intact chunk with a CRC before ``data_end``, else the data end."""
    at = data.find(bytes([Opcode.CHUNK]), offset + 1, data_end)
    while at >= 0:
        try:
            chunk = _record(data, at)[0]
            if chunk.uncompressed_crc:
                return at
        except _DAMAGE:
            pass
        at = data.find(bytes([Opcode.CHUNK]), at + 1, data_end)
    return data_end if offset < data_end < len(data) else None


def _indexed(data: mmap.mmap, start: int, stop: int) -> Optional[dict[int, int]]:
    """Messages per channel id the message indexes after the chunks in ``start``-``stop`` list.

    None if the records there do not frame exactly (a damaged length): the indexes are then unknown.
    """
    counts: dict[int, int] = {}
    after_chunk = False
    at = start
    while at < stop:
        if at + 9 > stop:
            return None
        opcode, length = struct.unpack_from("<BQ", data, at)
        if at + 9 + length > stop:
            return None
        after_chunk = after_chunk or opcode == Opcode.CHUNK
        if opcode == Opcode.MESSAGE_INDEX and after_chunk:
            try:
                index = _record(data, at)[0]
            except _DAMAGE:
                return None
            counts[index.channel_id] = counts.get(index.channel_id, 0) + len(index.records)
        at += 9 + length
    return counts


def _summary_records(data: mmap.mmap, data_end: int) -> list[McapRecord]:
    """The schemas and channels of the summary section, as far as it reads; none without a data end record."""
    found: list[McapRecord] = []
    at = data_end + len(_DATA_END) + 4
    try:
        while at < len(data) - len(_MAGIC) - _FOOTER_SIZE:
            record, _, at = _record(data, at)
            found += [record] if isinstance(record, (Schema, Channel)) else []
    except _DAMAGE:
        pass
    return found


def recover_bag(path: os.PathLike, output: Optional[os.PathLike] = None) -> Recovery:
    """Write every readable message of ``path`` into a new complete bag, skipping damaged records.

    Parameters
    ----------
    path : path-like
        The damaged or unfinished bag.
    output : path-like, optional
        The new file (default `recovered_path`); an existing file is refused.

    Raises
    ------
    BagError
        If ``path`` is missing, not MCAP or does not start with a readable header record, or ``output`` exists.
    """
    path = Path(path)
    output = Path(output) if output is not None else recovered_path(path)
    if not path.is_file():
        raise not_a_file(path)
    with open(path, "rb") as source:
        if source.read(len(_MAGIC)) != _MAGIC:
            raise BagError(f"{path}: not an MCAP file (no MCAP magic at the start)")
        with mmap.mmap(source.fileno(), 0, access=mmap.ACCESS_READ) as data:
            try:
                header, _, offset = _record(data, len(_MAGIC))
            except _DAMAGE:
                header = None
            if not isinstance(header, Header):
                raise BagError(f"{path}: nothing readable (no MCAP header record at the start)")
            try:
                target = open(output, "xb")
            except FileExistsError:
                raise BagError(f"{output}: exists; refusing to overwrite it (give another -o)") from None
            with target:
                return _copy(path, output, data, header, offset, Writer(target))


def _copy(path: Path, output: Path, data: mmap.mmap, header: Header, offset: int, writer: Writer) -> Recovery:
    """`recover_bag` from the record at ``offset`` (after the header): copy what reads, skip what is damaged."""
    writer.start(profile=header.profile, library=header.library)
    data_end = _data_end(data)
    summary = _summary_records(data, data_end)
    spare_schemas = {record.id: record for record in summary if isinstance(record, Schema)}
    spare = {record.id: record for record in summary if isinstance(record, Channel)}
    schemas: dict[int, int] = {}
    channels: dict[int, int] = {}
    topics: dict[int, str] = {}
    counts: dict[str, int] = {}
    spans: list[DamagedSpan] = []
    waiting = 0  # the last spans still without the log time of the first message kept after them
    orphans = 0
    last: Optional[int] = None
    stopped = "end of file"

    def add_schema(schema: Schema) -> None:
        if schema.id not in schemas:
            schemas[schema.id] = writer.register_schema(schema.name, schema.encoding, schema.data)

    def add_channel(channel: Channel) -> None:
        if channel.schema_id not in schemas and channel.schema_id in spare_schemas:
            add_schema(spare_schemas[channel.schema_id])
        if channel.id not in channels:
            channels[channel.id] = writer.register_channel(
                channel.topic, channel.message_encoding, schemas.get(channel.schema_id, 0), channel.metadata)
            topics[channel.id] = channel.topic

    while offset < len(data):
        try:
            record, held, end = _record(data, offset)
        except _DAMAGE as error:
            restart = _restart(data, offset, data_end)
            if restart is None:
                stopped = f"byte {offset}: {_reason(error)}; no intact chunk after it"
                break
            lost = _indexed(data, offset, restart)
            named = None if lost is None else {
                topics.get(key) or (spare[key].topic if key in spare else f"<channel {key}>"): count
                for key, count in lost.items()}
            spans.append(DamagedSpan(offset, restart, _reason(error), named, last, None))
            waiting += 1
            offset = restart
            continue
        if isinstance(record, (DataEnd, Footer)):
            stopped = "end of data section"
            break
        for item in held:
            if isinstance(item, Schema):
                add_schema(item)
            elif isinstance(item, Channel):
                add_channel(item)
            elif isinstance(item, Message):
                if item.channel_id not in channels and item.channel_id in spare:
                    add_channel(spare[item.channel_id])
                if item.channel_id not in channels:
                    orphans += 1
                    continue
                writer.add_message(channels[item.channel_id], item.log_time, item.data, item.publish_time,
                                   item.sequence)
                counts[topics[item.channel_id]] = counts.get(topics[item.channel_id], 0) + 1
                last = item.log_time
                if waiting:
                    spans[-waiting:] = [dataclasses.replace(span, after=last) for span in spans[-waiting:]]
                    waiting = 0
        offset = end
    writer.finish()
    return Recovery(path, output, counts, stopped, tuple(spans), orphans)
