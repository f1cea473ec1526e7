"""What ``hawt view`` serves, without ROS or the Foxglove SDK: its options, and parameter names and values.

Each topic becomes a channel of message encoding ``cdr`` (the bytes as published) and schema encoding
``ros2msg``, named ``pkg/msg/Type``, holding the type's ``.msg`` text with every dependency: the text a
bag's schema holds (DESIGN §7, `hawt_bag.interface_files.schema_text`), so Foxglove decodes a live graph
and its bags alike. A node's parameter is the protocol parameter ``/ns/node.param``, as foxglove_bridge
names them: the fully qualified node name, a dot, the parameter name. The SDK's types are built in
`hawt_tools.view_node`: this module is imported by the ``hawt`` command, and the SDK takes 0.2 s to import.
"""
import argparse
from dataclasses import dataclass

__all__ = ["CDR", "ROS2MSG", "ViewOptions", "add_view_arguments", "coerce", "options_from", "parameter_name",
           "split_parameter_name"]

CDR = "cdr"
"""Message encoding of the channels: the raw bytes of the middleware (XCDR1, encapsulation header first)."""
ROS2MSG = "ros2msg"
"""Schema encoding of the channels."""


@dataclass(frozen=True)
class ViewOptions:
    """Where ``hawt view`` serves and how it follows the graph.

    Attributes
    ----------
    host : str
        Address the WebSocket server binds to (localhost by default: nothing beyond this machine).
    port : int
        TCP port (0: any free port; the one taken is printed).
    poll_period : float
        Graph discovery period [s].
    depth : int
        Keep-last depth of each subscription: messages a topic may be behind before the oldest are dropped.
    timeout : float
        Longest wait for a node's parameter service [s].
    """

    host: str = "127.0.0.1"
    port: int = 8765
    poll_period: float = 0.1
    depth: int = 100
    timeout: float = 2.0


def add_view_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of ``hawt view`` (and of the ``view`` executable)."""
    parser.add_argument("--host", default="127.0.0.1",
                        help="address to serve on (default 127.0.0.1: this machine only; 0.0.0.0 for every network)")
    parser.add_argument("--port", type=int, default=8765, help="TCP port (default 8765, Foxglove's; 0: any free one)")


def options_from(args: argparse.Namespace) -> ViewOptions:
    """ViewOptions from parsed `add_view_arguments` options."""
    return ViewOptions(host=args.host, port=args.port)


def parameter_name(node: str, name: str) -> str:
    """``/wt1/ipc_h1`` and ``gains.ki`` -> ``/wt1/ipc_h1.gains.ki``."""
    return f"{node}.{name}"


def split_parameter_name(full_name: str) -> tuple[str, str]:
    """``/wt1/ipc_h1.gains.ki`` -> (``/wt1/ipc_h1``, ``gains.ki``): a node name has no dot.

    Raises
    ------
    ValueError
        If the name is not ``/node.parameter``.
    """
    node, dot, name = full_name.partition(".")
    if not node.startswith("/") or not dot or not name:
        raise ValueError(f"parameter {full_name!r}: expected /NODE.PARAMETER (e.g. /wt1/ipc_h1.ki)")
    return node, name


def coerce(value: object, current: object) -> object:
    """A value from the protocol in the type of the parameter's ``current`` value where JSON lost it.

    A whole number for a float parameter (``2`` for ``2.0``) becomes a float, element-wise in arrays;
    anything else is returned as it is, for the node to accept or refuse.
    """
    if isinstance(current, float) and isinstance(value, int) and not isinstance(value, bool):
        return float(value)
    if isinstance(value, list) and current is not None and not isinstance(current, (str, bytes)):
        items = list(current)
        if items and all(isinstance(item, float) for item in items):
            return [coerce(item, 0.0) for item in value]
    return value
