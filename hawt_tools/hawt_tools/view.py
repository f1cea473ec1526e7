"""What ``hawt view`` serves, without ROS or the Foxglove SDK: its options, and parameter names and values.

Each topic becomes a channel of message encoding ``cdr`` (the bytes as published) and schema encoding
``ros2msg``, named ``pkg/msg/Type``, holding the type's ``.msg`` text with every dependency: the text a
bag's schema holds (DESIGN §7, `hawt_bag.interface_files.schema_text`), so Foxglove decodes a live graph
and its bags alike. A node's parameter is the protocol parameter ``/ns/node.param``, as foxglove_bridge
names them: the fully qualified node name, a dot, the parameter name. The SDK's types are built in
`hawt_tools.view_node`: this module is imported by the ``hawt`` command, and the SDK takes 0.2 s to import.
"""
import argparse
import ipaddress
from dataclasses import dataclass

__all__ = ["CDR", "ROS2MSG", "ViewOptionError", "ViewOptions", "add_view_arguments", "coerce", "is_loopback",
           "options_from", "parameter_name", "split_parameter_name"]

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
    allow_origins : tuple of str
        Web-page Origins let in besides native clients (hawt_tools.origin_gate).
    allow_parameter_sets : bool
        Whether clients may set parameters (off: they may read them).
    """

    host: str = "127.0.0.1"
    port: int = 8765
    poll_period: float = 0.1
    depth: int = 100
    timeout: float = 2.0
    allow_origins: tuple = ()
    allow_parameter_sets: bool = False


def add_view_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of ``hawt view`` (and of the ``view`` executable)."""
    parser.add_argument("--host", default="127.0.0.1",
                        help="address to serve on (default 127.0.0.1: this machine only; another needs "
                             "--allow-remote)")
    parser.add_argument("--port", type=int, default=8765, help="TCP port (default 8765, Foxglove's; 0: any free one)")
    parser.add_argument("--allow-remote", action="store_true",
                        help="serve on a --host other than loopback: anyone who reaches it sees the graph")
    parser.add_argument("--allow-origin", action="append", default=[], metavar="ORIGIN",
                        help="let in web pages of this Origin, e.g. https://app.foxglove.dev (default: native "
                             "clients only, such as the Foxglove desktop app; repeatable)")
    parser.add_argument("--allow-parameter-sets", action="store_true",
                        help="let clients set the nodes' parameters (checked as any live set; default: read only)")


class ViewOptionError(ValueError):
    """An option of ``hawt view`` that cannot be served; the message is one line."""


def options_from(args: argparse.Namespace) -> ViewOptions:
    """ViewOptions from parsed `add_view_arguments` options.

    Raises
    ------
    ViewOptionError
        A port outside 0-65535, or a host other than loopback without ``--allow-remote``.
    """
    if not 0 <= args.port <= 65535:
        raise ViewOptionError(f"--port {args.port}: expected 0 to 65535")
    if not is_loopback(args.host) and not args.allow_remote:
        raise ViewOptionError(f"--host {args.host}: not this machine's loopback; anyone who reaches it would see the "
                              "graph (add --allow-remote to serve it anyway)")
    return ViewOptions(host=args.host, port=args.port, allow_origins=tuple(args.allow_origin),
                       allow_parameter_sets=args.allow_parameter_sets)


def is_loopback(host: str) -> bool:
    """Whether ``host`` is a loopback address or ``localhost``."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


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
