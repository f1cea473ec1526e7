"""The ``repetitive_ipc`` controller: individual pitch by spatial repetitive control of each blade's flap moment.

Claims ``blade_pitch``. Fratini 2019 §4.2 and §5.1 (R8, Fig. 5.17): every blade has its own
azimuth-indexed learning memory (:class:`hawt_controllers.laws.repetitive.AzimuthMemory`, eq. 4.4),
indexed by the blade's own azimuth ψ_i = ψ + 2π(i − 1)/B, learning on its flap
(out-of-plane) root moment error

    e_i = M_ref − M_oop,i,     M_ref = the running mean of the blades' mean flap moment

(the thesis's "mean nominal flapping moment value obtained from a previous analysis" is not
given; a first-order mean over ``reference_time`` follows the operating point instead), plus
a per-blade PI on the same error (R8's "gain P = −0.0005 in the IPC feedback loop"; with
``learning_gain`` 0 it is the thesis's "individual PI on M_flap" baseline of R8 (b)). Each blade's
increment is

    Δθ_i = u_i(ψ_i) + PI(e_i) / k,     u learnt with G = g / k,

with k = ``pitch_sensitivity`` = dM_oop/dθ of a blade (negative: feathering unloads it), so g,
k_p and k_i are the fractions of the error corrected and carry over between turbines. B is
the plant's. The memories learn only while the controller is active and not frozen; an
activation from off starts from zero learning; a deactivation fades the increment out.
A learning gain and shift that would diverge for the configured Q and ``plant_lag`` are
refused with the harmonic at fault (:func:`hawt_controllers.laws.repetitive.convergence_problem`).
"""
from __future__ import annotations

import math
from typing import Any, List, Mapping, Optional, Sequence, Tuple

from hawt_core.command_interfaces import BLADE_PITCH
from hawt_core.parameter_table import ParameterError, ParameterSpec, resolve_values
from hawt_core.plant_description import PlantDescription

from hawt_core.validation import finite_floats
from hawt_controllers.plugins.controller import (BladeContribution, Contribution, Controller, MeasuredFactor,
                                                 OutputRamp, mean_pitch)
from hawt_core.exceptions import InputError
from hawt_controllers.laws.pi import PIController
from hawt_controllers.laws.repetitive import (AzimuthMemory, RepetitiveConfig, convergence_problem, memory_config,
                                              memory_parameters)
from hawt_controllers.laws.saturation import BoxSaturation

__all__ = ["RepetitiveIpcController", "repetitive_config"]

TWO_PI = 2.0 * math.pi
_MEASURED_LAG = 0.43  # 1P phase of the NREL 5 MW's flap moment response, 11.4-18 m/s (hawt_controllers.design.ipc_design)


def repetitive_config(values: Mapping[str, Any]) -> RepetitiveConfig:
    """The memory's tuning from parameter values: its values within ±max_amplitude."""
    return memory_config(values, -values["max_amplitude"], values["max_amplitude"])


