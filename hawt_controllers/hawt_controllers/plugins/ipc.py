"""The ``ipc`` controller: one harmonic's individual pitch control in the non-rotating frame.

Claims ``harmonic/<n>``. Each step it transforms the blade-root out-of-plane moments
to harmonic n (:func:`hawt_core.rotor.mbc.mbc_forward_sample`, DESIGN §3) and steps the law
:class:`hawt_controllers.laws.ipc.HarmonicIpc` on them, with the mean measured pitch as the
operating point of its soft start and gain schedule and the headroom above
``min_pitch`` as an extra amplitude limit (ROSCO ``IPC_SatMode = 2``). The loop
assembler remodulates the demand at each blade's azimuth with φ_n.

Moments that are not finite (a dead blade-root load sensor, issue 34) are refused as input, and the
demand then fades out over ``ramp_time`` rather than holding its last value (:meth:`HarmonicIpc.hold`:
filters and integrator hold), and fades back in once the moments are finite again.

Bumpless switching: an incoming controller's filters start settled at the moments of
its first step, and one that replaces another on ``harmonic/<n>`` starts from the other's
last output (van Engelen 2006 §3.4; anchor_ros2 §3.3).
"""
from __future__ import annotations

import dataclasses
import math
from typing import Any, Mapping, Optional, Sequence, Tuple

from hawt_core.command_interfaces import harmonic_interface
from hawt_core.parameter_table import ParameterError, ParameterSpec, resolve_values
from hawt_core.plant_description import PlantDescription

from hawt_controllers.plugins.controller import Contribution, Controller, HarmonicContribution, mean_pitch
from hawt_controllers.laws.limits import NO_NARROWING
from hawt_controllers.laws.ipc import HarmonicIpc, HarmonicIpcConfig
from hawt_core.rotor.mbc import check_configuration, mbc_forward_sample

__all__ = ["HarmonicIpcController", "config_from"]

_DEFAULT = HarmonicIpcConfig(harmonic=1)
_LAW_FIELDS = tuple(f.name for f in dataclasses.fields(HarmonicIpcConfig))


def config_from(values: Mapping[str, Any]) -> HarmonicIpcConfig:
    """The law's configuration from parameter values (a one-value schedule means none)."""
    fields = {name: values[name] for name in _LAW_FIELDS if name in values}
    if len(fields["schedule_breakpoints"]) <= 1:
        fields["schedule_breakpoints"], fields["schedule_factors"] = (), ()
    else:
        fields["schedule_breakpoints"] = tuple(fields["schedule_breakpoints"])
        fields["schedule_factors"] = tuple(fields["schedule_factors"])
    return HarmonicIpcConfig(**fields)


MAX_FILTER_FREQUENCY = 250.0
"""Highest filter frequency a parameter may set [rad/s]: the Nyquist frequency of an 80 Hz loop."""
MAX_FILTER_DAMPING = 10.0
"""Highest filter damping ratio a parameter may set: ten times critical."""

MAX_GAIN = 1e-5
"""Largest IPC gain a parameter may set [rad/(N*m*s), rad/(N*m)]: the NREL 5 MW's designed k_i is about 1.2e-8 (a
0.09 rad/s crossover on its ~1e7 N*m/rad 1P plant gain), so 1e-5 is three decades beyond any design for a multi-MW
rotor."""


