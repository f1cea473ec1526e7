"""The ``main_bearing_ipc`` node: 2P main-bearing IPC of two-bladed rotors (hawt_controllers.main_bearing_ipc)."""
from hawt_controllers.controller_node import ControllerNode
from hawt_controllers.main_bearing_ipc import MainBearingIpcController
from hawt_node.node_main import node_entry_point

__all__ = ["MainBearingIpcNode", "main"]


class MainBearingIpcNode(ControllerNode):
    CONTROLLER = MainBearingIpcController


main = node_entry_point(MainBearingIpcNode)
