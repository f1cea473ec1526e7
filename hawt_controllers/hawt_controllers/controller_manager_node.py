"""The ``controller_manager`` node: which controllers are active, and switching them at one plant step.

Controllers announce themselves on ``controller_manager/controllers``. A switch
(service ``controller_manager/switch_controllers``, ``hawt switch``, or the
``schedule`` parameter) is checked with ros2_control's STRICT / BEST_EFFORT
semantics (hawt_controllers.switching.plan_switch) and published on
``controller_manager/switch`` for one future plant step: "as soon as possible"
means ``lead_steps`` after the newest step seen on ``plant/blade_loads``, so every
node has it before that step. Each node applies it when it handles that step;
a schedule given in steps therefore gives the same run every time in lockstep.
``controller_manager/list_controllers`` answers each controller's state as the
controller itself last reported it.
"""
import math
from typing import Dict, List

from hawt_msgs.msg import BladeLoads, ControllerState, ControllerSwitch, ControlEvent
from hawt_msgs.srv import ListControllers, SwitchControllers
from rclpy.node import Node

from hawt_controllers.switching import (STATE_NAMES, ControllerInfo, SwitchRefused, parse_schedule, plan_switch,
                                        ramp_steps, resolve_controller)
from hawt_tools.events import EventPublisher
from hawt_tools.node_main import node_entry_point
from hawt_tools.parameters import ParameterSpec, declare_parameters
from hawt_tools.qos import CONTROL_LOOP, LATCHED
from hawt_tools.topics import BLADE_LOADS, CONTROLLER_STATES, LIST_CONTROLLERS, SWITCH_CONTROLLERS, SWITCHES

__all__ = ["ControllerManagerNode", "PARAMETERS", "main"]

PARAMETERS = (
    ParameterSpec("ramp_time", 2.0, "default time over which an outgoing IPC contribution ramps out and an "
                  "incoming one ramps in", "s", minimum=0.0, maximum=600.0),
    ParameterSpec("lead_steps", 50, "an as-soon-as-possible switch takes effect this many steps after the newest "
                  "plant step seen", minimum=1, maximum=100000),
    ParameterSpec("schedule", [""], "switches given in steps, each 'STEP +NAME -NAME ...' (+ activates, - "
                  "deactivates), applied with STRICT checks and ramp_time; [''] = none", read_only=True),
    ParameterSpec("dt", 0.01, "plant step", "s", minimum=1e-4, maximum=1.0, read_only=True),
)


