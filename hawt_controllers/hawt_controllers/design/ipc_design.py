"""IPC tuning from the plant itself: harmonic response, integral gains, phase offsets, schedule.

For each operating point (wind speed) and harmonic n the design needs the plant's response in the
non-rotating frame to a constant demand ``(c_n, s_n)`` remodulated on the blades (DESIGN.md §3): a gain
``k = dM/dθ`` [N·m/rad] (negative: pitching to feather unloads the blade) and a rotation ``φ`` of the
(cos, sin) plane that the remodulation's phase offset ``φ_n`` undoes (Disario: the azimuth offset). Two
routes give them:

- the model route (:func:`model_harmonic_response`): the plant's Coleman-frame linear model at the
  wind speed (``hawt linearize``, :mod:`hawt_controllers.design.linear_models`), its nP plant P_n(0) at DC
  (:func:`harmonic_response`: the 1P model gives every harmonic of a three-bladed rotor);
- the measured route (:func:`measure_harmonic_response`): the turbine model (:mod:`hawt_plant.model`)
  open loop at its steady operating point in uniform wind, with and without the demand.

The design takes the model route where a linear model exists at every design wind speed and prints the
measured route beside it as the cross-check. The integral gain follows van Engelen's recipe
(:func:`hawt_controllers.laws.ipc_tuning.design_integral_gain`: ~0.1 Hz crossover with the pre-filter); on the
model route the crossover and phase margin the loop really has are computed on the model's frequency
response (:func:`loop_crossover`, the actuator and the law's discretisation inside). The gain schedule over
collective pitch keeps the loop gain ``k_i k`` constant across the operating points.
:func:`loop_analysis` closes the designed loop on the linear model (Disario ch. 5: RGA at the crossover,
the sensitivity's singular values).

Each harmonic's rate budget (:func:`rate_budget`) is what cancelling its moment of steady sheared wind asks of
the pitch actuator; the design leaves active only the harmonics that fit it together, 1P first
(:func:`within_budget`, :data:`RATE_BUDGET_LIMIT`), and writes the others inactive.

``hawt design ipc`` (:func:`write_tunings`) prints the design and writes the parameter file the ``ipc`` graph
uses, and the retuned 1P controller of the ``switching`` graph derived from it (:func:`retuned`);
``--retuned-only`` derives that one again from the existing file.
"""
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np
import yaml
from numpy.typing import ArrayLike
from scipy.optimize import brentq

from hawt_controllers.laws.coleman_coupling import offset_from_dc_response, relative_gain_array
from hawt_controllers.plugins.controller import HarmonicContribution
from hawt_controllers.laws.ipc import HarmonicIpcConfig, design_prefilter
from hawt_controllers.laws.ipc_tuning import IntegralGainDesign, design_integral_gain
from hawt_controllers.laws.limits import PitchLimits
from hawt_controllers.laws.coleman_models import ColemanModel, load_models, state_space_response
from hawt_controllers.design.linear_models import tilt_yaw_response
from hawt_controllers.design.tunings import PACKAGED, TuningError, tuning_file, tuning_path
from hawt_controllers.plugins.loop_assembly import LoopAssembler
from hawt_controllers.laws.lqg_design import _MOMENT_UNIT, _PITCH_UNIT
from hawt_controllers.laws.lqg_ipc import integrator_ipc
from hawt_core.rotor.mbc import mbc_forward
from hawt_plant.model import ModelConfig, TurbineModel
from hawt_plant.shear_wind import PowerLawWind
from hawt_plant.turbine import Turbine, turbine_from

__all__ = ["HarmonicResponse", "RateBudget", "CouplingPoint", "LoopAnalysis", "RATE_BUDGET_LIMIT",
           "measure_harmonic_response", "rate_budget", "within_budget", "harmonic_response", "model_harmonic_response",
           "loop_response", "loop_crossover", "loop_analysis", "coupling_survey", "design", "retuned", "write_tunings"]

