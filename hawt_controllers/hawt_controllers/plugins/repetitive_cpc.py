"""The ``repetitive_cpc`` controller: collective pitch by PD plus spatial repetitive control of the speed (Fratini).

Claims ``collective_pitch`` and ``generator_torque``, like ``cpc``, for which it is swapped live
(a collective controller is never switched off alone). Fratini 2019 §4.2 and §5.1 (R3, R4, R6:
"repetitive-PD", Table 5.2: P = −0.018, I = 0, D = −0.01 in the thesis's sign): the baseline's
torque law and gain schedule GK (:class:`hawt_controllers.plugins.cpc.CollectivePitchController`)
with its own gains, plus a derivative term and a learning memory indexed by the rotor azimuth
(:class:`hawt_controllers.laws.repetitive.AzimuthMemory`, eq. 4.4) on the generator-speed error::

    θ = GK(θ)·(K_P e + K_D de/dt) + u(ψ),   u_{j+1}(ψ) = Q[u_j](ψ) + GK·g·e_j(ψ + δ),

the memory holding the whole learnt pitch within the pitch limits (it starts at the operating point's
pitch, so its bounds are the anti-windup; the PD acts on the filtered speed of the step before),

with e = ω − ω_ref (generator speed; filtered for the PD as in the baseline, as measured for the
memory, whose bins average it; the thesis's sign is the opposite, hence its negative gains). There
is no K_I (the thesis's choice): the memory's mean is the integral action. It learns the operating
point's pitch revolution by revolution (R3), and its harmonics cancel a periodic disturbance of the
speed that a PI leaves (R4). g [rad/(rad/s)] is the pitch learnt per revolution per rad/s of error.
Its mean converges for 0 < g < 2 K_P (:meth:`RepetitiveCollectiveController.check_values` refuses
the rest, naming the factor; measured: 0.02 settles, 0.04 oscillates), the harmonics through the
shift, which leads the speed's lag behind pitch (2.2 rad at 1P on the NREL 5 MW).
"""
from __future__ import annotations

import dataclasses
import math
from typing import Any, Mapping, Optional

from hawt_core.parameter_table import ParameterError, ParameterSpec, resolve_values
from hawt_core.plant_description import PlantDescription

from hawt_controllers.laws.collective import BaselineCollectiveConfig, gain_correction_factor
from hawt_controllers.plugins.cpc import CollectivePitchController
from hawt_controllers.laws.limits import PitchLimits
from hawt_controllers.laws.repetitive import AzimuthMemory, RepetitiveConfig, memory_config, memory_parameters

__all__ = ["RepetitiveCollectiveController"]


def _memory_config(values: Mapping[str, Any], limits: PitchLimits) -> RepetitiveConfig:
    """The memory's tuning: it holds the learnt pitch, within the pitch limits."""
    return memory_config(values, limits.min_angle, limits.max_angle)


