"""The installed interface files of a message type: its ``ros2msg`` schema text and type hash.

Packages are found with the ament index (``AMENT_PREFIX_PATH``: the workspace's
``hawt_msgs`` and the wheels' ``std_msgs``, ``builtin_interfaces``, ``rosgraph_msgs``
… under ``<prefix>/share/<pkg>/msg/``). The schema text is built as rosbag2's
``LocalMessageDefinitionSource::get_full_text`` does: the type's ``.msg`` text, then
each dependency once, depth first, after a line of 80 ``=`` and ``MSG: pkg/Type``.
"""
import json
from functools import lru_cache
from pathlib import Path

from .errors import BagError
from .msg_definition import DELIMITER, parse_msg, short_type_name

__all__ = ["has_header", "msg_file", "schema_text", "type_hash"]


def msg_file(type_name: str, suffix: str = ".msg") -> Path:
    """``<share>/<pkg>/msg/<Type><suffix>`` of a type (BagError naming the type if absent)."""
    package, _, name = short_type_name(type_name).partition("/")
    try:
        from ament_index_python.packages import PackageNotFoundError, get_package_share_directory
    except ImportError:
        raise BagError(f"{type_name}: writing a bag needs the message definitions of a ROS install "
                       "(ament_index_python is not importable here)") from None
    try:
        share = Path(get_package_share_directory(package))
    except (PackageNotFoundError, ValueError):
        raise BagError(f"{type_name}: package {package!r} not found in AMENT_PREFIX_PATH") from None
    path = share / "msg" / f"{name}{suffix}"
    if not path.is_file():
        raise BagError(f"{type_name}: no {path}")
    return path


@lru_cache(maxsize=None)
def schema_text(type_name: str) -> str:
    """The ``ros2msg`` schema text of ``pkg/msg/Type``: its ``.msg`` and every dependency's.

    Raises
    ------
    BagError
        If the type or one of its dependencies has no ``.msg`` file.
    """
    root = short_type_name(type_name)
    parts = [msg_file(root).read_text()]
    seen = {root}

    def add_dependencies(name: str, text: str) -> None:
        for field in parse_msg(text, name).fields:
            if field.is_primitive or field.type in seen:
                continue
            seen.add(field.type)
            dependency = msg_file(field.type).read_text()
            parts.append(f"\n{DELIMITER}\nMSG: {field.type}\n{dependency}")
            add_dependencies(field.type, dependency)

    add_dependencies(root, parts[0])
    return "".join(parts)


@lru_cache(maxsize=None)
def type_hash(type_name: str) -> str:
    """``RIHS01_…`` from the ``.json`` beside the type's ``.msg``, or ``""`` if there is none."""
    try:
        path = msg_file(type_name, ".json")
    except BagError:
        return ""
    hashes = json.loads(path.read_text()).get("type_hashes", [])
    return hashes[0]["hash_string"] if hashes else ""


@lru_cache(maxsize=None)
def has_header(type_name: str) -> bool:
    """True if the type's first field is a ``std_msgs/Header`` (its CDR starts with the stamp: `header_stamp_ns`)."""
    fields = parse_msg(msg_file(type_name).read_text(), type_name).fields
    return bool(fields) and fields[0].type == "std_msgs/Header"
