"""The ``ipc`` node: one harmonic's individual pitch control (hawt_controllers.ipc_controller).

One process per controller (``ipc_h1``, ``ipc_h2``, … from this one executable, each with
its ``harmonic``); every parameter but ``harmonic`` can be set while running.
"""
from hawt_controllers.controller_node import ControllerNode
from hawt_controllers.ipc_controller import HarmonicIpcController
from hawt_node.node_main import node_entry_point

__all__ = ["IpcNode", "main"]


class IpcNode(ControllerNode):
    CONTROLLER = HarmonicIpcController


main = node_entry_point(IpcNode)
