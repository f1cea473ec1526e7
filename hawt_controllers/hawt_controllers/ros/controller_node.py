"""The controller node: the lifecycle, step matching and switching of every controller, done once.

One node class runs every controller type. Its ``type`` parameter names the type, which the registry turns into the
core class (hawt_controllers.plugins.registry, the ``hawt.controllers`` entry points); the executables named after a
type (``ipc``, ``cpc``, …) are aliases of the generic ``controller`` executable whose type is their name.

What the node does for every controller (ros2_controllers' ``forward_controllers_base``):

- **configure** (once ``plant/description`` has arrived, or a standard ``configure``
  transition): read the parameter table, build the core with the plant's dt and B (the
  core's own validation refuses bad or conflicting values: FAILURE, one line naming the
  parameter, an ``invalid_parameter`` event), create the contribution publishers and the
  input subscriptions. ``active`` decides whether it then starts active at step 0.
- **steps**: the inputs the core declares (``plant/blade_loads``, ``plant/state``) are joined
  by step (with ``await_schedule``, only once controller_manager's schedule has arrived); the
  core is updated at every step, active or not; its contributions are
  published while active or ramping out. A repeated step is answered again, never
  recomputed (hawt_core.step_sync). Input the core refuses gets the core's answer without input
  (``Controller.without_input``: the held output, or the IPC's fade-out) and is reported
  (``invalid_input``, at the first of consecutive refused steps, as ``hawt run`` does); a core that fails for good (``ControllerFailure``) is reported
  (``controller_failed``) and answers no more steps, so the plant's safety system takes over.
- **switches** from ``controller_manager`` take effect at their plant step (bumpless: the
  core ramps in or out; one that replaces another on its interfaces starts from the
  other's output of the step before, which it follows while inactive, and waits for it if
  that message is not there yet; the effect on the core is hawt_controllers.plugins.switching.switch_effect,
  shared with ``hawt run``). Standard lifecycle
  ``activate``/``deactivate`` transitions from outside are passed to ``controller_manager``
  as a switch, so they reach the same state at a plant step; ``cleanup`` destroys what
  configure made.
- **live parameters** are checked by the core (rejected with the reason) and applied at
  the next step boundary, reported as ``parameter_change``.
"""
import math
import sys
from functools import partial
from pathlib import Path
from typing import Any, Dict, List, NamedTuple, Optional, Sequence, Tuple

import hawt_msgs.msg
from hawt_msgs.msg import BladeLoads, ControllerState, ControlEvent, TurbineState
from hawt_msgs.msg import PlantDescription as PlantDescriptionMessage
from hawt_msgs.srv import SwitchControllers
from rclpy.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn

from hawt_controllers.ros.contribution_messages import from_message, message_type, to_message
from hawt_controllers.plugins.controller import (Contribution, Controller, ControllerFailure, contribution_topic,
                                                update_or_hold)
from hawt_controllers.plugins.registry import TYPE, controller_class, controller_types, node_parameters
from hawt_controllers.ros.switch_listener import SwitchListener
from hawt_controllers.plugins.switching import Switch, switch_effect
from hawt_core.command_interfaces import parse_interface
from hawt_core.parameter_table import ParameterError, check_values
from hawt_core.plant_description import PlantDescription
from hawt_core.step_sync import StepAnswer, StepJoin
from hawt_core.topics import (BLADE_LOADS, PLANT_DESCRIPTION, RECORDER_NODE, SWITCH_CONTROLLERS, TURBINE_STATE,
                              estimate_topic)
from hawt_node.events import EventPublisher
from hawt_node.node_main import run_node
from hawt_node.parameters import accepted, declare_parameters, rejection
from hawt_node.qos import CONTROL_LOOP, CONTROL_LOOP_HISTORY, LATCHED
from hawt_node.writer_matching import MatchedWriterGate

__all__ = ["ControllerNode", "main"]

_INPUT_TOPICS = {"blade_loads": (BladeLoads, BLADE_LOADS), "turbine_state": (TurbineState, TURBINE_STATE)}


class _Deferred(NamedTuple):
    """A step whose handover waits for the outgoing controller's output of the step before."""

    step: int
    header: Any
    loads: Any
    state: Any
    due: Sequence[Switch]


class _Answer:
    """The contributions a controller answered one step with (what a repeated step gets again)."""

    def __init__(self, step: int, header: Any, contributions: Sequence[Contribution]) -> None:
        self.step, self.header, self.contributions = step, header, tuple(contributions)


