"""Steady inflow with a power-law vertical wind shear."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hawt_plant.compiled import njit, unchecked

__all__ = ["PowerLawWind", "power_law"]

_MIN_HEIGHT = 1e-3  # [m] heights at or below ground are evaluated here (the profile is 0 at z = 0)


@dataclass(frozen=True)
class PowerLawWind:
    """Steady wind along +x with a power-law profile; implements :class:`~hawt_plant.wind_field.WindField`.

    Parameters
    ----------
    mean_speed : float
        Wind speed at ``hub_height`` [m/s], > 0.
    hub_height : float
        Reference height [m], > 0.
    shear_exponent : float
        Power-law exponent alpha [-], 0 for uniform wind.

    Notes
    -----
    Fratini (2019) eq. 2.2, ``U(z) = U(z_r) (z / z_r)^alpha``. On the rotor this is
    ``U(z_r) ((z_r + r cos psi) / z_r)^alpha``, the corrected form of eq. 3.41 (erratum 2 of
    the notes, seed000_fratini.md §8). Lateral and vertical components are zero.

    Examples
    --------
    >>> wind = PowerLawWind(11.4, hub_height=90.0, shear_exponent=0.1)
    >>> float(np.round(wind.velocity(0.0, np.zeros(1), np.zeros(1), np.array([151.5]))[0, 0], 2))
    12.01
    """

    mean_speed: float
    hub_height: float = 90.0
    shear_exponent: float = 0.0

    def __post_init__(self) -> None:
        for name in ("mean_speed", "hub_height"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"{name}: expected a finite value > 0, found {value}")
        if not (math.isfinite(self.shear_exponent) and -1.0 < self.shear_exponent < 1.0):
            raise ValueError(f"shear_exponent: expected a value in (-1, 1), found {self.shear_exponent}")

    def velocity(self, t: float, x: np.ndarray, y: np.ndarray, z: np.ndarray) -> np.ndarray:
        """Wind velocity (u, v, w) [m/s] at the points (x, y, z) [m]; shape ``(3,) + x.shape``."""
        z = np.ascontiguousarray(z, dtype=float)
        out = np.empty((3,) + z.shape)
        _power_law(z.reshape(-1), float(self.mean_speed), float(self.hub_height), float(self.shear_exponent),
                   out.reshape(3, -1))
        return out


@njit
def power_law(z: np.ndarray, mean_speed: float, hub_height: float, shear_exponent: float, out: np.ndarray) -> None:
    """:class:`PowerLawWind`'s velocity at the heights ``z`` (M,) into ``out`` (3, M): U(z_r) (z / z_r)^alpha along x,
    z at least 1 mm (the profile is 0 at the ground), 0 across (compiled: the plant samples the wind every step)."""
    for j in range(z.size):
        if shear_exponent == 0.0:
            out[0, j] = mean_speed
        else:
            out[0, j] = mean_speed * (max(z[j], _MIN_HEIGHT) / hub_height) ** shear_exponent
        out[1, j] = 0.0
        out[2, j] = 0.0


_power_law = unchecked(power_law)  # called with arrays the wind allocated (float64, C-contiguous) and floats
