"""Vectorised CDR: many messages of one type to numpy columns, and columns back to messages.

ROS 2 messages travel as XCDR1 little-endian (encapsulation ``00 01 00 00``): each
primitive is aligned to its size counted from the end of the 4-byte encapsulation
header; a sequence is a ``uint32`` count then its elements; a string a ``uint32``
byte count (terminating NUL included) then the bytes (OMG CDR 1.x, as rmw_fastrtps
writes it). Padding bytes carry whatever the serializer's buffer held, so two
serializations of equal values may differ there: compare decoded fields, not bytes.

Within one topic, messages whose string and sequence lengths are equal share one
*layout*: every field sits at the same byte offset. The decoder computes the layout
of one message, checks every other message's length prefixes against it in one
numpy step, and gathers each field of the whole group with one fancy index: no
per-message Python for a topic of constant-size messages, a loop over the few
distinct layouts otherwise.

Columns are named by field path: ``step``, ``header.stamp.sec``, ``header.frame_id``,
``root_moment_oop``. Numbers give arrays of shape (n,) or (n, length); strings give
str arrays. Fields inside arrays of strings or of messages are walked over but not
returned.
"""
from dataclasses import dataclass
from typing import Callable, Iterable, Mapping, Optional

import numpy as np

from .errors import BagError
from .msg_definition import PRIMITIVE_SIZES, MessageDefinition

__all__ = ["decode_columns", "encode_messages", "FieldReader", "header_stamp_ns"]

_DTYPES = {
    "bool": "?", "byte": "u1", "char": "u1", "int8": "i1", "uint8": "u1", "int16": "<i2", "uint16": "<u2",
    "int32": "<i4", "uint32": "<u4", "int64": "<i8", "uint64": "<u8", "float32": "<f4", "float64": "<f8",
}
_ENCAPSULATION = b"\x00\x01\x00\x00"
_ORIGIN = 4
"""CDR alignment is counted from the end of the encapsulation header."""
_VECTOR_GROUPS = 32
"""Layouts checked with one vector step each; messages left after that are taken one by one."""


def header_stamp_ns(data: bytes) -> int:
    """``header.stamp`` [ns] of a serialized message whose first field is a ``std_msgs/Header`` (0 before 1970).

    The stamp's ``int32 sec`` and ``uint32 nanosec`` are the first 8 bytes after the encapsulation header.
    """
    sec = int.from_bytes(data[_ORIGIN:_ORIGIN + 4], "little", signed=True)
    return max(sec * 1_000_000_000 + int.from_bytes(data[_ORIGIN + 4:_ORIGIN + 8], "little"), 0)

Definitions = Mapping[str, MessageDefinition]


@dataclass(frozen=True)
class _Slot:
    """A field at a fixed byte offset in every message of a layout.

    ``count`` is None for one value, else the number of elements; ``dtype`` is ``"str"``
    for a string, whose ``count`` is then its byte length without the NUL.
    """

    path: str
    dtype: str
    offset: int
    count: Optional[int]


@dataclass(frozen=True)
class _Layout:
    slots: tuple[_Slot, ...]
    prefixes: tuple[tuple[int, int], ...]
    """(byte offset, value) of every uint32 length prefix."""
    size: int


def _layout(definitions: Definitions, root: str, length_at: Callable[[int, str], int]) -> _Layout:
    """Walk the type, asking ``length_at(offset, path)`` for each sequence or string length."""
    slots: list[_Slot] = []
    prefixes: list[tuple[int, int]] = []
    pos = 0

    def prefix(path: str) -> int:
        nonlocal pos
        pos += (-pos) % 4
        value = length_at(_ORIGIN + pos, path)
        prefixes.append((_ORIGIN + pos, value))
        pos += 4
        return value

    def walk_type(name: str, path: str, emit: bool) -> None:
        for field in definitions[name].fields:
            walk_field(field.type, field.array, field.length, path + field.name, emit)

    def walk_field(kind: str, array: str, length: Optional[int], path: str, emit: bool) -> None:
        nonlocal pos
        count = prefix(path) if array == "sequence" else length
        if kind in PRIMITIVE_SIZES:
            size = PRIMITIVE_SIZES[kind]
            if count != 0:
                pos += (-pos) % size
            if emit:
                slots.append(_Slot(path, _DTYPES[kind], _ORIGIN + pos, count))
            pos += size * (1 if count is None else count)
        elif kind == "string":
            for _ in range(1 if count is None else count):
                nbytes = prefix(path)
                if emit and count is None:
                    slots.append(_Slot(path, "str", _ORIGIN + pos, max(nbytes - 1, 0)))
                pos += nbytes
        elif kind == "wstring":
            raise BagError(f"{root}.{path}: wstring fields are not supported")
        else:
            for _ in range(1 if count is None else count):
                walk_type(kind, path + ".", emit and count is None)

    walk_type(root, "", True)
    return _Layout(tuple(slots), tuple(prefixes), _ORIGIN + pos)


