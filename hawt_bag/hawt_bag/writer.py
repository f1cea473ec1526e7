"""Write a ROS 2 MCAP bag that ``ros2 bag info/play``, Foxglove and mcap_ros2 accept (DESIGN §7).

Profile ``ros2``; one schema per type, ``ros2msg`` text with every dependency;
one channel per topic and publisher with message encoding ``cdr`` and metadata
``offered_qos_profiles``, ``topic_type_hash`` and, when the publisher is known,
``publisher`` (the recorder's: the publishing node's fully qualified name); chunked,
zstd-compressed, message indexes and a summary with statistics (the `mcap` library's
defaults).

Crash safety: the file is written without a user-space buffer, so every finished
chunk is in the operating system's hands at once; a process killed later loses only
the chunk being filled (`hawt_bag.recover` reads what is there). `BagWriter.flush`
closes the chunk early, e.g. on a timer, to bound what a kill loses in time.
"""
import os
from pathlib import Path
from typing import Mapping, Optional

from mcap.well_known import MessageEncoding, Profile, SchemaEncoding
from mcap.writer import CompressionType, Writer

from .errors import BagError
from .interface_files import schema_text, type_hash
from .msg_definition import short_type_name
from .qos_profiles import QosOffer, offered_qos_yaml
from .reader import PUBLISHER

__all__ = ["LIBRARY", "BagWriter", "new_bag_path"]

LIBRARY = "hawt_bag 0.1.0"
"""The MCAP header's ``library`` field."""


def _full_name(type_name: str) -> str:
    """``pkg/Type`` or ``pkg/msg/Type`` -> ``pkg/msg/Type``."""
    return short_type_name(type_name).replace("/", "/msg/")


class _UnbufferedFile:
    """The minimal stream the mcap writer needs, writing straight to the file descriptor."""

    def __init__(self, path: Path) -> None:
        self._fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
        self._position = 0

    def write(self, data: bytes) -> int:
        view = memoryview(data)
        while view:
            written = os.write(self._fd, view)
            view = view[written:]
        self._position += len(data)
        return len(data)

    def tell(self) -> int:
        return self._position

    def flush(self) -> None:
        pass

    def close(self) -> None:
        if self._fd >= 0:
            os.close(self._fd)
            self._fd = -1