DEFAULT_FILE = PACKAGED["nrel_5mw"]["ipc"]
RETUNED_FILE = PACKAGED["nrel_5mw"]["ipc_retuned"]
RATE_BUDGET_WARNING = 0.5
"""Share of the actuator's rate limit that the harmonics take in steady shear above which ``design`` warns: on the
NREL 5 MW 1P+2P+3P take 36 % (3P rate-limited on 14 % of the steps in turbulence), on the IEA 15 MW 1P alone
62 % and 1P+2P 74 % (2P then tripped the protection)."""
RATE_BUDGET_LIMIT = 0.70
"""Share of the actuator's rate limit that the active harmonics may take together in steady shear
(:func:`within_budget`). The measurements on the IEA 15 MW (2 °/s, class B turbulence at 18 m/s, 600 s) bracket it:
1P alone, at 62 % (blades with their edgewise modes, on the flexible monopile), cut the blade-root DEL by 31 % and
tripped on none of three seeds with the CPC designed for 0.25 rad/s (on one, at t = 382 s, with the CPC for 0.2 rad/s,
which alone tripped there at 495 s); 1P+2P at 74 % tripped the protection on all three (rotor overspeed at t =
34.5 s, tower-top acceleration at 152.7 and 74.2 s), at 80 % (blades rigid edgewise) the rotor overspeed at t =
34.75 s, and at 94 % it raised the blade DEL by 110 % (README, the IEA 15 MW end to end). 0.70 lies between the
highest share that helped and the lowest that hurt; the NREL 5 MW's 1P+2P+3P (36 %) stay well inside it. Above
:data:`RATE_BUDGET_WARNING` the design still warns: turbulence asks several times the steady shear."""


@dataclass(frozen=True)
class HarmonicResponse:
    """The plant's non-rotating response of harmonic n at one operating point."""

    wind_speed: float
    harmonic: int
    collective_pitch: float
    rotor_speed: float
    sensitivity: float
    phase: float


def _mean_components(turbine: Turbine, wind_speed: float, harmonic: int, demand: float, dt: float,
                     settle: float, average: float, shear: float = 0.0):
    model = TurbineModel(turbine, PowerLawWind(wind_speed, hub_height=turbine.hub_height, shear_exponent=shear),
                         ModelConfig(dt=dt, tower_shadow=False))
    out = model.reset_to_operating_point()
    collective, torque = float(np.mean(out.pitch)), float(out.generator_torque)
    actuator = turbine.pitch_actuator
    assembler = LoopAssembler(model.number_of_blades, PitchLimits(actuator.min_angle, actuator.max_angle,
                                                                  actuator.max_rate), dt)
    samples = []
    for step in range(int((settle + average) / dt)):
        pitch = collective + assembler.individual([(HarmonicContribution(harmonic, demand, 0.0), 1.0)],
                                                  out.azimuth)
        out = model.step(pitch, torque)
        if step * dt >= settle:
            c = mbc_forward(out.root_moment_oop, out.azimuth, harmonic)
            samples.append((c.cos, c.sin))
    return np.mean(samples, axis=0), collective, out.rotor_speed


def measure_harmonic_response(turbine: Turbine, wind_speed: float, harmonic: int, amplitude: float = 0.01,
                              dt: float = 0.01, settle: float = 15.0, average: float = 10.0) -> HarmonicResponse:
    """dM/dθ and the phase rotation of harmonic n at the operating point of ``wind_speed`` (uniform wind).

    The rotor speed is held by holding the generator torque of the operating point; runs
    with and without the demand are differenced, so the residual of the operating point cancels.
    """
    loaded, collective, rotor_speed = _mean_components(turbine, wind_speed, harmonic, amplitude, dt, settle,
                                                       average)
    reference, _, _ = _mean_components(turbine, wind_speed, harmonic, 0.0, dt, settle, average)
    response = (loaded - reference) / amplitude
    gain = -float(np.hypot(*response))
    phase = math.atan2(-response[1], -response[0])
    return HarmonicResponse(wind_speed, harmonic, collective, rotor_speed, gain, phase)


