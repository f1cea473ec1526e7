"""Tower shadow: potential flow around the tower (a doublet in uniform flow) and, behind it, its wake."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hawt_plant.compiled import flat, njit
from hawt_plant.turbine import Tower

__all__ = ["TowerShadow", "WAKE_DEFICIT_LIMIT", "potential_flow_disturbance", "wake_deficit"]

WAKE_DEFICIT_LIMIT = -0.5
"""Largest wake deficit (AeroDyn: "to avoid excessive flow reversal behind the tower")."""



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
    shape, (x, y, radius) = flat(x, y, radius)
    out = np.empty((2, x.size))
    for k in range(x.size):
        out[0, k], out[1, k] = potential_flow(x[k], y[k], radius[k])
    return out[0].reshape(shape), out[1].reshape(shape)


@njit
def potential_flow(x: float, y: float, radius: float) -> tuple[float, float]:
    """:func:`potential_flow_disturbance` at one point."""
    x2, y2, a2 = x * x, y * y, radius * radius
    r2 = np.maximum(x2 + y2, a2 + 1e-12)
    q = a2 / (r2 * r2)
    return q * (y2 - x2), -2.0 * q * x * y


def wake_deficit(x: np.ndarray, y: np.ndarray, radius: np.ndarray, drag_coefficient: float) -> np.ndarray:
    """Velocity deficit in the tower's wake, per unit free-stream speed (Powles' model).

    Parameters
    ----------
    x, y : ndarray
        Downwind and lateral distance of the point from the tower centreline [m].
    radius : ndarray
        Tower radius at the point's height [m]; 0 gives no deficit.
    drag_coefficient : float
        Tower drag coefficient C_d [-].

    Returns
    -------
    du : ndarray
        ``u = U (1 + du)``: ``du = -C_d / sqrt(r) cos^2(pi/2 y / sqrt(r))`` with ``x, y`` in
        tower radii and ``r = sqrt(x^2 + y^2)``, for ``x > 0`` and ``|y| < sqrt(r)``, else 0;
        at least WAKE_DEFICIT_LIMIT.

    Notes
    -----
    AeroDyn's ``TwrShadow = 1`` (OpenFAST AeroDyn theory, "Tower shadow models"), the shadow
    model of downwind rotors; points inside the tower are evaluated on its surface (r >= 1).
    """
    shape, (x, y, radius) = flat(x, y, radius)
    out = np.empty(x.size)
    for k in range(x.size):
        out[k] = wake(x[k], y[k], radius[k], drag_coefficient)
    return out.reshape(shape)


@njit
def wake(x: float, y: float, radius: float, drag_coefficient: float) -> float:
    """:func:`wake_deficit` at one point."""
    if not radius > 0.0:
        return 0.0
    xr, yr = x / radius, y / radius
    root = math.sqrt(np.maximum(math.sqrt(xr * xr + yr * yr), 1.0))
    if not (xr > 0.0 and abs(yr) < root):
        return 0.0
    cos = math.cos(0.5 * math.pi * yr / root)
    deficit = -drag_coefficient / root * (cos * cos)
    return np.maximum(deficit, WAKE_DEFICIT_LIMIT)


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
    downwind : bool
        The rotor is behind the tower: its blades cross the tower's wake.
    drag_coefficient : float
        Tower drag coefficient [-], for the wake.

    Notes
    -----
    Fratini (2019) §3.2.3 applies eq. 3.44 only in the "tower-shadow zone" 90° < psi < 270°
    (seed000_fratini.md AC-11). Here the zone is where the tower physically is: points below
    the tower top and, for an upwind rotor, upwind of its centreline (x < 0); elsewhere the
    disturbance is zero. For a downwind rotor the potential flow acts on both sides and the
    wake deficit (:func:`wake_deficit`) behind the tower, as AeroDyn's ``TwrPotent = 1`` with
    ``TwrShadow = 1``. The disturbance scales the local free-stream speed rather than the hub
    speed V_h, so it also acts on sheared and turbulent inflow.
    """

    elevation: np.ndarray
    radius: np.ndarray
    top_height: float
    downwind: bool = False
    drag_coefficient: float = 1.0

    def __post_init__(self) -> None:
        # The outline up to just below the top, then no tower: interpolation in it with 0 to the
        # right is the radius below the top and 0 at and above it.
        below = np.nextafter(self.top_height, -np.inf)
        keep = self.elevation < below
        radius_below = np.interp(below, self.elevation, self.radius)
        object.__setattr__(self, "_outline", (np.append(self.elevation[keep], below),
                                              np.append(self.radius[keep], radius_below)))

    @classmethod
    def from_tower(cls, tower: Tower, downwind: bool = False) -> "TowerShadow":
        """The shadow of a turbine's tower (its aerodynamic outline, height and drag) on an up- or downwind rotor."""
        return cls(tower.outline_elevation, tower.outline_diameter / 2.0, tower.height, downwind,
                   tower.drag_coefficient)

    @property
    def outline(self) -> tuple[np.ndarray, np.ndarray]:
        """The heights and radii :func:`shadow` takes: the outline up to just below the top."""
        return self._outline

    def disturbance(self, x: np.ndarray, y: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Relative velocity change ``(du, dv)`` at points ``(x, y, z)`` [m] relative to the tower base.

        See :func:`potential_flow_disturbance` and :func:`wake_deficit`; zero above the tower top
        and, for an upwind rotor, downwind of the tower centreline.
        """
        shape, (x, y, z) = flat(x, y, z)
        out = np.empty((2, x.size))
        elevation, outline = self.outline
        _disturbances(x, y, z, elevation, outline, self.downwind, self.drag_coefficient, out)
        return out[0].reshape(shape), out[1].reshape(shape)


@njit
def shadow(x: float, y: float, z: float, elevation: np.ndarray, outline: np.ndarray, downwind: bool,
           drag_coefficient: float) -> tuple[float, float]:
    """:meth:`TowerShadow.disturbance` at one point, the tower's radius ``outline`` at ``elevation`` up to just below
    its top."""
    radius = 0.0 if z > elevation[-1] else np.interp(z, elevation, outline)
    if not downwind:
        return potential_flow(x, y, radius if x < 0.0 else 0.0)
    du, dv = potential_flow(x, y, radius)
    return du + wake(x, y, radius, drag_coefficient), dv


@njit
def _disturbances(x, y, z, elevation, outline, downwind, drag_coefficient, out):
    for k in range(x.size):
        out[0, k], out[1, k] = shadow(x[k], y[k], z[k], elevation, outline, downwind, drag_coefficient)
