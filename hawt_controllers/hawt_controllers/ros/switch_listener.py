"""A node's side of controller switching: the switches it must apply at its steps, and its announced state.

Every controller and the mbc node keep one :class:`SwitchListener`. It subscribes to
``controller_manager/switch`` and ``controller_manager/schedule`` (transient local: a node
that starts late still gets earlier switches) and hands out each switch when the node
handles the switch's step (:meth:`SwitchListener.due`); ``has_schedule`` says whether the
manager's schedule has arrived (a node with ``await_schedule`` answers no step before it has).
A controller also announces its lifecycle state on ``controller_manager/controllers``
(:meth:`SwitchListener.announce`), which is how the controller manager learns which controllers exist.
"""
from typing import List, Optional, Sequence

from hawt_msgs.msg import ControllerSchedule, ControllerState, ControllerSwitch
from rclpy.node import Node

from hawt_controllers.plugins.switching import Switch
from hawt_core.command_interfaces import join_claims, split_claims
from hawt_node.qos import LATCHED
from hawt_core.topics import CONTROLLER_STATES, SCHEDULE, SWITCHES

__all__ = ["SwitchListener", "switch_from_message", "switch_message"]


def switch_from_message(msg: ControllerSwitch) -> Switch:
    """The core's Switch of a ControllerSwitch message."""
    return Switch(step=msg.step, activate=tuple(zip(msg.activate, map(split_claims, msg.activate_interfaces))),
                  deactivate=tuple(zip(msg.deactivate, map(split_claims, msg.deactivate_interfaces))),
                  ramp_time=msg.ramp_time)


def switch_message(switch: Switch) -> ControllerSwitch:
    """The ControllerSwitch message of a core Switch."""
    return ControllerSwitch(step=switch.step, activate=[name for name, _ in switch.activate],
                            activate_interfaces=[join_claims(claims) for _, claims in switch.activate],
                            deactivate=[name for name, _ in switch.deactivate],
                            deactivate_interfaces=[join_claims(claims) for _, claims in switch.deactivate],
                            ramp_time=switch.ramp_time)


class SwitchListener:
    """Switches for ``node`` in step order; with ``controller_type`` set, the node also announces its state.

    Parameters
    ----------
    node : rclpy.node.Node
        The node that applies the switches.
    controller_type : str, optional
        The executable name (``ipc``, ``cpc``) of a controller; None for a node that only
        follows switches (mbc).
    interfaces : sequence of str
        The command interfaces the controller claims.
    switchable : bool
        Whether the controller manager may switch it.
    """

    def __init__(self, node: Node, controller_type: Optional[str] = None, interfaces: Sequence[str] = (),
                 switchable: bool = True) -> None:
        self.node = node
        self.name = node.get_fully_qualified_name()
        self.pending: List[Switch] = []
        self.has_schedule = False
        node.create_subscription(ControllerSwitch, SWITCHES, self._on_switch, LATCHED)
        node.create_subscription(ControllerSchedule, SCHEDULE, self._on_schedule, LATCHED)
        self._state = None
        if controller_type is not None:
            self._state = ControllerState(name=self.name, type=controller_type, interfaces=list(interfaces),
                                          switchable=switchable)
            self._state_publisher = node.create_publisher(ControllerState, CONTROLLER_STATES, LATCHED)

    def _on_switch(self, msg: ControllerSwitch) -> None:
        switch = switch_from_message(msg)
        if self._state is not None and self.name not in switch.names():
            return
        self.pending.append(switch)
        self.pending.sort(key=lambda s: s.step)

    def _on_schedule(self, msg: ControllerSchedule) -> None:
        if not self.has_schedule:
            self.has_schedule = True
            for switch in msg.switches:
                self._on_switch(switch)

    def due(self, step: int) -> List[Switch]:
        """The switches to apply when handling ``step``, in step order (a switch whose step has passed, too)."""
        ready = [s for s in self.pending if s.step <= step]
        self.pending = [s for s in self.pending if s.step > step]
        return ready

    def announce(self, state: int, step: int) -> None:
        """Publish the controller's lifecycle ``state`` (ControllerState id) entered at ``step``."""
        self._state.state, self._state.step = state, step
        self._state_publisher.publish(self._state)