class BagWriter:
    """A ROS 2 MCAP bag being written: ``open`` → ``add_topic`` → ``write`` … → ``finish``.

    Also a context manager (``finish`` on exit). Times are integer nanoseconds.

    Parameters
    ----------
    path : path-like
        The new file; an existing path is refused (BagError) so no run is overwritten.
    chunk_size : int
        Uncompressed bytes after which a chunk is closed [B] (rosbag2: 768 KiB; mcap: 1 MiB).
    compression : {"zstd", "lz4", "none"}
    """

    def __init__(self, path: os.PathLike, chunk_size: int = 1024 * 1024, compression: str = "zstd") -> None:
        self.path = Path(path)
        kinds = {"zstd": CompressionType.ZSTD, "lz4": CompressionType.LZ4, "none": CompressionType.NONE}
        if compression not in kinds:
            raise BagError(f"compression: expected one of {', '.join(kinds)}, found {compression!r}")
        if chunk_size <= 0:
            raise BagError(f"chunk_size: expected a positive number of bytes, found {chunk_size}")
        try:
            self._file = _UnbufferedFile(self.path)
        except FileExistsError:
            raise BagError(f"{self.path}: exists; refusing to overwrite a bag (choose another name)") from None
        except OSError as error:
            raise BagError(f"{self.path}: cannot create ({error.strerror})") from None
        self._writer = Writer(self._file, chunk_size=chunk_size, compression=kinds[compression])
        self._writer.start(profile=Profile.ROS2, library=LIBRARY)
        self._schemas: dict[str, int] = {}
        self._channels: dict[tuple[str, Optional[str]], int] = {}
        self._counts: dict[int, int] = {}
        self._finished = False

    @classmethod
    def open(cls, path: os.PathLike, **options) -> "BagWriter":
        """Same as the constructor; reads like the other steps."""
        return cls(path, **options)

    def __enter__(self) -> "BagWriter":
        return self

    def __exit__(self, *exc) -> None:
        self.finish()

    @property
    def channels(self) -> Mapping[tuple[str, Optional[str]], int]:
        """Channel id of each (topic, publisher) added so far (publisher None: added without one)."""
        return dict(self._channels)

    def add_topic(self, topic: str, type_name: str, offers: Optional[list[QosOffer]] = None,
                  definition: Optional[str] = None, publisher: Optional[str] = None) -> int:
        """Register a topic's channel (its type's schema once) and return its channel id.

        A topic with several publishers may have a channel for each (``publisher``).

        Parameters
        ----------
        topic : str
            Absolute topic name, e.g. ``/wt1/plant/blade_loads``.
        type_name : str
            ``pkg/msg/Type``.
        offers : list of QosOffer, optional
            The publishers' offered QoS (stored as ``offered_qos_profiles``; ``[]`` if None).
        definition : str, optional
            The ``ros2msg`` schema text; by default built from the installed ``.msg`` files.
        publisher : str, optional
            Who publishes the channel's messages (stored as `reader.PUBLISHER`): the recorder gives the
            publishing node's fully qualified name, or ``gid <hex>`` for a publisher the graph does
            not name. None: no such metadata (one channel for the whole topic).

        Raises
        ------
        BagError
            If the topic is already registered for that publisher, or the type's
            ``.msg`` files are not found.
        """
        if (topic, publisher) in self._channels:
            raise BagError(f"{topic}: topic already added to {self.path}"
                           + (f" for publisher {publisher}" if publisher is not None else ""))
        schema_id = self.add_schema(type_name, definition)
        metadata = {"offered_qos_profiles": offered_qos_yaml(offers or []),
                    "topic_type_hash": type_hash(_full_name(type_name))}
        if publisher is not None:
            metadata[PUBLISHER] = publisher
        channel_id = self._writer.register_channel(topic, MessageEncoding.CDR, schema_id, metadata)
        self._channels[(topic, publisher)] = channel_id
        self._counts[channel_id] = 0
        return channel_id

    def add_schema(self, type_name: str, definition: Optional[str] = None) -> int:
        """Register a type's schema (once) and return its id; `add_topic` does it for its topic's type.

        Raises
        ------
        BagError
            If ``definition`` is None and the type's ``.msg`` files are not found.
        """
        full_name = _full_name(type_name)
        schema_id = self._schemas.get(full_name)
        if schema_id is None:
            text = definition if definition is not None else schema_text(full_name)
            schema_id = self._writer.register_schema(full_name, SchemaEncoding.ROS2, text.encode())
            self._schemas[full_name] = schema_id
        return schema_id

    def write(self, channel_id: int, log_time: int, data: bytes, publish_time: Optional[int] = None,
              sequence: Optional[int] = None) -> None:
        """Add one serialized message (CDR with its 4-byte encapsulation header).

        Parameters
        ----------
        channel_id : int
            From `add_topic`.
        log_time : int
            Receive time [ns].
        data : bytes
        publish_time : int, optional
            [ns]; the header stamp of the message by convention (DESIGN §7); log_time if None.
        sequence : int, optional
            Counter per channel by default (starts at 0), so gaps are visible.
        """
        count = self._counts[channel_id]
        self._counts[channel_id] = count + 1
        self._writer.add_message(channel_id, log_time=int(log_time), data=data,
                                 publish_time=int(log_time if publish_time is None else publish_time),
                                 sequence=(count if sequence is None else sequence) & 0xFFFFFFFF)

    def flush(self) -> None:
        """Close the chunk being filled (if it holds a message) and write it to the file."""
        self._writer.flush()

    def finish(self) -> None:
        """Write the last chunk, the summary (statistics, indexes) and the footer; close the file."""
        if self._finished:
            return
        self._finished = True
        try:
            self._writer.finish()
        finally:
            self._file.close()


def new_bag_path(output: str, option: str) -> Path:
    """``output`` as the path of a new bag, checked before anything records, the folders it goes into made if
    missing (as ``mkdir -p``: ``bags/`` of the README's examples on a fresh clone, or any other).

    Raises
    ------
    BagError
        One line naming ``option``: ``output`` exists, a folder on its way is a file, or the deepest of its folders
        that exists cannot be written into.
    """
    path = Path(output)
    if path.exists() or path.is_symlink():
        raise BagError(f"{output}: exists; refusing to overwrite a bag (choose another {option} name)")
    folder = path.absolute().parent
    existing = next(parent for parent in (folder, *folder.parents) if parent.exists())
    if not existing.is_dir():
        raise BagError(f"{option} {output}: {existing} is a file, not a folder")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise BagError(f"{option} {output}: cannot write into the folder {existing}")
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise BagError(f"{option} {output}: cannot create the folder {folder} ({error.strerror})") from None
    return path