@dataclass(frozen=True)
class RateBudget:
    """What harmonic n asks of the pitch actuator to cancel the nP moment of steady sheared wind."""

    harmonic: int
    amplitude: float
    """Pitch amplitude [rad] that cancels it: the moment's amplitude over |dM/dθ|."""
    rate: float
    """Its pitch rate [rad/s]: n Ω times the amplitude."""
    max_rate: float
    """The actuator's rate limit [rad/s]."""

    @property
    def share(self) -> float:
        """The rate as a fraction of the limit; turbulence asks several times the steady shear's."""
        return self.rate / self.max_rate


def rate_budget(turbine: Turbine, response: HarmonicResponse, shear: float = 0.2, dt: float = 0.01,
                settle: float = 15.0, average: float = 10.0) -> RateBudget:
    """The pitch rate that cancelling the nP blade-root moment of steady wind with power-law ``shear`` at the
    response's operating point takes, against the actuator's limit (issue 20: on the IEA 15 MW, 2 °/s, 2P IPC
    designed for 0.1 Hz is rate-limited in turbulence and raises the loads)."""
    moment, _, rotor_speed = _mean_components(turbine, response.wind_speed, response.harmonic, 0.0, dt, settle,
                                              average, shear)
    amplitude = float(np.hypot(*moment)) / abs(response.sensitivity)
    return RateBudget(response.harmonic, amplitude, response.harmonic * rotor_speed * amplitude,
                      turbine.pitch_actuator.max_rate)


def within_budget(budgets: Sequence[RateBudget], limit: float = RATE_BUDGET_LIMIT) -> List[int]:
    """The harmonics to leave active: those of ``budgets``, in the order given (1P first), up to the first whose
    share of the rate limit, added to the shares before it, would exceed ``limit``; none if the first does."""
    active, used = [], 0.0
    for budget in budgets:
        used += budget.share
        if used > limit:
            break
        active.append(budget.harmonic)
    return active


def harmonic_response(model: ColemanModel, harmonic: int, omega: ArrayLike) -> np.ndarray:
    """P_n(jω): the frequency response [N m/rad] in the frame of harmonic n, from the cos/sin nP pitch command
    (c_n, s_n), remodulated without phase offset, to the cos/sin nP demodulation of the blade-root out-of-plane
    moments (hawt_core.rotor.mbc), of a three-bladed rotor's Coleman-frame model, at ``omega`` [rad/s], shape
    (len(omega), 2, 2).

    The Coleman model holds only the collective and the 1P cyclic coordinates, but on three blades every
    harmonic is one of them at a multiple of 3P. With m = round(n/3) and the demand z = c_n + j s_n, harmonic n
    is a forward cyclic pitch at 3mΩ (n = 3m + 1), a backward one (n = 3m − 1) or a collective one (n = 3m), and
    the nP demodulation brings the moment back: M_n = g_n(s) z with (our derivation; P the model's cos/sin block,
    :func:`hawt_controllers.design.linear_models.tilt_yaw_response`, p_0 the collective pitch command to the collective
    moment)::

        n = 3m + 1:  g_n(s) = [1, j] P(s − 3jmΩ) [1, −j]ᵀ / 2
        n = 3m − 1:  g_n(s) = [1, −j] P(s − 3jmΩ) [1, j]ᵀ / 2
        n = 3m:      g_n(s) = p_0(s − 3jmΩ)

    and P_n = [[g_r, −g_i], [g_i, g_r]] the real form of the complex-coefficient g_n = g_r + j g_i, with
    g_r(jω) = (g_n(jω) + conj(g_n(−jω))) / 2. For three first-order blades this is Disario's eq. 2-19 with
    ω0 → nω0 (the tests). Harmonic 1 is the tilt/yaw plant itself, which keeps the part of P(0) that is no
    rotation (the sheared, shadowed rotor's: 2.6-4.4 % of it at 13-24 m/s); for n > 1 that part only leaves a
    ripple at 6mΩ, and what the rotor's periodicity couples between harmonics is outside the azimuth-averaged
    model.
    """
    if harmonic < 1:
        raise ValueError(f"harmonic: expected >= 1, found {harmonic}")
    omega = np.atleast_1d(np.asarray(omega, dtype=float))
    if harmonic == 1:
        return tilt_yaw_response(model.model, omega)
    shift = 3 * round(harmonic / 3) * model.rotor_speed

    def gain(w: np.ndarray) -> np.ndarray:
        if harmonic % 3 == 0:
            m = model.model
            pitch, moment = m.inputs.index("pitch_command_collective"), m.outputs.index("root_moment_oop_collective")
            collective = (m.a, m.b[:, [pitch]], m.c[[moment]], m.d[[moment]][:, [pitch]])
            return state_space_response(collective, 1j * (w - shift))[:, 0, 0]
        forward, backward = np.array([1.0, 1j]), np.array([1.0, -1j])
        left, right = (forward, backward) if harmonic % 3 == 1 else (backward, forward)
        return left @ tilt_yaw_response(model.model, w - shift) @ right / 2.0

    plus, minus = gain(omega), np.conj(gain(-omega))
    real, imaginary = (plus + minus) / 2.0, (plus - minus) / 2j
    return np.stack([np.stack([real, -imaginary], axis=-1), np.stack([imaginary, real], axis=-1)], axis=-2)


