"""Specification of hawt_controllers.laws.ipc: one harmonic's IPC law in the non-rotating frame."""

import dataclasses
import math

import numpy as np
import pytest

from hawt_core.exceptions import ConfigurationError, InputError
from hawt_controllers.laws.filters import second_order_lowpass
from hawt_controllers.laws.ipc import HarmonicIpc, HarmonicIpcConfig, soft_start_factor
from hawt_controllers.laws.ipc_tuning import design_integral_gain
from hawt_core.rotor.mbc import blade_azimuths, mbc_forward, mbc_inverse

DT = 0.05
PURE_I = HarmonicIpcConfig(harmonic=1, integral_gain=1e-8, lowpass_order=0, max_amplitude=1.0)


def _running(config: HarmonicIpcConfig, dt: float = DT) -> HarmonicIpc:
    ipc = HarmonicIpc(config, dt)
    ipc.activate(ramp_time=0.0)
    return ipc


def test_pure_integral_law_integrates_a_constant_moment_at_the_right_slope():
    """θ_cos = k_i · M_cos · t, and nothing on the other axis."""
    ipc = _running(PURE_I)
    for _ in range(100):
        out = ipc.step(2.0e6, 0.0, DT)
    assert out.cos == pytest.approx(1e-8 * 2.0e6 * 100 * DT)
    assert out.sin == 0.0


@pytest.mark.parametrize("harmonic", [1, 2, 3])
def test_sine_axis_is_controlled_for_every_harmonic(harmonic):
    """The sin axis gets its own filtered input and law (ROSCO's unassigned 2P yaw input is not copied)."""
    ipc = _running(dataclasses.replace(PURE_I, harmonic=harmonic, lowpass_order=2))
    outputs = [ipc.step(0.0, 1.0e6, DT) for _ in range(400)]
    assert outputs[-1].cos == pytest.approx(0.0, abs=1e-15)
    assert (outputs[-1].sin - outputs[-2].sin) / DT == pytest.approx(1e-8 * 1.0e6, rel=1e-6)
    assert outputs[-1].harmonic == harmonic


def test_saturation_limits_the_magnitude_not_each_axis():
    """A demand along 45° stops on the circle of radius max_amplitude, keeping its direction."""
    ipc = _running(dataclasses.replace(PURE_I, max_amplitude=0.05))
    for _ in range(2000):
        out = ipc.step(1.0e6, 1.0e6, DT)
    assert math.hypot(out.cos, out.sin) == pytest.approx(0.05)
    assert out.cos == pytest.approx(out.sin)
    assert out.saturated


def test_pitch_headroom_tightens_the_amplitude_limit():
    """ROSCO IPC_SatMode 2: the limit is min(max_amplitude, collective − min pitch)."""
    ipc = _running(dataclasses.replace(PURE_I, max_amplitude=0.05))
    for _ in range(2000):
        out = ipc.step(1.0e6, 0.0, DT, pitch_headroom=0.02)
    assert out.cos == pytest.approx(0.02)
    assert ipc.step(1.0e6, 0.0, DT, pitch_headroom=-0.1).cos == 0.0


def test_soft_start_factor_is_roscos_cubic_ramp():
    """0 below the start, 1 above the end, 1/2 in the middle, zero slope at both ends."""
    assert soft_start_factor(9.0, 9.12, 11.4) == 0.0
    assert soft_start_factor(12.0, 9.12, 11.4) == 1.0
    assert soft_start_factor(10.26, 9.12, 11.4) == pytest.approx(0.5)
    assert soft_start_factor(9.12 + 1e-4, 9.12, 11.4) < 1e-7
    assert 1.0 - soft_start_factor(11.4 - 1e-4, 9.12, 11.4) < 1e-7


def test_soft_start_scales_the_integration_rate_with_the_operating_point():
    """Full rate above the ramp, half rate in its middle, and the integrator holds below it."""
    config = dataclasses.replace(PURE_I, soft_start_begin=9.12, soft_start_end=11.4)
    rates = []
    for wind in (12.0, 10.26, 8.0):
        ipc = _running(config)
        ipc.reset(initial=(0.01, 0.0))
        out = ipc.step(1.0e6, 0.0, DT, operating_point=wind)
        rates.append((out.cos - 0.01) / DT)
        assert out.gain_factor == pytest.approx(soft_start_factor(wind, 9.12, 11.4))
    assert rates == pytest.approx([1e-2, 0.5e-2, 0.0])


def test_gain_schedule_multiplies_the_gains_by_the_interpolated_factor():
    """A factor table over collective pitch scales the integration rate."""
    config = dataclasses.replace(PURE_I, schedule_breakpoints=(0.0, 0.2), schedule_factors=(1.0, 0.5))
    ipc = _running(config)
    out = ipc.step(1.0e6, 0.0, DT, operating_point=0.1)
    assert out.gain_factor == pytest.approx(0.75)
    assert out.cos == pytest.approx(0.75 * 1e-8 * 1.0e6 * DT)


