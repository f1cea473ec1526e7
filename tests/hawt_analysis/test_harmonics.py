"""Specification of hawt_analysis.harmonics: nP amplitudes fitted in the azimuth domain."""
import numpy as np
import pytest

from hawt_analysis.harmonics import harmonic_amplitudes

SAMPLE_RATE = 100.0


def _varying_speed_azimuth(duration=300.0, mean_speed=1.267, depth=0.3, period=60.0):
    """Time [s], unwrapped azimuth [rad] and speed [rad/s] of a rotor whose speed swings ±depth slowly."""
    t = np.arange(int(duration * SAMPLE_RATE) + 1) / SAMPLE_RATE
    speed = mean_speed * (1.0 + depth * np.sin(2 * np.pi * t / period))
    psi = mean_speed * (t + depth * period / (2 * np.pi) * (1.0 - np.cos(2 * np.pi * t / period)))
    return t, psi, speed


def test_known_1p_and_3p_amplitudes_are_recovered_under_slowly_varying_speed():
    """1P of 2.0 and 3P of 0.5 on a rotor whose speed swings ±30 % come back within 1 %, other nP near 0."""
    t, psi, _ = _varying_speed_azimuth()
    drift = 0.4 * np.sin(2 * np.pi * t / 200.0)
    load = 3.0 + drift + 2.0 * np.cos(psi + 0.4) + 0.5 * np.sin(3 * psi - 1.0)
    fit = harmonic_amplitudes(load, np.mod(psi, 2 * np.pi))
    assert fit.harmonics == (1, 2, 3, 4, 5, 6)
    assert fit.amplitude[0] == pytest.approx(2.0, rel=0.01)
    assert fit.amplitude[2] == pytest.approx(0.5, rel=0.01)
    assert np.all(fit.amplitude[[1, 3, 4, 5]] < 0.005)
    assert fit.amplitude_per_revolution_rms[[0, 2]] == pytest.approx([2.0, 0.5], rel=0.01)


def test_whole_revolutions_only_are_used():
    """A record of 10.6 turns is fitted over its 10 whole revolutions."""
    psi = np.linspace(0.0, 10.6 * 2 * np.pi, 8000)
    assert harmonic_amplitudes(np.cos(psi), psi).revolutions == 10


def test_amplitude_does_not_depend_on_the_blade_whose_azimuth_is_used():
    """Blade 2's moment fitted against blade 1's azimuth ψ has the same amplitudes as against ψ + 2π/3."""
    _, psi, _ = _varying_speed_azimuth(duration=120.0)
    blade_2 = psi + 2 * np.pi / 3
    load = 1.5 * np.cos(blade_2) + 0.2 * np.cos(2 * blade_2 + 0.7)
    np.testing.assert_allclose(
        harmonic_amplitudes(load, psi).amplitude, harmonic_amplitudes(load, blade_2).amplitude, atol=1e-9
    )


def test_several_channels_are_fitted_at_once_column_by_column():
    """A (samples, channels) array gives one row of amplitudes per channel, equal to fitting each alone."""
    _, psi, _ = _varying_speed_azimuth(duration=60.0)
    channels = np.column_stack((np.cos(psi), 0.3 * np.sin(2 * psi), np.cos(psi) + np.cos(6 * psi)))
    together = harmonic_amplitudes(channels, psi)
    assert together.amplitude.shape == (3, 6)
    for column in range(3):
        np.testing.assert_allclose(
            together.amplitude[column], harmonic_amplitudes(channels[:, column], psi).amplitude, atol=1e-12
        )


def test_random_content_raises_the_per_revolution_rms_above_the_periodic_amplitude():
    """Noise is not phase-locked: it averages out of the synchronous amplitude but not out of the RMS."""
    _, psi, _ = _varying_speed_azimuth()
    load = np.cos(psi) + np.random.default_rng(1).standard_normal(psi.size)
    fit = harmonic_amplitudes(load, psi)
    assert fit.amplitude[0] == pytest.approx(1.0, rel=0.05)
    assert np.all(fit.amplitude_per_revolution_rms > fit.amplitude)
    assert np.all(fit.amplitude[1:] < 0.05)


def test_a_record_shorter_than_one_revolution_is_refused():
    """Less than one whole turn of azimuth cannot give harmonics; the error names the azimuth."""
    psi = np.linspace(0.0, 5.0, 500)
    with pytest.raises(ValueError, match=r"azimuth: record covers 0.80 revolutions"):
        harmonic_amplitudes(np.cos(psi), psi)


def test_too_coarse_sampling_for_6p_is_refused():
    """Ten samples per revolution cannot resolve up to 6P."""
    psi = np.arange(0.0, 40 * np.pi, 2 * np.pi / 10)
    with pytest.raises(ValueError, match=r"azimuth: revolution \d+ has only (9|10) samples; harmonics up to 6P need at least 15"):
        harmonic_amplitudes(np.cos(psi), psi)


@pytest.mark.parametrize(
    ("signals", "azimuth", "message"),
    [
        (np.r_[np.nan, np.zeros(999)], np.linspace(0, 20, 1000), "root_moment_oop_1: NaN at sample 0"),
        (np.zeros(999), np.linspace(0, 20, 1000), "root_moment_oop_1: expected 1000 samples like azimuth, found 999"),
        (np.zeros(1000), np.r_[np.linspace(0, 20, 999), np.inf], "azimuth: infinite value at sample 999"),
    ],
)
def test_bad_input_raises_value_error_naming_the_channel(signals, azimuth, message):
    """NaN, infinities and mismatched lengths are refused with the channel's name."""
    with pytest.raises(ValueError, match=message):
        harmonic_amplitudes(signals, azimuth, name="root_moment_oop_1")