def model_harmonic_response(model: ColemanModel, harmonic: int) -> HarmonicResponse:
    """The model route: dM/dθ and the phase rotation of harmonic n from the linear model's P_n(0)
    (:func:`harmonic_response`) at its operating point.

    The part of P_n(0) that a phase offset can undo is the rotation ρ [[−cos φ, sin φ], [−sin φ, −cos φ]] (the
    mean of the diagonal and the half difference of the off-diagonal); the offset is its φ, and the gain the
    mean of the diagonal of P_n(0) R(φ) with that offset, −ρ. (For 1P the column of P(0) alone, which the
    measured route sees and :func:`hawt_controllers.design.linear_models.decoupling_offset` uses, gives 0.2° less at
    18 m/s and a 2.6 % larger gain.)
    """
    p = harmonic_response(model, harmonic, [0.0])[0].real
    cos, sin = (p[0, 0] + p[1, 1]) / 2.0, (p[1, 0] - p[0, 1]) / 2.0
    return HarmonicResponse(model.wind_speed, harmonic, model.pitch, model.rotor_speed, -math.hypot(cos, sin),
                            offset_from_dc_response(-cos, -sin))


def loop_response(model: ColemanModel, harmonic: int, integral_gain: float, phase_offset: float, dt: float,
                  omega: ArrayLike) -> np.ndarray:
    """L(jω): the return ratio of harmonic n's IPC on the linear model, S = (I + L)⁻¹, shape (len(omega), 2, 2).

    L = −P_n(jω) K(e^{jωdt}) F(e^{jωdt}): P_n from the pitch command (:func:`harmonic_response`, the actuator
    inside), K the integrators through the inverse transform's phase offset at the law's dt
    (:func:`hawt_controllers.laws.lqg_ipc.integrator_ipc`, forward Euler: a step's delay), F the law's pre-filter
    (:func:`hawt_controllers.laws.ipc.design_prefilter`); the minus sign because the law pitches to feather on a
    positive moment.
    """
    omega = np.atleast_1d(np.asarray(omega, dtype=float))
    law = state_space_response(integrator_ipc(integral_gain, phase_offset, dt), np.exp(1j * omega * dt))
    prefilter = design_prefilter(HarmonicIpcConfig(harmonic=harmonic), dt)
    filtered = 1.0 if prefilter is None else prefilter.frequency_response(omega)[:, None, None]
    return -harmonic_response(model, harmonic, omega) @ law * (filtered * _PITCH_UNIT / _MOMENT_UNIT)


def _axis_loop(model: ColemanModel, harmonic: int, integral_gain: float, phase_offset: float, dt: float,
               omega: ArrayLike) -> np.ndarray:
    loop = loop_response(model, harmonic, integral_gain, phase_offset, dt, omega)
    return (loop[:, 0, 0] + loop[:, 1, 1]) / 2.0


