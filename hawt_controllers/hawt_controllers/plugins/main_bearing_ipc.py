"""The ``main_bearing_ipc`` controller: 2P main-bearing IPC of a two-bladed rotor (Zalkind & Pao) as a plug-in.

Zalkind & Pao, "A Harmonic Model for Loads Analysis and Control Design of a 2-bladed Wind Turbine"
§III (notes: ``literature/notes/seed001_zalkind.md`` §3). For B = 2 the hub 1P reaches the main
bearing as 0P and 2P (eqs. 14–17); both 2P terms vanish when the hub 1P phasors meet

    m_hy^{1P} = j m_hz^{1P}                                            (eq. 20)

Each step the controller turns the main-bearing (fixed-frame hub) moments of ``plant/state`` into
the rotating hub moments m_hy, m_hz at the azimuth of ``plant/blade_loads`` (eq. 13 inverted),
estimates their 1P phasors over the last N_R revolutions (:mod:`hawt_core.rotor.harmonic_estimator`,
eqs. 4–7, true amplitudes) and drives the error e = j m_hz^{1P} − m_hy^{1P} to zero with a PI law on
the complex 1P pitch phasor P (the derivative of the paper's PID is left out: it would differentiate
a moving average)::

    P = (k_p e + k_i ∫ e dt) / G,    |P| ≤ max_amplitude (the integral held while saturated)

G = plant_gain·e^{j plant_phase} is the hub-y 1P response to P (m_hy^{1P} moves by G P), so e/G is the
pitch that cancels the error and k_i [1/s] is the loop's crossover (the estimator's window, about N_R/2
revolutions of delay, bounds it). The phasor P is contributed on ``harmonic/1`` as (cos, sin) = (Re P, Im P), phase offset 0:

    θ_i = Re P cos ψ_i + Im P sin ψ_i,  so blade 1's pitch has the 1P phasor P (the estimator's c + j s)

and for B = 2 the assembler gives θ_2 = −θ_1 (eqs. 18–19). **Phase convention**: eq. 18's θ^{1P} is
conj(P) (eqs. 7 and 18 use opposite phase signs, notes Appendix A).

The integral runs only while the controller is active and its window holds N_R whole revolutions
(soft start); activation starts it from zero and ramps the output in over ``ramp_time``. On a
three-bladed rotor eq. 20 holds by itself, so the controller does next to nothing (AC-10).
"""
from __future__ import annotations

import cmath
import math
from typing import Any, Mapping, Optional, Sequence, Tuple

from hawt_core.command_interfaces import harmonic_interface
from hawt_core.parameter_table import ParameterSpec
from hawt_core.plant_description import PlantDescription

from hawt_controllers.plugins.controller import (Contribution, Controller, HarmonicContribution, MeasuredFactor,
                                                 OutputRamp)
from hawt_core.exceptions import InputError
from hawt_core.rotor.harmonic_estimator import HarmonicEstimator
from hawt_core.rotor.hub_frame import main_bearing_to_hub

__all__ = ["MainBearingIpcController"]

# Measured on the two-bladed NREL 5 MW variant (turbines/nrel_5mw/two_bladed.yaml) at 15 m/s, alpha 0.14,
# open loop: P = 0.01 and 0.01j rad gave dm_hy^{1P}/P = -1.253e8 - 7.85e7j N*m/rad (docs/two_bladed.md).
_PLANT_GAIN = 1.48e8
_PLANT_PHASE = -2.582


