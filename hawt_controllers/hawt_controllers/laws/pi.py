"""PI law with clamping anti-windup, and gain scheduling by interpolation.

The law (ROSCO ``PIController``, anchor_windcontrol notes §1.2, for both the
collective and the IPC loops; Jonkman et al. 2009 ch. 7 for the baseline)::

    I_k = sat(I_{k−1} + k_i · e_k · dt)        integrator, clamped (anti-windup)
    u_k = sat(k_p · e_k + I_k)                 output, same saturation

The integrator is stored in output units, so a change of gains does not make
the output jump. The saturation is an argument of every update, so it can move
with the operating point (Jonkman's limits scale with the gain factor; the IPC
limit shrinks with the pitch headroom).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from hawt_core.validation import finite_array, finite_floats, require_finite, require_time_step
from hawt_core.exceptions import ConfigurationError
from hawt_controllers.laws.interpolation import interpolate
from hawt_controllers.laws.saturation import Saturation

__all__ = ["GainSchedule", "PIController"]


class PIController:
    """Discrete PI law with integrator clamping; state visible as ``integrator``.

    Parameters
    ----------
    shape : tuple of int, optional
        Shape of the error and output (``()`` scalar, ``(2,)`` for a cos/sin pair).

    Attributes
    ----------
    integrator : ndarray
        I_k, in output units.
    saturated : bool
        True if the last update hit the saturation (integrator or output).
    """

    def __init__(self, shape: tuple[int, ...] = ()) -> None:
        self.shape = tuple(shape)
        self._integrator = [0.0] * math.prod(self.shape)
        self.saturated = False

    @property
    def integrator(self) -> np.ndarray:
        return np.array(self._integrator).reshape(self.shape)

    def reset(self, initial: ArrayLike = 0.0) -> None:
        """Set the integrator so that the output is ``initial`` at zero error (bumpless start)."""
        if isinstance(initial, float) and math.isfinite(initial):  # the per-step reset of an idle law
            self._integrator = [initial] * len(self._integrator)
        else:
            self._integrator = np.broadcast_to(finite_array("initial", initial), self.shape).ravel().tolist()
        self.saturated = False

    def update(
        self, error: ArrayLike, dt: float, *, kp: float, ki: float, saturation: Saturation
    ) -> np.ndarray:
        """Advance one step and return the output u_k.

        Parameters
        ----------
        error : array_like, shape ``shape``
            e_k, in the unit the gains expect.
        dt : float
            Time since the previous update [s].
        kp : float
            Proportional gain [output unit / error unit].
        ki : float
            Integral gain [output unit / (error unit · s)].
        saturation : Saturation
            Limits applied to the integrator and then to the output.

        Returns
        -------
        ndarray, shape ``shape``
            u_k = sat(kp·e_k + I_k).
        """
        e = finite_array("error", error)
        if e.shape != self.shape:
            e = np.broadcast_to(e, self.shape)
        output = self.update_values(e.ravel().tolist(), require_time_step(dt), kp=require_finite("kp", kp),
                                    ki=require_finite("ki", ki), saturation=saturation)
        return np.array(output).reshape(self.shape)

    def update_values(self, error: list[float], dt: float, *, kp: float, ki: float,
                      saturation: Saturation) -> list[float]:
        """:meth:`update` on plain floats (the error flattened), already checked: the per-step path."""
        self._integrator, integrator_saturated = saturation.limit_values(
            [i + ki * e * dt for i, e in zip(self._integrator, error)])
        output, output_saturated = saturation.limit_values([kp * e + i for e, i in zip(error, self._integrator)])
        self.saturated = integrator_saturated or output_saturated
        return output


@dataclass(frozen=True)
class GainSchedule:
    """PI gains tabulated over a scheduling variable, linearly interpolated.

    Outside the table the end values are held (``numpy.interp``), as ROSCO's
    ``interp1d`` does for ``PC_GS_angles``.

    Attributes
    ----------
    breakpoints : tuple of float
        Scheduling variable values, strictly increasing (e.g. pitch [rad]).
    kp : tuple of float
        Proportional gains at the breakpoints.
    ki : tuple of float
        Integral gains at the breakpoints.
    """

    breakpoints: tuple[float, ...]
    kp: tuple[float, ...]
    ki: tuple[float, ...]

    def __post_init__(self) -> None:
        for name in ("breakpoints", "kp", "ki"):
            values = np.asarray(getattr(self, name), dtype=float)
            if values.ndim != 1 or values.size == 0:
                raise ConfigurationError(name, f"expected a non-empty 1-D table, found shape {values.shape}")
            if not np.all(np.isfinite(values)):
                raise ConfigurationError(name, "NaN or inf in the table")
            object.__setattr__(self, name, tuple(float(v) for v in values))
        n = len(self.breakpoints)
        for name in ("kp", "ki"):
            if len(getattr(self, name)) != n:
                found = len(getattr(self, name))
                raise ConfigurationError(name, f"expected {n} values like breakpoints, found {found}")
        if np.any(np.diff(self.breakpoints) <= 0):
            raise ConfigurationError("breakpoints", "must be strictly increasing")

    def gains_at(self, value: float) -> tuple[float, float]:
        """(kp, ki) at the scheduling variable ``value``."""
        x, = finite_floats("value", (value,))
        return interpolate(x, self.breakpoints, self.kp), interpolate(x, self.breakpoints, self.ki)
