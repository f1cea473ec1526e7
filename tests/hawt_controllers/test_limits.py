"""Specification of hawt_controllers.laws.limits: per-blade angle and rate limits with flags."""

import math

import numpy as np
import pytest

from hawt_core.exceptions import ConfigurationError, InputError
from hawt_controllers.laws.limits import LimitFlag, PitchLimits, limit_pitch

NREL5MW = PitchLimits(min_angle=0.0, max_angle=1.570796, max_rate=0.1396263)


def test_angle_and_rate_limits_are_never_exceeded():
    """Random demands far outside the envelope are held within angle and rate limits."""
    rng = np.random.default_rng(6)
    dt, pitch = 0.0125, np.zeros(3)
    for _ in range(2000):
        result = limit_pitch(rng.uniform(-1.0, 3.0, 3), pitch, dt, NREL5MW)
        assert np.all(result.pitch >= 0.0) and np.all(result.pitch <= 1.570796)
        assert np.all(np.abs(result.pitch - pitch) <= 0.1396263 * dt + 1e-15)
        pitch = result.pitch


def test_demand_within_limits_passes_unchanged_without_flags():
    """A small step inside the envelope is not touched."""
    result = limit_pitch([0.1, 0.1005, 0.0995], [0.1, 0.1, 0.1], 0.01, NREL5MW)
    np.testing.assert_array_equal(result.pitch, [0.1, 0.1005, 0.0995])
    assert result.flags == LimitFlag.NONE


def test_flags_name_the_limit_and_the_blade():
    """Blade 1 is clamped at the minimum angle, blade 3 is rate limited."""
    result = limit_pitch([-0.1, 0.2, 0.5], [0.0, 0.2, 0.2], 0.01, NREL5MW)
    np.testing.assert_array_equal(result.angle_saturated, [True, False, False])
    np.testing.assert_array_equal(result.rate_saturated, [False, False, True])
    assert result.pitch[2] == pytest.approx(0.2 + 0.001396263)
    assert result.flags == LimitFlag.ANGLE_SATURATED | LimitFlag.RATE_SATURATED
    assert int(LimitFlag.ANGLE_SATURATED) == 1 and int(LimitFlag.RATE_SATURATED) == 2


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"min_angle": 0.0, "max_angle": 0.0, "max_rate": 0.1}, "min_angle: must be < max_angle"),
        ({"min_angle": 0.0, "max_angle": 1.0, "max_rate": -0.1}, "max_rate: must be > 0"),
        ({"min_angle": math.nan, "max_angle": 1.0, "max_rate": 0.1}, "min_angle: must be finite"),
    ],
)
def test_invalid_limits_are_refused_naming_the_field(kwargs, message):
    """Limits are checked when built."""
    with pytest.raises(ConfigurationError, match=message):
        PitchLimits(**kwargs)


def test_mismatched_blade_counts_are_refused():
    """previous must have one value per blade like demand."""
    with pytest.raises(InputError, match=r"previous: expected shape \(3,\)"):
        limit_pitch([0.1, 0.1, 0.1], [0.1, 0.1], 0.01, NREL5MW)
