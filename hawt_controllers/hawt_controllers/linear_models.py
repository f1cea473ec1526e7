"""The plant's linear models in the Coleman frame over the power curve (``hawt linearize``).

Per wind speed: the plant (the plant node's defaults and overrides, steady sheared wind) is
linearised about its open-loop periodic orbit at N azimuths (hawt_plant.linearization), each
model is written in multi-blade coordinates (Bir 2008, hawt_controllers.mbc3: flap, flap rate,
pitch and pitch rate of the blades; pitch commands; root moments) and the N models are averaged
to one LTI model. The models go to one ``.npz`` file (:func:`save_models`, :func:`load_models`);
``scipy.signal.StateSpace(a[k], b[k], c[k], d[k])`` is the model at ``wind_speeds[k]``.
"""
from __future__ import annotations

import math
import re
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, List, Mapping, Optional, Sequence

import numpy as np

from hawt_plant.linearization import PeriodicLinearization, linearize_model

from .coleman_coupling import offset_from_dc_response
from .mbc3 import BladeGroups, LinearModel, azimuth_average, mbc3

__all__ = ["ColemanModel", "Mode", "blade_groups", "campbell_figure", "coleman_model", "dc_gain", "decoupling_offset",
           "labelled_modes", "linearize_at", "linearize_power_curve", "load_models", "save_models"]


@dataclass(frozen=True)
class ColemanModel:
    """The azimuth-averaged Coleman-frame model of the plant at one wind speed, and its operating point."""

    wind_speed: float
    rotor_speed: float
    pitch: float
    generator_torque: float
    model: LinearModel
    loops: str
    seconds: float = math.nan


def _group(names: Sequence[str], base: str, blades: int) -> tuple:
    return tuple(names.index(f"{base}_{i}") for i in range(1, blades + 1))


def blade_groups(periodic: PeriodicLinearization, blades: int) -> BladeGroups:
    """The blade-wise channels of the plant's linear model (hawt_plant.linearization's names)."""
    states = tuple(_group(periodic.states, base, blades) for base in ("flap", "flap_rate", "pitch", "pitch_rate"))
    return BladeGroups(states=states, rates=((1, 0), (3, 2)),
                       inputs=(_group(periodic.inputs, "pitch_command", blades),),
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
    over the plant node's defaults; the wind is steady)."""
    from hawt_core.parameter_table import resolve_values
    from hawt_plant.plant_setup import PARAMETERS, make_plant

    start = time.perf_counter()
    values = resolve_values(PARAMETERS, {**(plant or {}), "wind_type": "steady", "wind_speed": wind_speed})
    _, model, _ = make_plant(values)
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
    modes = []
    for k in np.flatnonzero(values.imag > 1e-9):
        participation = np.abs(left[:, k].conj() * right[:, k])
        names = [re.sub(r"_(cos|sin)$", "_cyclic", name.replace("_rate", "")) for name in model.states]
        shares: dict = {}
        for name, share in zip(names, participation):
            shares[name] = shares.get(name, 0.0) + share
        magnitude = abs(values[k])
        modes.append(Mode(magnitude / (2.0 * math.pi), -values[k].real / magnitude, max(shares, key=shares.get)))
    return sorted(modes, key=lambda mode: mode.frequency)


def dc_gain(model: LinearModel, outputs: Sequence[str], inputs: Sequence[str]) -> np.ndarray:
    """The steady-state gain D - C A^-1 B from ``inputs`` to ``outputs`` (names), shape (outputs, inputs)."""
    gain = model.d - model.c @ np.linalg.solve(model.a, model.b)
    return gain[np.ix_([model.outputs.index(n) for n in outputs], [model.inputs.index(n) for n in inputs])]


def decoupling_offset(model: LinearModel) -> float:
    """Disario's 1P offset [rad] from the model: the angle of the DC response of the cos/sin blade-root moments
    to a cos cyclic pitch, its sign taken out (pitch to feather lowers the moment): atan2(-P21(0), -P11(0)) with
    ψ = 0 (hawt_controllers.coleman_coupling.offset_from_dc_response)."""
    p = dc_gain(model, ("root_moment_oop_cos", "root_moment_oop_sin"), ("pitch_command_cos", "pitch_command_sin"))
    return offset_from_dc_response(-p[0, 0], -p[1, 0])


def save_models(path: Path, models: Sequence[ColemanModel]) -> None:
    """Write the models (same channels at every wind speed) to ``path`` (.npz): arrays ``a``, ``b``, ``c``,
    ``d`` stacked over ``wind_speeds``, the channel names ``states``, ``inputs``, ``outputs``, and the
    operating points ``rotor_speed`` [rad/s], ``pitch`` [rad], ``generator_torque`` [N m] and ``loops``."""
    first = models[0].model
    np.savez(path, wind_speeds=[m.wind_speed for m in models], a=[m.model.a for m in models],
             b=[m.model.b for m in models], c=[m.model.c for m in models], d=[m.model.d for m in models],
             states=list(first.states), inputs=list(first.inputs), outputs=list(first.outputs),
             rotor_speed=[m.rotor_speed for m in models], pitch=[m.pitch for m in models],
             generator_torque=[m.generator_torque for m in models], loops=models[0].loops)


def load_models(path: Path) -> List[ColemanModel]:
    """The models :func:`save_models` wrote."""
    with np.load(path) as data:
        names = [tuple(str(s) for s in data[key]) for key in ("states", "inputs", "outputs")]
        return [ColemanModel(float(v), float(data["rotor_speed"][k]), float(data["pitch"][k]),
                             float(data["generator_torque"][k]),
                             LinearModel(data["a"][k], data["b"][k], data["c"][k], data["d"][k], *names),
                             str(data["loops"]))
                for k, v in enumerate(data["wind_speeds"])]


def campbell_figure(models: Sequence[ColemanModel], path: Path, harmonics: Sequence[int] = (1, 3, 6)) -> None:
    """The Campbell diagram: every oscillating mode's frequency against wind speed, coloured by its damping
    ratio, with the rotor harmonics nP."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(8, 5))
    speeds = np.array([m.wind_speed for m in models])
    points = [(m.wind_speed, f, z) for m in models for f, z in m.model.modes() if 0.0 < z < 1.0]
    x, frequency, damping = np.array(points).T if points else ([], [], [])
    shown = axes.scatter(x, frequency, c=damping, cmap="viridis_r", vmin=0.0, vmax=1.0, s=18)
    figure.colorbar(shown, ax=axes, label="damping ratio")
    for n in harmonics:
        axes.plot(speeds, [n * m.rotor_speed / (2.0 * math.pi) for m in models], "--", color="grey", lw=0.8)
        axes.annotate(f"{n}P", (speeds[-1], n * models[-1].rotor_speed / (2.0 * math.pi)), fontsize=8)
    axes.set_xlabel("wind speed [m/s]")
    axes.set_ylabel("frequency [Hz]")
    axes.set_title(f"Campbell diagram: Coleman frame, azimuth average\nloops {models[0].loops}", fontsize=10)
    axes.grid(alpha=0.3)
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)
