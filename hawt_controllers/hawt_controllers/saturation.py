"""Saturations used by the PI law: per-axis bounds, or a bound on a vector's magnitude."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from ._validation import require_nonnegative
from .exceptions import ConfigurationError

__all__ = ["BoxSaturation", "NormSaturation", "Saturation"]


class Saturation(Protocol):
    """Something that limits a value and says whether it had to."""

    def apply(self, value: np.ndarray) -> tuple[np.ndarray, bool]:
        """Return the limited value and True if the limit was active."""


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
        limited = np.clip(value, self.lower, self.upper)
        return limited, bool(np.any(limited != value))


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
        norm = float(np.linalg.norm(value))
        if norm <= self.limit:
            return value, False
        return value * (self.limit / norm), True
