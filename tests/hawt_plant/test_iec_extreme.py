"""Specification of hawt_plant.iec_extreme: the IEC 61400-1 Ed. 3 EDC, ECD, EWS and EWM, each against its equation.

Every expected value is computed here from the standard's equation, independently of the module: sigma_1 =
I_ref (0.75 V_hub + 5.6), Lambda_1 = 42 m for the NREL 5 MW's 90 m hub, D = 126 m.
"""
import math

import numpy as np
import pytest

from hawt_plant.gusts import ExtremeOperatingGust
from hawt_plant.iec_extreme import (DirectionChange, ExtremeWindShear, cosine_pulse, cosine_ramp,
                                    ecd_direction_change, edc_direction_change, ews_amplitude, extreme_coherent_gust,
                                    extreme_direction_change, steady_extreme_wind)

Z = np.array([30.0, 90.0, 150.0])  # below the hub, the hub, above it [m]


def _at(wind, t: float, y=0.0, z=Z, x=0.0) -> np.ndarray:
    """(u, v, w) at points of heights z (and lateral positions y), shape (3, n)."""
    z = np.atleast_1d(np.asarray(z, dtype=float))
    return wind.velocity(t, np.full_like(z, x), np.broadcast_to(np.asarray(y, dtype=float), z.shape).copy(), z)


def _sigma_1(hub_speed: float, i_ref: float = 0.16) -> float:
    return i_ref * (0.75 * hub_speed + 5.6)


def _profile(hub_speed: float, z, alpha: float = 0.2) -> np.ndarray:
    return hub_speed * (np.asarray(z) / 90.0) ** alpha


# ---------------------------------------------------------------- EDC, §6.3.2.4

@pytest.mark.parametrize("hub_speed, i_ref, turbulence_class", [(11.4, 0.16, "A"), (3.0, 0.16, "A"), (25.0, 0.12, "C")])
def test_edc_magnitude_is_four_arctan_of_sigma_over_v_hub_and_rotor_size(hub_speed, i_ref, turbulence_class):
    """theta_e = 4 arctan(sigma_1 / (V_hub (1 + 0.1 D / Lambda_1))) (eq. 20); 34.7 deg for the NREL 5 MW at rated."""
    expected = 4.0 * math.atan(_sigma_1(hub_speed, i_ref) / (hub_speed * (1.0 + 0.1 * 126.0 / 42.0)))
    assert edc_direction_change(hub_speed, turbulence_class, 126.0, 90.0) == pytest.approx(expected, rel=1e-12)


def test_edc_magnitude_is_limited_to_180_degrees():
    """At 0.5 m/s class A, sigma_1 / (V_hub (1 + 0.3)) = 1.47: 4 arctan of it exceeds pi, so theta_e = pi."""
    assert 4.0 * math.atan(_sigma_1(0.5) / (0.5 * 1.3)) > math.pi
    assert edc_direction_change(0.5, "A", 126.0, 90.0) == math.pi


@pytest.mark.parametrize("sign", [1, -1])
@pytest.mark.parametrize("elapsed", [-1.0, 0.0, 1.5, 3.0, 4.5, 6.0, 30.0])
def test_edc_turns_the_sheared_wind_by_half_a_cosine_over_6_s_and_holds(sign, elapsed):
    """theta(t) = +-0.5 theta_e (1 - cos(pi t / 6 s)) over the change, +-theta_e after (eq. 21); the speed stays the
    normal profile V_hub (z / z_hub)^0.2 at every height: (u, v) = V(z) (cos theta, sin theta)."""
    edc = extreme_direction_change(11.4, start_time=20.0, sign=sign, turbulence_class="A")
    theta_e = 4.0 * math.atan(_sigma_1(11.4) / (11.4 * 1.3))
    s = min(max(elapsed, 0.0), 6.0)
    theta = sign * 0.5 * theta_e * (1.0 - math.cos(math.pi * s / 6.0))
    speed = _profile(11.4, Z)
    np.testing.assert_allclose(_at(edc, 20.0 + elapsed), [speed * math.cos(theta), speed * math.sin(theta),
                                                          np.zeros(3)], atol=1e-12)


# ---------------------------------------------------------------- ECD, §6.3.2.5

@pytest.mark.parametrize("hub_speed, degrees", [(2.0, 180.0), (3.99, 180.0), (4.0, 180.0), (12.0, 60.0),
                                                (24.0, 30.0)])
def test_ecd_direction_change_is_180_degrees_below_4_m_s_and_720_over_v_hub_above(hub_speed, degrees):
    """theta_cg = 180 deg for V_hub < 4 m/s, 720 deg m/s / V_hub otherwise (eq. 24): continuous at 4 m/s."""
    assert math.degrees(ecd_direction_change(hub_speed)) == pytest.approx(degrees)


