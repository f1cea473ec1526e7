"""Checks shared by the cores: each raises with the name of the value at fault."""

import math

import numpy as np

from hawt_core.arrays import finite_array as checked_array
from hawt_core.arrays import finite_floats as checked_floats

from hawt_core.exceptions import ConfigurationError, InputError


def require_finite(field: str, value: float) -> float:
    """Return ``float(value)`` or raise :class:`ConfigurationError` if NaN/inf."""
    value = float(value)
    if not math.isfinite(value):
        raise ConfigurationError(field, f"must be finite, found {value}")
    return value


def require_positive(field: str, value: float) -> float:
    """Return ``float(value)`` if finite and > 0, else raise :class:`ConfigurationError`."""
    value = require_finite(field, value)
    if value <= 0.0:
        raise ConfigurationError(field, f"must be > 0, found {value}")
    return value


def require_nonnegative(field: str, value: float) -> float:
    """Return ``float(value)`` if finite and >= 0, else raise :class:`ConfigurationError`."""
    value = require_finite(field, value)
    if value < 0.0:
        raise ConfigurationError(field, f"must be >= 0, found {value}")
    return value


def require_below_nyquist(field: str, frequency: float, dt: float) -> None:
    """Raise unless 0 < ``frequency`` [rad/s] < π/``dt`` (the Nyquist frequency)."""
    nyquist = math.pi / dt
    if frequency >= nyquist:
        raise ConfigurationError(
            field, f"{frequency} rad/s is at or above the Nyquist frequency {nyquist:.6g} rad/s (dt={dt} s)"
        )


def require_time_step(dt: float) -> float:
    """Return ``float(dt)`` if finite and > 0, else raise :class:`InputError` naming ``dt``."""
    dt = float(dt)
    if not (math.isfinite(dt) and dt > 0.0):
        raise InputError("dt", f"must be finite and > 0, found {dt}")
    return dt


def finite_array(argument: str, value, shape: tuple | None = None) -> np.ndarray:
    """``np.asarray(value, float)`` checked for NaN/inf and, if given, for ``shape`` (hawt_core.arrays);
    raises :class:`InputError` naming ``argument``."""
    return checked_array(argument, value, shape=shape, error=InputError)


def finite_float(argument: str, value) -> float:
    """One value as a plain float, checked for NaN/inf as :func:`finite_array` checks a scalar; raises
    :class:`InputError` naming ``argument``. The per-step path's scalars: a tenth of the cost of packing one into
    :func:`finite_floats`."""
    try:
        number = float(value)
    except (TypeError, ValueError) as cause:
        raise InputError(argument, f"not a number ({cause})") from None
    if not math.isfinite(number):
        raise InputError(argument, "NaN" if math.isnan(number) else "infinite value")
    return number


def finite_floats(argument: str, values) -> list[float]:
    """Plain floats of one sample checked for NaN/inf (hawt_core.arrays); raises :class:`InputError` naming
    ``argument``."""
    return checked_floats(argument, values, error=InputError)