def _message_lengths(data: bytes, root: str) -> Callable[[int, str], int]:
    def length_at(offset: int, path: str) -> int:
        if offset + 4 > len(data):
            raise BagError(f"{root}.{path}: message truncated at byte {offset} of {len(data)}")
        value = int.from_bytes(data[offset:offset + 4], "little")
        if value > len(data):
            raise BagError(f"{root}.{path}: length {value} exceeds the message size {len(data)}")
        return value
    return length_at


def _gather(buffer: np.ndarray, starts: np.ndarray, offset: int, width: int) -> np.ndarray:
    """Bytes ``[start + offset, start + offset + width)`` of each message: shape (n, width), uint8."""
    return buffer[starts[:, None] + (offset + np.arange(width))]


def _slot_values(buffer: np.ndarray, starts: np.ndarray, slot: _Slot) -> np.ndarray:
    if slot.dtype == "str":
        raw = np.ascontiguousarray(_gather(buffer, starts, slot.offset, slot.count))
        if slot.count == 0:
            return np.full(starts.size, "", dtype="<U1")
        return np.char.decode(raw.view(f"S{slot.count}")[:, 0], "utf-8", errors="replace")
    dtype = np.dtype(slot.dtype)
    width = dtype.itemsize * (1 if slot.count is None else slot.count)
    values = _gather(buffer, starts, slot.offset, width).view(dtype)
    return values[:, 0] if slot.count is None else values


def _selected(path: str, fields: Optional[tuple[str, ...]]) -> bool:
    return fields is None or any(path == f or path.startswith(f + ".") for f in fields)


def decode_columns(definitions: Definitions, root: str, buffer: np.ndarray, starts: np.ndarray,
                   lengths: np.ndarray, fields: Optional[Iterable[str]] = None) -> dict[str, np.ndarray]:
    """Decode n messages of type ``root`` held in ``buffer`` into columns.

    Parameters
    ----------
    definitions : mapping
        Every definition the type needs, by ``pkg/Type`` (`msg_definition.parse_schema`).
    root : str
        The messages' type, ``pkg/Type``.
    buffer : numpy.ndarray of uint8
        Holds the messages' CDR bytes (with encapsulation headers).
    starts, lengths : numpy.ndarray of int, shape (n,)
        Where each message begins in ``buffer`` and its size [bytes].
    fields : iterable of str, optional
        Field paths (or path prefixes such as ``header``) to return; all by default.

    Returns
    -------
    dict
        Path → array with one row per message, in the order of ``starts``. A sequence
        whose length changes between messages gives an object array of 1-D arrays.

    Raises
    ------
    BagError
        If a message is not little-endian XCDR1, is truncated, or holds a wstring.
    """
    starts = np.asarray(starts, dtype=np.int64)
    lengths = np.asarray(lengths, dtype=np.int64)
    wanted = None if fields is None else tuple(fields)
    n = starts.size
    if n == 0:
        return {}
    if np.any(lengths < 4):
        raise BagError(f"{root}: message {int(np.argmax(lengths < 4))} is shorter than its CDR header")
    heads = _gather(buffer, starts, 0, 2)
    bad = np.flatnonzero((heads[:, 0] != 0) | (heads[:, 1] != 1))
    if bad.size:
        raise BagError(f"{root}: message {int(bad[0])} is not little-endian XCDR1 "
                       f"(encapsulation {bytes(heads[bad[0]]).hex()})")
    parts: dict[str, list[tuple[np.ndarray, np.ndarray]]] = {}
    remaining = np.arange(n)
    groups = 0
    while remaining.size:
        first = int(remaining[0])
        data = buffer[starts[first]:starts[first] + lengths[first]].tobytes()
        layout = _layout(definitions, root, _message_lengths(data, root))
        if groups < _VECTOR_GROUPS:
            candidates = remaining[lengths[remaining] >= layout.size]
            match = np.ones(candidates.size, dtype=bool)
            for offset, value in layout.prefixes:
                match &= _gather(buffer, starts[candidates], offset, 4).view("<u4")[:, 0] == value
            members = candidates[match]
            remaining = np.setdiff1d(remaining, members, assume_unique=True)
        else:
            members, remaining = remaining[:1], remaining[1:]
        groups += 1
        for slot in layout.slots:
            if _selected(slot.path, wanted):
                parts.setdefault(slot.path, []).append((members, _slot_values(buffer, starts[members], slot)))
    return {path: _merge(pieces, n) for path, pieces in parts.items()}


def _merge(pieces: list[tuple[np.ndarray, np.ndarray]], n: int) -> np.ndarray:
    """Put each group's rows back at their message indices."""
    if len(pieces) == 1 and pieces[0][0].size == n:
        return pieces[0][1]
    shapes = {values.shape[1:] for _, values in pieces}
    if len(shapes) > 1:
        out = np.empty(n, dtype=object)
        for index, values in pieces:
            for i, row in zip(index, values):
                out[i] = row
        return out
    out = np.empty((n, *shapes.pop()), dtype=np.result_type(*(values.dtype for _, values in pieces)))
    for index, values in pieces:
        out[index] = values
    return out


