"""Specification of hawt_plant.gusts: wind step and IEC 61400-1 extreme operating gust."""

import numpy as np
import pytest

from hawt_plant.gusts import EOG_DURATION, ExtremeOperatingGust, WindStep, eog_amplitude

HUB = (np.zeros(1), np.zeros(1), np.full(1, 90.0))  # hub point of the NREL 5 MW, x = y = 0, z = 90 m


def _hub_u(wind, t: float) -> float:
    """Longitudinal speed at the hub point."""
    return float(wind.velocity(t, *HUB)[0, 0])


def test_eog_amplitude_for_nrel_5mw_at_rated_is_the_turbulence_branch():
    """Class IA, 11.4 m/s, D = 126 m, z_hub = 90 m: 3.3 * 0.16 (0.75*11.4 + 5.6) / (1 + 0.1*126/42) = 5.7471 m/s
    (the other branch, 1.35 (1.12*50 - 11.4) = 60.2 m/s, is larger)."""
    assert eog_amplitude(11.4, "I", "A", 126.0, 90.0) == pytest.approx(5.7471, abs=1e-4)


def test_eog_amplitude_near_v_e1_is_the_extreme_wind_branch():
    """Class IIIA at 40 m/s: V_e1 = 0.8 * 1.4 * 37.5 = 42 m/s, so V_gust = 1.35 * (42 - 40) = 2.7 m/s."""
    assert eog_amplitude(40.0, "III", "A", 126.0, 90.0) == pytest.approx(2.7)


def test_eog_peaks_at_half_duration_with_0_74_v_gust():
    """u_hub(t_0 + T/2) = V_hub + 0.74 V_gust, the gust maximum (sin(3 pi/2) (1 - cos pi) = -2)."""
    gust = ExtremeOperatingGust(11.4, start_time=20.0)
    assert _hub_u(gust, 20.0 + EOG_DURATION / 2) == pytest.approx(11.4 + 0.74 * gust.gust_amplitude)


def test_eog_dips_to_its_minimum_at_2_458_s_and_symmetrically_before_the_end():
    """The dips are where sin(3 pi s)(1 - cos 2 pi s) peaks: s = 0.234058 (2.4576 s), value 0.724486,
    so u_min = V_hub - 0.37 * 0.724486 V_gust, at t_0 + 2.4576 s and t_0 + T - 2.4576 s."""
    gust = ExtremeOperatingGust(11.4, start_time=20.0)
    times = 20.0 + np.arange(0.0, EOG_DURATION / 2, 1e-3)
    speeds = np.array([_hub_u(gust, t) for t in times])
    assert times[np.argmin(speeds)] - 20.0 == pytest.approx(2.4576, abs=2e-3)
    assert speeds.min() == pytest.approx(11.4 - 0.37 * 0.724486 * gust.gust_amplitude, abs=1e-5)
    assert _hub_u(gust, 20.0 + EOG_DURATION - 2.4576) == pytest.approx(speeds.min(), abs=1e-5)


@pytest.mark.parametrize("t", [0.0, 19.5, 20.0, 20.0 + EOG_DURATION, 31.0, 500.0])
def test_eog_leaves_the_mean_profile_unchanged_outside_the_gust(t):
    """For t outside [t_0, t_0 + T] (and at its ends) the wind is the steady power-law profile."""
    gust = ExtremeOperatingGust(11.4, start_time=20.0)
    z = np.array([30.0, 90.0, 150.0])
    np.testing.assert_allclose(gust.velocity(t, np.zeros(3), np.zeros(3), z)[0], 11.4 * (z / 90.0) ** 0.2,
                               atol=1e-12)


def test_eog_adds_the_same_gust_at_every_height():
    """IEC: V(z, t) = V(z) - 0.37 V_gust ...; the gust is additive, not scaled by the profile."""
    gust = ExtremeOperatingGust(11.4, start_time=0.0, shear_exponent=0.14)
    z = np.array([30.0, 90.0, 150.0])
    during = gust.velocity(4.0, np.zeros(3), np.zeros(3), z)[0]
    np.testing.assert_allclose(during - 11.4 * (z / 90.0) ** 0.14, gust.gust(4.0))


def test_transients_are_convected_downwind_at_the_initial_speed():
    """A point 11.4 m downwind sees the EOG and the step 1 s later than x = 0."""
    gust = ExtremeOperatingGust(11.4, start_time=0.0)
    step = WindStep(11.4, 15.0, step_time=0.0, ramp_duration=2.0)
    for wind in (gust, step):
        downwind = wind.velocity(4.0, np.array([11.4]), np.zeros(1), np.array([90.0]))
        np.testing.assert_allclose(downwind, wind.velocity(3.0, *HUB))


def test_step_changes_hub_speed_at_step_time():
    """Without a ramp the speed is U_1 before t_0 and U_2 from t_0 on."""
    step = WindStep(8.0, 12.0, step_time=5.0)
    assert [_hub_u(step, t) for t in (0.0, 4.999, 5.0, 100.0)] == pytest.approx([8.0, 8.0, 12.0, 12.0])


def test_ramped_step_is_linear_over_the_ramp():
    """With a ramp the speed moves linearly from U_1 at t_0 to U_2 at t_0 + ramp."""
    step = WindStep(8.0, 12.0, step_time=5.0, ramp_duration=4.0)
    assert [_hub_u(step, t) for t in (5.0, 6.0, 7.0, 9.0, 10.0)] == pytest.approx([8.0, 9.0, 10.0, 12.0, 12.0])


def test_step_scales_the_power_law_profile():
    """u(z, t) = U(t) (z / z_hub)^alpha, lateral and vertical components zero, zero at the ground."""
    step = WindStep(8.0, 12.0, step_time=5.0, shear_exponent=0.17)
    z = np.array([[0.0, 30.0], [90.0, 150.0]])
    velocity = step.velocity(6.0, np.zeros_like(z), np.ones_like(z), z)
    assert velocity.shape == (3, 2, 2)
    np.testing.assert_allclose(velocity[0], 12.0 * (z / 90.0) ** 0.17)
    np.testing.assert_array_equal(velocity[1:], 0.0)


@pytest.mark.parametrize("build, message", [
    (lambda: WindStep(0.0, 10.0, 1.0), "speed_before"),
    (lambda: WindStep(8.0, 10.0, 1.0, ramp_duration=-1.0), "ramp_duration"),
    (lambda: WindStep(8.0, 10.0, 1.0, shear_exponent=1.5), "shear_exponent"),
    (lambda: ExtremeOperatingGust(11.4, 0.0, turbine_class="IV"), "turbine_class"),
    (lambda: ExtremeOperatingGust(11.4, 0.0, turbulence_class="S"), "turbulence_class"),
    (lambda: ExtremeOperatingGust(11.4, 0.0, rotor_diameter=0.0), "rotor_diameter"),
    (lambda: WindStep(8.0, 10.0, 1.0).velocity(0.0, np.zeros(2), np.zeros(2), np.zeros(3)), "equal shapes"),
])
def test_invalid_arguments_are_rejected_naming_them(build, message):
    """Bad parameters raise a ValueError that names the argument."""
    with pytest.raises(ValueError, match=message):
        build()