class MainBearingIpcController(Controller):
    """Zalkind & Pao's 2P main-bearing IPC on harmonic 1 (see the module notes)."""

    TYPE = "main_bearing_ipc"
    WITHOUT_INPUT = "output fading out over its ramp time"
    PARAMETERS = (
        ParameterSpec("revolutions", 2.0, "window N_R of the harmonic estimator", "rev", minimum=0.5, maximum=10.0,
                      read_only=True),
        ParameterSpec("integral_gain", 0.1, "k_i: crossover of the loop", "1/s", minimum=0.0, maximum=10.0),
        ParameterSpec("proportional_gain", 0.0, "k_p", minimum=0.0, maximum=10.0),
        ParameterSpec("plant_gain", _PLANT_GAIN, "|G|: hub-y 1P moment per rad of 1P pitch", "N*m/rad",
                      minimum=1.0, maximum=1e4 * _PLANT_GAIN),
        ParameterSpec("plant_phase", _PLANT_PHASE, "arg G", "rad", minimum=-math.pi, maximum=math.pi),
        ParameterSpec("max_amplitude", math.radians(3.0), "largest |P|", "rad", minimum=0.0, maximum=0.5),
        ParameterSpec("ramp_time", 2.0, "time to ramp the output in or out", "s", minimum=0.0, maximum=600.0),
    )
    INPUTS = ("blade_loads", "turbine_state")

    def __init__(self, values: Mapping[str, Any], plant: PlantDescription) -> None:
        super().__init__(values, plant)
        self.estimator = HarmonicEstimator(2, self.values["revolutions"], max_harmonic=1)
        self.ramp = OutputRamp(plant.dt)
        self.measured = MeasuredFactor()  # 1 while the hub moments are finite (without_input)
        self.integral = 0j
        self.phasor = 0j
        self.error = 0j
        self.hub_1p = (0j, 0j)

    @classmethod
    def claimed(cls, values: Mapping[str, Any]) -> Tuple[str, ...]:
        return (harmonic_interface(1),)

    def update(self, step: int, loads: Any, state: Any = None) -> Tuple[HarmonicContribution, ...]:
        tilt, yaw, azimuth = state.hub_tilt_moment, state.hub_yaw_moment, loads.azimuth
        if not all(math.isfinite(v) for v in (tilt, yaw, azimuth)):
            raise InputError("measurements", f"hub_tilt_moment={tilt}, hub_yaw_moment={yaw}, azimuth={azimuth}: "
                                             "not finite")
        phasors = self.estimator.update(azimuth, main_bearing_to_hub(tilt, yaw, azimuth))
        hy, hz = complex(phasors[0, 1]), complex(phasors[1, 1])
        self.hub_1p = (hy, hz)
        self.error = 1j * hz - hy
        v = self.values
        gain = v["plant_gain"] * cmath.exp(1j * v["plant_phase"])
        if self.estimator.valid and self.ramp.target > 0.0:
            integral = self.integral + self.plant.dt * self.error
            phasor = (v["proportional_gain"] * self.error + v["integral_gain"] * integral) / gain
            if abs(phasor) <= v["max_amplitude"]:
                self.integral = integral
            else:  # saturated: keep the direction, hold the integral (anti-windup)
                phasor *= v["max_amplitude"] / abs(phasor)
            self.phasor = phasor
        factor = self.ramp.advance()
        measured = self.measured.step(True, self.plant.dt, self.ramp_time())
        return (HarmonicContribution(1, measured * factor * self.phasor.real, measured * factor * self.phasor.imag,
                                     0.0),)

    def without_input(self, held: Tuple[Contribution, ...]) -> Tuple[HarmonicContribution, ...]:
        """Without finite hub moments the estimator and the integral hold and the demand fades out over
        ``ramp_time``."""
        factor = self.ramp.advance() * self.measured.step(False, self.plant.dt, self.ramp_time())
        return (HarmonicContribution(1, factor * self.phasor.real, factor * self.phasor.imag, 0.0),)

    def on_activate(self, ramp_time: Optional[float], initial: Sequence[Contribution], loads: Any) -> None:
        self.integral = self.phasor = 0j
        self.ramp.start(self.ramp_time() if ramp_time is None else ramp_time)

    def on_deactivate(self, ramp_time: Optional[float]) -> None:
        self.ramp.stop(self.ramp_time() if ramp_time is None else ramp_time)
