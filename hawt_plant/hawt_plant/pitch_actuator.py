"""Second-order pitch actuator of every blade with rate and angle limits, discretized exactly."""
from __future__ import annotations

import numpy as np

from hawt_plant.compiled import njit, unchecked
from hawt_plant.disk_cache import kept
from hawt_plant.turbine import PitchActuator

__all__ = ["DiscretePitchActuator", "limited_step"]


def _transition(parameters: PitchActuator, dt: float) -> np.ndarray:
    """The zero-order-hold step of theta'' = w^2 (theta_c - theta) - 2 zeta w theta', shape (2, 3): angle and rate
    at the end of a step from angle, rate and the command held over it, the matrix exponential of the system
    augmented with the held command."""
    from scipy.linalg import expm  # only when not kept (hawt_plant.disk_cache.kept)

    w, zeta = parameters.natural_frequency, parameters.damping_ratio
    augmented = np.zeros((3, 3))
    augmented[:2, :2] = [[0.0, 1.0], [-w * w, -2.0 * zeta * w]]
    augmented[1, 2] = w * w
    return expm(augmented * dt)[:2]


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
        # Angle and rate at the end of the step from angle, rate and command at its start.
        self._transition = kept("pitch_actuator_transition", (parameters.natural_frequency, parameters.damping_ratio,
                                                              dt), lambda: _transition(parameters, dt))
        self._parameters = parameters
        # Lower and upper limits of the angle change per step, angle and rate.
        max_step, max_rate = parameters.max_rate * dt, parameters.max_rate
        self._limits = np.array((-max_step, max_step, parameters.min_angle, parameters.max_angle, -max_rate, max_rate))

    @property
    def parameters(self) -> PitchActuator:
        """The actuator's parameters."""
        return self._parameters

    @property
    def kernel_arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """What :func:`limited_step` takes of the actuator: its transition matrix (2, 3) and limits (6,)."""
        return self._transition, self._limits

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
        new_angle, new_rate = np.empty(len(angle)), np.empty(len(angle))
        _step_unchecked(self._transition, self._limits, np.ascontiguousarray(angle, dtype=float),
                        np.ascontiguousarray(rate, dtype=float), np.ascontiguousarray(command, dtype=float), new_angle,
                        new_rate)
        return new_angle, new_rate


@njit
def limited_step(transition: np.ndarray, limits: np.ndarray, angle: np.ndarray, rate: np.ndarray,
                 command: np.ndarray, new_angle: np.ndarray, new_rate: np.ndarray) -> None:
    """:meth:`DiscretePitchActuator.step` per blade: the exact linear step, then the limits (class notes). Each
    blade's angle and rate are read before its new ones are written, so ``new_angle`` and ``new_rate`` may be
    ``angle`` and ``rate`` (a step in place)."""
    step_low, step_high, angle_low, angle_high, rate_low, rate_high = (limits[0], limits[1], limits[2], limits[3],
                                                                       limits[4], limits[5])
    for i in range(angle.size):
        linear_angle = transition[0, 0] * angle[i] + transition[0, 1] * rate[i] + transition[0, 2] * command[i]
        linear_rate = transition[1, 0] * angle[i] + transition[1, 1] * rate[i] + transition[1, 2] * command[i]
        moved = angle[i] + min(max(linear_angle - angle[i], step_low), step_high)
        limited = min(max(moved, angle_low), angle_high)
        new_angle[i] = limited
        new_rate[i] = min(max(linear_rate, rate_low), rate_high) if limited == moved else 0.0


_step_unchecked = unchecked(limited_step)  # its arguments are the actuator's own arrays and float64 C-contiguous ones
