"""Specification of hawt_analysis.pitch_activity: travel, peak rate and acceleration, duty cycle."""
import numpy as np
import pytest

from hawt_analysis.pitch_activity import DEFAULT_RATE_THRESHOLD, pitch_activity

SAMPLE_RATE = 100.0


def _time(duration):
    return np.arange(int(round(duration * SAMPLE_RATE)) + 1) / SAMPLE_RATE


def test_ramp_gives_its_slope_as_rate_zero_acceleration_and_full_duty():
    """θ = θ_0 + r·t over T travels r·T at rate r with no acceleration, moving all the time."""
    t = _time(10.0)
    slope = np.deg2rad(2.0)
    activity = pitch_activity(t, (0.05 + slope * t)[:, None])
    assert activity.travel[0] == pytest.approx(slope * 10.0, rel=1e-12)
    assert activity.max_rate[0] == pytest.approx(slope, rel=1e-9)
    assert activity.max_acceleration[0] == pytest.approx(0.0, abs=1e-9)
    assert activity.duty_cycle[0] == 1.0


def test_sine_gives_analytic_travel_rate_acceleration_and_duty_cycle():
    """θ = A sin ωt over N periods: travel 4AN, max rate Aω, max acceleration Aω², duty (2/π)·arccos(thr/(Aω))."""
    amplitude, frequency, periods = np.deg2rad(4.0), 0.5, 10
    omega = 2 * np.pi * frequency
    t = _time(periods / frequency)
    threshold = 0.5 * amplitude * omega
    activity = pitch_activity(t, amplitude * np.sin(omega * t)[:, None], rate_threshold=threshold)
    assert activity.travel[0] == pytest.approx(4 * amplitude * periods, rel=1e-9)
    assert activity.max_rate[0] == pytest.approx(amplitude * omega, rel=1e-3)
    assert activity.max_acceleration[0] == pytest.approx(amplitude * omega**2, rel=1e-3)
    assert activity.duty_cycle[0] == pytest.approx(2 / np.pi * np.arccos(0.5), rel=0.01)


def test_blades_are_reported_separately_and_overall():
    """Per-blade arrays, with total travel, largest rate and acceleration, and mean duty cycle overall."""
    t = _time(20.0)
    pitch = np.column_stack((0.1 * np.sin(t), 0.2 * np.sin(t), np.full(t.size, 0.1)))
    activity = pitch_activity(t, pitch)
    assert activity.travel.shape == (3,)
    assert activity.travel[2] == 0.0 and activity.duty_cycle[2] == 0.0
    assert activity.total_travel == pytest.approx(activity.travel.sum())
    assert activity.overall_max_rate == activity.max_rate[1]
    assert activity.overall_max_acceleration == activity.max_acceleration[1]
    assert activity.mean_duty_cycle == pytest.approx(activity.duty_cycle.mean())


def test_lowpass_removes_the_steps_of_a_held_signal_from_the_acceleration():
    """A 1 Hz sine held for 10 samples has huge differenced acceleration; a 2 Hz zero-phase low-pass restores ≈ Aω²."""
    amplitude, omega = np.deg2rad(2.0), 2 * np.pi * 1.0
    t = _time(20.0)
    held = amplitude * np.sin(omega * (t // 0.1) * 0.1)
    raw = pitch_activity(t, held[:, None])
    smoothed = pitch_activity(t, held[:, None], lowpass_cutoff=2.0)
    assert raw.max_acceleration[0] > 10 * amplitude * omega**2
    assert smoothed.max_acceleration[0] == pytest.approx(amplitude * omega**2, rel=0.15)
    assert smoothed.lowpass_cutoff == 2.0


def test_default_threshold_is_a_tenth_of_a_degree_per_second():
    """The actuator counts as moving above 0.1 °/s unless told otherwise."""
    assert DEFAULT_RATE_THRESHOLD == pytest.approx(np.deg2rad(0.1))


@pytest.mark.parametrize(
    ("time", "pitch", "message"),
    [
        (np.arange(5.0), np.zeros(5), r"pitch: expected 2-D array \(samples, blades\), found shape \(5,\)"),
        (np.arange(5.0), np.zeros((4, 3)), "pitch: expected 5 samples like time, found 4"),
        (np.arange(5.0), np.r_[np.zeros((4, 3)), [[0.0, np.nan, 0.0]]], "pitch: NaN at sample 4"),
        (np.array([0.0, 1.0, 1.0, 2.0]), np.zeros((4, 3)), "time: not strictly increasing at sample 2"),
        (np.arange(2.0), np.zeros((2, 3)), "time: 2 samples are too few"),
    ],
)
def test_bad_input_raises_value_error_naming_it(time, pitch, message):
    """Wrong shapes, mismatched lengths, NaN, non-increasing or too short time are refused by name."""
    with pytest.raises(ValueError, match=message):
        pitch_activity(time, pitch)
