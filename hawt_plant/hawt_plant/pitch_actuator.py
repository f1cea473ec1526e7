"""Second-order pitch actuator of every blade with rate and angle limits, discretized exactly."""
from __future__ import annotations

import numpy as np
from scipy.linalg import expm

from hawt_plant.turbine import PitchActuator

__all__ = ["DiscretePitchActuator"]


class DiscretePitchActuator:
    """Pitch actuators of all blades advanced by a fixed time step.

    Parameters
    ----------
    parameters : PitchActuator
        Natural frequency, damping and limits.
    dt : float
        Time step [s], > 0.

    Notes
    -----
    Each blade follows ``theta'' = w^2 (theta_c - theta) - 2 zeta w theta'`` with the command
    theta_c held over the step (zero-order hold); the linear step is the exact matrix
    exponential. The result is then limited: the angle moves at most ``max_rate * dt`` per
    step and the rate to ``±max_rate``; the angle stays within [min_angle, max_angle], with
    the rate set to zero at a limit.
    """

    def __init__(self, parameters: PitchActuator, dt: float) -> None:
        if not dt > 0.0:
            raise ValueError(f"dt: expected > 0 s, found {dt}")
        w, zeta = parameters.natural_frequency, parameters.damping_ratio
        a = np.array([[0.0, 1.0], [-w * w, -2.0 * zeta * w]])
        augmented = np.zeros((3, 3))
        augmented[:2, :2] = a
        augmented[1, 2] = w * w
        # Angle and rate at the end of the step from angle, rate and command at its start.
        self._transition = expm(augmented * dt)[:2]
        self._parameters = parameters
        self._max_step = parameters.max_rate * dt

    @property
    def parameters(self) -> PitchActuator:
        """The actuator's parameters."""
        return self._parameters

    def step(self, angle: np.ndarray, rate: np.ndarray, command: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Advance all blades one step.

        Parameters
        ----------
        angle, rate : ndarray, shape (B,)
            Pitch angle [rad] and rate [rad/s] at the start of the step.
        command : ndarray, shape (B,)
            Pitch command held over the step [rad].

        Returns
        -------
        angle, rate : ndarray, shape (B,)
            At the end of the step.
        """
        p = self._parameters
        new_angle, new_rate = np.dot(self._transition, np.array((angle, rate, command)))
        moved = angle + np.minimum(np.maximum(new_angle - angle, -self._max_step), self._max_step)
        limited = np.minimum(np.maximum(moved, p.min_angle), p.max_angle)
        new_rate = np.minimum(np.maximum(new_rate, -p.max_rate), p.max_rate)
        return limited, new_rate * (limited == moved)
