"""Specification of hawt_core.rotor.mbc: the Coleman transform of DESIGN.md §3."""

import math

import numpy as np
import pytest

from hawt_core.exceptions import ConfigurationError, InputError
from hawt_core.rotor.mbc import (blade_azimuths, harmonic_rank, mbc_forward, mbc_forward_sample, mbc_inverse,
                                  mbc_inverse_sample)

RANK_TWO_CASES = [(3, 1), (3, 2), (3, 4), (4, 1), (5, 1), (5, 2)]


def _azimuth_series(revolutions: int = 4, samples_per_rev: int = 64) -> np.ndarray:
    """Azimuth of blade 1 at constant rotor speed, an integer number of revolutions."""
    return 2.0 * np.pi * np.arange(revolutions * samples_per_rev) / samples_per_rev


def _spectrum_in_rotor_harmonics(signal: np.ndarray, revolutions: int) -> np.ndarray:
    """Amplitude at 0P, 1P, 2P, ... of a signal sampled over whole revolutions."""
    amplitudes = np.abs(np.fft.rfft(signal)) / signal.size
    amplitudes[1:] *= 2.0
    return amplitudes[::revolutions]


@pytest.mark.parametrize("n_blades, harmonic", RANK_TWO_CASES)
def test_forward_of_inverse_is_the_identity_at_every_azimuth(n_blades, harmonic):
    """Remodulating (c, s) and demodulating again gives (c, s) back, with zero mean (Fratini AC-7)."""
    rng = np.random.default_rng(1)
    psi = rng.uniform(0, 2 * np.pi, 50)
    c, s = rng.normal(size=50), rng.normal(size=50)
    out = mbc_forward(mbc_inverse(c, s, psi, harmonic, n_blades), psi, harmonic)
    np.testing.assert_allclose(out.cos, c, atol=1e-12)
    np.testing.assert_allclose(out.sin, s, atol=1e-12)
    np.testing.assert_allclose(out.mean, 0.0, atol=1e-12)


def test_inverse_of_forward_restores_the_blade_values_minus_their_mean():
    """For B = 3, n = 1 the mean and the 1P pair carry every blade pattern (Disario A1: T_θ T_M = I − 11ᵀ/3)."""
    rng = np.random.default_rng(2)
    moments, psi = rng.normal(size=(20, 3)), rng.uniform(0, 2 * np.pi, 20)
    components = mbc_forward(moments, psi, 1)
    rebuilt = mbc_inverse(components.cos, components.sin, psi, 1, 3) + components.mean[:, None]
    np.testing.assert_allclose(rebuilt, moments, atol=1e-12)


@pytest.mark.parametrize("n_blades, harmonic", RANK_TWO_CASES)
def test_remodulated_pitch_sums_to_zero_over_the_blades(n_blades, harmonic):
    """An nP IPC demand with n not a multiple of B adds no collective pitch."""
    psi = np.linspace(0, 2 * np.pi, 37)
    pitch = mbc_inverse(0.7, -0.2, psi, harmonic, n_blades, phase_offset=0.4)
    np.testing.assert_allclose(pitch.sum(axis=-1), 0.0, atol=1e-12)


@pytest.mark.parametrize("n_blades", [3, 4, 5])
def test_harmonic_equal_to_the_blade_count_gives_the_same_pitch_on_every_blade(n_blades):
    """"3P IPC" on three blades is a 3P-modulated collective pitch (van Engelen 2006 eq. 24)."""
    psi = np.linspace(0, 2 * np.pi, 41)
    pitch = mbc_inverse(0.7, -0.2, psi, n_blades, n_blades)
    np.testing.assert_allclose(pitch, pitch[:, :1] * np.ones(n_blades), atol=1e-12)
    np.testing.assert_allclose(pitch[:, 0], 0.7 * np.cos(n_blades * psi) - 0.2 * np.sin(n_blades * psi), atol=1e-12)
    assert harmonic_rank(n_blades, n_blades) == 1


def test_three_p_round_trip_leaves_six_p_ripple_around_the_demand():
    """For B = 3, n = 3 forward∘inverse is not the identity: mean correct, 6P ripple (Fratini §3.4)."""
    psi = _azimuth_series(revolutions=4, samples_per_rev=3600)
    out = mbc_forward(mbc_inverse(0.7, -0.2, psi, 3, 3), psi, 3)
    assert np.mean(out.cos) == pytest.approx(0.7)
    assert out.cos.min() == pytest.approx(-0.028, abs=1e-3)
    assert out.cos.max() == pytest.approx(1.428, abs=1e-3)
    spectrum = _spectrum_in_rotor_harmonics(out.cos, 4)
    assert np.argmax(spectrum[1:]) + 1 == 6


