"""The plant's linear models in the Coleman frame over the power curve (``hawt linearize``).

Per wind speed: the plant (the plant node's defaults and overrides, steady sheared wind, quasi-steady
aerodynamics: :func:`linearized_plant`) is
linearised about its open-loop periodic orbit at N azimuths (hawt_plant.linearization), each
model is written in multi-blade coordinates (Bir 2008, hawt_controllers.laws.mbc3: flap, flap rate,
pitch and pitch rate of the blades; pitch commands and blade-effective winds; root moments) and
the N models are averaged to one LTI model. The models go to one ``.npz`` file
(hawt_controllers.laws.coleman_models);
``scipy.signal.StateSpace(a[k], b[k], c[k], d[k])`` is the model at ``wind_speeds[k]``.
"""
from __future__ import annotations

import math
import re
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, List, Mapping, Optional, Sequence, Tuple

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import minimize_scalar

from hawt_plant.linearization import PeriodicLinearization, linearize_model

from hawt_controllers.laws.coleman_coupling import offset_from_dc_response
from hawt_controllers.laws.collective import BaselineCollectiveConfig, gain_correction_factor, integral_gain_factor
from hawt_controllers.laws.coleman_models import ColemanModel, state_space_response
from hawt_controllers.laws.mbc3 import BladeGroups, LinearModel, azimuth_average, mbc3

__all__ = ["QUASI_STEADY", "Mode", "blade_groups", "campbell_figure", "coleman_model", "band_offset",
           "collective_loop_gain", "decoupling_offset", "stability_margins",
           "labelled_modes", "tilt_yaw_response", "linearize_at", "linearized_plant", "linearize_power_curve",
           "ModelSummary", "model_summary"]

QUASI_STEADY = {"unsteady_airfoil": False, "dynamic_inflow": False}
"""The aerodynamic options a linear model is of, over the turbine's own: static polars and the quasi-steady
induction (the model's continuous dynamics, TurbineModel.continuous_dynamics, have neither unsteady-airfoil nor
inflow states). The other options (tower shadow and drag, skewed wake) are the turbine's or the given ones."""


def linearized_plant(wind_speed: float, plant: Optional[Mapping[str, Any]] = None) -> dict:
    """The plant parameter values a linear model at ``wind_speed`` [m/s] is of: ``plant`` (name -> value) over
    :data:`QUASI_STEADY` and the plant node's defaults, the wind steady."""
    from hawt_core.parameter_table import resolve_values
    from hawt_plant.plant_setup import PARAMETERS

    return resolve_values(PARAMETERS, {**QUASI_STEADY, **(plant or {}), "wind_type": "steady",
                                       "wind_speed": wind_speed})


def _group(names: Sequence[str], base: str, blades: int) -> tuple:
    return tuple(names.index(f"{base}_{i}") for i in range(1, blades + 1))


def blade_groups(periodic: PeriodicLinearization, blades: int) -> BladeGroups:
    """The blade-wise channels of the plant's linear model (hawt_plant.linearization's names; the edgewise states of
    blades that have the mode)."""
    bases = ("flap", "pitch", "edge") if "edge_1" in periodic.states else ("flap", "pitch")
    states = tuple(_group(periodic.states, name, blades) for base in bases for name in (base, f"{base}_rate"))
    return BladeGroups(states=states, rates=tuple((2 * k + 1, 2 * k) for k in range(len(bases))),
                       inputs=tuple(_group(periodic.inputs, base, blades) for base in ("pitch_command", "wind")),
                       outputs=tuple(_group(periodic.outputs, base, blades)
                                     for base in ("root_moment_oop", "root_moment_ip")))


def coleman_model(periodic: PeriodicLinearization, blades: int) -> LinearModel:
    """Every azimuth's model in the Coleman frame, averaged over the revolution."""
    groups = blade_groups(periodic, blades)
    return azimuth_average([
        mbc3(LinearModel(periodic.a[k], periodic.b[k], periodic.c[k], periodic.d[k], periodic.states,
                         periodic.inputs, periodic.outputs), azimuth, periodic.rotor_speed, groups)
        for k, azimuth in enumerate(periodic.azimuths)])


