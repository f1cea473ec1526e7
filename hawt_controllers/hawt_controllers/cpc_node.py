"""The ``cpc`` node: the baseline collective pitch and torque controller (hawt_controllers.cpc_controller)."""
from hawt_controllers.controller_node import ControllerNode
from hawt_controllers.cpc_controller import CollectivePitchController
from hawt_node.node_main import node_entry_point

__all__ = ["CollectivePitchNode", "main"]


class CollectivePitchNode(ControllerNode):
    CONTROLLER = CollectivePitchController


main = node_entry_point(CollectivePitchNode)
