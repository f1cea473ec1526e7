"""Per-blade pitch angle and rate limits of the summed (collective + IPC) command.

Order as in ROSCO ``PitchControl`` (anchor_windcontrol notes §1.2): saturate each
blade's demand to [min_angle, max_angle], then limit its rate relative to the
previous value, then saturate again (so a previous value outside the range is
pulled back in). Flags say which blades were limited; their values equal the
``PitchCommand.FLAG_*`` bits of hawt_msgs.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from hawt_core.validation import finite_floats, require_finite, require_positive, require_time_step
from hawt_core.exceptions import ConfigurationError, InputError

__all__ = ["LimitFlag", "LimitedPitch", "NO_NARROWING", "PitchLimits", "limit_angle", "limit_pitch"]


class LimitFlag(enum.IntFlag):
    """Saturation bits; values equal ``hawt_msgs/PitchCommand`` FLAG_ANGLE_SATURATED / FLAG_RATE_SATURATED."""

    NONE = 0
    ANGLE_SATURATED = 1
    RATE_SATURATED = 2


@dataclass(frozen=True)
class PitchLimits:
    """Pitch actuator limits.

    Attributes
    ----------
    min_angle : float
        Lowest pitch [rad] (NREL 5 MW: 0).
    max_angle : float
        Highest pitch [rad] (NREL 5 MW: 1.570796 = 90°).
    max_rate : float
        Largest |pitch rate| [rad/s] (NREL 5 MW baseline: 0.1396263 = 8°/s).
    """

    min_angle: float
    max_angle: float
    max_rate: float

    def __post_init__(self) -> None:
        self.validate()

    def validate(self) -> None:
        """Raise :class:`ConfigurationError` naming the bad field."""
        low = require_finite("min_angle", self.min_angle)
        high = require_finite("max_angle", self.max_angle)
        if low >= high:
            raise ConfigurationError("min_angle", f"must be < max_angle ({high}), found {low}")
        require_positive("max_rate", self.max_rate)

    def within(self, turbine: "PitchLimits") -> "PitchLimits":
        """These limits narrowed to the turbine's: the higher floor, the lower ceiling, the lower rate.

        Raises :class:`ConfigurationError` if nothing is left between floor and ceiling.
        """
        return PitchLimits(max(self.min_angle, turbine.min_angle), min(self.max_angle, turbine.max_angle),
                           min(self.max_rate, turbine.max_rate))

    def widening(self, turbine: "PitchLimits") -> dict[str, str]:
        """The fields of these limits that lie beyond the turbine's, each with ``value beyond the turbine's value``
        (empty if they only narrow them)."""
        beyond = {}
        for name, wider in (("min_angle", self.min_angle < turbine.min_angle - 1e-12),
                            ("max_angle", self.max_angle > turbine.max_angle + 1e-12),
                            ("max_rate", self.max_rate > turbine.max_rate + 1e-12)):
            if wider:
                beyond[name] = f"{getattr(self, name):g} beyond the turbine's {getattr(turbine, name):g}"
        return beyond


NO_NARROWING = PitchLimits(-0.5, 1.6, 1.0)
"""The widest pitch range any parameter may name [rad, rad/s]: the loop assembler's limit parameters default to it
(the turbine's own limits apply), and a pitch a controller's parameter names (a gain schedule's) lies within it."""


_FLAGS = tuple(LimitFlag(bits) for bits in range(4))  # by ANGLE_SATURATED | RATE_SATURATED bits


class LimitedPitch(NamedTuple):
    """Result of :func:`limit_pitch`.

    Attributes
    ----------
    pitch : ndarray, shape (B,)
        Limited pitch per blade [rad].
    angle_saturated : tuple of bool, length B
        Blades whose demand was outside [min_angle, max_angle].
    rate_saturated : tuple of bool, length B
        Blades whose rate limit was active.
    flags : LimitFlag
        OR of the flags over all blades.
    """

    pitch: np.ndarray
    angle_saturated: tuple[bool, ...]
    rate_saturated: tuple[bool, ...]
    flags: LimitFlag


def limit_pitch(demand: ArrayLike, previous: ArrayLike, dt: float, limits: PitchLimits) -> LimitedPitch:
    """Apply angle and rate limits to a per-blade pitch demand.

    Parameters
    ----------
    demand : array_like, shape (B,)
        Requested pitch per blade [rad] (collective + IPC).
    previous : array_like, shape (B,)
        Pitch the rate is measured from [rad]: the previous command (ROSCO) or
        the measured pitch (Jonkman 2009). The caller passes the result back in
        at the next step, like scipy's ``zi``/``zf``.
    dt : float
        Time since ``previous`` [s].
    limits : PitchLimits
        Angle and rate limits.

    Returns
    -------
    LimitedPitch
        ``pitch`` with ``min_angle <= pitch <= max_angle`` and
        ``|pitch − previous| <= max_rate·dt`` whenever ``previous`` is in range.
    """
    demand = finite_floats("demand", demand)
    previous = finite_floats("previous", previous)
    if len(previous) != len(demand):
        raise InputError("previous", f"expected shape {(len(demand),)} like demand, found {(len(previous),)}")
    dt = require_time_step(dt)
    low, high, step = limits.min_angle, limits.max_angle, limits.max_rate * dt
    pitch, angle_saturated, rate_saturated = [], [], []
    for wanted, last in zip(demand, previous):  # per blade on floats: numpy's per-call cost on B values is larger
        value, angle, rate = limit_angle(wanted, last, low, high, step)
        pitch.append(value)
        angle_saturated.append(angle)
        rate_saturated.append(rate)
    flags = _FLAGS[any(angle_saturated) | any(rate_saturated) << 1]
    return LimitedPitch(np.array(pitch), tuple(angle_saturated), tuple(rate_saturated), flags)


def limit_angle(wanted: float, last: float, low: float, high: float, step: float) -> tuple[float, bool, bool]:
    """:func:`limit_pitch` of one blade on plain floats, already checked: ``wanted`` clamped to [low, high], moved at
    most ``step`` [rad] from ``last``, clamped again; with whether the angle and the rate limit acted."""
    clamped = low if wanted < low else high if wanted > high else wanted
    wanted_change = clamped - last
    change = -step if wanted_change < -step else step if wanted_change > step else wanted_change
    value = last + change
    return low if value < low else high if value > high else value, clamped != wanted, change != wanted_change
