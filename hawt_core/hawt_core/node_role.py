"""What a node of a graph is to the engines, found without ROS: its role, its parameter table and its rules.

Every hawt executable an engine must recognise registers a :class:`NodeRole` under the ``hawt.nodes`` entry-point
group of its distribution, named after the executable (``plant``, ``mbc``, ``controller_manager``, …), as
ros2_control's pluginlib registers a controller class under its type. A controller type registers its core class
under ``hawt.controllers`` (hawt_controllers.plugins.registry); the generic ``controller`` executable and its
aliases, one per type, register the function that makes a controller's role from its type. The launcher's
parameter check, the in-process engine and campaigns read the roles (hawt_tools.node_registry); the ROS nodes
declare the same tables.
"""
import sys
from dataclasses import dataclass
from functools import lru_cache
from typing import Any, Callable, Mapping, Optional, Tuple

from hawt_core.parameter_table import ParameterSpec
from hawt_core.topics import RECORDER_NODE

__all__ = ["AWAIT_SCHEDULE", "HOLD_LIMIT", "KINDS", "NODES_GROUP", "NodeRole", "WAIT_FOR_RECORDER", "entry_points"]

NODES_GROUP = "hawt.nodes"
"""The entry-point group of node roles: executable name -> NodeRole (or, for controllers, type -> NodeRole)."""

KINDS = ("plant", "description", "assembler", "manager", "controller", "other")
"""What an engine can step or must know of: the plant, the description publisher, the loop assembler (mbc), the
controller manager, a controller; ``other`` for a node only ``hawt launch`` starts (its table read off its class)."""


def entry_points(group: str) -> Tuple[Any, ...]:
    """The ``importlib.metadata`` entry points of ``group`` in the distributions on ``sys.path``. Every group is read
    in one pass over the distributions (a pass reads each one's metadata: tens of milliseconds), kept while
    ``sys.path`` stays the same."""
    return _group(tuple(sys.path), group)


@lru_cache(maxsize=16)
def _group(path: Tuple[str, ...], group: str) -> Tuple[Any, ...]:
    return tuple(_every_group(path).select(group=group))


@lru_cache(maxsize=4)
def _every_group(path: Tuple[str, ...]) -> Any:
    import importlib.metadata  # here: the ROS nodes that import this module never read entry points

    return importlib.metadata.entry_points()


@dataclass(frozen=True)
class NodeRole:
    """One kind of node: its parameter table (hawt_core.parameter_table rows), its cheap rules across parameters
    (``check_parameters(values)`` raising ParameterError), and for a controller its core class."""

    kind: str
    parameters: Tuple[ParameterSpec, ...]
    check_parameters: Optional[Callable[[Mapping[str, Any]], None]] = None
    controller: Optional[type] = None

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"node role kind {self.kind!r}: expected one of {', '.join(KINDS)}")


HOLD_LIMIT = 2.0
"""Wall time [s] a node holds its first messages at most for the recorder (hawt_node.writer_matching); then it
publishes them and says which readers it missed (a reader the graph still lists after its process died never
matches)."""

WAIT_FOR_RECORDER = ParameterSpec(
    "wait_for_recorder", False, f"hold the first messages until the node {RECORDER_NODE} subscribes to this node's "
    f"topics and is matched (at most {HOLD_LIMIT:g} s); hawt launch --record sets it", read_only=True)
"""The parameter of every node that answers the plant's steps (the plant has its own, with its start rule)."""

AWAIT_SCHEDULE = ParameterSpec(
    "await_schedule", False, "answer the first step only once controller_manager has published its schedule "
    "(every scheduled switch is then known before its step); hawt launch sets it when the graph has a "
    "controller_manager", read_only=True)
"""The parameter of every node that applies switches (the loop assembler and each controller)."""