def test_even_blade_count_at_half_the_blades_is_an_alternating_rank_one_pattern():
    """B = 4, n = 2: blades alternate in sign, so the pair has rank 1 and is not recovered exactly."""
    psi = np.linspace(0, 2 * np.pi, 19)
    pitch = mbc_inverse(0.7, -0.2, psi, 2, 4)
    np.testing.assert_allclose(pitch[:, 1], -pitch[:, 0], atol=1e-12)
    np.testing.assert_allclose(pitch[:, 2], pitch[:, 0], atol=1e-12)
    assert harmonic_rank(2, 4) == 1
    out = mbc_forward(pitch, psi, 2)
    assert not np.allclose(out.cos, 0.7)


@pytest.mark.parametrize(
    "rotating, fixed",
    [(1, {0}), (2, {3}), (3, set()), (4, {3}), (5, {6}), (7, {6})],
)
def test_rotating_harmonic_maps_to_non_rotating_n_plus_minus_one(rotating, fixed):
    """With the 1P transform on three blades: 1P→0P, 2P→3P, 3P→none, 4P→3P, 5P→6P, 7P→6P (Fratini AC-5)."""
    psi = _azimuth_series()
    moments = np.cos(rotating * blade_azimuths(psi, 3) + 0.3)
    out = mbc_forward(moments, psi, 1)
    for axis in (out.cos, out.sin):
        spectrum = _spectrum_in_rotor_harmonics(axis, 4)
        assert set(np.flatnonzero(spectrum > 1e-9)) == fixed


@pytest.mark.parametrize("n_blades, harmonic", [(3, 1), (3, 2), (4, 1), (4, 2), (5, 1), (5, 2)])
def test_rotating_m_p_appears_only_at_m_plus_minus_n_multiples_of_the_blade_count(n_blades, harmonic):
    """Rotating mP reaches the non-rotating frame at |m − n|P and (m + n)P where that is a multiple of B."""
    psi = _azimuth_series(revolutions=2, samples_per_rev=128)
    for rotating in range(0, 9):
        moments = np.cos(rotating * blade_azimuths(psi, n_blades) + 0.3)
        out = mbc_forward(moments, psi, harmonic)
        expected = {k for k in (abs(rotating - harmonic), rotating + harmonic) if k % n_blades == 0}
        found = set(np.flatnonzero(_spectrum_in_rotor_harmonics(out.cos, 2) > 1e-9))
        assert found == expected, f"m={rotating}"


def test_phase_shifted_one_p_load_gives_constant_tilt_and_yaw():
    """M_i = A cos(ψ_i + φ) gives cos = A cos φ and sin = −A sin φ at every azimuth (Fratini AC-3)."""
    psi = np.linspace(0, 2 * np.pi, 25)
    out = mbc_forward(2.0 * np.cos(blade_azimuths(psi, 3) + math.radians(30)), psi, 1)
    np.testing.assert_allclose(out.cos, 2.0 * math.cos(math.radians(30)), atol=1e-12)
    np.testing.assert_allclose(out.sin, -2.0 * math.sin(math.radians(30)), atol=1e-12)


def test_demodulation_recovers_mean_and_one_p_amplitude_and_phase():
    """M_i = 5 + 2 cos(ψ_i − 30°) gives (5, 1.7321, 1.0000) (Disario A3)."""
    psi = np.linspace(0, 2 * np.pi, 25)
    out = mbc_forward(5.0 + 2.0 * np.cos(blade_azimuths(psi, 3) - math.radians(30)), psi, 1)
    np.testing.assert_allclose([out.mean, out.cos, out.sin], [[5.0] * 25, [1.7320508] * 25, [1.0] * 25], atol=1e-7)


def test_two_p_blade_load_gives_three_p_tilt_and_yaw():
    """M_i = cos(2ψ_i) gives cos = cos 3ψ and sin = sin 3ψ with the 1P transform (Fratini AC-2)."""
    psi = np.linspace(0, 2 * np.pi, 31)
    out = mbc_forward(np.cos(2 * blade_azimuths(psi, 3)), psi, 1)
    np.testing.assert_allclose(out.cos, np.cos(3 * psi), atol=1e-12)
    np.testing.assert_allclose(out.sin, np.sin(3 * psi), atol=1e-12)


