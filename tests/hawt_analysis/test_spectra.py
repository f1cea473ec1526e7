"""Specification of hawt_analysis.spectra: Welch PSD, its peaks and the rotor harmonics."""
import numpy as np
import pytest

from hawt_analysis.spectra import power_spectrum, rotor_harmonic_frequencies, spectral_peaks

SAMPLE_RATE = 100.0


def _sines_in_noise(duration=600.0, seed=0):
    """1.0 at 0.2 Hz and 0.3 at 0.6 Hz on white noise of σ = 0.2, sampled at 100 Hz."""
    t = np.arange(int(duration * SAMPLE_RATE)) / SAMPLE_RATE
    noise = 0.2 * np.random.default_rng(seed).standard_normal(t.size)
    return np.sin(2 * np.pi * 0.2 * t) + 0.3 * np.sin(2 * np.pi * 0.6 * t + 1.0) + noise


def test_psd_peaks_sit_at_the_injected_frequencies_and_are_labelled_as_harmonics():
    """The two strongest peaks are within one bin of 0.2 Hz and 0.6 Hz, labelled 1P and 3P for 1P = 0.2 Hz."""
    spectrum = power_spectrum(_sines_in_noise(), SAMPLE_RATE)
    peaks = spectral_peaks(spectrum, n_peaks=2, rotor_frequency=0.2)
    assert [peak.frequency for peak in peaks] == pytest.approx([0.2, 0.6], abs=spectrum.resolution)
    assert [peak.harmonic for peak in peaks] == [1, 3]
    assert peaks[0].density > peaks[1].density


def test_psd_integrates_to_the_variance():
    """∫ PSD df equals the signal variance within 2 % (density scaling, Parseval)."""
    values = _sines_in_noise(seed=1)
    spectrum = power_spectrum(values, SAMPLE_RATE)
    assert np.sum(spectrum.density) * spectrum.resolution == pytest.approx(values.var(), rel=0.02)


def test_default_segment_resolves_a_tenth_of_a_multi_megawatt_1p():
    """60 s segments give Δf ≈ 0.017 Hz, and records shorter than a segment use the whole record."""
    assert power_spectrum(_sines_in_noise(), SAMPLE_RATE).resolution == pytest.approx(1 / 60)
    short = power_spectrum(_sines_in_noise(duration=20.0), SAMPLE_RATE)
    assert short.segment_duration == pytest.approx(20.0)


def test_white_noise_without_tones_has_no_labelled_harmonic_peaks():
    """A flat spectrum has no peak standing 7 scatters above its surroundings, so no nP is claimed."""
    noise = np.random.default_rng(4).standard_normal(60000)
    peaks = spectral_peaks(power_spectrum(noise, SAMPLE_RATE), rotor_frequency=0.2)
    assert all(peak.harmonic is None for peak in peaks)


def test_rotor_harmonic_frequencies_are_multiples_of_the_rotation_frequency():
    """At 15 rpm 1P, 2P, 3P are 0.25, 0.50, 0.75 Hz (van Engelen 2006 §4.1)."""
    speed = 15.0 * 2 * np.pi / 60.0
    assert rotor_harmonic_frequencies(speed, (1, 2, 3)) == pytest.approx([0.25, 0.5, 0.75])


def test_bad_input_raises_value_error_naming_the_channel():
    """NaN and too short a record are refused with the channel's name."""
    with pytest.raises(ValueError, match="hub_tilt_moment: NaN at sample 2"):
        power_spectrum([0.0, 1.0, np.nan, 3.0], SAMPLE_RATE, name="hub_tilt_moment")
    with pytest.raises(ValueError, match="hub_tilt_moment: 4 samples are too few for a spectrum"):
        power_spectrum([0.0, 1.0, 2.0, 3.0], SAMPLE_RATE, name="hub_tilt_moment")
