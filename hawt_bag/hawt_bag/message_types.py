"""The Python class of a message type, for the nodes (they need rclpy's generated types)."""
import importlib

from .errors import BagError
from .msg_definition import short_type_name

__all__ = ["message_class"]


def message_class(type_name: str) -> type:
    """``pkg/msg/Type`` → the generated class ``pkg.msg.Type`` (BagError naming the type if not installed)."""
    package, _, name = short_type_name(type_name).partition("/")
    try:
        return getattr(importlib.import_module(f"{package}.msg"), name)
    except (ImportError, AttributeError):
        raise BagError(f"{type_name}: message type not installed (no Python module {package}.msg.{name})") from None
