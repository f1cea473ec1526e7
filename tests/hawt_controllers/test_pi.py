"""Specification of hawt_controllers.laws.pi and hawt_controllers.laws.saturation."""

import math

import numpy as np
import pytest

from hawt_core.exceptions import ConfigurationError, InputError
from hawt_controllers.laws.pi import GainSchedule, PIController
from hawt_controllers.laws.saturation import BoxSaturation, NormSaturation

LIMITS = BoxSaturation(0.0, 1.0)


def test_pure_integral_law_integrates_a_constant_error_at_ki_times_error():
    """With kp = 0 the output grows by ki·e·dt per step."""
    pi = PIController()
    outputs = [pi.update(2.0, 0.1, kp=0.0, ki=0.5, saturation=BoxSaturation()) for _ in range(10)]
    np.testing.assert_allclose(outputs, 0.1 * np.arange(1, 11))


def test_anti_windup_holds_the_integrator_at_the_clamp():
    """A long positive error leaves the integrator at the upper limit, not beyond."""
    pi = PIController()
    for _ in range(1000):
        pi.update(1.0, 0.1, kp=0.2, ki=1.0, saturation=LIMITS)
    assert float(pi.integrator) == 1.0
    assert pi.saturated


def test_output_leaves_the_limit_at_once_when_the_error_reverses():
    """Without windup the first reversed error moves the output off the clamp."""
    pi = PIController()
    for _ in range(1000):
        pi.update(1.0, 0.1, kp=0.2, ki=1.0, saturation=LIMITS)
    assert pi.update(-0.1, 0.1, kp=0.2, ki=1.0, saturation=LIMITS) == pytest.approx(1.0 - 0.01 - 0.02)
    assert not pi.saturated


def test_reset_to_an_initial_output_is_bumpless():
    """After reset(u0) a zero error gives u0 at once, and the proportional part adds on top."""
    pi = PIController()
    pi.reset(0.3)
    assert pi.update(0.0, 0.01, kp=5.0, ki=1.0, saturation=LIMITS) == pytest.approx(0.3)
    assert pi.update(0.01, 0.01, kp=5.0, ki=1.0, saturation=LIMITS) == pytest.approx(0.3 + 0.05 + 0.0001)


def test_norm_saturation_limits_the_magnitude_and_keeps_the_direction():
    """A (cos, sin) pair beyond the limit is scaled down along itself."""
    limited, active = NormSaturation(1.0).apply(np.array([3.0, 4.0]))
    np.testing.assert_allclose(limited, [0.6, 0.8])
    assert active
    unchanged, active = NormSaturation(1.0).apply(np.array([0.3, 0.4]))
    np.testing.assert_allclose(unchanged, [0.3, 0.4])
    assert not active


def test_vector_law_with_norm_saturation_clamps_the_integrator_magnitude():
    """Two axes with one magnitude limit: the integrator stays on the circle, in the error's direction."""
    pi = PIController(shape=(2,))
    for _ in range(500):
        pi.update([1.0, 1.0], 0.1, kp=0.0, ki=1.0, saturation=NormSaturation(0.5))
    np.testing.assert_allclose(pi.integrator, [0.5 / math.sqrt(2)] * 2)


def test_gain_schedule_interpolates_and_holds_its_end_values():
    """Linear between breakpoints, constant outside, like ROSCO's PC_GS tables."""
    schedule = GainSchedule(breakpoints=(0.0, 0.1, 0.3), kp=(1.0, 0.5, 0.1), ki=(2.0, 1.0, 0.2))
    assert schedule.gains_at(0.05) == pytest.approx((0.75, 1.5))
    assert schedule.gains_at(-1.0) == (1.0, 2.0)
    assert schedule.gains_at(1.0) == pytest.approx((0.1, 0.2))


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"breakpoints": (0.0, 0.0), "kp": (1.0, 1.0), "ki": (1.0, 1.0)}, "breakpoints: must be strictly increasing"),
        ({"breakpoints": (0.0, 1.0), "kp": (1.0,), "ki": (1.0, 1.0)}, "kp: expected 2 values"),
        ({"breakpoints": (0.0, 1.0), "kp": (1.0, math.nan), "ki": (1.0, 1.0)}, "kp: NaN"),
    ],
)
def test_gain_schedule_refuses_bad_tables_naming_the_table(kwargs, message):
    """Tables must be finite, equally long, with increasing breakpoints."""
    with pytest.raises(ConfigurationError, match=message):
        GainSchedule(**kwargs)


def test_bad_updates_are_refused_naming_the_argument():
    """NaN error, non-positive dt and NaN gains are refused."""
    pi = PIController()
    with pytest.raises(InputError, match="error: NaN"):
        pi.update(math.nan, 0.1, kp=1.0, ki=1.0, saturation=LIMITS)
    with pytest.raises(InputError, match="dt: must be finite and > 0"):
        pi.update(1.0, 0.0, kp=1.0, ki=1.0, saturation=LIMITS)
    with pytest.raises(ConfigurationError, match="ki: must be finite"):
        pi.update(1.0, 0.1, kp=1.0, ki=math.nan, saturation=LIMITS)


def test_saturations_refuse_inconsistent_bounds():
    """lower > upper and a negative magnitude limit are refused."""
    with pytest.raises(ConfigurationError, match="lower: must be <= upper"):
        BoxSaturation(1.0, 0.0)
    with pytest.raises(ConfigurationError, match="limit: must be >= 0"):
        NormSaturation(-1.0)
