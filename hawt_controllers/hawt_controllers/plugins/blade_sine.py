"""The ``blade_sine`` controller: a sine added to each blade's pitch, for system identification.

Claims ``blade_pitch``. Blade i gets

    Δθ_i(t) = ρ(t) · A_i · sin(2π f t + φ_0 + (i − 1) Δφ),    t = k · dt,

with per-blade amplitudes A_i [rad], frequency f [Hz], phase φ_0 and blade-to-blade
phase step Δφ [rad]; ρ ramps 0 → 1 over ``ramp_time`` after an activation and back to 0
after a deactivation. Equal amplitudes with Δφ = 0 excite the collective mode;
Δφ = 2π/B with f = 0 gives a tilt/yaw-like static pattern, f = nΩ/2π with Δφ = 2πn/B
a rotating one. Identification signals for the linear models of the MBC frame
(Disario's coupling design, van Engelen's dM/dθ) are made this way.
"""
from __future__ import annotations

import math
from typing import Any, Mapping, Optional, Sequence, Tuple

import numpy as np

from hawt_core.command_interfaces import BLADE_PITCH
from hawt_core.parameter_table import ParameterSpec
from hawt_core.plant_description import DescriptionMismatch, PlantDescription

from hawt_controllers.plugins.controller import BladeContribution, Contribution, Controller, OutputRamp

__all__ = ["BladeSineController"]


class BladeSineController(Controller):
    """Per-blade sine injection (see the module notes)."""

    TYPE = "blade_sine"
    PARAMETERS = (
        ParameterSpec("amplitudes", [0.01745, 0.01745, 0.01745], "amplitude A_i per blade, blade 1 first "
                      "(one entry per blade of the plant)", "rad", minimum=0.0, maximum=0.2),
        ParameterSpec("frequency", 0.5, "frequency f of the sine", "Hz", minimum=0.0, maximum=10.0),
        ParameterSpec("phase", 0.0, "phase phi_0 of blade 1", "rad", minimum=-2 * math.pi, maximum=2 * math.pi),
        ParameterSpec("blade_phase_step", 0.0, "phase added per blade (blade i: (i-1) times this)", "rad",
                      minimum=-2 * math.pi, maximum=2 * math.pi),
        ParameterSpec("ramp_time", 2.0, "time to ramp the sine in or out", "s", minimum=0.0, maximum=600.0),
    )

    def __init__(self, values: Mapping[str, Any], plant: PlantDescription) -> None:
        super().__init__(values, plant)
        self.check(self.values)
        self.ramp = OutputRamp(plant.dt)

    @classmethod
    def claimed(cls, values: Mapping[str, Any]) -> Tuple[str, ...]:
        return (BLADE_PITCH,)

    def check(self, values: Mapping[str, Any]) -> None:
        super().check(values)
        if len(values["amplitudes"]) != self.plant.blades:
            raise DescriptionMismatch(f"amplitudes: {len(values['amplitudes'])} entries conflict with "
                                      f"plant/description blades {self.plant.blades}")

    def update(self, step: int, loads: Any, state: Any = None) -> Tuple[BladeContribution, ...]:
        v = self.values
        angle = 2 * math.pi * v["frequency"] * step * self.plant.dt + v["phase"] \
            + v["blade_phase_step"] * np.arange(self.plant.blades)
        factor = self.ramp.advance()
        return (BladeContribution(tuple((factor * np.asarray(v["amplitudes"]) * np.sin(angle)).tolist())),)

    def on_activate(self, ramp_time: Optional[float], initial: Sequence[Contribution], loads: Any) -> None:
        self.ramp.start(self.ramp_time() if ramp_time is None else ramp_time)

    def on_deactivate(self, ramp_time: Optional[float]) -> None:
        self.ramp.stop(self.ramp_time() if ramp_time is None else ramp_time)