def linearize_at(wind_speed: float, azimuths: int = 12, settle_time: float = 60.0,
                 plant: Optional[Mapping[str, Any]] = None) -> ColemanModel:
    """The Coleman-frame model at ``wind_speed`` [m/s] of the plant with parameters ``plant`` (name -> value,
    over the plant node's defaults and quasi-steady aerodynamics; the wind is steady: :func:`linearized_plant`)."""
    from hawt_plant.plant_setup import make_plant

    start = time.perf_counter()
    _, model, _ = make_plant(linearized_plant(wind_speed, plant))
    periodic = linearize_model(model, azimuths, settle_time)
    return ColemanModel(wind_speed, periodic.rotor_speed, periodic.pitch, periodic.generator_torque,
                        coleman_model(periodic, model.number_of_blades), periodic.loops,
                        time.perf_counter() - start)


def linearize_power_curve(wind_speeds: Sequence[float], azimuths: int = 12, settle_time: float = 60.0,
                          plant: Optional[Mapping[str, Any]] = None, workers: int = 1,
                          progress: Optional[Callable[[ColemanModel, int, int], None]] = None) -> List[ColemanModel]:
    """:func:`linearize_at` at every wind speed, in ``workers`` processes; sorted by wind speed.
    ``progress(model, done, total)`` after each."""
    results: List[ColemanModel] = []
    with ProcessPoolExecutor(max_workers=max(1, workers)) as pool:
        futures = [pool.submit(linearize_at, float(v), azimuths, settle_time, plant) for v in wind_speeds]
        for future in as_completed(futures):
            results.append(future.result())
            if progress is not None:
                progress(results[-1], len(results), len(futures))
    return sorted(results, key=lambda r: r.wind_speed)


@dataclass(frozen=True)
class Mode:
    """One oscillating mode of a linear model: frequency [Hz], damping ratio and the state that takes the
    largest part in it (participation factor |v_i w_i|, Verghese et al. 1982: scale-free)."""

    frequency: float
    damping: float
    state: str


def labelled_modes(model: LinearModel) -> List[Mode]:
    """The model's oscillating modes (complex eigenvalue pairs), by frequency, each named by its dominant state.

    A displacement and its rate count as one (``tower_fa_rate`` adds to ``tower_fa``), and so do the cos and
    sin coordinates of a blade group (``flap_cyclic``: its two modes are the backward and forward whirl, the
    blade's frequency -/+ the rotor speed).
    """
    from scipy.linalg import eig

    values, left, right = eig(model.a, left=True, right=True)
    names = [re.sub(r"_(cos|sin)$", "_cyclic", name.replace("_rate", "")) for name in model.states]
    modes = []
    for k in np.flatnonzero(values.imag > 1e-9):
        participation = np.abs(left[:, k].conj() * right[:, k])
        shares: dict = {}
        for name, share in zip(names, participation):
            shares[name] = shares.get(name, 0.0) + share
        magnitude = abs(values[k])
        modes.append(Mode(magnitude / (2.0 * math.pi), -values[k].real / magnitude, max(shares, key=shares.get)))
    return sorted(modes, key=lambda mode: mode.frequency)


def tilt_yaw_response(model: LinearModel, omega: ArrayLike, pitch: str = "command") -> np.ndarray:
    """P(jω): the frequency response [N m/rad] from the cos/sin 1P cyclic pitch to the cos/sin blade-root
    out-of-plane moments at ``omega`` [rad/s], shape (len(omega), 2, 2) (Disario's tilt/yaw plant with ψ = 0).

    ``pitch`` "command": from the pitch command (the actuator inside: what a controller sets); "angle": from
    the pitch angle (the actuator's states held as inputs), Disario's input.
    """
    moments = [model.outputs.index(n) for n in ("root_moment_oop_cos", "root_moment_oop_sin")]
    if pitch == "command":
        inputs = [model.inputs.index(n) for n in ("pitch_command_cos", "pitch_command_sin")]
        a, b, c, d = model.a, model.b[:, inputs], model.c[moments], model.d[np.ix_(moments, inputs)]
    elif pitch == "angle":
        held = [model.states.index(n) for n in ("pitch_cos", "pitch_sin")]
        rest = [i for i, name in enumerate(model.states) if not name.startswith("pitch_")]
        a, b = model.a[np.ix_(rest, rest)], model.a[np.ix_(rest, held)]
        c, d = model.c[np.ix_(moments, rest)], model.c[np.ix_(moments, held)]
    else:
        raise ValueError(f"pitch: expected 'command' or 'angle', found {pitch!r}")
    return state_space_response((a, b, c, d), 1j * np.atleast_1d(omega))


