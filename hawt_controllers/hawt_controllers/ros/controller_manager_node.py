"""The ``controller_manager`` node: which controllers are active, and switching them at one plant step.

Controllers announce themselves on ``controller_manager/controllers``. A switch
(service ``controller_manager/switch_controllers``, ``hawt switch``, or the
``schedule`` parameter) is checked with ros2_control's STRICT / BEST_EFFORT
semantics (hawt_controllers.plugins.switching.plan_switch) and published on
``controller_manager/switch`` for one future plant step: "as soon as possible"
means ``lead_steps`` after the newest step seen on ``plant/blade_loads``, so every
node has it before that step. Each node applies it when it handles that step.
The schedule is published once, all of it in one message on
``controller_manager/schedule``, when every controller it names has announced itself
(at once, empty, when there is none); a lockstep loop assembler waits for it before the
first step, so a schedule given in steps gives the same run every time.
``controller_manager/list_controllers`` answers each controller's state and claimed
command interfaces as the controller itself last reported them. A switch that would leave
an interface with two active claimants, or activate a controller whose interface the
graph's loop assembler cannot assemble for the plant's blades (``plant/description``),
is refused naming both.
"""
import math
from typing import Dict, List

from hawt_msgs.msg import BladeLoads, ControllerSchedule, ControllerState, ControllerSwitch, ControlEvent
from hawt_msgs.msg import PlantDescription as PlantDescriptionMessage
from hawt_msgs.srv import ListControllers, SwitchControllers
from rclpy.node import Node

from hawt_controllers.plugins.loop_assembly import assembly_problem
from hawt_controllers.ros.switch_listener import switch_message
from hawt_controllers.plugins.switching import (PARAMETERS, STATE_NAMES, ControllerInfo, Switch, SwitchRefused,
                                                parse_schedule, plan_switch, planned_states, ramp_steps,
                                                resolve_controller)
from hawt_core.command_interfaces import join_claims
from hawt_node.events import EventPublisher
from hawt_node.node_main import node_entry_point
from hawt_node.parameters import declare_parameters
from hawt_node.qos import CONTROL_LOOP, LATCHED
from hawt_core.topics import (BLADE_LOADS, CONTROLLER_STATES, LIST_CONTROLLERS, PLANT_DESCRIPTION, SCHEDULE,
                              SWITCH_CONTROLLERS, SWITCHES)

__all__ = ["ControllerManagerNode", "main"]