def loop_crossover(model: ColemanModel, harmonic: int, integral_gain: float, phase_offset: float,
                   dt: float) -> Tuple[float, float]:
    """The crossover ω_c [rad/s] of the designed loop on the linear model, where the loop of one axis (the mean
    of L11 and L22, :func:`loop_response`) first has |L| = 1, and the phase margin π + ∠L(jω_c) [rad]."""
    grid = np.geomspace(1e-3, 10.0, 200)
    below = np.abs(_axis_loop(model, harmonic, integral_gain, phase_offset, dt, grid)) < 1.0
    if below[0] or not below.any():
        raise ValueError("the loop does not cross over between 1e-3 and 10 rad/s")
    k = int(np.argmax(below))
    crossover = brentq(lambda w: abs(_axis_loop(model, harmonic, integral_gain, phase_offset, dt, w)[0]) - 1.0,
                       grid[k - 1], grid[k], xtol=1e-9)
    return crossover, float(np.angle(-_axis_loop(model, harmonic, integral_gain, phase_offset, dt, crossover)[0]))


@dataclass(frozen=True)
class LoopAnalysis:
    """Harmonic n's integrator IPC closed on the linear model (:func:`loop_analysis`; Disario §5-3-2).

    ``crossover`` [rad/s] and ``phase_margin`` [rad] as :func:`loop_crossover`; ``rga`` |RGA11| of the plant
    with the offset, P_n(jω_c) R(φ), at the crossover (1: tilt and yaw decoupled); ``peak`` the largest singular
    value of the sensitivity S = (I + L)⁻¹ over frequency, at ``peak_frequency`` [rad/s]; ``at_1p`` the largest
    at the rotor speed Ω; ``bandwidth`` where the largest and the smallest singular value of S first reach
    1/√2 [rad/s] (Disario: a region [0.38, 0.65] rad/s without the offset, one 0.47 rad/s with it).
    """

    crossover: float
    phase_margin: float
    rga: float
    peak: float
    peak_frequency: float
    at_1p: float
    bandwidth: Tuple[float, float]


def loop_analysis(model: ColemanModel, harmonic: int, integral_gain: float, phase_offset: float, dt: float,
                  omega: ArrayLike = np.geomspace(0.01, 10.0, 1501)) -> LoopAnalysis:
    """:class:`LoopAnalysis` of the loop :func:`loop_response`, the sensitivity sampled at ``omega`` [rad/s]."""
    omega = np.asarray(omega, dtype=float)
    crossover, margin = loop_crossover(model, harmonic, integral_gain, phase_offset, dt)
    loop = loop_response(model, harmonic, integral_gain, phase_offset, dt,
                         np.append(omega, [crossover, model.rotor_speed]))
    # RGA is blind to a scalar factor, and L is P_n R(φ) times one: RGA(L) = RGA(P_n R(φ))
    rga = abs(complex(relative_gain_array(loop[-2])[0, 0]))
    sigma = np.linalg.svd(np.linalg.inv(np.eye(2) + loop), compute_uv=False)
    over = sigma[:-2]
    peak = int(np.argmax(over[:, 0]))
    level = 1.0 / math.sqrt(2.0)
    reach = [int(np.argmax(over[:, i] >= level)) for i in (0, 1)]
    bandwidth = tuple(float(np.interp(level, over[k - 1:k + 1, i], omega[k - 1:k + 1])) for i, k in enumerate(reach))
    return LoopAnalysis(crossover, margin, rga, float(over[peak, 0]), float(omega[peak]), float(sigma[-1, 0]),
                        bandwidth)


def tune(responses: Sequence[HarmonicResponse], reference_speed: float, bandwidth: float, loop_delay: float,
         dt: float) -> Tuple[Dict[str, object], IntegralGainDesign]:
    """The ipc_h{n} parameters from one harmonic's responses over the operating points: van Engelen's integral
    gain for the crossover ``bandwidth`` [rad/s] at the response nearest ``reference_speed``, its phase offset,
    and the schedule over collective pitch (factors k_ref/k); and the gain design."""
    reference = min(responses, key=lambda r: abs(r.wind_speed - reference_speed))
    prefilter = design_prefilter(HarmonicIpcConfig(harmonic=reference.harmonic), dt)
    gain = design_integral_gain(reference.sensitivity, bandwidth, loop_delay, prefilter)
    ordered = sorted(responses, key=lambda r: r.collective_pitch)
    return {"harmonic": reference.harmonic,
            "integral_gain": float(gain.integral_gain),
            "phase_offset": float(reference.phase),
            "schedule_breakpoints": [float(r.collective_pitch) for r in ordered],
            "schedule_factors": [float(reference.sensitivity / r.sensitivity) for r in ordered]}, gain


