"""ROS 2 ``.msg`` definitions: parse one text, and the ``ros2msg`` schema text that joins a type's dependencies.

``ros2msg`` (rosbag2 ``docs/message_definition_encoding.md``; MCAP registry §ros2msg):
the top-level ``.msg`` text first, then each dependency after a line of 80 ``=`` and
a line ``MSG: pkg/Type``. A field type written without a package (``Type``) means
``<own package>/Type``. Names are normalised here to ``pkg/Type`` (the ``msg``
part of ``pkg/msg/Type`` dropped).
"""
import re
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Mapping

from .errors import BagError

__all__ = [
    "DELIMITER",
    "PRIMITIVE_SIZES",
    "Field",
    "MessageDefinition",
    "parse_msg",
    "parse_schema",
    "short_type_name",
]

DELIMITER = "=" * 80
"""Line between the definitions of a ``ros2msg`` schema text."""

PRIMITIVE_SIZES = MappingProxyType({
    "bool": 1, "byte": 1, "char": 1, "int8": 1, "uint8": 1, "int16": 2, "uint16": 2,
    "int32": 4, "uint32": 4, "int64": 8, "uint64": 8, "float32": 4, "float64": 8,
})
"""CDR size [bytes] of each fixed-size primitive (= its alignment in XCDR1)."""

_STRINGS = ("string", "wstring")
_FIELD = re.compile(
    r"^(?P<type>[A-Za-z][\w/]*)(?:<=(?P<string_bound>\d+))?"
    r"(?:\[(?P<array>(?:<=)?\d*)\])?\s+(?P<name>[A-Za-z]\w*)\s*(?P<rest>.*)$")


@dataclass(frozen=True)
class Field:
    """One field of a message.

    Attributes
    ----------
    name : str
    type : str
        A primitive (``float64``, ``string``, ...) or a message ``pkg/Type``.
    array : str
        ``""`` single value, ``"sequence"`` (``T[]`` or ``T[<=N]``, length-prefixed) or
        ``"fixed"`` (``T[N]``, no prefix).
    length : int or None
        N of a fixed array, else None.
    """

    name: str
    type: str
    array: str = ""
    length: int | None = None

    @property
    def is_primitive(self) -> bool:
        """True for numbers, bool, byte, char and strings."""
        return self.type in PRIMITIVE_SIZES or self.type in _STRINGS


@dataclass(frozen=True)
class MessageDefinition:
    """A message type's fields in order, and its constants (name → value text)."""

    name: str
    fields: tuple[Field, ...]
    constants: Mapping[str, str] = field(default_factory=lambda: MappingProxyType({}))


def short_type_name(type_name: str) -> str:
    """``pkg/msg/Type`` or ``pkg/Type`` -> ``pkg/Type``."""
    parts = type_name.strip("/").split("/")
    if len(parts) == 3 and parts[1] == "msg":
        return f"{parts[0]}/{parts[2]}"
    if len(parts) == 2:
        return "/".join(parts)
    raise BagError(f"{type_name}: not a message type name (expected pkg/msg/Type or pkg/Type)")


def parse_msg(text: str, type_name: str) -> MessageDefinition:
    """Parse the text of one ``.msg`` file.

    Parameters
    ----------
    text : str
        The ``.msg`` text (comments, blank lines and constants allowed).
    type_name : str
        ``pkg/msg/Type`` or ``pkg/Type``; its package completes bare field types.

    Raises
    ------
    BagError
        Naming the type and the line that is not ``TYPE NAME [DEFAULT]`` or a constant.
    """
    name = short_type_name(type_name)
    package = name.split("/")[0]
    fields = []
    constants = {}
    for number, raw in enumerate(text.splitlines(), 1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        match = _FIELD.match(line)
        if match is None:
            raise BagError(f"{name}: line {number} is not a field or constant: {raw.strip()!r}")
        rest = match["rest"]
        if rest.startswith("="):
            constants[match["name"]] = rest[1:].strip()
            continue
        field_type = match["type"]
        if field_type not in PRIMITIVE_SIZES and field_type not in _STRINGS:
            field_type = short_type_name(field_type if "/" in field_type else f"{package}/{field_type}")
        array, length = "", None
        if match["array"] is not None:
            bound = match["array"]
            if bound and not bound.startswith("<="):
                array, length = "fixed", int(bound)
            else:
                array = "sequence"
        fields.append(Field(match["name"], field_type, array, length))
    return MessageDefinition(name, tuple(fields), MappingProxyType(constants))


def parse_schema(text: str, type_name: str) -> Mapping[str, MessageDefinition]:
    """Parse a ``ros2msg`` schema text into every definition it holds, by ``pkg/Type``.

    Raises
    ------
    BagError
        If a section lacks its ``MSG: pkg/Type`` line or a field's type has no definition.
    """
    sections = re.split(r"(?:^|\n)={80}\n", text)
    definitions = {short_type_name(type_name): parse_msg(sections[0], type_name)}
    for section in sections[1:]:
        header, _, body = section.partition("\n")
        if not header.startswith("MSG: "):
            raise BagError(f"{type_name}: schema section without 'MSG: pkg/Type' line (found {header[:40]!r})")
        dependency = header[5:].strip()
        definitions.setdefault(short_type_name(dependency), parse_msg(body, dependency))
    for definition in definitions.values():
        for entry in definition.fields:
            if not entry.is_primitive and entry.type not in definitions:
                raise BagError(f"{type_name}: schema has no definition of {entry.type} "
                               f"(field {definition.name}.{entry.name})")
    return MappingProxyType(definitions)
