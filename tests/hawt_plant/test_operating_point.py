"""Specification of hawt_plant.operating_point: the NREL baseline steady schedule."""
import math

import pytest

from hawt_plant.operating_point import baseline_operating_point


def test_below_rated_the_rotor_runs_at_the_optimal_tip_speed_ratio(turbine, blade):
    """At 8 m/s: lambda = 7.55 and fine pitch (Jonkman 2009 region 2)."""
    op = baseline_operating_point(turbine, 8.0, blade)
    assert op.rotor_speed * 63.0 / 8.0 == pytest.approx(7.55)
    assert op.pitch == 0.0
    assert op.performance.power < 5.0e6 / 0.944


def test_low_wind_is_limited_by_the_minimum_rotor_speed(turbine, blade):
    """At 3 m/s the rotor turns at the 6.9 rpm minimum."""
    assert baseline_operating_point(turbine, 3.0, blade).rotor_speed == pytest.approx(6.9 * math.pi / 30, rel=1e-6)


@pytest.mark.parametrize(("wind", "jonkman_pitch_deg"), [(14.0, 8.70), (18.0, 14.92), (24.0, 22.35)])
def test_above_rated_the_pitch_gives_rated_power(turbine, blade, wind, jonkman_pitch_deg):
    """Rated speed, rated shaft power, pitch within 0.5 deg of Jonkman 2009 Table 7-1."""
    op = baseline_operating_point(turbine, wind, blade)
    assert op.rotor_speed == turbine.schedule.rated_rotor_speed
    assert op.performance.power == pytest.approx(5.0e6 / 0.944, rel=1e-5)
    assert math.degrees(op.pitch) == pytest.approx(jonkman_pitch_deg, abs=0.5)


def test_invalid_wind_speed_is_rejected(turbine):
    """A non-positive wind speed names the argument."""
    with pytest.raises(ValueError, match="wind_speed"):
        baseline_operating_point(turbine, 0.0)