@pytest.mark.parametrize("harmonic", [1, 2])
def test_phase_offset_rotates_the_cos_sin_plane_by_minus_the_offset(harmonic):
    """forward(inverse(c, s, φ)) = (c cos φ + s sin φ, −c sin φ + s cos φ)."""
    psi, phi, c, s = np.linspace(0, 2 * np.pi, 13), 0.6, 0.7, -0.2
    out = mbc_forward(mbc_inverse(c, s, psi, harmonic, 3, phase_offset=phi), psi, harmonic)
    np.testing.assert_allclose(out.cos, c * math.cos(phi) + s * math.sin(phi), atol=1e-12)
    np.testing.assert_allclose(out.sin, -c * math.sin(phi) + s * math.cos(phi), atol=1e-12)


def test_phase_offset_of_nineteen_degrees_is_a_static_rotation():
    """An inverse offset of 19° is the rotation [[cos, sin], [−sin, cos]] = (0.945519, 0.325568) (Disario A2)."""
    psi = np.linspace(0, 2 * np.pi, 11)
    unit_cos = mbc_forward(mbc_inverse(1.0, 0.0, psi, 1, 3, phase_offset=math.radians(19)), psi, 1)
    np.testing.assert_allclose(unit_cos.cos, 0.945519, atol=1e-6)
    np.testing.assert_allclose(unit_cos.sin, -0.325568, atol=1e-6)


def test_one_sample_and_a_time_series_give_the_same_components():
    """The transform is vectorised over time: row by row equals all at once."""
    rng = np.random.default_rng(3)
    moments, psi = rng.normal(size=(7, 4)), rng.uniform(0, 7, 7)
    batch = mbc_forward(moments, psi, 2)
    for k in range(7):
        single = mbc_forward(moments[k], psi[k], 2)
        assert np.shape(single.cos) == ()
        np.testing.assert_allclose([single.mean, single.cos, single.sin], [batch.mean[k], batch.cos[k], batch.sin[k]])
    assert mbc_inverse(0.1, 0.2, 0.3, 1, 4).shape == (4,)


@pytest.mark.parametrize("n_blades, harmonic", [(3, 1), (3, 2), (3, 3), (4, 1), (5, 4)])
def test_the_per_step_forms_equal_the_array_forms_bit_for_bit(n_blades, harmonic):
    """mbc_forward_sample / mbc_inverse_sample (plain floats, the controllers' per-step path) give exactly what
    mbc_forward / mbc_inverse give for one sample, so every engine's numbers are the transform's."""
    rng = np.random.default_rng(11)
    for _ in range(200):
        moments, psi, phi = rng.normal(size=n_blades) * 1e6, rng.uniform(-20, 20), rng.uniform(-1, 1)
        array, sample = mbc_forward(moments, psi, harmonic), mbc_forward_sample(moments.tolist(), psi, harmonic)
        assert (float(array.mean), float(array.cos), float(array.sin)) == tuple(sample)
        assert mbc_inverse(0.01, -0.02, psi, harmonic, n_blades, phi).tolist() == \
            mbc_inverse_sample(0.01, -0.02, psi, harmonic, n_blades, phi)
    with pytest.raises(InputError, match="blade_values: NaN at sample 1"):
        mbc_forward_sample([1.0, math.nan, 2.0], 0.0, 1)


def test_two_blades_are_refused_by_the_forward_transform_with_the_reason():
    """B = 2 is singular forwards; the error names n_blades and points to the harmonic estimator. The inverse
    exists for B = 2 (Zalkind & Pao's pitch law, tests/hawt_controllers/test_harmonic_estimator.py); B = 1 has none."""
    with pytest.raises(ConfigurationError, match="n_blades: the MBC transform is singular for B=2.*harmonic_estimator"):
        mbc_forward(np.ones(2), 0.0, 1)
    with pytest.raises(ConfigurationError, match="n_blades: must be >= 2"):
        mbc_inverse(0.1, 0.2, 0.0, 1, 1)


@pytest.mark.parametrize("harmonic", [0, -1, 1.5, True])
def test_harmonics_that_are_not_positive_integers_are_refused(harmonic):
    """n must be an integer >= 1."""
    with pytest.raises(ConfigurationError, match="harmonic"):
        mbc_forward(np.ones(3), 0.0, harmonic)


def test_bad_inputs_name_the_argument():
    """NaN moments and a mismatched azimuth shape are refused with the argument named."""
    with pytest.raises(InputError, match="blade_values: NaN"):
        mbc_forward([1.0, np.nan, 2.0], 0.0, 1)
    with pytest.raises(InputError, match=r"azimuth: expected shape \(4,\)"):
        mbc_forward(np.ones((4, 3)), np.zeros(3), 1)
