"""The ``coleman_excitation`` controller: random-binary tilt and yaw pitch, for identifying the Coleman-frame plant.

Claims ``blade_pitch``. Two independent pseudo-random binary sequences of ±A switch every
``clock_period`` seconds on θ_tilt and θ_yaw of harmonic n; each blade gets their inverse
Coleman transform at its own azimuth (DESIGN §3, no phase offset):

    Δθ_i = ρ(t) · (θ_tilt cos(n ψ_i) + θ_yaw sin(n ψ_i))

with ρ the ramp in and out of a switch. A random-binary signal has a flat spectrum up to
about 1/(2·clock_period) Hz, so the recorded (M_tilt, M_yaw) against (θ_tilt, θ_yaw) give the
2×2 transfer matrix by cross-spectra (hawt_analysis.identification; Disario 2018 §5-1 used
RBS of 1° for this). The bit of clock interval j is drawn from a generator seeded with
(``seed``, j), so the sequence depends on the step alone and every engine draws the same one.
"""
from __future__ import annotations

from typing import Any, Mapping, Optional, Sequence, Tuple

import numpy as np

from hawt_core.command_interfaces import BLADE_PITCH
from hawt_core.parameter_table import ParameterError, ParameterSpec
from hawt_core.plant_description import PlantDescription

from hawt_core.validation import finite_floats
from hawt_controllers.plugins.controller import BladeContribution, Contribution, Controller, OutputRamp
from hawt_core.rotor.mbc import check_configuration, mbc_inverse_sample

__all__ = ["ColemanExcitationController", "binary_levels"]


def binary_levels(seed: int, interval: int) -> Tuple[float, float]:
    """(θ_tilt, θ_yaw) signs, ±1, of clock interval ``interval``: independent fair bits seeded by (seed, interval)."""
    bits = np.random.default_rng([seed, interval]).integers(0, 2, size=2)
    return float(2 * bits[0] - 1), float(2 * bits[1] - 1)


class ColemanExcitationController(Controller):
    """Random-binary θ_tilt and θ_yaw on the blades (see the module notes)."""

    TYPE = "coleman_excitation"
    PARAMETERS = (
        ParameterSpec("amplitude", 0.0175, "A: the level of each binary sequence", "rad", minimum=0.0, maximum=0.1),
        ParameterSpec("clock_period", 0.5, "time between possible switches of a sequence", "s", minimum=0.01,
                      maximum=60.0),
        ParameterSpec("harmonic", 1, "harmonic n of the Coleman transform the sequences are remodulated with",
                      minimum=1, maximum=4),
        ParameterSpec("seed", 1, "seed of the sequences", minimum=0, maximum=2**31 - 1),
        ParameterSpec("ramp_time", 2.0, "time to ramp the excitation in or out", "s", minimum=0.0, maximum=600.0),
    )

    def __init__(self, values: Mapping[str, Any], plant: PlantDescription) -> None:
        super().__init__(values, plant)
        try:
            check_configuration(self.values["harmonic"], plant.blades)
        except ValueError as error:
            raise ParameterError(f"harmonic: {error}") from None
        self.ramp = OutputRamp(plant.dt)
        self._interval: Optional[int] = None
        self._levels = (0.0, 0.0)

    @classmethod
    def claimed(cls, values: Mapping[str, Any]) -> Tuple[str, ...]:
        return (BLADE_PITCH,)

    def levels(self, step: int) -> Tuple[float, float]:
        """(θ_tilt, θ_yaw) [rad] of ``step``, before the ramp."""
        interval = int(step * self.plant.dt / self.values["clock_period"])
        if interval != self._interval:
            self._interval, self._levels = interval, binary_levels(self.values["seed"], interval)
        amplitude = self.values["amplitude"]
        return amplitude * self._levels[0], amplitude * self._levels[1]

    def update(self, step: int, loads: Any, state: Any = None) -> Tuple[BladeContribution, ...]:
        psi, = finite_floats("azimuth", (loads.azimuth,))
        tilt, yaw = self.levels(step)
        factor = self.ramp.advance()
        pitch = mbc_inverse_sample(tilt, yaw, psi, self.values["harmonic"], self.plant.blades)
        return (BladeContribution(tuple(factor * value for value in pitch)),)

    def on_activate(self, ramp_time: Optional[float], initial: Sequence[Contribution], loads: Any) -> None:
        self.ramp.start(self.ramp_time() if ramp_time is None else ramp_time)

    def on_deactivate(self, ramp_time: Optional[float]) -> None:
        self.ramp.stop(self.ramp_time() if ramp_time is None else ramp_time)
