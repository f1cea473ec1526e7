"""What each node of a graph is, read from the registry without ROS (hawt_core.node_role).

A node's role comes from the ``hawt.nodes`` entry point its package registers under the node's executable: the
plant, the plant description, the loop assembler (mbc), the controller manager, or a controller — whose role comes
from its type, the ``type`` parameter or the executable's name for the aliases named after a type
(hawt_controllers.plugins.registry). A node no package registers (an example node, the view, a C++ node) has no
role: ``hawt launch`` starts it with its values unchecked beyond its own table, and the in-process engine refuses it.

The launcher also gives each node what the graph implies (:func:`implied_parameters`): an alias its type, and the
loop assembler the names of the graph's controllers in its namespace, which it waits for before the first step.
"""
from functools import lru_cache
from typing import Any, Dict, Mapping, Optional, Sequence, Tuple

from hawt_core.node_role import NODES_GROUP, NodeRole, entry_points
from hawt_core.parameter_table import ParameterError
from hawt_tools.graph_file import Graph, GraphError, NodeSpec
from hawt_tools.node_parameters import node_parameters

__all__ = ["implied_parameters", "node_role"]

Overrides = Mapping[str, Sequence[Tuple[str, Any]]]


@lru_cache(maxsize=4)
def _by_executable(entries: Tuple[Any, ...]) -> Dict[Tuple[str, str], Any]:
    return {(_package(entry.dist.name), entry.name): entry for entry in entries}


def _package(name: str) -> str:
    return name.replace("-", "_")


def node_role(graph: Graph, spec: NodeSpec, overrides: Overrides = ()) -> Optional[NodeRole]:
    """The role of node ``spec`` (None if no package registers its executable).

    Raises
    ------
    GraphError
        A controller node whose type is not registered (naming the registered ones), or the generic ``controller``
        executable without a ``type``.
    """
    entry = _by_executable(entry_points(NODES_GROUP)).get((_package(spec.package), spec.executable))
    if entry is None:
        return None
    role = entry.load()
    if isinstance(role, NodeRole):
        return role
    given = node_parameters(spec, overrides).get("type", "")
    type_name = given if isinstance(given, str) and given else spec.executable
    try:
        return role(type_name)
    except ParameterError as error:
        if not given and spec.executable == "controller":
            error = ParameterError("type: the generic controller executable needs the controller's type (a "
                                   "hawt.controllers entry point, e.g. {name: type, value: ipc})")
        raise GraphError(f"{graph.path}:{spec.line}: node {spec.name!r}: {error}") from None


def implied_parameters(graph: Graph, spec: NodeSpec, overrides: Overrides = ()) -> Dict[str, Any]:
    """What the graph gives node ``spec`` beyond its own entries (its own entries win): a controller alias its
    ``type``; the loop assembler the names of the controllers in its namespace (``controllers``: so every run
    starts alike, it answers no step before each has announced itself)."""
    role = node_role(graph, spec, overrides)
    if role is None:
        return {}
    if role.kind == "controller":
        return {"type": role.controller.TYPE}
    if role.kind == "assembler":
        names = [other.name for other in graph.nodes if other.full_namespace == spec.full_namespace
                 and (other_role := node_role(graph, other, overrides)) is not None
                 and other_role.kind == "controller"]
        return {"controllers": names or [""]}
    return {}