def design(turbine: Turbine, harmonics: Sequence[int], wind_speeds: Sequence[float], reference_speed: float,
           bandwidth: float, loop_delay: float, dt: float, models: Sequence[ColemanModel] = ()) -> Dict[str, dict]:
    """Parameters of each ipc_h{n} node (:func:`tune`), the harmonics in ascending order: from the linear ``models``
    (the model route) if they hold every wind speed, with the measured route printed beside them; else from the
    measured route. Each harmonic's rate budget at the reference operating point is printed; the harmonics past
    the budget (:func:`within_budget`) get ``active: false``, and the last line says which."""
    at: Dict[float, Optional[ColemanModel]] = {
        v: next((m for m in models if abs(m.wind_speed - v) < 1e-6), None) for v in wind_speeds}
    missing = [v for v, m in at.items() if m is None]
    if models and missing:
        print("no linear model at " + ", ".join(f"{v:g}" for v in missing) + " m/s: the measured route")
    nodes = {}
    budgets = []
    for n in sorted(set(harmonics)):
        print(f"h{n}: measuring the plant's {n}P response at " + ", ".join(f"{v:g}" for v in wind_speeds) + " m/s",
              flush=True)
        measured = [measure_harmonic_response(turbine, v, n, dt=dt) for v in wind_speeds]
        responses = measured if missing else [model_harmonic_response(at[v], n) for v in wind_speeds]
        parameters, gain = tune(responses, reference_speed, bandwidth, loop_delay, dt)
        nodes[f"/**/ipc_h{n}"] = {"ros__parameters": parameters}
        route = "measured" if missing else "linear model"
        print(f"h{n} ({route}): " + "; ".join(
            f"{r.wind_speed:g} m/s pitch {math.degrees(r.collective_pitch):.1f} deg: dM/dtheta "
            f"{r.sensitivity / 1e6:.2f} MN*m/rad, phase {math.degrees(r.phase):.1f} deg" for r in responses))
        reference = min(responses, key=lambda r: abs(r.wind_speed - reference_speed))
        budgets.append(rate_budget(turbine, reference, dt=dt))
        used = sum(b.share for b in budgets)
        print(f"h{n}: cancelling the {n}P moment of steady wind with shear 0.2 at {reference.wind_speed:g} m/s takes "
              f"±{math.degrees(budgets[-1].amplitude):.2f} deg at {math.degrees(budgets[-1].rate):.2f} deg/s, "
              f"{100 * budgets[-1].share:.0f} % of the actuator's {math.degrees(budgets[-1].max_rate):.1f} deg/s "
              f"({100 * used:.0f} % with the harmonics before it)"
              + ("; turbulence asks several times the steady shear: expect the pitch rate-limited with it"
                 if used > RATE_BUDGET_WARNING else ""))
        if missing:
            print(f"h{n}: k_i {gain.integral_gain:.3e} rad/(N*m*s) at {reference.wind_speed:g} m/s, crossover "
                  f"{gain.crossover_frequency / (2 * math.pi):.3f} Hz, phase margin "
                  f"{math.degrees(gain.phase_margin):.1f} deg (with the loop delay)")
            continue
        print(f"h{n} cross-check, the measured static response against the model's: " + "; ".join(
            f"{m.wind_speed:g} m/s phase {math.degrees(m.phase - r.phase):+.2f} deg, dM/dtheta "
            f"{100 * (m.sensitivity / r.sensitivity - 1):+.1f} %, pitch "
            f"{math.degrees(m.collective_pitch - r.collective_pitch):+.2f} deg" for m, r in zip(measured, responses)))
        crossover, margin = loop_crossover(at[reference.wind_speed], n, gain.integral_gain, reference.phase, dt)
        print(f"h{n}: k_i {gain.integral_gain:.3e} rad/(N*m*s) at {reference.wind_speed:g} m/s, crossover on the "
              f"model {crossover / (2 * math.pi):.3f} Hz (designed {bandwidth / (2 * math.pi):.3f}), phase margin "
              f"{math.degrees(margin):.1f} deg")
    active = within_budget(budgets)
    inactive = [b.harmonic for b in budgets if b.harmonic not in active]
    for n in inactive:
        nodes[f"/**/ipc_h{n}"]["ros__parameters"]["active"] = False
    print(_budget_summary(budgets, active, inactive))
    return nodes