def test_operating_point_is_required_when_a_schedule_uses_it():
    """Without a finite operating point a soft start cannot be evaluated."""
    ipc = _running(dataclasses.replace(PURE_I, soft_start_begin=9.12, soft_start_end=11.4))
    with pytest.raises(InputError, match="operating_point"):
        ipc.step(1.0, 0.0, DT)


def test_ramp_out_reaches_zero_after_ramp_time_and_stays_there():
    """deactivate(2 s): the output falls to exactly zero after 2 s, not before, and the integrator is cleared."""
    ipc = _running(PURE_I)
    for _ in range(100):
        ipc.step(1.0e6, 0.0, DT)
    ipc.deactivate(ramp_time=2.0)
    outputs = [ipc.step(1.0e6, 0.0, DT).cos for _ in range(60)]
    steps = round(2.0 / DT)
    assert outputs[steps - 2] > 0.0
    assert outputs[steps - 1] == 0.0
    assert all(value == 0.0 for value in outputs[steps - 1 :])
    assert not ipc.active and float(np.linalg.norm(ipc.law.integrator)) == 0.0


def test_ramp_in_starts_from_zero_and_grows_linearly():
    """activate(1 s) from rest: output = ramp · law output, ramp rising by dt/1 s per step."""
    ipc = HarmonicIpc(PURE_I, DT)
    ipc.reset(initial=(0.02, 0.0))
    assert ipc.step(0.0, 0.0, DT).cos == 0.0
    ipc.activate(ramp_time=1.0)
    ramps = [ipc.step(0.0, 0.0, DT).ramp for _ in range(25)]
    np.testing.assert_allclose(ramps[:20], DT * np.arange(1, 21))
    assert ramps[-1] == 1.0 and ipc.active


def test_activation_from_a_tracked_state_starts_there():
    """activate(initial=(c, s)) with an immediate ramp continues from the tracked demand."""
    ipc = HarmonicIpc(PURE_I, DT)
    ipc.activate(ramp_time=0.0, initial=(0.01, 0.02))
    out = ipc.step(0.0, 0.0, DT)
    assert (out.cos, out.sin) == (0.01, 0.02)


def test_time_step_jitter_does_not_redesign_the_filter():
    """A dt within 1 % of the design dt keeps the filter (and its coefficients)."""
    ipc = _running(HarmonicIpcConfig(harmonic=1))
    sos = ipc.prefilter.sos
    ipc.step(1.0, 0.0, DT * 1.005)
    assert ipc.dt == DT and ipc.prefilter.sos is sos


def test_reset_with_an_initial_demand_is_bumpless():
    """reset(initial=(c, s)) with zero moments gives exactly (c, s) on the next step."""
    ipc = _running(dataclasses.replace(PURE_I, lowpass_order=2))
    ipc.reset(initial=(0.01, -0.02))
    out = ipc.step(0.0, 0.0, DT)
    assert (out.cos, out.sin) == pytest.approx((0.01, -0.02), abs=1e-15)


def test_prefilter_reset_to_steady_state_gives_no_transient():
    """reset(moments=m) makes a constant moment m pass the low-pass and notch unchanged."""
    config = dataclasses.replace(PURE_I, lowpass_order=2, notch_frequency=3.8)
    ipc = _running(config)
    ipc.reset(moments=(3.0e6, -1.0e6))
    out = ipc.step(3.0e6, -1.0e6, DT)
    assert (out.filtered_cos, out.filtered_sin) == pytest.approx((3.0e6, -1.0e6), rel=1e-12)


def test_prefilter_attenuates_three_p_ripple_in_the_non_rotating_frame():
    """The default second-order low-pass at 2 rad/s passes 0P and cuts 3P at rated (3.80 rad/s)."""
    ipc = _running(HarmonicIpcConfig(harmonic=1))
    t = np.arange(0.0, 40.0, DT)
    filtered = np.array([ipc.step(1.0 + math.cos(3.80 * tk), 0.0, DT).filtered_cos for tk in t])
    tail = filtered[t > 30.0]
    assert np.mean(tail) == pytest.approx(1.0, abs=0.05)
    assert (tail.max() - tail.min()) / 2.0 < 0.3


def test_changing_the_time_step_redesigns_the_filter_without_a_jump():
    """A new dt keeps the filtered value continuous."""
    ipc = _running(HarmonicIpcConfig(harmonic=1))
    ipc.reset(moments=(1.0e6, 0.0))
    out = ipc.step(1.0e6, 0.0, 0.01)
    assert ipc.dt == 0.01
    assert out.filtered_cos == pytest.approx(1.0e6, rel=1e-12)