def collective_loop_gain(model: ColemanModel, config: BaselineCollectiveConfig, omega: ArrayLike) -> np.ndarray:
    """L(jω) at ``omega`` [rad/s] (> 0) of the baseline collective pitch loop (Jonkman et al. 2009 ch. 7,
    hawt_controllers.laws.collective) at the model's operating point, broken at the pitch command:

        L(s) = -GK(θ_op) (K_P + f(θ_op) K_I/s) ω_c/(s + ω_c) P(s),

    P the model's pitch_command_collective -> generator_speed [rad/s per rad]: the PI on the low-passed generator
    speed, gain-scheduled at the operating pitch θ_op (f: the near-rated factor on K_I), in the convention of
    negative feedback (the PI pitches to feather on a positive speed error, which slows the rotor: L > 0 at low
    frequency). The generator torque is held, as in the model (the region-3 torque law's loop is open), and the
    law is taken in continuous time."""
    m = model.model
    column, row = m.inputs.index("pitch_command_collective"), m.outputs.index("generator_speed")
    plant = state_space_response((m.a, m.b[:, [column]], m.c[[row]], m.d[[row]][:, [column]]),
                                 1j * np.atleast_1d(omega))[:, 0, 0]
    s = 1j * np.atleast_1d(omega)
    corner = config.generator_speed_corner_frequency
    schedule = gain_correction_factor(model.pitch, config.gain_doubling_pitch)
    integral = config.integral_gain * integral_gain_factor(model.pitch, config)
    return -schedule * (config.proportional_gain + integral / s) * corner / (s + corner) * plant


def _crossings(values: np.ndarray, loop: np.ndarray) -> np.ndarray:
    """``loop`` interpolated linearly where ``values`` changes sign between samples."""
    k = np.flatnonzero(np.sign(values[:-1]) * np.sign(values[1:]) < 0)
    t = values[k] / (values[k] - values[k + 1])
    return loop[k] + t * (loop[k + 1] - loop[k])


def stability_margins(loop: ArrayLike) -> Tuple[float, float]:
    """The gain margin [-] and the phase margin [rad] of a loop gain L(jω) (negative feedback, 1 + L) sampled on a
    fine, increasing frequency grid: the smallest 1/|L| where L crosses the negative real axis and the smallest
    ∠L + π (in (-π, π]) where |L| crosses 1, each crossing interpolated between its samples; inf where none."""
    loop = np.asarray(loop)
    phase = _crossings(loop.imag, loop)
    phase = phase[phase.real < 0.0]
    gain = _crossings(np.abs(loop) - 1.0, loop)
    return (float(np.min(1.0 / np.abs(phase))) if phase.size else math.inf,
            float(np.min(np.angle(-gain))) if gain.size else math.inf)


def _rotation(offset: float) -> np.ndarray:
    """The cos/sin pitch of a demand (θ_c, θ_s) with phase offset φ: θ_i = θ_c cos(ψ_i + φ) + θ_s sin(ψ_i + φ)."""
    c, s = math.cos(offset), math.sin(offset)
    return np.array([[c, s], [-s, c]])


def decoupling_offset(model: LinearModel, pitch: str = "command") -> float:
    """Disario's DC-decoupling 1P offset [rad]: atan2(-P21(0), -P11(0)), the sign of the response taken out
    (pitch to feather lowers the moment; hawt_controllers.laws.coleman_coupling.offset_from_dc_response)."""
    p = tilt_yaw_response(model, [0.0], pitch)[0].real
    return offset_from_dc_response(-p[0, 0], -p[1, 0])