def _budget_summary(budgets: Sequence[RateBudget], active: Sequence[int], inactive: Sequence[int]) -> str:
    """The design's last line: which harmonics fit the rate budget and are active, which are written inactive."""
    limit = f"within {100 * RATE_BUDGET_LIMIT:.0f} % of the actuator's {math.degrees(budgets[0].max_rate):.1f} deg/s"
    fits = sum(b.share for b in budgets[:len(active)])
    names = ", ".join(f"h{n}" for n in active)
    if not inactive:
        return f"rate budget: {names} take {100 * fits:.0f} % together, {limit}: all active"
    first = budgets[len(active)]
    return ((f"rate budget: {names} take{'s' if len(active) == 1 else ''} {100 * fits:.0f} %, {limit}; "
             f"h{first.harmonic} would bring it to {100 * (fits + first.share):.0f} %: " if active else
             f"rate budget: h{first.harmonic} alone takes {100 * first.share:.0f} %, not {limit}: ")
            + ", ".join(f"h{n}" for n in inactive) + " written inactive (active: false, which the graphs' ipc_hN "
            f"arguments do not override; -p ipc_h{first.harmonic}.active:=true starts one active, hawt switch "
            f"--activate ipc_h{first.harmonic} brings one in)")


@dataclass(frozen=True)
class CouplingPoint:
    """Disario's analysis of one measured response (hawt_controllers.laws.coleman_coupling, the notes' check B10).

    ``offset`` is the phase offset φ_n = nψ_n [rad] that decouples tilt from yaw at DC (atan2(P21(0), P11(0))
    of the response measured without offset); ``cross_gain`` |P21/P11| and ``rga`` RGA11 at DC without it
    (with it: 0 and 1); ``time_constant`` the first-order blade K/(τs + 1) with the same offset,
    τ = tan(φ_n)/(nω0) (Disario eq. 3-7).
    """

    response: HarmonicResponse
    offset: float
    cross_gain: float
    rga: float
    time_constant: float


def coupling_survey(turbine: Turbine, wind_speeds: Sequence[float], harmonics: Sequence[int], dt: float = 0.01,
                    progress=lambda line: None) -> List[CouplingPoint]:
    """The decoupling offset and the coupling without it, per wind speed and harmonic, from the plant's response."""
    points = []
    for v in wind_speeds:
        for n in harmonics:
            r = measure_harmonic_response(turbine, v, n, dt=dt)
            p11, p21 = math.cos(r.phase), math.sin(r.phase)  # the response rotated by φ, its sign taken out
            dc = np.array([[p11, -p21], [p21, p11]])
            rga = float(relative_gain_array(dc)[0, 0])
            points.append(CouplingPoint(r, offset_from_dc_response(p11, p21), abs(p21 / p11), rga,
                                        math.tan(r.phase) / (n * r.rotor_speed)))
            progress(f"{v:g} m/s, harmonic {n}: offset {math.degrees(r.phase):.1f} deg")
    return points


def retuned(nodes: Dict[str, dict], harmonic: int = 1, gain_factor: float = 1.3) -> Dict[str, dict]:
    """The ``ipc_h{n}_retuned`` controller of the switching graph: harmonic n's design with ``gain_factor`` times
    its integral gain and no gain schedule."""
    design_n = nodes[f"/**/ipc_h{harmonic}"]["ros__parameters"]
    return {f"/**/ipc_h{harmonic}_retuned": {"ros__parameters": {
        "harmonic": harmonic, "integral_gain": gain_factor * design_n["integral_gain"],
        "phase_offset": design_n["phase_offset"]}}}


