"""``hawt bridge`` on the ROS graph: the bridged graph launched as ``hawt launch`` launches it, with the bridge plant
node (hawt_tools.bridge_node) in place of its plant node.

On the library's first call this process checks the bridge file, the graph and the simulator as the in-process path
does (:func:`hawt_tools.discon_bridge.bridged_graph`: one line, exit 2, and ``aviFAIL = -1`` with the same line in the
library), then starts the graph (hawt_tools.commands.graphs.launch_graph: one process per node, lockstep, ``--record``
with the recorder's back-pressure and respawn) and hands the library's connection and its first call to the bridge
plant node over a private Unix socket (:func:`hand_over`, :func:`take_over`). The connection's descriptor itself goes
over (``SCM_RIGHTS``), so each DISCON call goes from the library straight to the node, which answers it with that
step's ``control/pitch_command``: the launcher starts a node with its standard streams only, and relaying the calls
through this process would add a socket round trip to each. This process keeps no copy once it is handed over, so a
bridge node that dies is a closed connection to the library at once. The simulator's last call ends the node and,
through its ``on_exit: shutdown``, the graph.
"""
import socket
import tempfile
import threading
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path
from typing import Callable, Iterator, Optional, Tuple

from hawt_tools.discon_bridge import (REQUEST, BridgeClosed, BridgeError, BridgeFile, BridgeRun, bridged_graph,
                                      checked_first_call, encode_reply, first_call, listen)
from hawt_tools.graph_file import Graph, NodeSpec

__all__ = ["BRIDGE_EXECUTABLE", "bridge_graph", "hand_over", "serve_graph", "take_over"]

BRIDGE_EXECUTABLE = ("hawt_tools", "bridge_plant")
"""Package and executable of the bridge plant node (hawt_tools.bridge_node)."""


def bridge_graph(graph: Graph, plant: NodeSpec) -> Graph:
    """``graph`` with its plant node ``plant`` replaced by the bridge plant node: the same name, namespace, parameters
    and remappings; it ends the graph when it ends (``on_exit: shutdown``) and is never respawned (the simulator's
    connection cannot be handed over twice)."""
    package, executable = BRIDGE_EXECUTABLE
    bridge = replace(plant, package=package, executable=executable, shutdown_on_exit=True, respawn=False)
    return replace(graph, nodes=tuple(bridge if spec is plant else spec for spec in graph.nodes))


@contextmanager
def hand_over(connection: socket.socket, first: bytes, timeout: float) -> Iterator[Tuple[str, threading.Event]]:
    """Offer ``connection`` and the library's first message ``first`` on a Unix socket in a private folder, for
    ``timeout`` s, to the one node that calls :func:`take_over` on it; yields the socket's path and an event set once
    handed over (this process's copy of the connection is then closed)."""
    done = threading.Event()
    with tempfile.TemporaryDirectory(prefix="hawt-handover-") as folder:  # mode 0700: this user's only
        path = str(Path(folder) / "handover.sock")
        server = listen(path)
        server.settimeout(timeout)

        def give() -> None:
            try:
                peer, _ = server.accept()
            except OSError:
                return
            with peer:
                socket.send_fds(peer, [first], [connection.fileno()])
            connection.close()
            done.set()

        giver = threading.Thread(target=give, name="bridge hand-over", daemon=True)
        giver.start()
        try:
            yield path, done
        finally:
            server.close()
            giver.join(timeout=1.0)


def take_over(path: str, timeout: float = 10.0) -> Tuple[socket.socket, bytes]:
    """The simulator's connection and its first message, from the ``hawt bridge`` that offers them at ``path``
    (:func:`hand_over`). A :class:`BridgeError` if nothing is offered there within ``timeout`` s."""
    with socket.socket(socket.AF_UNIX, socket.SOCK_SEQPACKET) as handover:
        handover.settimeout(timeout)
        try:
            handover.connect(path)
            data, descriptors, _, _ = socket.recv_fds(handover, REQUEST.size + 1, 1)
        except OSError as error:
            raise BridgeError(f"handover {path}: no connection from hawt bridge: {error}") from None
    if len(descriptors) != 1:
        raise BridgeError(f"handover {path}: hawt bridge sent {len(descriptors)} connections, not 1")
    connection = socket.socket(fileno=descriptors[0])
    connection.settimeout(None)
    return connection, data


def serve_graph(bridge: BridgeFile, server: Optional[socket.socket] = None,
                progress: Callable[[str], None] = lambda _: None) -> BridgeRun:
    """Serve one simulator run on the ROS graph: accept the library's connection, check the graph on its first call,
    launch it with the bridge plant node and hand that node the connection; returns once the graph has ended (the
    simulator's last call ends it). ``server`` is a socket from :func:`hawt_tools.discon_bridge.listen` (default:
    listen at the file's ``socket``).

    Raises
    ------
    BridgeError
        A graph or simulator the bridge cannot run with (also sent to the library, which fails with it).
    BridgeClosed
        The simulator went away before its first call.
    RuntimeError
        The graph failed once started (a node died, the simulator went away: the launcher names it).
    """
    from hawt_core.parameter_table import ParameterError
    from hawt_tools.commands.graphs import launch_graph
    from hawt_tools.graph_file import GraphError

    connection, data = first_call(bridge, server)
    with connection:
        bridged = checked_first_call(connection, data, lambda *call: bridged_graph(bridge, *call))
        progress(f"{bridged.graph.path.name}: launching the graph, {bridged.plant.label} is the bridge")
        with hand_over(connection, data, bridge.start_timeout) as (path, handed):
            try:
                launch_graph(bridge_graph(bridged.graph, bridged.plant),
                             [*bridged.parameters, f"{bridged.plant.label}.handover:={path}"], "lockstep", None,
                             False, str(bridge.record) if bridge.record is not None else None)
            except (GraphError, ParameterError, RuntimeError) as error:
                if not handed.is_set():  # the node never took the connection: the library hears it from here
                    connection.sendall(encode_reply(fail=-1, message=f"hawt bridge: {error}"))
                if isinstance(error, RuntimeError):
                    raise
                raise BridgeError(f"bridge file {bridge.path}: graph {bridge.graph}: {error}") from None
            if not handed.is_set():
                raise BridgeClosed("the graph ended before its bridge plant node took the simulator's connection")
    return BridgeRun(None, None, bridge.record, summary="the simulator's last call ended the graph (the plant's "
                                                        "finished line above counts its steps)")

