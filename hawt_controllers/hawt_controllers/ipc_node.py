"""The ``ipc`` node: one harmonic's individual pitch control in the non-rotating frame.

One process per harmonic (``ipc_h1``, ``ipc_h2``, … from this one executable):
``control/mbc/h{n}`` of step k in, ``control/ipc/h{n}`` of step k out. It never
needs the azimuth. The law is :class:`hawt_controllers.ipc.HarmonicIpc`; every
parameter can be set while running: a new value is checked (the whole
configuration is validated, so a NaN gain or an unstable filter is refused with
the reason), applied at the next step and reported on ``control/events``.

It is a lifecycle node (configured at start, then active or inactive). Its
transitions come from ``controller_manager`` switches and take effect at the
switch's plant step (hawt_controllers.switching): an active controller publishes
every step, a deactivated one publishes its ramp to zero and then falls silent,
and one that replaces another of its harmonic starts from the other's last output,
which it follows on ``control/ipc/h{n}`` while inactive. An incoming controller's
filters start settled at the moments of its first step: what it saw while inactive
depends on when its process started, and a lockstep run must not.
"""
import dataclasses
import math

from hawt_msgs.msg import ControllerState, ControlEvent, HarmonicLoads, HarmonicPitch
from rclpy.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn

from hawt_controllers.ipc import HarmonicIpc, HarmonicIpcConfig
from hawt_controllers.switch_listener import SwitchListener
from hawt_controllers.switching import Switch, ramp_steps
from hawt_tools.events import EventPublisher
from hawt_tools.node_main import node_entry_point
from hawt_tools.parameters import (ParameterError, ParameterSpec, accepted, check_values, declare_parameters,
                                   rejection)
from hawt_tools.qos import CONTROL_LOOP, CONTROL_LOOP_HISTORY
from hawt_tools.step_sync import StepAnswer
from hawt_tools.topics import ipc_topic, mbc_topic

__all__ = ["IpcNode", "PARAMETERS", "main"]

_DEFAULT = HarmonicIpcConfig(harmonic=1)

#: The law's parameters (HarmonicIpcConfig fields) and the node's own.
PARAMETERS = (
    ParameterSpec("harmonic", 1, "harmonic n this node controls", minimum=1, maximum=12, read_only=True),
    ParameterSpec("integral_gain", _DEFAULT.integral_gain, "k_i of both axes", "rad/(N*m*s)", minimum=0.0),
    ParameterSpec("proportional_gain", _DEFAULT.proportional_gain, "k_p of both axes", "rad/(N*m)", minimum=0.0),
    ParameterSpec("max_amplitude", _DEFAULT.max_amplitude, "limit of the demand's magnitude |(cos, sin)|", "rad",
                  minimum=0.0, maximum=0.5),
    ParameterSpec("phase_offset", _DEFAULT.phase_offset, "phase offset phi_n of the inverse transform", "rad",
                  minimum=-2 * math.pi, maximum=2 * math.pi),
    ParameterSpec("lowpass_order", _DEFAULT.lowpass_order, "order of the low-pass on the loads (0 = none)",
                  minimum=0, maximum=2),
    ParameterSpec("lowpass_corner_frequency", _DEFAULT.lowpass_corner_frequency, "low-pass corner", "rad/s",
                  minimum=0.0),
    ParameterSpec("lowpass_damping", _DEFAULT.lowpass_damping, "damping of the second-order low-pass", minimum=0.0),
    ParameterSpec("notch_frequency", _DEFAULT.notch_frequency, "notch frequency (0 = no notch)", "rad/s",
                  minimum=0.0),
    ParameterSpec("notch_beta_num", _DEFAULT.notch_beta_num, "notch numerator damping", minimum=0.0),
    ParameterSpec("notch_beta_den", _DEFAULT.notch_beta_den, "notch denominator damping", minimum=0.0),
    ParameterSpec("soft_start_begin", _DEFAULT.soft_start_begin,
                  "collective pitch where the gain ramp starts (both 0: no soft start)", "rad"),
    ParameterSpec("soft_start_end", _DEFAULT.soft_start_end, "collective pitch where the gain ramp ends", "rad"),
    ParameterSpec("schedule_breakpoints", [0.0], "collective pitches of the gain schedule (one value: none)", "rad"),
    ParameterSpec("schedule_factors", [1.0], "gain factors at the breakpoints"),
    ParameterSpec("ramp_time", _DEFAULT.ramp_time, "time to ramp the output in or out", "s", minimum=0.0,
                  maximum=600.0),
    ParameterSpec("min_pitch", 0.0, "lowest pitch: the demand is limited to the collective's headroom above it",
                  "rad", minimum=-0.5, maximum=1.6),
    ParameterSpec("dt", 0.01, "plant step", "s", minimum=1e-4, maximum=1.0, read_only=True),
    ParameterSpec("active", True, "state at start: active (ramps in over ramp_time) or inactive; later "
                  "switches come from controller_manager", read_only=True),
    ParameterSpec("ipc_harmonics", list(range(1, 13)), "harmonics whose IPC controllers start active (the "
                  "graph's ipc_harmonics, as mbc's): the node starts active only if its harmonic is listed",
                  read_only=True),
)

