"""Specification of hawt_controllers.laws.collective: the NREL 5 MW baseline of Jonkman et al. (2009) ch. 7."""

import dataclasses
import math

import numpy as np
import pytest

from hawt_controllers.laws.collective import (
    BaselineCollectiveController,
    TorqueRegion,
    gain_correction_factor,
    integral_gain_factor,
    load_baseline_config,
    torque_demand,
)
from hawt_core.exceptions import ConfigurationError

CONFIG = load_baseline_config()
DT = 0.0125
RPM = 2 * math.pi / 60


def test_data_file_holds_jonkmans_pitch_gains_and_gain_schedule_constant():
    """K_P(0) = 0.01882681 s, K_I(0) = 0.008068634, θ_K = 6.302336° (Jonkman 2009 ch. 7; notes §2.3)."""
    assert CONFIG.proportional_gain == 0.01882681
    assert CONFIG.integral_gain == 0.008068634
    assert math.degrees(CONFIG.gain_doubling_pitch) == pytest.approx(6.302336, abs=1e-5)


def test_region_two_constant_is_jonkmans_value_in_either_unit():
    """k = 2.332287 N·m/(rad/s)² on the HSS is 0.0255764 N·m/rpm²."""
    assert CONFIG.region2_torque_constant == 2.332287
    assert CONFIG.region2_torque_constant * RPM**2 == pytest.approx(0.0255764, abs=5e-8)


def test_rated_torque_is_43093_55_newton_metres():
    """P_rated/ω_ref = 5 296 610 W / 122.9096 rad/s = 43 093.55 N·m (VS_RtTq comment)."""
    assert CONFIG.rated_torque == pytest.approx(43093.55, abs=0.01)


@pytest.mark.parametrize(
    "speed_rpm, region",
    [
        (600, TorqueRegion.REGION_1),
        (750, TorqueRegion.REGION_1_5),
        (1000, TorqueRegion.REGION_2),
        (1150, TorqueRegion.REGION_2_5),
        (1170, TorqueRegion.REGION_3),
    ],
)
def test_region_follows_the_filtered_generator_speed(speed_rpm, region):
    """Cut-in 670 rpm, region 2 from 871 rpm, region 2½ from ~1137 rpm, region 3 from 1162 rpm (99 % rated)."""
    assert torque_demand(CONFIG, speed_rpm * RPM, 0.0)[1] == region


def test_pitch_above_one_degree_selects_region_three_at_any_speed():
    """VS_Rgn3MP: with the previous pitch command >= 1° the torque is the constant-power law."""
    torque, region = torque_demand(CONFIG, 1000 * RPM, math.radians(1.0))
    assert region == TorqueRegion.REGION_3
    assert torque == pytest.approx(min(5296610.0 / (1000 * RPM), CONFIG.max_generator_torque))


def test_torque_law_matches_jonkman_in_every_region():
    """0; linear ramp; k ω²; induction-generator line; P/ω, as in the DISCON."""
    c = CONFIG
    assert torque_demand(c, 60.0, 0.0)[0] == 0.0
    assert torque_demand(c, 80.0, 0.0)[0] == pytest.approx(c.region15_slope * (80.0 - 70.16224))
    assert torque_demand(c, 100.0, 0.0)[0] == pytest.approx(2.332287 * 100.0**2)
    assert torque_demand(c, 120.0, 0.0)[0] == pytest.approx(c.region25_slope * (120.0 - 121.6805 / 1.1))
    assert torque_demand(c, 125.0, 0.0)[0] == pytest.approx(5296610.0 / 125.0)


def test_torque_law_is_continuous_across_region_boundaries():
    """Each region starts where the previous one ends (no torque jump)."""
    c = CONFIG
    for speed in (c.cut_in_generator_speed, c.region2_start_generator_speed, c.region2_end_generator_speed):
        below, above = torque_demand(c, speed - 1e-7, 0.0)[0], torque_demand(c, speed + 1e-7, 0.0)[0]
        assert above == pytest.approx(below, abs=1e-3)
    assert c.region2_end_generator_speed == pytest.approx(119.0138, abs=1e-3)


@pytest.mark.parametrize("speed", [122.0, 123.0, 126.0, 130.0, 140.0])
def test_region_three_holds_the_generator_power_constant(speed):
    """T·ω = 5 296 610 W above rated speed."""
    torque, region = torque_demand(CONFIG, speed, 0.1)
    assert region == TorqueRegion.REGION_3
    assert torque * speed == pytest.approx(5296610.0)


def test_torque_is_capped_at_the_maximum_and_rate_limited():
    """T ≤ 47 402.91 N·m and |dT/dt| ≤ 15 000 N·m/s."""
    controller = BaselineCollectiveController(CONFIG)
    controller.reset(generator_speed=80.0, pitch=0.8, generator_torque=0.0)
    out = controller.step(130.0, 0.8, DT)
    assert out.generator_torque == pytest.approx(15000.0 * DT)
    assert out.torque_saturated
    torque = out.generator_torque
    for _ in range(500):  # region 3 while the pitch falls from 0.8 rad at 8 deg/s (5.6 s to 1 deg)
        out = controller.step(100.0, 0.8, DT)
        assert abs(out.generator_torque - torque) <= 15000.0 * DT + 1e-9
        torque = out.generator_torque
    assert torque == pytest.approx(CONFIG.max_generator_torque)


def test_gain_correction_factor_halves_the_gains_at_theta_k():
    """GK(θ) = 1/(1 + θ/θ_K): 1 at 0, 0.5 at 6.302336°."""
    assert gain_correction_factor(0.0, CONFIG.gain_doubling_pitch) == 1.0
    assert gain_correction_factor(math.radians(6.302336), CONFIG.gain_doubling_pitch) == pytest.approx(0.5, abs=1e-7)


