"""A recording made in parts, its recorder respawned after it died: the parts joined into one bag.

``hawt launch --record run.mcap`` respawns a recorder that dies (hawt_tools.recording); the dead
recorder's file becomes part 1 and the new recorder writes the next part. A respawned recorder
subscribes transient-local where every publisher offers it (`recorder.adapted_qos`), so it first
receives the last samples each publisher keeps (hawt_node.qos: 2000 per control-loop topic), which
overlap the end of the part before. `join_parts` writes every part's messages into one new bag in
order, part after part, leaving out a message whose topic and bytes an earlier part already holds
(a step's message carries its step and stamp, so equal bytes are the same message). The joined bag
has one channel per topic and publisher (`reader.PUBLISHER`), as each part has. A part whose
writer was killed is first read as `hawt bag recover` reads it: its complete chunks.
"""
import hashlib
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Optional, Sequence

from mcap.reader import make_reader
from mcap.writer import Writer

from .errors import BagError
from .reader import PUBLISHER, BagReader, UnfinishedBagError
from .recover import recover_bag

__all__ = ["JoinedParts", "join_parts", "part_path"]


@dataclass(frozen=True)
class JoinedParts:
    """What `join_parts` wrote: the output, and per part the messages taken and those already held."""

    output: Path
    taken: tuple[int, ...]
    repeated: tuple[int, ...]

    def text(self) -> str:
        parts = "; ".join(f"part {index}: {taken} messages" + (f" ({repeated} already held)" if repeated else "")
                          for index, (taken, repeated) in enumerate(zip(self.taken, self.repeated), 1))
        return f"joined {len(self.taken)} parts into {self.output} ({parts})"


def part_path(path: os.PathLike, index: int) -> Path:
    """``run.mcap``, 2 -> ``run.part2.mcap`` beside it."""
    path = Path(path)
    return path.with_name(f"{path.stem}.part{index}{path.suffix or '.mcap'}")


def _readable(part: Path, folder: Path) -> Path:
    """``part`` itself if it is a finished bag, else its complete chunks recovered into ``folder``."""
    try:
        BagReader(part).close()
        return part
    except UnfinishedBagError:
        return recover_bag(part, folder / part.name).output


def join_parts(parts: Sequence[os.PathLike], output: os.PathLike) -> JoinedParts:
    """Write the messages of ``parts``, in order, into the new bag ``output``, each message once.

    Parameters
    ----------
    parts : sequence of path-like
        The parts in the order they were recorded; unfinished ones (a killed writer) are recovered first.
    output : path-like
        The new bag; an existing file is refused.

    Raises
    ------
    BagError
        If ``output`` exists, or a part is missing, not MCAP or has nothing readable.
    """
    output = Path(output)
    try:
        target = open(output, "xb")
    except FileExistsError:
        raise BagError(f"{output}: exists; refusing to overwrite it") from None
    held: dict[str, set[bytes]] = {}
    taken, repeated = [], []
    channels: dict[tuple[str, Optional[str]], int] = {}  # (topic, publisher): channel of the joined bag
    schemas: dict[tuple[str, bytes], int] = {}
    try:
        with target, tempfile.TemporaryDirectory(prefix="hawt_join_") as folder:
            writer = Writer(target)
            writer.start(profile="ros2", library="hawt_bag join_parts")
            for part in map(Path, parts):
                seen: dict[str, set[bytes]] = {}
                counts = [0, 0]
                with open(_readable(part, Path(folder)), "rb") as source:
                    for schema, channel, message in make_reader(source).iter_messages(log_time_order=False):
                        digest = hashlib.blake2b(message.data, digest_size=16).digest()
                        if digest in held.get(channel.topic, ()):
                            counts[1] += 1
                            continue
                        seen.setdefault(channel.topic, set()).add(digest)
                        joined = (channel.topic, channel.metadata.get(PUBLISHER))
                        if joined not in channels:
                            key = (schema.name, schema.data) if schema is not None else ("", b"")
                            if schema is not None and key not in schemas:
                                schemas[key] = writer.register_schema(schema.name, schema.encoding, schema.data)
                            channels[joined] = writer.register_channel(
                                channel.topic, channel.message_encoding, schemas.get(key, 0), channel.metadata)
                        writer.add_message(channels[joined], message.log_time, message.data,
                                           message.publish_time, message.sequence)
                        counts[0] += 1
                for topic, digests in seen.items():
                    held.setdefault(topic, set()).update(digests)
                taken.append(counts[0])
                repeated.append(counts[1])
            writer.finish()
    except BaseException:
        output.unlink(missing_ok=True)
        raise
    return JoinedParts(output, tuple(taken), tuple(repeated))
