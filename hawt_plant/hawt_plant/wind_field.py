"""The interface every inflow model of the plant implements.

Frame (OpenFAST inertial convention): origin on the tower centreline at ground
level, x downwind, z up, y = z × x (to the left when looking downwind).
A wind field gives the undisturbed inflow; the tower's own disturbance (tower
shadow) is applied by the rotor model, which knows where the tower is.
"""
from typing import Protocol

import numpy as np

__all__ = ["WindChange", "WindField", "YawedWind"]


class WindField(Protocol):
    """Undisturbed inflow sampled at points of the rotor, at a time.

    Implementations are deterministic: the same arguments give the same result.
    """

    @property
    def mean_speed(self) -> float:
        """Mean longitudinal speed at hub height [m/s]; used for the initial operating point."""

    @property
    def hub_height(self) -> float:
        """Reference height the field's mean speed refers to [m]."""

    def velocity(self, t: float, x: np.ndarray, y: np.ndarray, z: np.ndarray) -> np.ndarray:
        """Wind velocity at the points (x, y, z) [m] at time t [s].

        Returns an array of shape ``(3,) + x.shape``: the components (u, v, w)
        along (x, y, z) [m/s]. Frozen turbulence is convected downwind at the
        mean speed, so a point at x sees the field of time ``t - x / mean_speed``.
        """


class WindChange:
    """A wind field with ``change`` [m/s] added to its longitudinal component: one value everywhere, or one per
    blade when the points are sampled one blade per row (as the rotor model samples them; rows after the blades',
    such as the tower's, get none) — the wind inputs of a linear model."""

    def __init__(self, field: WindField, change) -> None:
        self.field = field
        self.change = np.asarray(change, dtype=float)

    @property
    def mean_speed(self) -> float:
        return self.field.mean_speed + float(np.mean(self.change))

    @property
    def hub_height(self) -> float:
        return self.field.hub_height

    def velocity(self, t: float, x: np.ndarray, y: np.ndarray, z: np.ndarray) -> np.ndarray:
        velocity = np.array(self.field.velocity(t, x, y, z), dtype=float)  # a copy: the field may keep its own
        if self.change.ndim == 0:
            velocity[0] += self.change
        else:
            velocity[0, :len(self.change)] += self.change.reshape((-1,) + (1,) * (x.ndim - 1))
        return velocity


class YawedWind:
    """A wind field met by a rotor yawed against it: the field turned about the tower's axis (z through the origin)
    by the yaw misalignment gamma, so that its mean wind blows along (cos gamma, sin gamma, 0), from +x towards +y
    for gamma > 0 (as :class:`hawt_plant.iec_extreme.DirectionChange` turns it; the nacelle yawed by -gamma).

    A point p of the rotor's frame is the field's point R(-gamma) p, and the field's velocity there turns by
    R(gamma): a frozen turbulent field is convected along its own mean wind. The rotor model's tower shadow stays
    the potential flow of a wind along the shaft (:mod:`hawt_plant.tower_shadow`), right for small misalignments;
    the tower's drag takes the turned wind.
    """

    def __init__(self, field: WindField, yaw_misalignment: float) -> None:
        if not abs(yaw_misalignment) <= np.pi:
            raise ValueError(f"yaw_misalignment: expected an angle in [-pi, pi] rad, found {yaw_misalignment}")
        self.field = field
        self.yaw_misalignment = float(yaw_misalignment)
        self._cos, self._sin = np.cos(self.yaw_misalignment), np.sin(self.yaw_misalignment)

    @property
    def mean_speed(self) -> float:
        return self.field.mean_speed

    @property
    def hub_height(self) -> float:
        return self.field.hub_height

    def velocity(self, t: float, x: np.ndarray, y: np.ndarray, z: np.ndarray) -> np.ndarray:
        c, s = self._cos, self._sin
        u, v, w = self.field.velocity(t, c * x + s * y, c * y - s * x, z)
        return np.stack((c * u - s * v, s * u + c * v, w))
