"""The ``mbc`` node: forward MBC transform of the blade loads, and the pitch command of every step.

Forward: each ``plant/blade_loads`` of step k gives ``control/mbc/h{n}`` for every
configured harmonic n (DESIGN.md §3). Return: the collective of step k plus the
remodulated demand of every active IPC harmonic, limited per blade in angle and
rate, is ``control/pitch_command`` of step k.

Lockstep waits for every input of step k: the loads, the collective and the
demand of every harmonic that has a publishing IPC controller at step k
(``ipc_harmonics`` at start, then as ``controller_manager`` switches say:
hawt_controllers.switching.HarmonicWindows). Realtime answers each collective
with the latest IPC demands at the azimuth extrapolated to the moment of sending.

An IPC controller that stops answering (its process died: no demand of the step
within ``input_timeout`` in lockstep, none for ``stale_steps`` in realtime) is
"lost": its last demand fades to zero over ``fade_time`` while the others go on,
the command is flagged FLAG_STALE_IPC and an ``ipc_lost`` event says so. When it
answers again (respawned) it is followed again (``ipc_returned``). A missing
collective is never skipped: without it the plant's safety system takes over.
"""
import math
import time

import numpy as np
from hawt_msgs.msg import BladeLoads, CollectivePitch, ControlEvent, HarmonicLoads, HarmonicPitch, PitchCommand
from rclpy.node import Node

from hawt_controllers.collective import DEFAULT_BASELINE_FILE, load_baseline_config
from hawt_controllers.limits import PitchLimits, limit_pitch
from hawt_controllers.mbc import check_configuration, mbc_forward, mbc_inverse
from hawt_controllers.switch_listener import SwitchListener
from hawt_controllers.switching import HarmonicWindows
from hawt_tools.events import EventPublisher
from hawt_tools.node_main import node_entry_point
from hawt_tools.parameters import (ParameterError, ParameterSpec, accepted, check_values, declare_parameters,
                                   rejection)
from hawt_tools.qos import CONTROL_LOOP, CONTROL_LOOP_HISTORY
from hawt_tools.step_sync import StepAnswer, StepJoin
from hawt_tools.topics import BLADE_LOADS, COLLECTIVE, PITCH_COMMAND, ipc_topic, mbc_topic

__all__ = ["MbcNode", "PARAMETERS", "main"]

_LIMITS = load_baseline_config(DEFAULT_BASELINE_FILE).pitch_limits

PARAMETERS = (
    ParameterSpec("blades", 3, "number of blades B", minimum=3, maximum=12, read_only=True),
    ParameterSpec("harmonics", [1, 2, 3], "harmonics n published on control/mbc/h{n}", read_only=True),
    ParameterSpec("ipc_harmonics", [0], "harmonics whose IPC controller is active at step 0 ([0]: none); "
                  "controller_manager switches change the set", read_only=True),
    ParameterSpec("dt", 0.01, "plant step", "s", minimum=1e-4, maximum=1.0, read_only=True),
    ParameterSpec("mode", "lockstep", "timing mode", choices=("lockstep", "realtime"), read_only=True),
    ParameterSpec("min_pitch", _LIMITS.min_angle, "lowest pitch command", "rad", minimum=-0.5, maximum=1.6),
    ParameterSpec("max_pitch", _LIMITS.max_angle, "highest pitch command", "rad", minimum=-0.5, maximum=1.6),
    ParameterSpec("max_pitch_rate", _LIMITS.max_rate, "largest pitch rate", "rad/s", minimum=1e-3, maximum=1.0),
    ParameterSpec("stale_steps", 5, "realtime: an IPC controller whose newest demand is older than this many "
                  "steps is lost", minimum=1, maximum=1000),
    ParameterSpec("input_timeout", 1.0, "lockstep: an IPC controller that has not answered the step this long "
                  "(wall clock) after the plant's loads is lost (keep it below the plant's command_timeout; a "
                  "busy machine can delay a live node by a fraction of a second)", "s", minimum=0.01,
                  maximum=60.0),
    ParameterSpec("fade_time", 2.0, "time over which a lost controller's last demand fades to zero", "s",
                  minimum=0.0, maximum=600.0),
    ParameterSpec("latency", 0.0, "realtime: extra time the command takes to reach the plant, added to the "
                  "azimuth extrapolation", "s", minimum=0.0, maximum=0.1),
)