class RepetitiveCollectiveController(CollectivePitchController):
    """Repetitive-PD collective pitch with the baseline torque law (see the module notes)."""

    TYPE = "repetitive_cpc"
    PARAMETERS = (
        *CollectivePitchController.PARAMETERS,
        ParameterSpec("proportional_gain", 0.01882681, "K_P at zero pitch (Jonkman's; the thesis's -0.018)", "s",
                      minimum=0.0, maximum=1.0),
        ParameterSpec("derivative_gain", 0.03, "K_D at zero pitch, on the filtered speed error", "s^2",
                      minimum=0.0, maximum=1.0),
        ParameterSpec("learning_gain", 0.005, "g: pitch learnt per revolution per rad/s of generator-speed error "
                      "(below 2 x proportional_gain, or the learnt mean diverges)", "rad/(rad/s)", minimum=0.0,
                      maximum=1.0),
        ParameterSpec("shift", 2.2, "delta: forward shift of the error as an azimuth (Fratini eq. 4.4); 2.2 rad "
                      "leads the speed's lag behind pitch at 1P on the NREL 5 MW (R4)", "rad", minimum=0.0,
                      maximum=2 * math.pi),
        *memory_parameters(q_harmonics=1),
        ParameterSpec("freeze", False, "stop learning and keep playing the memory"),
    )
    SWITCHABLE = False

    def __init__(self, values: Mapping[str, Any], plant: PlantDescription) -> None:
        super().__init__(values, plant)
        self.memory = AzimuthMemory(_memory_config(self.values, self.law.pitch_limits), -1.0)
        self.memory.freeze(True)  # learns only while active
        self.speeds: list = []

    def tuned(self, config: BaselineCollectiveConfig) -> BaselineCollectiveConfig:
        """The baseline's torque law and limits; its PI gains zero: the PD and the memory are :meth:`extra`."""
        return dataclasses.replace(config, proportional_gain=0.0, integral_gain=0.0)

    @classmethod
    def check_values(cls, values: Mapping[str, Any]) -> None:
        """The memory's rules, and the convergence of its mean (the learnt integral action, module notes).

        A change Δu of the learnt pitch is met, once the speed has settled, by a speed error Δe with
        GK·K_P·Δe = −Δu (the proportional term gives the pitch back); the next revolution learns
        GK·g·Δe, so the mean changes by the factor 1 − g/K_P per revolution (Q keeps the mean: Q_0 = 1),
        and converges for 0 < g < 2 K_P. Measured on the NREL 5 MW after the 11.4 -> 15 m/s step:
        g = 0.02 settles, g = 0.04 (> 2 × 0.0188) oscillates by 3.4 rpm.
        """
        try:
            config = _memory_config(values, PitchLimits(0.0, 1.0, 1.0))
            config.validate()
        except ValueError as error:
            raise ParameterError(str(error)) from None
        gain, proportional = config.learning_gain, values["proportional_gain"]
        if gain > 0.0 and not gain < 2.0 * proportional:
            factor = abs(1.0 - gain / proportional) if proportional > 0.0 else math.inf
            raise ParameterError(
                f"learning_gain: {gain:g} with proportional_gain {proportional:g} makes the learnt mean pitch diverge "
                f"(factor |1 - g/K_P| = {factor:.3g} >= 1 per revolution): keep learning_gain below "
                f"2 x proportional_gain = {2.0 * proportional:g}")

    def check(self, values: Mapping[str, Any]) -> None:
        self.check_values(resolve_values(self.PARAMETERS, values))

    def reconfigure(self, values: Mapping[str, Any]) -> None:
        super().reconfigure(values)
        self.law.config = self.tuned(self.law.config)
        self.memory.reconfigure(_memory_config(self.values, self.law.pitch_limits), self.memory.error_scale)
        self.memory.freeze(self.values["freeze"])

    def restart(self, generator_speed: float, pitch: float, generator_torque: float, proportional: float) -> None:
        """The law starts at the operating point with an empty integrator; the memory holds the pitch less the
        proportional part of the first step, so that the first command is ``pitch``."""
        super().restart(generator_speed, pitch, generator_torque, 0.0)
        self.law.pitch_integrator.reset(0.0)
        self.speeds = []
        first = self._pd(generator_speed, gain_correction_factor(pitch, self.law.config.gain_doubling_pitch))
        self.memory.reset([pitch - first] * self.memory.config.bins)
        self.memory.freeze(self.values["freeze"])

    def extra(self, loads: Any, state: Any) -> float:
        """GK·(K_P e + K_D de/dt) + u(ψ), the memory at the rotor azimuth learning on this step's error."""
        config = self.law.config
        gain = gain_correction_factor(self.law.pitch_command, config.gain_doubling_pitch)
        self.memory.error_scale = -gain
        learnt = self.memory.step(loads.azimuth, config.rated_generator_speed - state.generator_speed)
        return self._pd(state.generator_speed, gain) + learnt

    def _pd(self, generator_speed: float, gain: float) -> float:
        """GK·(K_P e + K_D de/dt) on the filtered speed of the step before (this step's measurement at a start)."""
        speeds = self.speeds or [generator_speed]
        derivative = (speeds[-1] - speeds[-2]) / self.plant.dt if len(speeds) == 2 else 0.0
        error = speeds[-1] - self.law.config.rated_generator_speed
        return gain * (self.values["proportional_gain"] * error + self.values["derivative_gain"] * derivative)

    def update(self, step: int, loads: Any, state: Any = None):
        contributions = super().update(step, loads, state)
        self.speeds = [*self.speeds[-1:], contributions[0].generator_speed_filtered]
        return contributions

    def on_deactivate(self, ramp_time: Optional[float]) -> None:
        self.memory.freeze(True)
