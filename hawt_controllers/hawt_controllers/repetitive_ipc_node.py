"""The ``repetitive_ipc`` node: per-blade repetitive flap-moment control (hawt_controllers.repetitive_ipc)."""
from hawt_controllers.controller_node import ControllerNode
from hawt_controllers.repetitive_ipc import RepetitiveIpcController
from hawt_node.node_main import node_entry_point

__all__ = ["RepetitiveIpcNode", "main"]


class RepetitiveIpcNode(ControllerNode):
    CONTROLLER = RepetitiveIpcController


main = node_entry_point(RepetitiveIpcNode)
