"""Linear interpolation of a table with the end values held, on plain floats (gain schedules, every step)."""
from __future__ import annotations

from bisect import bisect_right
from typing import Sequence

__all__ = ["interpolate"]


def interpolate(x: float, breakpoints: Sequence[float], values: Sequence[float]) -> float:
    """``values`` at ``x``, linear between strictly increasing ``breakpoints``, the end values held outside.

    The result of ``numpy.interp`` (the same formula, slope·(x − x_j) + y_j) and of ROSCO's
    ``interp1d`` for its gain schedules, without numpy's per-call cost, which on a
    two-point table is many times the arithmetic.

    Examples
    --------
    >>> interpolate(0.05, (0.0, 0.1), (1.0, 0.5)), interpolate(-1.0, (0.0, 0.1), (1.0, 0.5))
    (0.75, 1.0)
    """
    if x <= breakpoints[0]:
        return float(values[0])
    if x >= breakpoints[-1]:
        return float(values[-1])
    j = bisect_right(breakpoints, x) - 1
    slope = (values[j + 1] - values[j]) / (breakpoints[j + 1] - breakpoints[j])
    return float(slope * (x - breakpoints[j]) + values[j])