class ControllerNode(LifecycleNode):
    """Lifecycle node around one controller core of the type its ``type`` parameter names (module notes)."""

    def __init__(self, default_type: str = "", **node_kwargs) -> None:
        super().__init__(default_type or "controller", **node_kwargs)
        type_name = declare_parameters(self, (TYPE,))["type"] or default_type
        self.controller = controller_class(type_name)
        self.table = node_parameters(self.controller)
        self.values = {"type": type_name, **declare_parameters(self, self.table[1:])}
        self.name = self.get_fully_qualified_name()
        self.core: Optional[Controller] = None
        self.plant: Optional[PlantDescription] = None
        self.events = EventPublisher(self)
        self.pending: Optional[str] = None
        self.publish_until = -math.inf
        self.followed: Dict[str, Tuple[int, Contribution]] = {}
        self.deferred: Optional[_Deferred] = None
        self.refusing = False  # the last step's input was refused
        self.following: List[Any] = []
        self.made: List[Any] = []
        self.publishers_by_topic: Dict[str, Any] = {}
        self.estimate: Optional[Tuple[Any, MatchedWriterGate]] = None  # publisher and its gate
        self.switches: Optional[SwitchListener] = None
        self.internal = False
        self.announce_configured = True
        self.recorder = RECORDER_NODE if self.values["wait_for_recorder"] else None
        self.answer = StepAnswer(MatchedWriterGate(self, self.publishers_by_topic, self._publish, self.events,
                                                   recorder=self.recorder).send)
        self.join = StepJoin(self.controller.INPUTS)
        self.manager = self.create_client(SwitchControllers, SWITCH_CONTROLLERS)
        self.create_subscription(PlantDescriptionMessage, PLANT_DESCRIPTION, self._on_description, LATCHED)
        self.add_on_set_parameters_callback(self._check_parameters)
        self.add_post_set_parameters_callback(self._store_parameters)

    # --- lifecycle -------------------------------------------------------------------------------

    def _on_description(self, msg: PlantDescriptionMessage) -> None:
        if self.plant is not None:
            return
        self.plant = PlantDescription.from_fields(msg)
        # A controller that activates itself announces itself once, active: controller_manager plans a schedule
        # on the first state it hears, and an 'inactive' heard between the two once refused '-rosco' as already
        # inactive (a busy machine).
        self.announce_configured = not self.values["active"]
        configured = self.trigger_configure() == TransitionCallbackReturn.SUCCESS
        self.announce_configured = True
        if configured and self.values["active"]:
            self._switch_to(True, 0)

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Build the core from the parameters and the plant's description; FAILURE names what is wrong."""
        if self.plant is None:
            self.get_logger().error("configure: no plant/description yet (is the plant running?)")
            return TransitionCallbackReturn.FAILURE
        try:
            self.core = self.controller(self.values, self.plant)
        except ValueError as error:
            self.events(ControlEvent.ERROR, "invalid_parameter", f"{self.name}: {error}")
            return TransitionCallbackReturn.FAILURE
        claims = self.core.claims()
        for interface in claims:
            topic = parse_interface(interface).topic
            if topic not in self.publishers_by_topic:
                self.publishers_by_topic[topic] = self.create_publisher(message_type(interface), topic,
                                                                        CONTROL_LOOP_HISTORY)
        if self.controller.ESTIMATE is not None and self.estimate is None:
            kind, type_name = self.controller.ESTIMATE
            topic = estimate_topic(self.get_name(), kind)
            publisher = self.create_publisher(getattr(hawt_msgs.msg, type_name), topic, CONTROL_LOOP_HISTORY)
            self.estimate = publisher, MatchedWriterGate(self, {topic: publisher}, publisher.publish, self.events,
                                                         recorder=self.recorder)
        for name in self.controller.INPUTS:
            kind, topic = _INPUT_TOPICS[name]
            self.made.append(self.create_subscription(kind, topic, lambda m, n=name: self._input(n, m),
                                                      CONTROL_LOOP))
        if self.switches is None:
            self.switches = SwitchListener(self, self.controller.TYPE, claims, self.controller.SWITCHABLE)
        self._follow_others(True)
        if self.announce_configured:
            self.switches.announce(ControllerState.INACTIVE, self._last_step())
        return TransitionCallbackReturn.SUCCESS

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Destroy exactly what configure made; the controller is unconfigured."""
        for subscription in self.made:
            self.destroy_subscription(subscription)
        self.made = []
        self._follow_others(False)
        self.core = None
        if self.switches is not None:
            self.switches.announce(ControllerState.UNCONFIGURED, self._last_step())
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        if self.switches is not None:
            self.switches.announce(ControllerState.FINALIZED, self._last_step())
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._outside_transition("activate")

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._outside_transition("deactivate")

    def _outside_transition(self, kind: str) -> TransitionCallbackReturn:
        """A switch applies at once; a transition from outside asks controller_manager for a switch at a step."""
        if self.internal:
            return TransitionCallbackReturn.SUCCESS
        if not self.manager.service_is_ready():
            self.get_logger().error(f"{kind}: no controller_manager to switch at a plant step")
            return TransitionCallbackReturn.FAILURE
        request = SwitchControllers.Request(strictness=SwitchControllers.Request.STRICT, ramp_time=-1.0)
        setattr(request, kind, [self.name])
        self.manager.call_async(request).add_done_callback(lambda f: self._switch_answered(kind, f))
        return TransitionCallbackReturn.SUCCESS

    def _switch_answered(self, kind: str, future) -> None:
        """A refused outside transition goes back to the state the controller is in."""
        response = future.result()
        if response is not None and response.ok:
            self.get_logger().info(f"{kind}: {response.message}")
            return
        reason = response.message if response is not None else "no answer from controller_manager"
        self.events(ControlEvent.WARN, "switch_refused", f"{kind} refused: {reason}", step=self._last_step())
        self.internal = True
        try:
            (self.trigger_deactivate if kind == "activate" else self.trigger_activate)()
        finally:
            self.internal = False

    # --- switching ---------------------------------------------------------------------------------

    def _lifecycle_label(self) -> str:
        return self._state_machine.current_state[1]

    def _switch_to(self, active: bool, step: int, ramp_time: Optional[float] = None,
                   initial: Sequence[Contribution] = (), loads: Any = None, publish_until: float = math.inf) -> None:
        """Activate or deactivate the core and the lifecycle state at ``step``."""
        self.internal = True
        try:
            if active:
                self.core.on_activate(ramp_time, initial, loads)
                self.publish_until = math.inf
                if self._lifecycle_label() != "active":
                    self.trigger_activate()
            else:
                self.core.on_deactivate(ramp_time)
                self.publish_until = publish_until
                if self._lifecycle_label() == "active":
                    self.trigger_deactivate()
        finally:
            self.internal = False
        self._follow_others(not active)
        self.switches.announce(ControllerState.ACTIVE if active else ControllerState.INACTIVE, step)

    def _apply_switch(self, switch: Switch, step: int, stamp: Any, loads: Any) -> None:
        """Apply ``switch`` while handling ``step``; reported at the step it took effect, with a warning if after its
        own."""
        effect = switch_effect(switch, self.name, self.core.claims(), self.plant.dt)
        if effect is None:
            return
        at = step
        if not effect.active and effect.publish_until <= switch.step and self._last_step() < switch.step:
            # Handed over: from its step on nothing of this controller is used, so the plant does not wait for it and a
            # busy node may never see those steps. None of them answered here, the switch took effect at its step.
            at = switch.step
        late = f" (due at step {switch.step}, applied late)" if switch.step < at else ""
        if effect.active:
            initial = tuple(self.followed[t][1] for t in self._claimed_topics() if t in self.followed) \
                if effect.replaced else ()
            self._switch_to(True, at, effect.ramp_time, initial, loads)
            how = ("from the outgoing controller's last output" if initial
                   else f"ramping in over {effect.ramp_time:g} s")
            what = "activated"
        else:
            self._switch_to(False, at, effect.ramp_time, publish_until=effect.publish_until)
            how = "handing over" if effect.replaced else \
                f"ramping out over {switch.ramp_time:g} s until step {effect.publish_until}"
            what = "deactivated"
        self.events(ControlEvent.WARN if late else ControlEvent.INFO, "switch", f"{what} at step {at}, {how}{late}",
                    step=at, stamp=stamp)

    def _follow_others(self, follow: bool) -> None:
        """While inactive, remember the contributions another controller publishes on this one's interfaces."""
        if follow and not self.following and self.core is not None:
            for interface in self.core.claims():
                topic = parse_interface(interface).topic
                self.following.append(self.create_subscription(
                    message_type(interface), topic, lambda m, t=topic: self._follow(t, m), CONTROL_LOOP))
        elif not follow:
            for subscription in self.following:
                self.destroy_subscription(subscription)
            self.following = []

    def _follow(self, topic: str, msg: Any) -> None:
        if msg.step >= self.publish_until:
            self.followed[topic] = (msg.step, from_message(msg))
        if self.deferred is not None and not self._awaited_handover(self.deferred.step, self.deferred.due):
            self._finish_step(*self.deferred)

    def _claimed_topics(self) -> List[str]:
        """The contribution topics of the interfaces the core claims, in a fixed order."""
        return sorted({parse_interface(i).topic for i in self.core.claims()})

    def _awaited_handover(self, step: int, due: Sequence[Switch]) -> List[str]:
        """Topics whose outgoing contribution of step - 1 a replacing activation due at ``step`` still waits for."""
        claims = self.core.claims()
        handovers = [s for s in due if s.replaces(claims) and any(name == self.name for name, _ in s.activate)]
        topics = sorted({parse_interface(i).topic for i in claims if any(s.replaced(i) for s in handovers)})
        return [t for t in topics if self.followed.get(t, (-1, None))[0] < step - 1]

    # --- parameters --------------------------------------------------------------------------------

    def _check_parameters(self, changes):
        try:
            values = check_values(self.table, self.values, changes)
            if self.core is not None:
                self.core.check(values)
        except (ParameterError, ValueError) as error:
            return rejection(error)
        return accepted()

    def _store_parameters(self, changes) -> None:
        self.values = check_values(self.table, self.values, changes)
        self.pending = ", ".join(f"{p.name}={p.value}" for p in changes)

    # --- steps -------------------------------------------------------------------------------------

    def _last_step(self) -> int:
        return self.answer.last.step if self.answer.last is not None else 0

    def _input(self, name: str, msg: Any) -> None:
        if self.core is None or self.answer.handled(msg.step) \
                or (self.values["await_schedule"] and not self.switches.has_schedule):
            return  # (before the schedule: the plant resends the step until it is answered)
        if self.deferred is not None:
            if msg.step == self.deferred.step:
                return  # a resend of the step that waits for the handover
            waited = ", ".join(self._awaited_handover(self.deferred.step, self.deferred.due))
            self.events(ControlEvent.WARN, "switch", f"step {self.deferred.step}: taking over without the outgoing "
                        f"output of the step before on {waited} (not received)", step=self.deferred.step)
            self._finish_step(*self.deferred)
        inputs = self.join.add(name, msg.step, msg)
        if inputs is not None:
            self._step(msg.step, msg.header, inputs.get("blade_loads"), inputs.get("turbine_state"))

    def _step(self, step: int, header: Any, loads: Any, state: Any) -> None:
        if self.pending is not None:
            self.core.reconfigure(self.values)
            self.events(ControlEvent.INFO, "parameter_change", f"{self.pending} (from step {step})", step=step,
                        stamp=header.stamp)
            self.pending = None
        due = self.switches.due(step)
        if self._awaited_handover(step, due):
            # until _follow has the outgoing controller's output of step - 1
            self.deferred = _Deferred(step, header, loads, state, due)
            return
        self._finish_step(step, header, loads, state, due)

    def _finish_step(self, step: int, header: Any, loads: Any, state: Any, due: Sequence[Switch]) -> None:
        self.deferred = None
        for switch in due:
            self._apply_switch(switch, step, header.stamp, loads)
        held = self.answer.last.contributions if self.answer.last is not None else ()
        try:
            contributions, refusal = update_or_hold(self.core, step, loads, state, held)
        except ControllerFailure as failure:
            self.events(ControlEvent.ERROR, "controller_failed", f"step {step}: {failure}; no more output (the "
                        "plant's safety system takes over)", step=step, stamp=header.stamp)
            self.core = None  # answers no more steps
            return
        refused_before, self.refusing = self.refusing, refusal is not None
        if refusal is not None:
            if not refused_before:  # once per run of refused steps, as hawt run reports it
                self.events(ControlEvent.ERROR, "invalid_input", f"step {step}: {refusal}; "
                            + (self.core.WITHOUT_INPUT if held else "no output yet")
                            + " (reported at the first of consecutive refused steps)", step=step, stamp=header.stamp)
            if not held:
                return
        elif self.estimate is not None:
            publisher, gate = self.estimate
            message = publisher.msg_type(header=header, step=step)
            for name, value in self.core.estimate().items():
                setattr(message, name, value)
            gate.send(message)
        self.answer.send(_Answer(step, header, contributions), publish=step < self.publish_until)

    def _publish(self, answer: _Answer) -> None:
        for contribution in answer.contributions:
            self.publishers_by_topic[contribution_topic(contribution)].publish(
                to_message(contribution, answer.step, answer.header, self.name))


def main(args: Optional[List[str]] = None) -> None:
    """The ``controller`` executable and its aliases: an alias's name is its type
    (``ros2 run hawt_controllers ipc``)."""
    executable = Path(sys.argv[0]).name
    run_node(partial(ControllerNode, executable if executable in controller_types() else ""), args)


main.node_class = ControllerNode
