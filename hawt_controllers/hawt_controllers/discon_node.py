"""The ``discon`` node: a Bladed-style DISCON library, ROSCO by default (hawt_controllers.discon_controller)."""
from hawt_controllers.controller_node import ControllerNode
from hawt_controllers.discon_controller import DisconController
from hawt_node.node_main import node_entry_point

__all__ = ["DisconNode", "main"]


class DisconNode(ControllerNode):
    CONTROLLER = DisconController


main = node_entry_point(DisconNode)