class ControllerManagerNode(Node):
    """Thin node around hawt_controllers.plugins.switching."""

    PARAMETERS = PARAMETERS

    def __init__(self, **node_kwargs) -> None:
        super().__init__("controller_manager", **node_kwargs)
        self.values = declare_parameters(self, PARAMETERS)
        self.schedule = parse_schedule([entry for entry in self.values["schedule"] if entry.strip()])
        self.reported: Dict[str, ControllerState] = {}
        self.planned: Dict[str, ControllerInfo] = {}
        self.switched_at: Dict[str, int] = {}
        self.newest_step = -1
        self.last_switch_step = -1
        self.events = EventPublisher(self)
        self.switch_publisher = self.create_publisher(ControllerSwitch, SWITCHES, LATCHED)
        self.schedule_publisher = self.create_publisher(ControllerSchedule, SCHEDULE, LATCHED)
        self.create_subscription(ControllerState, CONTROLLER_STATES, self._on_state, LATCHED)
        self.create_subscription(BladeLoads, BLADE_LOADS, self._on_loads, CONTROL_LOOP)
        self.blades = None
        self.dt = None
        self.create_subscription(PlantDescriptionMessage, PLANT_DESCRIPTION, self._on_description, LATCHED)
        self.create_service(SwitchControllers, SWITCH_CONTROLLERS, self._on_switch)
        self.create_service(ListControllers, LIST_CONTROLLERS, self._on_list)
        self.schedule_timer = self.create_timer(0.05, self._run_schedule) if self.schedule else None
        if not self.schedule:
            self.schedule_publisher.publish(ControllerSchedule())

    def _on_state(self, msg: ControllerState) -> None:
        """A controller's own report; it is what switches are planned on unless a switch of it is still ahead."""
        self.reported[msg.name] = msg
        if self.switched_at.get(msg.name, -1) > self.newest_step:
            return
        state = STATE_NAMES.get(msg.state, "unknown")
        ramping = self.planned[msg.name].publishing_until if msg.name in self.planned else 0.0
        publishing = math.inf if state == "active" else (ramping if math.isfinite(ramping) else 0.0)
        self.planned[msg.name] = ControllerInfo(msg.name, msg.type, tuple(msg.interfaces), state, msg.switchable,
                                                publishing)

    def _on_description(self, msg: PlantDescriptionMessage) -> None:
        self.blades, self.dt = int(msg.blades), float(msg.dt)

    def _on_loads(self, msg: BladeLoads) -> None:
        self.newest_step = max(self.newest_step, msg.step)

    def _switch(self, activate: List[str], deactivate: List[str], strict: bool, ramp_time: float,
                at_step: int) -> tuple:
        """Check one switch and plan on it; (the switch, what was done). Raises SwitchRefused."""
        if self.dt is None:
            raise SwitchRefused("no plant/description yet: the plant is not running")
        step = at_step or self.newest_step + self.values["lead_steps"]
        if at_step and at_step <= self.newest_step:
            raise SwitchRefused(f"at_step {at_step}: the plant is already at step {self.newest_step}")
        if step < self.last_switch_step:
            raise SwitchRefused(f"at_step {step}: a switch is already set for the later step {self.last_switch_step}")
        ramp = self.values["ramp_time"] if ramp_time < 0 else ramp_time
        ramp_steps(ramp, self.dt)  # a ramp time that is not finite and >= 0 is refused before anything is planned
        incoming, outgoing, skipped = plan_switch(self.planned, activate, deactivate, strict, step,
                                                  lambda interface: assembly_problem(interface, self.blades))
        switch = Switch(step, tuple((c.name, c.interfaces) for c in incoming),
                        tuple((c.name, c.interfaces) for c in outgoing), ramp)
        states = planned_states(switch, incoming, outgoing, self.dt)
        self.last_switch_step = step
        self.planned.update(states)
        self.switched_at.update((name, step) for name in states)
        done = "; ".join(part for part in (
            "activate " + ", ".join(c.name for c in incoming) if incoming else "",
            "deactivate " + ", ".join(c.name for c in outgoing) if outgoing else "",
            f"ramp {ramp:g} s",
            "skipped: " + "; ".join(skipped) if skipped else "") if part)
        self.events(ControlEvent.INFO, "switch", f"at step {step}: {done}", step=step)
        return switch, done

    def _on_switch(self, request: SwitchControllers.Request, response: SwitchControllers.Response):
        try:
            if request.strictness not in (SwitchControllers.Request.STRICT, SwitchControllers.Request.BEST_EFFORT):
                raise SwitchRefused(f"strictness {request.strictness}: expected 1 (BEST_EFFORT) or 2 (STRICT)")
            switch, done = self._switch(list(request.activate), list(request.deactivate),
                                        request.strictness == SwitchControllers.Request.STRICT, request.ramp_time,
                                        request.at_step)
            self.switch_publisher.publish(switch_message(switch))
            response.ok, response.message = True, f"at step {switch.step}: {done}"
            response.effective_step = switch.step
        except SwitchRefused as refusal:
            response.ok, response.message = False, str(refusal)
            self.events(ControlEvent.WARN, "switch_refused", str(refusal), step=max(self.newest_step, 0))
        return response

    def _run_schedule(self) -> None:
        """Publish the scheduled switches once the plant and every controller they name have announced themselves."""
        if self.dt is None:
            return
        try:
            for entry in self.schedule:
                for name in (*entry.activate, *entry.deactivate):
                    resolve_controller(name, self.planned)
        except SwitchRefused:
            return
        planned = ControllerSchedule()
        try:
            while self.schedule:
                entry = self.schedule.pop(0)
                switch, _ = self._switch(list(entry.activate), list(entry.deactivate), True, -1.0, entry.step)
                planned.switches.append(switch_message(switch))
        except SwitchRefused as refusal:
            self.events(ControlEvent.ERROR, "switch_refused", f"schedule: {refusal}; the switches before it stand",
                        step=max(self.newest_step, 0))
            self.schedule = []
        self.schedule_publisher.publish(planned)
        self.schedule_timer.cancel()

    def _on_list(self, request: ListControllers.Request, response: ListControllers.Response):
        for name in sorted(self.reported):
            state = self.reported[name]
            response.names.append(name)
            response.types.append(state.type)
            response.states.append(STATE_NAMES.get(state.state, "unknown"))
            response.interfaces.append(join_claims(state.interfaces))
        return response


main = node_entry_point(ControllerManagerNode)
