"""Coleman-frame linear models of the plant over the power curve, and their ``.npz`` file.

A :class:`ColemanModel` is the azimuth-averaged multi-blade-coordinate model (Bir 2008, hawt_controllers.laws.mbc3)
at one wind speed with its operating point; hawt_controllers.design.linear_models computes them from the plant
(``hawt linearize``), and the LQG plug-in designs from them at configure. ``scipy.signal.StateSpace(a[k], b[k],
c[k], d[k])`` is the model at ``wind_speeds[k]`` of a file.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import List, Sequence, Tuple

import numpy as np
from numpy.typing import ArrayLike

from hawt_controllers.laws.mbc3 import LinearModel

__all__ = ["ColemanModel", "load_models", "save_models", "state_space_response"]


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


def state_space_response(system: Tuple[np.ndarray, ...], points: ArrayLike) -> np.ndarray:
    """c (pI − a)⁻¹ b + d of the system (a, b, c, d) at every complex point p (s = jω, or z = e^{jωdt} for a
    discrete system), shape (len(points), outputs, inputs)."""
    a, b, c, d = system
    identity = np.eye(a.shape[0])
    return np.array([c @ np.linalg.solve(p * identity - a, b) + d for p in np.atleast_1d(points)])


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