_LAW_FIELDS = tuple(f.name for f in dataclasses.fields(HarmonicIpcConfig))


def config_from(values) -> HarmonicIpcConfig:
    """The law's configuration from the node's parameter values (a one-value schedule means none)."""
    fields = {name: values[name] for name in _LAW_FIELDS if name in values}
    if len(fields["schedule_breakpoints"]) <= 1:
        fields["schedule_breakpoints"], fields["schedule_factors"] = (), ()
    else:
        fields["schedule_breakpoints"] = tuple(fields["schedule_breakpoints"])
        fields["schedule_factors"] = tuple(fields["schedule_factors"])
    return HarmonicIpcConfig(**fields)


class IpcNode(LifecycleNode):
    """Thin node around HarmonicIpc."""

    def __init__(self, **node_kwargs) -> None:
        super().__init__("ipc", **node_kwargs)
        self.values = declare_parameters(self, PARAMETERS)
        self.harmonic = self.values["harmonic"]
        self.dt = self.values["dt"]
        self.law = HarmonicIpc(config_from(self.values), self.dt)
        self.pending = None
        self.publish_until = -math.inf
        self.followed = None
        self.transition = None
        self.events = EventPublisher(self)
        self.answer = StepAnswer(
            self.create_publisher(HarmonicPitch, ipc_topic(self.harmonic), CONTROL_LOOP_HISTORY).publish)
        self.create_subscription(HarmonicLoads, mbc_topic(self.harmonic), self._on_loads, CONTROL_LOOP)
        self.following = None
        self.switches = SwitchListener(self, "ipc", self.harmonic)
        self.add_on_set_parameters_callback(self._check_parameters)
        self.add_post_set_parameters_callback(self._store_parameters)
        self.trigger_configure()
        if self.values["active"] and self.harmonic in self.values["ipc_harmonics"]:
            self._switch_to(True, step=0)
        else:
            self._follow_others(True)
            self.switches.announce(ControllerState.INACTIVE, 0)

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._transition_allowed()

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._transition_allowed()

    def _transition_allowed(self) -> TransitionCallbackReturn:
        """Transitions happen at a plant step through a controller_manager switch, never from outside."""
        if self.transition is None:
            self.get_logger().error("switch through controller_manager/switch_controllers (hawt switch): it "
                                    "changes controllers at one plant step")
            return TransitionCallbackReturn.FAILURE
        return TransitionCallbackReturn.SUCCESS

    def _switch_to(self, active: bool, step: int, ramp_time: float = None, initial=None,
                   publish_until: float = None) -> None:
        """Activate or deactivate the law and the lifecycle state at ``step``."""
        self.transition = active
        try:
            if active:
                self.law.activate(ramp_time, initial)
                self.publish_until = math.inf
                self.trigger_activate()
            else:
                self.law.deactivate(ramp_time)
                self.publish_until = publish_until
                self.trigger_deactivate()
        finally:
            self.transition = None
        self._follow_others(not active)
        self.switches.announce(ControllerState.ACTIVE if active else ControllerState.INACTIVE, step)

    def _apply_switch(self, switch: Switch, loads: HarmonicLoads) -> None:
        step, stamp = loads.step, loads.header.stamp
        late = f" (due at step {switch.step}, applied late)" if switch.step < step else ""
        replaced = switch.replaced(self.harmonic)
        if any(name == self.switches.name for name, _ in switch.activate):
            followed = self.followed if replaced else None
            initial = (followed.cos, followed.sin) if followed is not None else None
            fully_off = self.law.ramp == 0.0
            if (fully_off or initial is not None) and math.isfinite(loads.cos) and math.isfinite(loads.sin):
                self.law.reset(initial or (0.0, 0.0), moments=(loads.cos, loads.sin))
            self._switch_to(True, step, 0.0 if replaced else switch.ramp_time, initial)
            how = (f"from the outgoing controller's output of step {followed.step} ({followed.cos:.5f}, "
                   f"{followed.sin:.5f}) rad" if followed is not None else f"ramping in over {switch.ramp_time:g} s")
        else:
            end = switch.step + (0 if replaced else ramp_steps(switch.ramp_time, self.dt))
            self._switch_to(False, step, 0.0 if replaced else switch.ramp_time, publish_until=end)
            how = "handing over" if replaced else f"ramping out over {switch.ramp_time:g} s until step {end}"
        self.events(ControlEvent.WARN if late else ControlEvent.INFO, "switch",
                    f"{'activated' if self.publish_until == math.inf else 'deactivated'} at step {step}, "
                    f"{how}{late}", step=step, stamp=stamp)

    def _follow_others(self, follow: bool) -> None:
        """Listen to control/ipc/h{n} only while inactive (an active node would hear itself every step)."""
        if follow and self.following is None:
            self.following = self.create_subscription(HarmonicPitch, ipc_topic(self.harmonic), self._follow,
                                                      CONTROL_LOOP)
        elif not follow and self.following is not None:
            self.destroy_subscription(self.following)
            self.following = None

    def _follow(self, msg: HarmonicPitch) -> None:
        """Remember another controller's demand (a step this node is silent at): the start of a bumpless takeover."""
        if msg.step >= self.publish_until:
            self.followed = msg

    def _check_parameters(self, changes):
        try:
            values = check_values(PARAMETERS, self.values, changes)
            try:
                config_from(values).validate(self.dt)
            except ValueError as error:
                raise ParameterError(str(error)) from None
        except ParameterError as error:
            return rejection(error)
        return accepted()

    def _store_parameters(self, changes) -> None:
        self.values = check_values(PARAMETERS, self.values, changes)
        self.pending = ", ".join(f"{p.name}={p.value}" for p in changes)

    def _apply_pending(self, step: int, stamp) -> None:
        self.law.reconfigure(config_from(self.values))
        self.events(ControlEvent.INFO, "parameter_change", f"{self.pending} (from step {step})", step=step,
                    stamp=stamp)
        self.pending = None

    def _on_loads(self, msg: HarmonicLoads) -> None:
        if self.answer.handled(msg.step):
            return
        if self.pending is not None:
            self._apply_pending(msg.step, msg.header.stamp)
        for switch in self.switches.due(msg.step):
            self._apply_switch(switch, msg)
        if not all(math.isfinite(v) for v in (msg.cos, msg.sin, msg.collective_pitch)):
            self.events(ControlEvent.ERROR, "invalid_input", f"control/mbc/h{self.harmonic} step {msg.step}: "
                        f"cos={msg.cos}, sin={msg.sin}, collective_pitch={msg.collective_pitch}; demand held",
                        step=msg.step, stamp=msg.header.stamp)
            held = self.answer.last if self.answer.published else None
            out = HarmonicPitch(harmonic=self.harmonic, cos=held.cos if held else 0.0, sin=held.sin if held else 0.0,
                                phase_offset=self.values["phase_offset"])
        else:
            result = self.law.step(msg.cos, msg.sin, self.dt, operating_point=msg.collective_pitch,
                                   pitch_headroom=msg.collective_pitch - self.values["min_pitch"])
            out = HarmonicPitch(harmonic=self.harmonic, cos=result.cos, sin=result.sin,
                                phase_offset=result.phase_offset)
        out.step, out.header = msg.step, msg.header
        self.answer.send(out, publish=msg.step < self.publish_until)


main = node_entry_point(IpcNode)