def _active(harmonics) -> tuple:
    return tuple(n for n in harmonics if n > 0)


class MbcNode(Node):
    """Thin node around hawt_controllers.mbc and hawt_controllers.limits."""

    def __init__(self, **node_kwargs) -> None:
        super().__init__("mbc", **node_kwargs)
        self.values = declare_parameters(self, PARAMETERS)
        self.blades = self.values["blades"]
        for n in (*self.values["harmonics"], *_active(self.values["ipc_harmonics"])):
            check_configuration(n, self.blades)
        self.limits = self._limits(self.values)
        self.events = EventPublisher(self)
        self.forward = {n: self.create_publisher(HarmonicLoads, mbc_topic(n), CONTROL_LOOP_HISTORY)
                        for n in self.values["harmonics"]}
        self.answer = StepAnswer(self.create_publisher(PitchCommand, PITCH_COMMAND, CONTROL_LOOP_HISTORY).publish)
        self.lockstep = self.values["mode"] == "lockstep"
        self.join = StepJoin(())
        self.demands = {}
        self.ipc_subscriptions = {}
        self.windows = HarmonicWindows(_active(self.values["ipc_harmonics"]), self.values["dt"])
        self.lost = {}
        self.switches = SwitchListener(self)
        self._follow_windows(0)
        if self.lockstep:
            self.create_timer(0.05, self._watch_inputs)
        self.loads: BladeLoads = None
        self.loads_received = 0.0
        self.create_subscription(BladeLoads, BLADE_LOADS, self._on_loads, CONTROL_LOOP)
        self.create_subscription(CollectivePitch, COLLECTIVE, lambda m: self._input("collective", m), CONTROL_LOOP)
        self.add_on_set_parameters_callback(self._check_parameters)
        self.add_post_set_parameters_callback(self._apply_parameters)

    @staticmethod
    def _limits(values) -> PitchLimits:
        return PitchLimits(values["min_pitch"], values["max_pitch"], values["max_pitch_rate"])

    def _check_parameters(self, changes):
        try:
            values = check_values(PARAMETERS, self.values, changes)
            self._limits(values).validate()
        except (ParameterError, ValueError) as error:
            return rejection(error)
        return accepted()

    def _apply_parameters(self, changes) -> None:
        self.values = check_values(PARAMETERS, self.values, changes)
        self.limits = self._limits(self.values)
        self.events(ControlEvent.INFO, "parameter_change",
                    ", ".join(f"{p.name}={p.value}" for p in changes), step=self.join.step or 0)

    def _follow_windows(self, step: int):
        """Subscribe to every harmonic a controller may publish; require those publishing at ``step`` and not
        lost. Returns the step's inputs if that change completes them (StepJoin.set_required), else None."""
        for n in self.windows.harmonics():
            if n not in self.ipc_subscriptions:
                self.ipc_subscriptions[n] = self.create_subscription(
                    HarmonicPitch, ipc_topic(n), lambda m, n=n: self._input(f"h{n}", m), CONTROL_LOOP)
        return self.join.set_required(
            {"loads", "collective", *(f"h{n}" for n in self.windows.publishing(step) if n not in self.lost)}
            if self.lockstep else {"collective"})

    def _lose(self, harmonic: int, step: int, why: str) -> None:
        """Fade out a controller that stopped answering, from its last demand."""
        self.lost[harmonic] = (self.demands.get(harmonic), step)
        self.events(ControlEvent.WARN, "ipc_lost", f"control/ipc/h{harmonic}: {why}; its last demand fades out "
                    f"over {self.values['fade_time']:g} s, the other harmonics go on", step=step)

    def _watch_inputs(self) -> None:
        """Lockstep: give up on IPC demands of the pending step after input_timeout."""
        inputs = self.join.inputs
        if self.loads is None or self.join.step != self.loads.step or "collective" not in inputs:
            return  # no step pending, or its collective is missing (never skipped: the plant's safety system acts)
        if self.answer.last is not None and self.answer.last.step >= self.loads.step:
            return
        if time.monotonic() - self.loads_received < self.values["input_timeout"]:
            return
        missing = [n for n in self.windows.publishing(self.loads.step)
                   if f"h{n}" not in inputs and n not in self.lost]
        for n in missing:
            self._lose(n, self.loads.step, f"no demand for step {self.loads.step} within "
                                           f"{self.values['input_timeout']:g} s")
        complete = self._follow_windows(self.loads.step)
        if complete is not None:
            self._command(complete["collective"])

    def _on_loads(self, msg: BladeLoads) -> None:
        oop = np.asarray(msg.root_moment_oop)
        if oop.shape != (self.blades,) or len(msg.pitch) != self.blades or not np.all(np.isfinite(oop)) \
                or not math.isfinite(msg.azimuth):
            self.events(ControlEvent.ERROR, "invalid_input",
                        f"plant/blade_loads step {msg.step}: expected {self.blades} finite moments and pitches, "
                        f"got {list(msg.root_moment_oop)} / {list(msg.pitch)}", step=msg.step, stamp=msg.header.stamp)
            return
        if self.loads is None or msg.step != self.loads.step:  # a resent step keeps its first arrival time
            self.loads_received = time.monotonic()
        self.loads = msg
        for switch in self.switches.due(msg.step):
            try:
                for n in {n for _, n in switch.activate if n > 0}:
                    check_configuration(n, self.blades)
                self.windows.apply(switch)
            except ValueError as error:
                self.events(ControlEvent.ERROR, "switch", f"switch of step {switch.step} not followed: {error}",
                            step=msg.step, stamp=msg.header.stamp)
        complete = self._follow_windows(msg.step)
        collective_pitch = float(np.mean(msg.pitch))
        for n, publisher in self.forward.items():
            components = mbc_forward(oop, msg.azimuth, n)
            out = HarmonicLoads(step=msg.step, harmonic=n, azimuth=msg.azimuth, rotor_speed=msg.rotor_speed,
                                cos=float(components.cos), sin=float(components.sin), mean=float(components.mean),
                                collective_pitch=collective_pitch)
            out.header = msg.header
            publisher.publish(out)
        if complete is not None:
            self._command(complete["collective"])
        self._input("loads", msg)

    def _input(self, name: str, msg) -> None:
        if name.startswith("h"):
            self.demands[msg.harmonic] = msg
            if msg.harmonic in self.lost:
                del self.lost[msg.harmonic]
                self.events(ControlEvent.INFO, "ipc_returned", f"control/ipc/h{msg.harmonic} answers again from "
                            f"step {msg.step}", step=msg.step)
            if not self.lockstep:
                return  # realtime: a demand waits for the next collective (no repeated command per demand)
        if self.answer.handled(msg.step) or self.loads is None:
            return
        inputs = self.join.add(name, msg.step, msg)
        if inputs is not None:
            self._command(inputs["collective"])

    def _command(self, collective: CollectivePitch) -> None:
        loads, flags = self.loads, 0
        azimuth = loads.azimuth
        if not self.lockstep:
            azimuth += loads.rotor_speed * (time.monotonic() - self.loads_received + self.values["latency"])
        individual = np.zeros(self.blades)
        for n in self.windows.publishing(collective.step):
            demand, fade = self.demands.get(n), 1.0
            if n not in self.lost and not self.lockstep and demand is not None \
                    and collective.step - demand.step > self.values["stale_steps"]:
                self._lose(n, collective.step, f"no demand for {collective.step - demand.step} steps")
            if n in self.lost:
                demand, since = self.lost[n]
                fade = max(0.0, 1.0 - (collective.step - since) * self.values["dt"] / self.values["fade_time"]) \
                    if self.values["fade_time"] > 0 else 0.0
                flags |= PitchCommand.FLAG_STALE_IPC
            if demand is None or not (math.isfinite(demand.cos) and math.isfinite(demand.sin)):
                flags |= PitchCommand.FLAG_STALE_IPC
                continue
            individual += fade * mbc_inverse(demand.cos, demand.sin, azimuth, n, self.blades, demand.phase_offset)
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
        limited = limit_pitch(collective.pitch + individual, previous, self.values["dt"], self.limits)
        msg = PitchCommand(step=collective.step, pitch=limited.pitch.tolist(),
                           generator_torque=collective.generator_torque, collective=collective.pitch,
                           individual=(limited.pitch - collective.pitch).tolist(), flags=flags | int(limited.flags))
        msg.header = collective.header
        self.answer.send(msg)


main = node_entry_point(MbcNode)
