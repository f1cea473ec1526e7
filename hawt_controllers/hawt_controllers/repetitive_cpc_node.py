"""The ``repetitive_cpc`` node: repetitive-PD collective pitch and torque (hawt_controllers.repetitive_cpc)."""
from hawt_controllers.controller_node import ControllerNode
from hawt_controllers.repetitive_cpc import RepetitiveCollectiveController
from hawt_node.node_main import node_entry_point

__all__ = ["RepetitiveCollectiveNode", "main"]


class RepetitiveCollectiveNode(ControllerNode):
    CONTROLLER = RepetitiveCollectiveController


main = node_entry_point(RepetitiveCollectiveNode)