def test_live_reconfiguration_keeps_the_integrator():
    """New gains act from the next step on; the accumulated demand stays."""
    ipc = _running(PURE_I)
    for _ in range(10):
        before = ipc.step(1.0e6, 0.0, DT).cos
    ipc.reconfigure(dataclasses.replace(PURE_I, integral_gain=2e-8, phase_offset=0.3))
    out = ipc.step(0.0, 0.0, DT)
    assert out.cos == pytest.approx(before)
    assert out.phase_offset == 0.3
    assert ipc.step(1.0e6, 0.0, DT).cos == pytest.approx(before + 2e-8 * 1.0e6 * DT)


def test_live_filter_change_keeps_the_filtered_moment_continuous():
    """A new low-pass starts in steady state at the last filtered value."""
    ipc = _running(PURE_I)
    ipc.step(1.0e6, 0.0, DT)
    ipc.reconfigure(dataclasses.replace(PURE_I, lowpass_order=2))
    assert ipc.step(1.0e6, 0.0, DT).filtered_cos == pytest.approx(1.0e6, rel=1e-12)


@pytest.mark.parametrize(
    "change, message",
    [
        ({"integral_gain": math.nan}, "integral_gain: must be finite"),
        ({"proportional_gain": math.inf}, "proportional_gain: must be finite"),
        ({"lowpass_corner_frequency": -1.0}, "lowpass_corner_frequency: must be > 0"),
        ({"lowpass_corner_frequency": 100.0}, "lowpass_corner_frequency: .*Nyquist"),
        ({"lowpass_damping": 0.0}, "lowpass_damping: must be > 0"),
        ({"lowpass_order": 3}, "lowpass_order: must be 0, 1 or 2"),
        ({"notch_frequency": 3.8, "notch_beta_den": -0.1}, "notch_beta_den: must be > 0 \\(the notch is unstable"),
        ({"notch_frequency": -3.8}, "notch_frequency: must be >= 0"),
        ({"max_amplitude": 0.0}, "max_amplitude: must be > 0"),
        ({"harmonic": 0}, "harmonic: must be an integer >= 1"),
        ({"soft_start_begin": 12.0, "soft_start_end": 11.4}, "soft_start_begin: must be <= soft_start_end"),
        ({"schedule_breakpoints": (0.1, 0.0), "schedule_factors": (1.0, 1.0)}, "schedule_breakpoints: must be str"),
        ({"schedule_breakpoints": (0.0, 0.1), "schedule_factors": (1.0,)}, "schedule_factors: expected 2 values"),
        ({"ramp_time": -1.0}, "ramp_time: must be >= 0"),
    ],
)
def test_validate_refuses_bad_parameters_naming_the_field(change, message):
    """NaN gains, negative bandwidths, unstable filters and bad tables are refused with the field named."""
    config = dataclasses.replace(HarmonicIpcConfig(harmonic=1), **change)
    with pytest.raises(ConfigurationError, match=message):
        config.validate(dt=DT)
    with pytest.raises(ConfigurationError, match=message):
        HarmonicIpc(config, DT)


def test_invalid_reconfiguration_leaves_the_controller_unchanged():
    """A refused live change keeps the old parameters."""
    ipc = _running(PURE_I)
    with pytest.raises(ConfigurationError, match="integral_gain"):
        ipc.reconfigure(dataclasses.replace(PURE_I, integral_gain=math.nan))
    assert ipc.config == PURE_I


def test_parallel_one_p_and_two_p_loops_remove_their_blade_load_harmonics():
    """IPC-1P and IPC-2P at 0.1 Hz on a delayed rigid-blade plant remove the 1P and 2P blade loads (Fratini AC-22)."""
    rotor_speed, sensitivity, samples_per_rev, revolutions = 1.26711, -5.0e7, 100, 60
    dt = 2 * math.pi / rotor_speed / samples_per_rev
    gain = design_integral_gain(
        sensitivity, 0.1 * 2 * math.pi, loop_delay=dt, prefilter=second_order_lowpass(2.0, 0.7071, dt)
    ).integral_gain
    loops = {n: _running(HarmonicIpcConfig(harmonic=n, integral_gain=gain), dt) for n in (1, 2)}
    pitch, moments = np.zeros(3), []
    for k in range(samples_per_rev * revolutions):
        psi = rotor_speed * dt * k
        blades = blade_azimuths(psi, 3)
        disturbance = 1.0e6 * np.cos(blades) + 4.0e5 * np.cos(2 * blades + 0.5)
        moment = sensitivity * pitch + disturbance
        moments.append(moment[0])
        pitch = np.zeros(3)
        for n, ipc in loops.items():
            harmonic = mbc_forward(moment, psi, n)
            out = ipc.step(harmonic.cos, harmonic.sin, dt)
            pitch += mbc_inverse(out.cos, out.sin, psi + rotor_speed * dt, n, 3, out.phase_offset)
    last = np.array(moments[-10 * samples_per_rev :])
    spectrum = 2 * np.abs(np.fft.rfft(last)) / last.size
    assert spectrum[10] < 0.01 * 1.0e6
    assert spectrum[20] < 0.01 * 4.0e5