def _write(path: Path, nodes: Dict[str, dict], what: str, how: str) -> None:
    header = (f"# {what}, written by hawt design ipc {how}.\n"
              "# Gains, phase offsets and schedules come from the plant's response: its linear models or its "
              "measured static response (hawt_controllers.design.ipc_design).\n")
    path.write_text(header + yaml.safe_dump(nodes, sort_keys=False))
    print(f"wrote {path}")


def write_tunings(turbine: str, harmonics: Sequence[int], wind_speeds: Sequence[float], reference_speed: float,
                  bandwidth: float, loop_delay: float, dt: float, linear_models: Optional[Path], measured: bool,
                  output: Optional[Path], retuned_output: Optional[Path],
                  retuned_only: bool) -> Tuple[Path, Optional[Path]]:
    """``hawt design ipc``: :func:`design` for ``turbine`` (a packaged turbine's name or an imported turbine's
    folder) written as the ipc graph's parameter file, and :func:`retuned` from it; returns the two paths (the
    second None when the design has no 1P to derive it from).

    Parameters
    ----------
    turbine : str
        What :func:`hawt_plant.turbine.turbine_from` takes.
    harmonics, wind_speeds, reference_speed, bandwidth, loop_delay, dt
        As :func:`design` takes them (wind speeds [m/s], ``bandwidth`` the crossover [rad/s], ``loop_delay`` and
        ``dt`` [s]).
    linear_models : Path or None
        The Coleman-frame models (``hawt linearize``); None: the turbine's ``linear`` tuning if it has one, else
        the measured route (said in one line).
    measured : bool
        The measured static response only, no linear models.
    output, retuned_output : Path or None
        The files to write; None: the turbine's ``ipc`` and ``ipc_retuned`` tunings, or for ``retuned_output`` with an
        ``output`` given, ``<output>_retuned`` beside it
        (:func:`hawt_controllers.design.tunings.tuning_path`).
    retuned_only : bool
        Only derive the retuned controller again from the existing ``output``.

    Raises
    ------
    TurbineDefinitionError
        No such turbine, or a bad definition.
    TuningError
        ``retuned_only`` without an ``output`` to derive from.
    """
    model = turbine_from(turbine)
    # beside a given output rather than over the turbine's own (a design written elsewhere is the user's)
    retuned_output = retuned_output or (output.with_name(f"{output.stem}_retuned{output.suffix}") if output else
                                        tuning_path(turbine, "ipc_retuned"))
    output = output or tuning_path(turbine, "ipc")
    if retuned_only:
        if not output.is_file():
            raise TuningError(f"--retuned-only: no {output} to derive the retuned controller from (write it first: "
                              f"hawt design ipc --turbine {turbine})")
        nodes = yaml.safe_load(output.read_text())
    else:
        if linear_models is None and not measured:
            try:
                linear_models = tuning_file(turbine, "linear")
            except TuningError as error:
                print(f"designing from the plant's measured static response (the measured route): {error}")
        nodes = design(model, harmonics, wind_speeds, reference_speed, bandwidth, loop_delay, dt,
                       () if measured or linear_models is None else load_models(linear_models))
        route = "the measured static response" if measured or linear_models is None else f"{linear_models}"
        _write(output, nodes, f"IPC parameters of the {model.name}",
               f"--turbine {turbine} (harmonics {' '.join(map(str, sorted(set(harmonics))))} at "
               f"{' '.join(f'{v:g}' for v in wind_speeds)} m/s, gain at {reference_speed:g} m/s for "
               f"{bandwidth / (2 * math.pi):g} Hz, loop delay {loop_delay:g} s, dt {dt:g} s; from {route})")
    if "/**/ipc_h1" not in nodes:
        print(f"no 1P design in {output}: the retuned 1P controller is not written")
        return output, None
    _write(retuned_output, retuned(nodes), f"The retuned 1P controller, derived from {output.name}",
           f"--turbine {turbine}" + (" --retuned-only" if retuned_only else ""))
    return output, retuned_output
