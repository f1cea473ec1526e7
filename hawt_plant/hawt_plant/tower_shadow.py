"""Tower shadow of an upwind rotor: potential flow around the tower (a doublet in uniform flow)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hawt_plant.turbine import Tower

__all__ = ["TowerShadow", "potential_flow_disturbance"]

# Constants of the per-step formulas as 0-d arrays: numpy 2 combines an array of a few dozen
# elements with a 0-d array about twice as fast as with a Python float.
_ZERO, _MINUS_TWO, _INSIDE = np.array(0.0), np.array(-2.0), np.array(1e-12)


def potential_flow_disturbance(x: np.ndarray, y: np.ndarray, radius: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Velocity change around a cylinder in uniform flow, per unit free-stream speed.

    Parameters
    ----------
    x : ndarray
        Downwind distance of the point from the tower centreline [m] (negative upwind).
    y : ndarray
        Lateral distance of the point from the tower centreline [m].
    radius : ndarray
        Tower radius a at the point's height [m]; 0 gives no disturbance. Points inside the
        tower are evaluated on its surface.

    Returns
    -------
    du, dv : ndarray
        Change of the longitudinal and lateral velocity divided by the free-stream speed:
        ``u = U (1 + du)``, ``v = U dv``.

    Notes
    -----
    Stream function of a doublet in uniform flow, Fratini (2019) eq. 2.5; the longitudinal
    part is eq. 3.43, ``v_tower = V a^2 (y^2 - x^2) / (x^2 + y^2)^2``; the lateral part
    ``-2 V a^2 x y / (x^2 + y^2)^2`` is the same potential's other derivative (AeroDyn
    ``TwrPotent = 1``). Straight upwind of the tower (y = 0) the deficit is ``-a^2 / x^2``;
    the largest speed-up, ``a^2 / (8 x^2)`` at ``|y| = sqrt(3) |x|``, is 1/8 of it
    (seed000_fratini.md AC-11).
    """
    x2, y2, a2 = x * x, y * y, radius * radius
    r2 = np.maximum(x2 + y2, a2 + _INSIDE)
    q = a2 / (r2 * r2)
    return q * (y2 - x2), _MINUS_TWO * q * x * y


@dataclass(frozen=True, eq=False)
class TowerShadow:
    """Tower shadow applied by the rotor model to points upwind of and below the tower top.

    Parameters
    ----------
    elevation : ndarray, shape (A,)
        Heights of the tower outline [m], increasing.
    radius : ndarray, shape (A,)
        Tower radius at those heights [m].
    top_height : float
        Tower-top height [m]; there is no tower above it.

    Notes
    -----
    Fratini (2019) §3.2.3 applies eq. 3.44 only in the "tower-shadow zone" 90° < psi < 270°
    (seed000_fratini.md AC-11). Here the zone is where the tower physically is: points below
    the tower top and upwind of its centreline (x < 0); elsewhere the disturbance is zero.
    The disturbance scales the local free-stream speed rather than the hub speed V_h, so it
    also acts on sheared and turbulent inflow.
    """

    elevation: np.ndarray
    radius: np.ndarray
    top_height: float

    def __post_init__(self) -> None:
        # The outline up to just below the top, then no tower: interpolation in it with 0 to the
        # right is the radius below the top and 0 at and above it.
        below = np.nextafter(self.top_height, -np.inf)
        keep = self.elevation < below
        radius_below = np.interp(below, self.elevation, self.radius)
        object.__setattr__(self, "_outline", (np.append(self.elevation[keep], below),
                                              np.append(self.radius[keep], radius_below)))

    @classmethod
    def from_tower(cls, tower: Tower) -> "TowerShadow":
        """The shadow of a turbine's tower (its aerodynamic outline and height)."""
        return cls(tower.outline_elevation, tower.outline_diameter / 2.0, tower.height)

    def disturbance(self, x: np.ndarray, y: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Relative velocity change ``(du, dv)`` at points ``(x, y, z)`` [m] relative to the tower base.

        See :func:`potential_flow_disturbance`; zero above the tower top and downwind of the
        tower centreline.
        """
        elevation, radius = self._outline
        return potential_flow_disturbance(x, y, np.interp(z, elevation, radius, right=0.0) * (x < _ZERO))