@pytest.mark.parametrize("pitch", [0.0, 0.1099965, 0.3])
def test_pitch_response_to_a_speed_error_is_scaled_by_the_gain_schedule(pitch):
    """First step after a bumpless start at θ0 with speed error δ: Δθ = GK(θ0)(K_P δ + f(θ0) K_I δ dt)."""
    delta = 0.01
    controller = BaselineCollectiveController(CONFIG)
    controller.reset(generator_speed=CONFIG.rated_generator_speed + delta, pitch=pitch)
    out = controller.step(CONFIG.rated_generator_speed + delta, pitch, DT)
    expected = gain_correction_factor(pitch, CONFIG.gain_doubling_pitch) * (
        0.01882681 + integral_gain_factor(pitch, CONFIG) * 0.008068634 * DT) * delta
    assert out.pitch - pitch == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("degrees, factor", [(0.0, 0.4), (1.0, 0.4), (2.5, 0.7), (4.0, 1.0), (20.0, 1.0)])
def test_near_rated_the_integral_gain_is_reduced_and_from_4_degrees_it_is_jonkmans(degrees, factor):
    assert integral_gain_factor(math.radians(degrees), CONFIG) == pytest.approx(factor, rel=1e-6)


def test_bumpless_start_holds_the_measured_pitch_at_rated_speed():
    """reset() at (ω_ref, θ0) keeps the pitch at θ0 while the speed stays at the reference."""
    controller = BaselineCollectiveController(CONFIG)
    controller.reset(generator_speed=CONFIG.rated_generator_speed, pitch=0.2)
    for _ in range(100):
        out = controller.step(CONFIG.rated_generator_speed, 0.2, DT)
    assert out.pitch == pytest.approx(0.2, abs=1e-12)
    assert out.region == TorqueRegion.REGION_3
    assert math.isnan(out.wind_speed_estimate)


def test_first_step_without_reset_starts_from_the_measurements():
    """Like the DISCON's first call: filter at the measured speed, pitch held at the measured pitch."""
    out = BaselineCollectiveController(CONFIG).step(CONFIG.rated_generator_speed, 0.15, DT)
    assert out.generator_speed_filtered == CONFIG.rated_generator_speed
    assert out.pitch == pytest.approx(0.15, abs=1e-12)


def test_pitch_rate_and_angle_limits_are_never_exceeded():
    """Over a violent speed history the pitch stays in 0–90° and moves at most 8°/s from the measured pitch."""
    controller = BaselineCollectiveController(CONFIG)
    t = np.arange(0.0, 120.0, DT)
    speed = np.where(t < 60.0, 122.9 + 60.0 * np.sin(2 * np.pi * 0.05 * t), 250.0)
    measured, pitches = 0.0, []
    for w in speed:
        out = controller.step(w, measured, DT)
        assert 0.0 <= out.pitch <= 1.570796
        assert abs(out.pitch - measured) <= 0.1396263 * DT + 1e-12
        measured = out.pitch
        pitches.append(out.pitch)
    assert max(pitches) == pytest.approx(1.570796)
    assert np.max(np.abs(np.diff(pitches))) == pytest.approx(0.1396263 * DT)


def test_integrator_does_not_wind_up_below_rated():
    """After a long underspeed the pitch leaves 0 as soon as the speed exceeds the reference."""
    controller = BaselineCollectiveController(CONFIG)
    controller.reset(generator_speed=100.0, pitch=0.0)
    for _ in range(5000):
        out = controller.step(100.0, 0.0, DT)
    assert out.pitch == 0.0 and out.pitch_saturated
    controller.speed_filter.reset(CONFIG.rated_generator_speed + 5.0)
    assert controller.step(CONFIG.rated_generator_speed + 5.0, 0.0, DT).pitch > 0.0


def test_loader_refuses_unknown_and_missing_parameters(tmp_path):
    """The data file maps one to one onto the config fields."""
    values = dataclasses.asdict(CONFIG)
    extra = tmp_path / "extra.yaml"
    extra.write_text("parameters:\n" + "".join(f"  {k}: {v}\n" for k, v in values.items()) + "  pc_kp: 1.0\n")
    with pytest.raises(ConfigurationError, match="pc_kp: unknown parameter"):
        load_baseline_config(extra)
    del values["max_torque_rate"]
    missing = tmp_path / "missing.yaml"
    missing.write_text("parameters:\n" + "".join(f"  {k}: {v}\n" for k, v in values.items()))
    with pytest.raises(ConfigurationError, match="max_torque_rate: missing"):
        load_baseline_config(missing)


@pytest.mark.parametrize(
    "change, message",
    [
        ({"integral_gain": -0.001}, "integral_gain: must be >= 0"),
        ({"generator_speed_corner_frequency": math.nan}, "generator_speed_corner_frequency: must be finite"),
        ({"region2_start_generator_speed": 60.0}, "region2_start_generator_speed: must be > cut_in"),
        ({"max_generator_torque": 40000.0}, "max_generator_torque: must be >= P_rated"),
        ({"min_pitch": 1.6}, "min_pitch: must be < max_pitch"),
        ({"near_rated_integral_factor": 0.0}, "near_rated_integral_factor: must be in"),
        ({"near_rated_pitch_high": 0.0}, "near_rated_pitch_high: must be >= near_rated_pitch_low"),
    ],
)
def test_invalid_tuning_is_refused_naming_the_field(change, message):
    """The DISCON's own parameter checks, with the field named."""
    with pytest.raises(ConfigurationError, match=message):
        dataclasses.replace(CONFIG, **change)
