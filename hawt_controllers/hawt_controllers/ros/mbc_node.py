"""The ``mbc`` node: the loop assembler of the ROS graph, ``control/pitch_command`` of every step.

Every controller's contribution of step k — the collective, each ``harmonic/<n>`` demand,
the ``blade_pitch`` increments — goes into the command of step k through
:class:`hawt_controllers.plugins.loop_assembly.LoopAssembler` (the same core the in-process
runner uses). The node learns which interfaces exist from the controllers' own
announcements and from the switches (``controller_manager/controllers``,
``controller_manager/switch``), so a new controller type needs no change here. It also
publishes the forward transform of the blade loads for the ``harmonics`` it is given
(``control/mbc/h{n}``, for watching; controllers transform the loads themselves).

Lockstep waits for every input of step k: the loads, the collective and the contribution
of every interface that has a publishing controller at step k (controllers active at the
start, then as switches say: hawt_controllers.plugins.switching.InterfaceWindows). So that the
first steps are the same in every run, no step is answered before every controller
named in ``controllers`` has announced itself and, with ``await_schedule``, before
controller_manager's schedule has arrived (so a scheduled switch is never late).
Realtime answers each collective with the latest contributions at the azimuth
extrapolated to the moment of sending.

A contributor that stops answering (its process died: nothing for step k within
``input_timeout`` in lockstep — ``start_timeout`` for the first step, while nodes still start —,
nothing for ``stale_steps`` in realtime) is "lost": its last
contribution fades to zero over ``fade_time`` while the others go on, the command is
flagged FLAG_STALE_IPC and a ``contribution_lost`` event says so; when it answers again
(respawned) it is followed again (``contribution_returned``). A missing collective is never
skipped: without it the plant's safety system takes over.

Authority: a contribution topic is read only from its claimants, the controllers that have
announced an interface on it (``controller_manager/controllers``), and from the controllers the
graph names in ``controllers`` (their first contributions may overtake their announcements on a
busy machine); which of them contributes at a step is then the switches' business. Each
message's publisher is identified by its GID and named through the ROS graph
(hawt_node.command_senders, as the plant does for its commands); a message from any other
publisher is refused before it is read, the first from each is an ``intruder`` event. A
message whose sender has not announced itself yet waits for it (at most
hawt_node.command_senders.ANNOUNCE_GRACE).
"""
import math
import time
from typing import Any, Dict, Optional, Set

import numpy as np
from hawt_msgs.msg import BladeLoads, CollectivePitch, ControllerState, ControlEvent, HarmonicLoads, PitchCommand
from hawt_msgs.msg import PlantDescription as PlantDescriptionMessage
from rclpy.node import Node

from hawt_controllers.ros.contribution_messages import from_message, message_type
from hawt_controllers.laws.limits import NO_NARROWING
from hawt_controllers.plugins.loop_assembly import (LIMIT_PARAMETER, PARAMETERS, LoopAssembler, assembly_problem,
                                                     extrapolated_azimuth, fade_factor, pitch_limits,
                                                     requested_limits, turbine_limits)
from hawt_core.rotor.mbc import check_configuration, mbc_forward
from hawt_controllers.ros.switch_listener import SwitchListener
from hawt_controllers.plugins.switching import InterfaceWindows
from hawt_core.command_interfaces import parse_interface
from hawt_core.parameter_table import ParameterError, check_values
from hawt_core.plant_description import PlantDescription
from hawt_core.step_sync import StepAnswer, StepJoin
from hawt_core.topics import (BLADE_LOADS, COLLECTIVE, CONTROLLER_STATES, PITCH_COMMAND, PLANT_DESCRIPTION,
                              RECORDER_NODE, mbc_topic)
from hawt_node.command_senders import GuardedSubscription, Sample
from hawt_node.events import EventPublisher
from hawt_node.node_main import node_entry_point
from hawt_node.parameters import accepted, declare_parameters, rejection
from hawt_node.qos import CONTROL_LOOP, CONTROL_LOOP_HISTORY, LATCHED
from hawt_node.writer_matching import MatchedWriterGate

__all__ = ["MbcNode", "main"]