@pytest.mark.parametrize("sign", [1, -1])
@pytest.mark.parametrize("elapsed", [-2.0, 0.0, 2.5, 5.0, 10.0, 40.0])
def test_ecd_adds_15_m_s_and_turns_by_theta_cg_over_10_s(sign, elapsed):
    """V(z, t) = V(z) + 0.5 V_cg (1 - cos(pi t / T)), theta(t) = +-0.5 theta_cg (1 - cos(pi t / T)) over T = 10 s,
    V(z) + V_cg and +-theta_cg after, V_cg = 15 m/s (eq. 22-25); the gust is added at every height alike."""
    ecd = extreme_coherent_gust(12.0, start_time=5.0, sign=sign)
    ramp = 0.5 * (1.0 - math.cos(math.pi * min(max(elapsed, 0.0), 10.0) / 10.0))
    speed, theta = _profile(12.0, Z) + 15.0 * ramp, sign * math.radians(60.0) * ramp
    np.testing.assert_allclose(_at(ecd, 5.0 + elapsed), [speed * math.cos(theta), speed * math.sin(theta),
                                                         np.zeros(3)], atol=1e-12)


# ---------------------------------------------------------------- EWS, §6.3.2.6

def test_ews_amplitude_is_2_5_plus_0_2_beta_sigma_times_d_over_lambda_to_the_quarter():
    """2.5 m/s + 0.2 beta sigma_1 (D / Lambda_1)^(1/4), beta = 6.4 (eq. 26-27): 6.314 m/s for the NREL 5 MW at rated,
    class A."""
    expected = 2.5 + 0.2 * 6.4 * _sigma_1(11.4) * (126.0 / 42.0) ** 0.25
    assert ews_amplitude(11.4, "A", 126.0, 90.0) == pytest.approx(expected, rel=1e-12)
    assert expected == pytest.approx(6.3139, abs=1e-4)


@pytest.mark.parametrize("sign", [1, -1])
@pytest.mark.parametrize("elapsed", [-1.0, 0.0, 3.0, 6.0, 9.0, 12.0, 13.0])
def test_vertical_ews_adds_a_linear_shear_pulse_across_the_height(sign, elapsed):
    """u(z, t) = V(z) +- ((z - z_hub) / D) A (1 - cos(2 pi t / 12 s)) over the EWS, V(z) outside (eq. 26); the same at
    any lateral position."""
    ews = ExtremeWindShear(18.0, start_time=10.0, orientation="vertical", sign=sign, turbulence_class="B")
    amplitude = 2.5 + 0.2 * 6.4 * _sigma_1(18.0, 0.14) * (126.0 / 42.0) ** 0.25
    pulse = 1.0 - math.cos(2.0 * math.pi * elapsed / 12.0) if 0.0 <= elapsed <= 12.0 else 0.0
    expected = _profile(18.0, Z) + sign * (Z - 90.0) / 126.0 * amplitude * pulse
    for y in (0.0, -40.0):
        np.testing.assert_allclose(_at(ews, 10.0 + elapsed, y=y), [expected, np.zeros(3), np.zeros(3)], atol=1e-12)


@pytest.mark.parametrize("sign", [1, -1])
@pytest.mark.parametrize("elapsed", [-1.0, 3.0, 6.0, 12.5])
def test_horizontal_ews_adds_a_linear_shear_pulse_across_the_width(sign, elapsed):
    """u(y, z, t) = V(z) +- (y / D) A (1 - cos(2 pi t / 12 s)) over the EWS (eq. 27): at the hub height, from -60 m to
    +60 m (y to the left looking downwind)."""
    ews = ExtremeWindShear(18.0, start_time=10.0, orientation="horizontal", sign=sign, turbulence_class="B")
    amplitude = 2.5 + 0.2 * 6.4 * _sigma_1(18.0, 0.14) * (126.0 / 42.0) ** 0.25
    pulse = 1.0 - math.cos(2.0 * math.pi * elapsed / 12.0) if 0.0 <= elapsed <= 12.0 else 0.0
    y = np.array([-60.0, 0.0, 60.0])
    expected = 18.0 + sign * y / 126.0 * amplitude * pulse
    np.testing.assert_allclose(_at(ews, 10.0 + elapsed, y=y, z=np.full(3, 90.0))[0], expected, atol=1e-12)


# ---------------------------------------------------------------- EWM, §6.3.2.1

@pytest.mark.parametrize("turbine_class, reference_speed", [("I", 50.0), ("II", 42.5), ("III", 37.5)])
def test_ewm_is_1_4_v_ref_with_exponent_0_11_for_50_years_and_0_8_of_it_for_1_year(turbine_class, reference_speed):
    """V_e50(z) = 1.4 V_ref (z / z_hub)^0.11 (eq. 14), V_e1(z) = 0.8 V_e50(z) (eq. 15), steady, along x."""
    expected = 1.4 * reference_speed * (Z / 90.0) ** 0.11
    for years, factor in ((50, 1.0), (1, 0.8)):
        ewm = steady_extreme_wind(turbine_class, years)
        assert ewm.mean_speed == pytest.approx(factor * 1.4 * reference_speed)
        for t in (0.0, 100.0):
            np.testing.assert_allclose(_at(ewm, t), [factor * expected, np.zeros(3), np.zeros(3)], rtol=1e-12)