def band_offset(model: LinearModel, pitch: str = "angle", band: Tuple[float, float] = (0.1, 1.0)) -> float:
    """The offset in [0, 90°] [rad] that minimises η(ψ), the mean |P12(jω)| with the offset over ``band``
    [rad/s] (Disario eq. 4-4, §4-4-4: 19° at 25 m/s for FAST's NREL 5 MW, from the pitch angle)."""
    response = tilt_yaw_response(model, np.linspace(band[0], band[1], 200), pitch)

    def eta(offset: float) -> float:
        return float(np.mean(np.abs((response @ _rotation(offset))[:, 0, 1])))

    grid = np.radians(np.arange(0.0, 90.5, 1.0))
    start = float(grid[int(np.argmin([eta(psi) for psi in grid]))])
    return float(minimize_scalar(eta, bounds=(max(start - math.radians(1.0), 0.0), start + math.radians(1.0)),
                                 method="bounded", options={"xatol": 1e-6}).x)


@dataclass(frozen=True)
class ModelSummary:
    """What ``hawt linearize`` prints of one operating point's model besides its operating point."""

    gain: float
    """dM_cos/dθ_cos at DC [N m/rad], from the pitch command."""
    offsets: Tuple[float, float, float]
    """Disario's 1P offsets [rad]: decoupling at DC from the pitch command (the IPC design's) and from the pitch
    angle (:func:`decoupling_offset`), and minimising the mean |P12| over 0.1-1 rad/s from the angle
    (:func:`band_offset`)."""
    modes: List[Mode]
    """The oscillating modes, by frequency (:func:`labelled_modes`)."""


def model_summary(model: LinearModel) -> ModelSummary:
    """The 1P tilt/yaw gain at DC, Disario's offsets and the labelled modes of ``model``."""
    modes = labelled_modes(model)
    return ModelSummary(tilt_yaw_response(model, [0.0])[0, 0, 0].real,
                        (decoupling_offset(model, "command"), decoupling_offset(model, "angle"), band_offset(model)),
                        modes)


def campbell_figure(models: Sequence[ColemanModel], path: Path, harmonics: Sequence[int] = (1, 3, 6)) -> None:
    """The Campbell diagram: every oscillating mode's frequency against wind speed, coloured by its damping
    ratio, with the rotor harmonics nP."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(8, 5))
    speeds = np.array([m.wind_speed for m in models])
    points = [(m.wind_speed, mode.frequency, mode.damping) for m in models for mode in labelled_modes(m.model)]
    x, frequency, damping = np.array(points).T if points else ([], [], [])
    labels: List[list] = []  # [frequency, names]: modes closer than 0.03 Hz share one label
    for mode in labelled_modes(models[0].model):
        if labels and mode.frequency - labels[-1][0] < 0.03:
            labels[-1][1].append(mode.state)
        else:
            labels.append([mode.frequency, [mode.state]])
    for label_frequency, names in labels:
        axes.annotate(", ".join(names), (speeds[0], label_frequency), xytext=(-6, 0), textcoords="offset points",
                      ha="right", va="center", fontsize=7)
    shown = axes.scatter(x, frequency, c=damping, cmap="viridis_r", vmin=0.0, vmax=1.0, s=18)
    figure.colorbar(shown, ax=axes, label="damping ratio")
    for n in harmonics:
        axes.plot(speeds, [n * m.rotor_speed / (2.0 * math.pi) for m in models], "--", color="grey", lw=0.8)
        axes.annotate(f"{n}P", (speeds[-1], n * models[-1].rotor_speed / (2.0 * math.pi)), fontsize=8)
    axes.set_xlim(speeds[0] - 0.25 * (speeds[-1] - speeds[0]) - 1.0, speeds[-1] + 1.0)
    axes.set_xlabel("wind speed [m/s]")
    axes.set_ylabel("frequency [Hz]")
    axes.set_title(f"Campbell diagram: Coleman frame, azimuth average\nloops {models[0].loops}", fontsize=10)
    axes.grid(alpha=0.3)
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)