class MbcNode(Node):
    """Thin node around hawt_controllers.plugins.loop_assembly (module notes)."""

    PARAMETERS = PARAMETERS

    def __init__(self, **node_kwargs) -> None:
        super().__init__("mbc", **node_kwargs)
        self.values = declare_parameters(self, PARAMETERS)
        self.expected = {name.strip("/").rsplit("/", 1)[-1] for name in self.values["controllers"] if name.strip()}
        self.announced: Set[str] = set()
        self.events = EventPublisher(self)
        self.assembler: Optional[LoopAssembler] = None
        self.plant: Optional[PlantDescription] = None
        self.forward = {}
        command = self.create_publisher(PitchCommand, PITCH_COMMAND, CONTROL_LOOP_HISTORY)
        recorder = RECORDER_NODE if self.values["wait_for_recorder"] else None
        self.answer = StepAnswer(MatchedWriterGate(self, {PITCH_COMMAND: command}, command.publish, self.events,
                                                   recorder=recorder).send)
        self.lockstep = self.values["mode"] == "lockstep"
        self.join = StepJoin(())
        self.demands: Dict[str, Any] = {}
        self.subscribed: Dict[str, GuardedSubscription] = {}
        self.claimants: Dict[str, Set[str]] = {}
        self.windows = InterfaceWindows((), 1.0)
        self.lost: Dict[str, tuple] = {}
        self.loads: Optional[BladeLoads] = None
        self.loads_received = 0.0
        self.switches = SwitchListener(self)
        self._subscribe(COLLECTIVE, CollectivePitch)
        if self.lockstep:
            self.create_timer(0.05, self._watch_inputs)
        self.create_subscription(PlantDescriptionMessage, PLANT_DESCRIPTION, self._on_description, LATCHED)
        self.create_subscription(ControllerState, CONTROLLER_STATES, self._on_controller, LATCHED)
        self.create_subscription(BladeLoads, BLADE_LOADS, self._on_loads, CONTROL_LOOP)
        self.add_on_set_parameters_callback(self._check_parameters)
        self.add_post_set_parameters_callback(self._apply_parameters)

    def _on_description(self, msg: PlantDescriptionMessage) -> None:
        if self.plant is not None:
            return
        self.plant = PlantDescription.from_fields(msg)
        for n in self.values["harmonics"]:
            if n > 0:
                check_configuration(n, self.plant.blades)
                self.forward[n] = self.create_publisher(HarmonicLoads, mbc_topic(n), CONTROL_LOOP_HISTORY)
        requested = requested_limits(self.values)
        beyond = {name: text for name, text in requested.widening(turbine_limits(self.plant)).items()
                  if getattr(requested, name) != getattr(NO_NARROWING, name)}
        if beyond:
            self.events(ControlEvent.WARN, "parameter_change", "; ".join(
                f"{LIMIT_PARAMETER[name]} {text}: the turbine's applies" for name, text in beyond.items()))
        self.assembler = LoopAssembler(self.plant.blades, pitch_limits(self.values, self.plant), self.plant.dt)
        self.windows.dt = self.plant.dt

    def _on_controller(self, msg: ControllerState) -> None:
        """A controller's announcement: subscribe to what it claims; one active from step 0 contributes from 0."""
        self.announced.add(msg.name.rsplit("/", 1)[-1])
        for interface in msg.interfaces:
            topic = parse_interface(interface).topic
            self.claimants.setdefault(topic, set()).add(msg.name)
            self._subscribe(topic, message_type(interface))
            self.subscribed[topic].allow(self._allowed(topic))
        if msg.state == ControllerState.ACTIVE and msg.step == 0:
            self.windows.start(msg.interfaces)

    def _subscribe(self, topic: str, kind: type) -> None:
        """Follow a contribution topic, taking only its claimants' messages (the module notes' authority)."""
        if topic not in self.subscribed:
            self.subscribed[topic] = GuardedSubscription(
                self, kind, topic, CONTROL_LOOP, self._allowed(topic),
                lambda m, t=topic: self._input(t, m), lambda sample, t=topic: self._report_intruder(t, sample),
                wait_for_allowed=True)

    def _allowed(self, topic: str) -> list:
        """Who may contribute on ``topic``: its claimants so far and the graph's own controllers (``controllers``),
        whose first contributions may overtake their announcements on a busy machine."""
        return sorted(self.claimants.get(topic, set()) | self.expected)

    def _report_intruder(self, topic: str, sample: Sample) -> None:
        """The first contribution of a publisher that is not a claimant of ``topic`` (the guard counts the rest)."""
        claimants = ", ".join(sorted(self.subscribed[topic].allowed)) or "no controller"
        self.events(ControlEvent.ERROR, "intruder", f"{topic} step {sample.message.step} from {sample.who} refused: "
                    f"only {claimants} claim it (its later messages are refused and counted)",
                    step=self.loads.step if self.loads is not None else 0)

    def destroy_node(self) -> None:
        for guard in self.subscribed.values():
            guard.close()
        super().destroy_node()

    def _check_parameters(self, changes):
        try:
            requested = requested_limits(check_values(PARAMETERS, self.values, changes))
            if self.plant is not None:
                turbine, changed = turbine_limits(self.plant), {change.name for change in changes}
                beyond = {name: text for name, text in requested.widening(turbine).items()
                          if LIMIT_PARAMETER[name] in changed}
                if beyond:
                    raise ParameterError(", ".join(f"{LIMIT_PARAMETER[name]} {text}" for name, text in beyond.items())
                                         + ": the loop assembler may narrow the turbine's pitch limits, never widen "
                                           "them")
                requested.within(turbine)  # something left between floor and ceiling
        except (ParameterError, ValueError) as error:
            return rejection(error)
        return accepted()

    def _apply_parameters(self, changes) -> None:
        self.values = check_values(PARAMETERS, self.values, changes)
        if self.assembler is not None:
            self.assembler.limits = pitch_limits(self.values, self.plant)
        self.events(ControlEvent.INFO, "parameter_change",
                    ", ".join(f"{p.name}={p.value}" for p in changes), step=self.join.step or 0)

    def _publishing_topics(self, step: int) -> Set[str]:
        """Contribution topics whose contribution of ``step`` comes from a controller (the collective always)."""
        return {COLLECTIVE, *(parse_interface(i).topic for i in self.windows.publishing(step))}

    def _require(self, step: int) -> Optional[dict]:
        """Require the inputs of ``step``; the step's inputs if that change completes them (StepJoin.set_required)."""
        if not self.lockstep:
            return self.join.set_required({COLLECTIVE})
        return self.join.set_required({"loads", *(t for t in self._publishing_topics(step) if t not in self.lost)})

    def _lose(self, topic: str, step: int, why: str) -> None:
        """Fade out a contributor that stopped answering, from its last contribution."""
        self.lost[topic] = (self.demands.get(topic), step)
        self.events(ControlEvent.WARN, "contribution_lost", f"{topic}: {why}; its last contribution fades out over "
                    f"{self.values['fade_time']:g} s, the others go on", step=step)

    def _watch_inputs(self) -> None:
        """Lockstep: give up on contributions of the pending step after input_timeout."""
        inputs = self.join.inputs
        if self.loads is None or self.join.step != self.loads.step or COLLECTIVE not in inputs:
            return  # no step pending, or its collective is missing (never skipped: the plant's safety system acts)
        if self.answer.last is not None and self.answer.last.step >= self.loads.step:
            return
        # before the first command the nodes are still starting (discovery, the schedule): start_timeout, as the
        # plant waits startup_timeout for its first command
        timeout = self.values["input_timeout" if self.answer.last is not None else "start_timeout"]
        if time.monotonic() - self.loads_received < timeout:
            return
        for topic in sorted(self._publishing_topics(self.loads.step) - inputs.keys() - self.lost.keys()):
            self._lose(topic, self.loads.step, f"nothing for step {self.loads.step} within {timeout:g} s")
        complete = self._require(self.loads.step)
        if complete is not None:
            self._command(complete[COLLECTIVE])

    def _on_loads(self, msg: BladeLoads) -> None:
        if self.assembler is None or not self.expected <= self.announced \
                or (self.values["await_schedule"] and not self.switches.has_schedule):
            return  # the plant resends the step until it is answered
        oop = np.asarray(msg.root_moment_oop)
        if oop.shape != (self.plant.blades,) or len(msg.pitch) != self.plant.blades \
                or not math.isfinite(msg.azimuth):
            self.events(ControlEvent.ERROR, "invalid_input",
                        f"plant/blade_loads step {msg.step}: expected {self.plant.blades} moments and pitches and a "
                        f"finite azimuth, got {list(msg.root_moment_oop)} / {list(msg.pitch)} / {msg.azimuth}",
                        step=msg.step, stamp=msg.header.stamp)
            return
        if self.loads is None or msg.step != self.loads.step:  # a resent step keeps its first arrival time
            self.loads_received = time.monotonic()
        self.loads = msg
        for switch in self.switches.due(msg.step):
            incoming = [i for _, claims in switch.activate for i in claims]
            problems = [p for p in (assembly_problem(i, self.plant.blades) for i in incoming) if p]
            if problems:
                self.events(ControlEvent.ERROR, "switch", f"switch of step {switch.step} not followed: {problems[0]}",
                            step=msg.step, stamp=msg.header.stamp)
                continue
            for interface in incoming:
                self._subscribe(parse_interface(interface).topic, message_type(interface))
            self.windows.apply(switch)
        complete = self._require(msg.step)
        # The command needs only the azimuth: a dead load sensor (NaN) leaves the IPC controllers to fade out
        # (issue 34) and only the watched transform out.
        for n, publisher in (self.forward.items() if np.all(np.isfinite(oop)) else ()):
            components = mbc_forward(oop, msg.azimuth, n)
            out = HarmonicLoads(step=msg.step, harmonic=n, azimuth=msg.azimuth, rotor_speed=msg.rotor_speed,
                                cos=float(components.cos), sin=float(components.sin), mean=float(components.mean),
                                collective_pitch=float(np.mean(msg.pitch)))
            out.header = msg.header
            publisher.publish(out)
        if complete is not None:
            self._command(complete[COLLECTIVE])
        self._input("loads", msg)

    def _input(self, name: str, msg) -> None:
        if name not in ("loads", COLLECTIVE):
            self.demands[name] = msg
            if name in self.lost:
                del self.lost[name]
                self.events(ControlEvent.INFO, "contribution_returned", f"{name} answers again from step {msg.step}",
                            step=msg.step)
            if not self.lockstep:
                return  # realtime: a contribution waits for the next collective (one command per step)
        if self.answer.handled(msg.step) or self.loads is None:
            return
        inputs = self.join.add(name, msg.step, msg)
        if inputs is not None:
            self._command(inputs[COLLECTIVE])

    def _contributions(self, step: int) -> tuple:
        """(contribution, weight) of every publishing contributor at ``step``, and the FLAG_STALE_IPC bit if any is
        lost or not finite."""
        weighted, flags = [], 0
        for topic in sorted(self._publishing_topics(step) - {COLLECTIVE}):
            demand, weight = self.demands.get(topic), 1.0
            if topic not in self.lost and not self.lockstep and demand is not None \
                    and step - demand.step > self.values["stale_steps"]:
                self._lose(topic, step, f"nothing for {step - demand.step} steps")
            if topic in self.lost:
                demand, since = self.lost[topic]
                weight = fade_factor(step - since, self.plant.dt, self.values["fade_time"])
                flags |= PitchCommand.FLAG_STALE_IPC
            contribution = from_message(demand) if demand is not None else None
            if contribution is None or not contribution.finite():
                flags |= PitchCommand.FLAG_STALE_IPC
                continue
            weighted.append((contribution, weight))
        return weighted, flags

    def _command(self, collective: CollectivePitch) -> None:
        loads = self.loads
        azimuth = loads.azimuth if self.lockstep else extrapolated_azimuth(
            loads.azimuth, loads.rotor_speed, time.monotonic() - self.loads_received + self.values["latency"])
        contributions, flags = self._contributions(collective.step)
        if not (math.isfinite(collective.pitch) and math.isfinite(collective.generator_torque)):
            self.events(ControlEvent.ERROR, "invalid_input",
                        f"control/collective step {collective.step}: pitch {collective.pitch}, torque "
                        f"{collective.generator_torque} not finite; command held", step=collective.step)
            if self.answer.last is None:
                return
            collective = CollectivePitch(pitch=self.answer.last.collective,
                                         generator_torque=self.answer.last.generator_torque,
                                         step=collective.step, header=collective.header)
            flags |= PitchCommand.FLAG_INVALID_INPUT
        previous = np.asarray(self.answer.last.pitch if self.answer.last is not None else loads.pitch)
        try:
            command = self.assembler.assemble(collective.pitch, contributions, azimuth, previous)
        except ValueError as error:
            self.events(ControlEvent.ERROR, "invalid_input", f"step {collective.step}: {error}; contributions "
                        "left out", step=collective.step)
            command = self.assembler.assemble(collective.pitch, (), azimuth, previous)
            flags |= PitchCommand.FLAG_INVALID_INPUT
        msg = PitchCommand(step=collective.step, pitch=command.pitch.tolist(),
                           generator_torque=collective.generator_torque, collective=collective.pitch,
                           individual=command.individual.tolist(), flags=flags | int(command.flags))
        msg.header = collective.header
        self.answer.send(msg)


main = node_entry_point(MbcNode)