# ---------------------------------------------------------------- all transients

TRANSIENTS = {
    "eog": (lambda: ExtremeOperatingGust(11.4, 20.0), 10.5),
    "edc": (lambda: extreme_direction_change(11.4, 20.0), 6.0),
    "ecd": (lambda: extreme_coherent_gust(11.4, 20.0, sign=-1), 10.0),
    "ews_vertical": (lambda: ExtremeWindShear(11.4, 20.0), 12.0),
    "ews_horizontal": (lambda: ExtremeWindShear(11.4, 20.0, orientation="horizontal"), 12.0),
}


@pytest.mark.parametrize("kind", TRANSIENTS)
def test_each_transient_is_continuous_at_its_start_and_end(kind):
    """At t_0 and t_0 + T the wind at every point of the rotor moves by no more than the time step times a slope of
    a few m/s per second: no jump where the transient starts or ends."""
    build, duration = TRANSIENTS[kind]
    wind = build()
    y, z = np.meshgrid(np.linspace(-63.0, 63.0, 5), np.linspace(27.0, 153.0, 5))
    x = np.zeros_like(y)
    for edge in (20.0, 20.0 + duration):
        before, after = wind.velocity(edge - 1e-6, x, y, z), wind.velocity(edge + 1e-6, x, y, z)
        assert np.abs(after - before).max() < 1e-4, edge


@pytest.mark.parametrize("kind", TRANSIENTS)
def test_each_transient_is_convected_downwind_at_the_hub_speed(kind):
    """A point 11.4 m downwind sees at t + 1 s what the rotor plane saw at t."""
    wind = TRANSIENTS[kind][0]()
    for t in (21.0, 24.0, 27.0):
        np.testing.assert_allclose(_at(wind, t + 1.0, y=20.0, x=11.4), _at(wind, t, y=20.0), atol=1e-12)


def test_the_time_shapes_rise_as_half_a_cosine_and_pulse_as_a_full_one():
    """cosine_ramp: 0 before, 0.5 (1 - cos(pi s)) on [0, 1], 1 after; cosine_pulse: 1 - cos(2 pi s) on [0, 1], 0
    outside."""
    s = np.array([-0.5, 0.0, 0.25, 0.5, 1.0, 1.5])
    np.testing.assert_allclose(cosine_ramp(s), [0.0, 0.0, 0.5 * (1 - math.cos(math.pi / 4)), 0.5, 1.0, 1.0])
    np.testing.assert_allclose(cosine_pulse(s), [0.0, 0.0, 1.0, 2.0, 0.0, 0.0], atol=1e-15)


@pytest.mark.parametrize("build, message", [
    (lambda: extreme_direction_change(11.4, 0.0, sign=0), "sign"),
    (lambda: extreme_direction_change(0.0, 0.0), "hub_speed"),
    (lambda: extreme_direction_change(11.4, 0.0, turbulence_class="D"), "turbulence_class"),
    (lambda: extreme_direction_change(11.4, 0.0, rotor_diameter=0.0), "rotor_diameter"),
    (lambda: extreme_direction_change(11.4, 0.0, shear_exponent=1.0), "shear_exponent"),
    (lambda: extreme_coherent_gust(11.4, 0.0, sign=2), "sign"),
    (lambda: extreme_coherent_gust(-3.0, 0.0), "hub_speed"),
    (lambda: extreme_coherent_gust(11.4, 0.0, hub_height=0.0), "hub_height"),
    (lambda: DirectionChange(11.4, 0.0, speed_change=-1.0, direction_change=0.1, duration=6.0), "speed_change"),
    (lambda: DirectionChange(11.4, 0.0, speed_change=1.0, direction_change=4.0, duration=6.0), "direction_change"),
    (lambda: DirectionChange(11.4, 0.0, speed_change=1.0, direction_change=0.1, duration=0.0), "duration"),
    (lambda: ExtremeWindShear(11.4, 0.0, orientation="diagonal"), "orientation"),
    (lambda: ExtremeWindShear(11.4, 0.0, sign=-2), "sign"),
    (lambda: ExtremeWindShear(11.4, 0.0, rotor_diameter=-1.0), "rotor_diameter"),
    (lambda: ExtremeWindShear(11.4, 0.0, turbulence_class="a"), "turbulence_class"),
    (lambda: steady_extreme_wind("IV", 50), "turbine_class"),
    (lambda: steady_extreme_wind("I", 10), "recurrence_period"),
    (lambda: steady_extreme_wind("I", 50, hub_height=0.0), "hub_height"),
    (lambda: ExtremeWindShear(11.4, 0.0).velocity(0.0, np.zeros(2), np.zeros(2), np.zeros(3)), "x, y, z"),
])
def test_bad_parameters_are_refused_in_one_line_naming_them(build, message):
    """A ValueError whose one-line message starts with the parameter's name."""
    with pytest.raises(ValueError, match=message) as error:
        build()
    assert str(error.value).startswith(f"{message}: ")
    assert "\n" not in str(error.value)
