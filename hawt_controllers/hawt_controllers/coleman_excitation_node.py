"""The ``coleman_excitation`` node: random-binary tilt and yaw pitch (hawt_controllers.coleman_excitation)."""
from hawt_controllers.coleman_excitation import ColemanExcitationController
from hawt_controllers.controller_node import ControllerNode
from hawt_node.node_main import node_entry_point

__all__ = ["ColemanExcitationNode", "main"]


class ColemanExcitationNode(ControllerNode):
    CONTROLLER = ColemanExcitationController


main = node_entry_point(ColemanExcitationNode)
