"""The ``lqg_ipc`` node: LQG 1P IPC with wind-estimate feedforward (hawt_controllers.lqg_controller)."""
from hawt_controllers.controller_node import ControllerNode
from hawt_controllers.lqg_controller import LqgIpcController
from hawt_node.node_main import node_entry_point

__all__ = ["LqgIpcNode", "main"]


class LqgIpcNode(ControllerNode):
    CONTROLLER = LqgIpcController


main = node_entry_point(LqgIpcNode)