class FieldReader:
    """One field of single messages, e.g. ``step``, with the layout cached while lengths repeat.

    Parameters
    ----------
    definitions, root
        As for `decode_columns`.
    path : str
        A numeric field outside arrays (BagError if the type has none of that name).
    """

    def __init__(self, definitions: Definitions, root: str, path: str) -> None:
        self._definitions, self._root, self._path = definitions, root, path
        self._layout: Optional[_Layout] = None
        self._slot: Optional[_Slot] = None

    def __call__(self, data: bytes):
        layout = self._layout
        if layout is None or len(data) < layout.size or any(
                int.from_bytes(data[o:o + 4], "little") != v for o, v in layout.prefixes):
            layout = self._layout = _layout(self._definitions, self._root, _message_lengths(data, self._root))
            self._slot = next((s for s in layout.slots if s.path == self._path and s.dtype != "str"), None)
            if self._slot is None:
                raise BagError(f"{self._root}: no numeric field {self._path!r}")
        slot = self._slot
        dtype = np.dtype(slot.dtype)
        values = np.frombuffer(data, dtype=dtype, count=slot.count or 1, offset=slot.offset)
        return values[0].item() if slot.count is None else values.copy()


def encode_messages(definitions: Definitions, root: str, columns: Mapping[str, np.ndarray],
                    n: int) -> list[bytes]:
    """Serialize n messages of type ``root`` from columns (the inverse of `decode_columns`).

    Parameters
    ----------
    definitions, root
        As for `decode_columns`.
    columns : mapping
        Path → values with one row per message: numbers of shape (n,), or (n, length)
        for arrays and sequences; str arrays of shape (n,) for strings. A field left
        out is zero, an empty string or an empty sequence.
    n : int
        Number of messages.

    Returns
    -------
    list of bytes
        CDR with the encapsulation header, padding zeroed.

    Raises
    ------
    BagError
        Naming a column of the wrong length or a field of the type that cannot be
        written from columns (inside an array of strings or messages).
    """
    arrays = {path: np.asarray(values) for path, values in columns.items()}
    for path, values in arrays.items():
        if values.shape[:1] != (n,):
            raise BagError(f"{root}.{path}: expected {n} rows, found shape {values.shape}")
    encoded = {path: np.char.encode(values.astype(str), "utf-8") for path, values in arrays.items()
               if values.dtype.kind in "US"}
    string_lengths = {path: np.char.str_len(values) + 1 for path, values in encoded.items()}

    def probe(offset: int, path: str) -> int:
        if path in string_lengths:
            return 0
        return 0 if path not in arrays else (arrays[path].shape[1] if arrays[path].ndim > 1 else 0)

    string_paths = [s.path for s in _layout(definitions, root, probe).slots if s.dtype == "str"]
    key = np.column_stack([string_lengths[p] if p in string_lengths else np.ones(n, int) for p in string_paths]) \
        if string_paths else np.zeros((n, 1), int)
    unique, group_of = np.unique(key, axis=0, return_inverse=True)
    group_of = group_of.ravel()
    messages: list[bytes] = [b""] * n
    for g, lengths in enumerate(unique):
        rows = np.flatnonzero(group_of == g)
        per_path = dict(zip(string_paths, (int(v) for v in lengths)))
        seen: set[str] = set()

        def length_at(offset: int, path: str) -> int:
            if path in per_path and path not in seen:
                seen.add(path)
                return per_path[path]
            if path in per_path or path in string_lengths:
                raise BagError(f"{root}.{path}: strings inside arrays cannot be written from columns")
            return probe(offset, path)

        layout = _layout(definitions, root, length_at)
        out = np.zeros((rows.size, layout.size), dtype=np.uint8)
        out[:, :4] = np.frombuffer(_ENCAPSULATION, dtype=np.uint8)
        for offset, value in layout.prefixes:
            out[:, offset:offset + 4] = np.frombuffer(np.uint32(value).tobytes(), dtype=np.uint8)
        for slot in layout.slots:
            if slot.path not in arrays:
                continue
            if slot.dtype == "str":
                width = slot.count + 1
                raw = encoded[slot.path][rows].astype(f"S{width}")
                out[:, slot.offset:slot.offset + width] = raw.view(np.uint8).reshape(rows.size, width)
                continue
            dtype = np.dtype(slot.dtype)
            values = np.ascontiguousarray(arrays[slot.path][rows], dtype=dtype).reshape(rows.size, -1)
            width = values.shape[1] * dtype.itemsize
            out[:, slot.offset:slot.offset + width] = values.view(np.uint8).reshape(rows.size, width)
        for row, data in zip(rows, out):
            messages[row] = data.tobytes()
    return messages