class HarmonicIpcController(Controller):
    """One harmonic's IPC as a plug-in (see the module notes)."""

    TYPE = "ipc"
    WITHOUT_INPUT = "output fading out over its ramp time"
    PARAMETERS = (
        ParameterSpec("harmonic", 1, "harmonic n this controller acts on", minimum=1, maximum=12, read_only=True),
        ParameterSpec("integral_gain", _DEFAULT.integral_gain, "k_i of both axes (at most 1e-5: a thousand times "
                      "the NREL 5 MW's design, a loop crossover far beyond the rotor's bandwidth)", "rad/(N*m*s)",
                      minimum=0.0, maximum=MAX_GAIN),
        ParameterSpec("proportional_gain", _DEFAULT.proportional_gain, "k_p of both axes (at most 1e-5)", "rad/(N*m)",
                      minimum=0.0, maximum=MAX_GAIN),
        ParameterSpec("max_amplitude", _DEFAULT.max_amplitude, "limit of the demand's magnitude |(cos, sin)|",
                      "rad", minimum=0.0, maximum=0.5),
        ParameterSpec("phase_offset", _DEFAULT.phase_offset, "phase offset phi_n of the inverse transform", "rad",
                      minimum=-2 * math.pi, maximum=2 * math.pi),
        ParameterSpec("lowpass_order", _DEFAULT.lowpass_order, "order of the low-pass on the loads (0 = none)",
                      minimum=0, maximum=2),
        ParameterSpec("lowpass_corner_frequency", _DEFAULT.lowpass_corner_frequency, "low-pass corner (below the "
                      "Nyquist frequency of an 80 Hz loop)", "rad/s", minimum=0.0, maximum=MAX_FILTER_FREQUENCY),
        ParameterSpec("lowpass_damping", _DEFAULT.lowpass_damping, "damping of the second-order low-pass",
                      minimum=0.0, maximum=MAX_FILTER_DAMPING),
        ParameterSpec("notch_frequency", _DEFAULT.notch_frequency, "notch frequency (0 = no notch)", "rad/s",
                      minimum=0.0, maximum=MAX_FILTER_FREQUENCY),
        ParameterSpec("notch_beta_num", _DEFAULT.notch_beta_num, "notch numerator damping", minimum=0.0,
                      maximum=MAX_FILTER_DAMPING),
        ParameterSpec("notch_beta_den", _DEFAULT.notch_beta_den, "notch denominator damping", minimum=0.0,
                      maximum=MAX_FILTER_DAMPING),
        ParameterSpec("soft_start_begin", _DEFAULT.soft_start_begin,
                      "collective pitch where the gain ramp starts (both 0: no soft start)", "rad",
                      minimum=NO_NARROWING.min_angle, maximum=NO_NARROWING.max_angle),
        ParameterSpec("soft_start_end", _DEFAULT.soft_start_end, "collective pitch where the gain ramp ends", "rad",
                      minimum=NO_NARROWING.min_angle, maximum=NO_NARROWING.max_angle),
        ParameterSpec("schedule_breakpoints", [0.0], "collective pitches of the gain schedule (one value: none)",
                      "rad"),
        ParameterSpec("schedule_factors", [1.0], "gain factors at the breakpoints"),
        ParameterSpec("ramp_time", _DEFAULT.ramp_time, "time to ramp the output in or out", "s", minimum=0.0,
                      maximum=600.0),
        ParameterSpec("min_pitch", 0.0, "lowest pitch: the demand is limited to the collective's headroom above it",
                      "rad", minimum=-0.5, maximum=1.6),
    )

    def __init__(self, values: Mapping[str, Any], plant: PlantDescription) -> None:
        super().__init__(values, plant)
        self.harmonic = self.values["harmonic"]
        try:
            check_configuration(self.harmonic, plant.blades)
            self.law = HarmonicIpc(config_from(self.values), plant.dt)
        except ValueError as error:
            raise ParameterError(str(error)) from None

    @classmethod
    def claimed(cls, values: Mapping[str, Any]) -> Tuple[str, ...]:
        return (harmonic_interface(values["harmonic"]),)

    def _moments(self, loads: Any):
        return mbc_forward_sample(loads.root_moment_oop, loads.azimuth, self.harmonic)

    def update(self, step: int, loads: Any, state: Any = None) -> Tuple[HarmonicContribution, ...]:
        moments = self._moments(loads)
        collective = mean_pitch(loads.pitch)
        out = self.law.step(moments.cos, moments.sin, self.plant.dt, operating_point=collective,
                            pitch_headroom=collective - self.values["min_pitch"])
        return (HarmonicContribution(self.harmonic, out.cos, out.sin, out.phase_offset),)

    def without_input(self, held: Tuple[Contribution, ...]) -> Tuple[HarmonicContribution, ...]:
        out = self.law.hold(self.plant.dt)
        return (HarmonicContribution(self.harmonic, out.cos, out.sin, out.phase_offset),)

    @classmethod
    def check_values(cls, values: Mapping[str, Any]) -> None:
        """The law's own rules without the plant's dt (positive max_amplitude, soft start in order, schedule)."""
        try:
            config_from(values).validate()
        except ValueError as error:
            raise ParameterError(str(error)) from None

    def check(self, values: Mapping[str, Any]) -> None:
        try:
            config_from(resolve_values(self.PARAMETERS, values)).validate(self.plant.dt)
        except ValueError as error:
            raise ParameterError(str(error)) from None

    def reconfigure(self, values: Mapping[str, Any]) -> None:
        super().reconfigure(values)
        self.law.reconfigure(config_from(self.values))

    def on_activate(self, ramp_time: Optional[float], initial: Sequence[Contribution], loads: Any) -> None:
        start = next(((c.cos, c.sin) for c in initial if isinstance(c, HarmonicContribution)), None)
        if loads is not None and (self.law.ramp == 0.0 or start is not None):
            try:
                moments = self._moments(loads)
                self.law.reset(start or (0.0, 0.0), moments=(moments.cos, moments.sin))
            except ValueError:
                pass  # no finite moments at this step: the filters keep their state
        self.law.activate(ramp_time, start)

    def on_deactivate(self, ramp_time: Optional[float]) -> None:
        self.law.deactivate(ramp_time)
