"""The ``blade_sine`` node: a sine per blade on the ``blade_pitch`` interface (hawt_controllers.blade_sine)."""
from hawt_controllers.blade_sine import BladeSineController
from hawt_controllers.controller_node import ControllerNode
from hawt_node.node_main import node_entry_point

__all__ = ["BladeSineNode", "main"]


class BladeSineNode(ControllerNode):
    CONTROLLER = BladeSineController


main = node_entry_point(BladeSineNode)
