"""Saturations used by the PI law: per-axis bounds, or a bound on a vector's magnitude."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from hawt_core.validation import require_nonnegative
from hawt_core.exceptions import ConfigurationError

__all__ = ["BoxSaturation", "NormSaturation", "Saturation"]


class Saturation(Protocol):
    """Something that limits a value and says whether it had to."""

    def apply(self, value: np.ndarray) -> tuple[np.ndarray, bool]:
        """Return the limited value and True if the limit was active."""

    def limit_values(self, values: list[float]) -> tuple[list[float], bool]:
        """:meth:`apply` on plain floats (the value flattened): the per-step path."""


def _apply(saturation: Saturation, value: np.ndarray) -> tuple[np.ndarray, bool]:
    array = np.asarray(value, dtype=float)
    limited, active = saturation.limit_values(array.ravel().tolist())
    return np.array(limited).reshape(array.shape), active


@dataclass(frozen=True)
class BoxSaturation:
    """Clamp every element to [lower, upper] (either may be ±inf).

    Attributes
    ----------
    lower, upper : float
        Bounds in the unit of the value; lower <= upper, not NaN.
    """

    lower: float = -math.inf
    upper: float = math.inf

    def __post_init__(self) -> None:
        if math.isnan(self.lower) or math.isnan(self.upper):
            raise ConfigurationError("lower/upper", "saturation bounds must not be NaN")
        if self.lower > self.upper:
            raise ConfigurationError("lower", f"must be <= upper ({self.upper}), found {self.lower}")

    def apply(self, value: np.ndarray) -> tuple[np.ndarray, bool]:
        """Clamp ``value`` elementwise; flag if any element was clamped."""
        return _apply(self, value)

    def limit_values(self, values: list[float]) -> tuple[list[float], bool]:
        limited = [min(max(v, self.lower), self.upper) for v in values]
        return limited, limited != values


@dataclass(frozen=True)
class NormSaturation:
    """Scale a vector (last axis) down so that its Euclidean norm is at most ``limit``.

    The direction is kept, so an IPC demand keeps its phase when limited
    (amplitude saturation of the (cos, sin) pair rather than per axis).

    Attributes
    ----------
    limit : float
        Largest allowed magnitude, >= 0 (inf for none).
    """

    limit: float = math.inf

    def __post_init__(self) -> None:
        if not (math.isinf(self.limit) and self.limit > 0):
            require_nonnegative("limit", self.limit)

    def apply(self, value: np.ndarray) -> tuple[np.ndarray, bool]:
        """Scale ``value`` if its norm exceeds the limit; flag if it did."""
        return _apply(self, value)

    def limit_values(self, values: list[float]) -> tuple[list[float], bool]:
        norm = math.hypot(*values)
        if norm <= self.limit:
            return values, False
        scale = self.limit / norm
        return [v * scale for v in values], True