class ControllerManagerNode(Node):
    """Thin node around hawt_controllers.switching."""

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
        self.create_subscription(ControllerState, CONTROLLER_STATES, self._on_state, LATCHED)
        self.create_subscription(BladeLoads, BLADE_LOADS, self._on_loads, CONTROL_LOOP)
        self.create_service(SwitchControllers, SWITCH_CONTROLLERS, self._on_switch)
        self.create_service(ListControllers, LIST_CONTROLLERS, self._on_list)
        self.schedule_timer = self.create_timer(0.05, self._run_schedule) if self.schedule else None

    def _on_state(self, msg: ControllerState) -> None:
        """A controller's own report; it is what switches are planned on unless a switch of it is still ahead."""
        self.reported[msg.name] = msg
        if self.switched_at.get(msg.name, -1) > self.newest_step:
            return
        state = STATE_NAMES.get(msg.state, "unknown")
        ramping = self.planned[msg.name].publishing_until if msg.name in self.planned else 0.0
        publishing = math.inf if state == "active" else (ramping if math.isfinite(ramping) else 0.0)
        self.planned[msg.name] = ControllerInfo(msg.name, msg.type, int(msg.harmonic), state, msg.switchable,
                                                publishing)

    def _on_loads(self, msg: BladeLoads) -> None:
        self.newest_step = max(self.newest_step, msg.step)

    def _switch(self, activate: List[str], deactivate: List[str], strict: bool, ramp_time: float,
                at_step: int) -> tuple:
        """Check and publish one switch; (effective step, what was done). Raises SwitchRefused."""
        step = at_step or self.newest_step + self.values["lead_steps"]
        if at_step and at_step <= self.newest_step:
            raise SwitchRefused(f"at_step {at_step}: the plant is already at step {self.newest_step}")
        if step < self.last_switch_step:
            raise SwitchRefused(f"at_step {step}: a switch is already set for the later step {self.last_switch_step}")
        ramp = self.values["ramp_time"] if ramp_time < 0 else ramp_time
        end = step + ramp_steps(ramp, self.values["dt"])
        incoming, outgoing, skipped = plan_switch(self.planned, activate, deactivate, strict, step)
        msg = ControllerSwitch(step=step, activate=[c.name for c in incoming],
                               activate_harmonics=[c.harmonic for c in incoming],
                               deactivate=[c.name for c in outgoing],
                               deactivate_harmonics=[c.harmonic for c in outgoing], ramp_time=ramp)
        self.switch_publisher.publish(msg)
        self.last_switch_step = step
        swapped = {c.harmonic for c in incoming} & {c.harmonic for c in outgoing}
        for c in incoming:
            self.planned[c.name] = ControllerInfo(c.name, c.type, c.harmonic, "active", c.switchable, math.inf)
            self.switched_at[c.name] = step
        for c in outgoing:
            self.planned[c.name] = ControllerInfo(c.name, c.type, c.harmonic, "inactive", c.switchable,
                                                  step if c.harmonic in swapped else end)
            self.switched_at[c.name] = step
        done = "; ".join(part for part in (
            "activate " + ", ".join(msg.activate) if msg.activate else "",
            "deactivate " + ", ".join(msg.deactivate) if msg.deactivate else "",
            f"ramp {ramp:g} s",
            "skipped: " + "; ".join(skipped) if skipped else "") if part)
        self.events(ControlEvent.INFO, "switch", f"at step {step}: {done}", step=step)
        return step, done

    def _on_switch(self, request: SwitchControllers.Request, response: SwitchControllers.Response):
        try:
            if request.strictness not in (SwitchControllers.Request.STRICT, SwitchControllers.Request.BEST_EFFORT):
                raise SwitchRefused(f"strictness {request.strictness}: expected 1 (BEST_EFFORT) or 2 (STRICT)")
            step, done = self._switch(list(request.activate), list(request.deactivate),
                                      request.strictness == SwitchControllers.Request.STRICT, request.ramp_time,
                                      request.at_step)
            response.ok, response.message, response.effective_step = True, f"at step {step}: {done}", step
        except SwitchRefused as refusal:
            response.ok, response.message = False, str(refusal)
            self.events(ControlEvent.WARN, "switch_refused", str(refusal), step=max(self.newest_step, 0))
        return response

    def _run_schedule(self) -> None:
        """Publish the scheduled switches once every controller they name has announced itself."""
        try:
            for entry in self.schedule:
                for name in (*entry.activate, *entry.deactivate):
                    resolve_controller(name, self.planned)
        except SwitchRefused:
            return
        try:
            while self.schedule:
                entry = self.schedule.pop(0)
                self._switch(list(entry.activate), list(entry.deactivate), True, -1.0, entry.step)
        except SwitchRefused as refusal:
            self.events(ControlEvent.ERROR, "switch_refused", f"schedule: {refusal}", step=max(self.newest_step, 0))
            self.schedule = []
        self.schedule_timer.cancel()

    def _on_list(self, request: ListControllers.Request, response: ListControllers.Response):
        for name in sorted(self.reported):
            state = self.reported[name]
            response.names.append(name)
            response.types.append(state.type)
            response.states.append(STATE_NAMES.get(state.state, "unknown"))
            response.harmonics.append(state.harmonic)
        return response


main = node_entry_point(ControllerManagerNode)
