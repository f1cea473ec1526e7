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
        # Lower and upper limits of the angle change per step, angle and rate, as 0-d arrays:
        # numpy 2 combines an array with a 0-d array faster than with a Python float.
        max_step, max_rate = parameters.max_rate * dt, parameters.max_rate
        self._limits = tuple(np.array(limit) for limit in (
            -max_step, max_step, parameters.min_angle, parameters.max_angle, -max_rate, max_rate))

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
        step_low, step_high, angle_low, angle_high, rate_low, rate_high = self._limits
        new_angle, new_rate = np.dot(self._transition, np.array((angle, rate, command)))
        moved = angle + np.minimum(np.maximum(new_angle - angle, step_low), step_high)
        limited = np.minimum(np.maximum(moved, angle_low), angle_high)
        new_rate = np.minimum(np.maximum(new_rate, rate_low), rate_high)
        return limited, new_rate * (limited == moved)
