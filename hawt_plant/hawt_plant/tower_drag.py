"""Aerodynamic drag on the tower, as AeroDyn's tower loads (``TwrAero = True``).

Each node of the tower's aerodynamic outline (elevation z_k, diameter D_k) carries the drag of a
cylinder in the horizontal wind relative to the moving tower (AeroDyn v15 theory, tower loads:
f = 1/2 rho Cd D |V_rel| V_rel per unit length),

    V_rel = (u(z_k) - phi_fa(z_k) x', v(z_k) - phi_ss(z_k) y'),

with x', y' the tower-top velocities and phi the first fore-aft and side-side mode shapes
(ElastoDyn's polynomials, phi(1) = 1). The distributed load is integrated with the trapezoidal
rule over the nodes. The tower's motion in the relative wind is the aerodynamic damping of its
first modes.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hawt_plant.compiled import njit
from hawt_plant.modal import polynomial_mode
from hawt_plant.turbine import Turbine

__all__ = ["TowerDrag", "TowerDragLoads", "node_drag"]


@dataclass(frozen=True)
class TowerDragLoads:
    """Tower drag in the modal and base coordinates.

    Attributes
    ----------
    fa_force, ss_force : float
        Generalized forces of the first fore-aft and side-side modes [N] (per metre of tower-top motion).
    base_fa_moment, base_ss_moment : float
        Tower-base moments about y and x [N m], with the signs of the plant's tower-base moments
        (OpenFAST TwrBsMyt, TwrBsMxt): downwind drag gives a positive fore-aft moment, drag to +y a
        negative side-side moment.
    """

    fa_force: float
    ss_force: float
    base_fa_moment: float
    base_ss_moment: float


@dataclass(frozen=True, eq=False)
class TowerDrag:
    """Drag of the tower's outline nodes; build one with :meth:`from_turbine`.

    Attributes
    ----------
    elevation : ndarray, shape (K,)
        Node heights above the ground [m], increasing.
    lever : ndarray, shape (K,)
        Node heights above the tower's base [m], 0 for a node below it (on the substructure): the arms of the
        tower-base moments.
    coefficient : ndarray, shape (K,)
        1/2 rho Cd D_k w_k [kg/m]: the drag per squared relative speed of node k, w_k its trapezoidal
        weight [m].
    fa_shape, ss_shape : ndarray, shape (K,)
        First fore-aft and side-side mode shapes at the nodes [-].
    """

    elevation: np.ndarray
    lever: np.ndarray
    coefficient: np.ndarray
    fa_shape: np.ndarray
    ss_shape: np.ndarray

    @classmethod
    def from_turbine(cls, turbine: Turbine) -> "TowerDrag":
        tower = turbine.tower
        elevation = np.asarray(tower.outline_elevation, dtype=float)
        weight = np.zeros_like(elevation)
        spacing = np.diff(elevation)
        weight[:-1] += spacing / 2.0
        weight[1:] += spacing / 2.0
        coefficient = 0.5 * turbine.environment.air_density * tower.drag_coefficient * np.asarray(
            tower.outline_diameter, dtype=float) * weight
        fraction = np.clip((elevation - tower.clamp_height) / tower.length, 0.0, 1.0)  # along the beam
        return cls(elevation=elevation, lever=np.maximum(elevation - tower.base_height, 0.0), coefficient=coefficient,
                   fa_shape=polynomial_mode(tower.fa_mode_shape, fraction)[0],
                   ss_shape=polynomial_mode(tower.ss_mode_shape, fraction)[0])

    def loads(self, u: np.ndarray, v: np.ndarray, fa_rate: float, ss_rate: float) -> TowerDragLoads:
        """The drag of the wind (u downwind, v to +y [m/s] at each node) on the tower moving at the tower-top
        velocities ``fa_rate``, ``ss_rate`` [m/s]."""
        u, v = np.asarray(u, dtype=float), np.asarray(v, dtype=float)
        if not u.shape == v.shape == self.elevation.shape:
            raise ValueError(f"u, v: expected {self.elevation.size} values each, found shapes {u.shape}, {v.shape}")
        return TowerDragLoads(*node_drag(u, v, float(fa_rate), float(ss_rate), self.coefficient, self.fa_shape,
                                     self.ss_shape, self.lever))


@njit
def node_drag(u, v, fa_rate, ss_rate, coefficient, fa_shape, ss_shape, lever):
    """:meth:`TowerDrag.loads`: the node forces 1/2 rho Cd D w |V_rel| V_rel summed against the mode shapes and the
    arms to the base."""
    fa_force = ss_force = base_fa = base_ss = 0.0
    for k in range(u.size):
        relative_u = u[k] - fa_shape[k] * fa_rate
        relative_v = v[k] - ss_shape[k] * ss_rate
        scale = coefficient[k] * math.sqrt(relative_u * relative_u + relative_v * relative_v)
        force_x, force_y = scale * relative_u, scale * relative_v
        fa_force += force_x * fa_shape[k]
        ss_force += force_y * ss_shape[k]
        base_fa += force_x * lever[k]
        base_ss -= force_y * lever[k]
    return fa_force, ss_force, base_fa, base_ss