class RepetitiveIpcController(Controller):
    """Per-blade repetitive flap-moment control (see the module notes)."""

    TYPE = "repetitive_ipc"
    WITHOUT_INPUT = "output fading out over its ramp time"
    PARAMETERS = (
        ParameterSpec("learning_gain", 0.3, "g: fraction of each revolution's flap-moment error the next one "
                      "removes (0: no learning, the companion PI alone)", minimum=0.0, maximum=1.99),
        ParameterSpec("shift", _MEASURED_LAG, "delta: forward shift of the error as an azimuth (Fratini eq. 4.4)",
                      "rad", minimum=0.0, maximum=2 * math.pi),
        ParameterSpec("plant_lag", _MEASURED_LAG, "lag of a blade's flap moment behind its pitch, as an azimuth, "
                      "for the convergence check (measured by hawt_controllers.design.ipc_design as the 1P phase)", "rad",
                      minimum=-math.pi, maximum=math.pi),
        *memory_parameters(q_harmonics=4),
        ParameterSpec("max_amplitude", 0.0873, "bound of each memory and of each blade's increment", "rad",
                      minimum=0.0, maximum=0.5),
        ParameterSpec("pitch_sensitivity", -45.0e6, "k = dM_oop/dtheta of a blade (NREL 5 MW: -38e6 at "
                      "11.4 m/s, -54e6 at 18 m/s, measured by hawt_controllers.design.ipc_design)", "N*m/rad",
                      minimum=-1.0e10, maximum=-1.0),
        ParameterSpec("proportional_gain", 0.0, "k_p of the companion PI, as a fraction of the error", minimum=0.0,
                      maximum=2.0),
        ParameterSpec("integral_gain", 0.0, "k_i of the companion PI, fraction of the error per second", "1/s",
                      minimum=0.0, maximum=10.0),
        ParameterSpec("reference_time", 30.0, "time constant of the running-mean flap-moment reference", "s",
                      minimum=0.1, maximum=3600.0),
        ParameterSpec("limit_to_headroom", False, "limit each increment to the collective's headroom above "
                      "min_pitch (ROSCO IPC_SatMode 2: no blade clipped at the floor, but near rated little "
                      "authority left); false: the command's limits clip it"),
        ParameterSpec("min_pitch", 0.0, "lowest pitch, for limit_to_headroom", "rad", minimum=-0.5, maximum=1.6),
        ParameterSpec("freeze", False, "stop learning and keep playing the memory"),
        ParameterSpec("ramp_time", 2.0, "time to fade the increment in or out", "s", minimum=0.0, maximum=600.0),
    )

    def __init__(self, values: Mapping[str, Any], plant: PlantDescription) -> None:
        super().__init__(values, plant)
        self.check(self.values)
        config = repetitive_config(self.values)
        scale = 1.0 / self.values["pitch_sensitivity"]
        self.memories = [AzimuthMemory(config, scale) for _ in range(plant.blades)]
        self.companion = PIController((plant.blades,))
        self.ramp = OutputRamp(plant.dt)
        self.measured = MeasuredFactor()  # 1 while the moments are finite (without_input)
        self.unmeasured = (0.0,) * plant.blades  # the last increments before that factor
        self.reference = math.nan
        self._apply_freeze()

    @classmethod
    def check_values(cls, values: Mapping[str, Any]) -> None:
        """The memory's rules and the convergence condition (no plant needed)."""
        try:
            config = repetitive_config(values)
            config.validate()
        except ValueError as error:
            raise ParameterError(str(error)) from None
        problem = convergence_problem(config, values["plant_lag"])
        if problem is not None and config.learning_gain > 0.0:
            raise ParameterError(f"learning_gain: {problem}")

    def check(self, values: Mapping[str, Any]) -> None:
        self.check_values(resolve_values(self.PARAMETERS, values))

    def reconfigure(self, values: Mapping[str, Any]) -> None:
        super().reconfigure(values)
        for memory in self.memories:
            memory.reconfigure(repetitive_config(self.values), 1.0 / self.values["pitch_sensitivity"])
        self._apply_freeze()

    @classmethod
    def claimed(cls, values: Mapping[str, Any]) -> Tuple[str, ...]:
        return (BLADE_PITCH,)

    def _apply_freeze(self) -> None:
        learning = self.ramp.target > 0.0 and not self.values["freeze"]
        for memory in self.memories:
            memory.freeze(not learning)

    def update(self, step: int, loads: Any, state: Any = None) -> Tuple[BladeContribution, ...]:
        moments = finite_floats("root_moment_oop", loads.root_moment_oop)
        if len(moments) != self.plant.blades:
            raise InputError("root_moment_oop", f"expected {self.plant.blades} blades, found {len(moments)}")
        psi, = finite_floats("azimuth", (loads.azimuth,))
        mean = sum(moments) / len(moments)
        if math.isnan(self.reference):
            self.reference = mean
        self.reference += (1.0 - math.exp(-self.plant.dt / self.values["reference_time"])) * (mean - self.reference)
        errors = [self.reference - m for m in moments]
        k = self.values["pitch_sensitivity"]
        limit = self.values["max_amplitude"]
        if self.values["limit_to_headroom"]:
            headroom = mean_pitch(finite_floats("pitch", loads.pitch)) - self.values["min_pitch"]
            limit = min(limit, max(headroom, 0.0))
        companion = self.companion.update_values(
            [e / k for e in errors], self.plant.dt, kp=self.values["proportional_gain"],
            ki=self.values["integral_gain"], saturation=BoxSaturation(-limit, limit))
        spacing = TWO_PI / self.plant.blades
        factor = self.ramp.advance()
        if factor == 0.0 and self.ramp.target == 0.0:
            self.companion.reset(0.0)
        increments: List[float] = []
        for i, (memory, error, extra) in enumerate(zip(self.memories, errors, companion)):
            learnt = memory.step(psi + spacing * i, error)
            increments.append(factor * min(max(learnt + extra, -limit), limit))
        self.unmeasured = tuple(increments)
        measured = self.measured.step(True, self.plant.dt, self.ramp_time())
        return (BladeContribution(tuple(measured * value for value in increments)),)

    def without_input(self, held: Tuple[Contribution, ...]) -> Tuple[BladeContribution, ...]:
        """Without every blade's moment the memories and the PI hold and the last increments fade out over
        ``ramp_time``."""
        measured = self.measured.step(False, self.plant.dt, self.ramp_time())
        return (BladeContribution(tuple(measured * value for value in self.unmeasured)),)

    def on_activate(self, ramp_time: Optional[float], initial: Sequence[Contribution], loads: Any) -> None:
        if self.ramp.value == 0.0:
            for memory in self.memories:
                memory.reset()
            self.companion.reset(0.0)
        self.ramp.start(self.ramp_time() if ramp_time is None else ramp_time)
        self._apply_freeze()

    def on_deactivate(self, ramp_time: Optional[float]) -> None:
        self.ramp.stop(self.ramp_time() if ramp_time is None else ramp_time)
        self._apply_freeze()
