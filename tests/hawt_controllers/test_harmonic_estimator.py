"""Harmonic estimator (Zalkind & Pao eqs. 2–7) and the two-bladed pitch law (eqs. 18–19): acceptance checks
AC-01 … AC-05, AC-12 and AC-13 of literature/notes/seed001_zalkind.md §6."""
import math

import numpy as np
import pytest

from hawt_core.exceptions import ConfigurationError, InputError
from hawt_core.rotor.harmonic_estimator import HarmonicEstimator, sliding_phasors
from hawt_core.rotor.mbc import mbc_inverse

RNG = np.random.default_rng(17)
C = RNG.normal(size=5)
S = np.concatenate(([0.0], RNG.normal(size=4)))
EXPECTED = C + 1j * S  # m_0, then m_c + j m_s of 1P…4P


def _signal(psi):
    """m(ψ) = m_0 + Σ_{i=1..4} c_i cos iψ + s_i sin iψ (eq. 2)."""
    return C[0] + sum(C[i] * np.cos(i * psi) + S[i] * np.sin(i * psi) for i in range(1, 5))


def _varying_speed_azimuth(samples_per_revolution, revolutions, seed=3):
    """Azimuth of a rotor whose speed varies ±10 % sinusoidally, sampled with a random (non-uniform) time step."""
    rng = np.random.default_rng(seed)
    mean_step = 2.0 * math.pi / samples_per_revolution
    t = np.cumsum(mean_step * (0.85 + 0.3 * rng.random(int(1.2 * samples_per_revolution * revolutions))))
    omega = 1.0 + 0.1 * np.sin(2.0 * math.pi * t / 7.3)
    psi = np.concatenate(([0.0], np.cumsum(omega[1:] * np.diff(t))))
    return psi[psi <= 2.0 * math.pi * revolutions]


def test_ac01_exact_recovery_over_a_window_of_exactly_two_revolutions():
    """AC-01: 64 samples per revolution, uniform in azimuth: m_0, c_i, s_i recovered to 1e-9 relative."""
    psi = np.arange(0, 3 * 128 + 1) * (2.0 * math.pi / 64)
    estimate = sliding_phasors(_signal(psi), psi, revolutions=2)
    relative = np.abs(estimate.phasors[-1] - EXPECTED).max() / np.abs(EXPECTED).max()
    assert relative <= 1e-9
    assert estimate.phasors[-1, 0].imag == 0.0  # the 0P component is real
    assert estimate.valid[128] and not estimate.valid[127]


def test_ac02_true_amplitudes_by_default_and_the_printed_factor_gives_half():
    """AC-02: m = A cos ψ gives m_c^{1P} = A (1/(πN_R)); the printed 1/(2πN_R) gives A/2, the same mean."""
    psi = np.linspace(0.0, 4.0 * math.pi, 257)
    m = 1.25 + 3.0 * np.cos(psi)
    amplitude = sliding_phasors(m, psi).phasors[-1]
    printed = sliding_phasors(m, psi, normalisation="printed").phasors[-1]
    assert amplitude[1] == pytest.approx(3.0, abs=1e-12) and printed[1] == pytest.approx(1.5, abs=1e-12)
    assert amplitude[0] == pytest.approx(1.25, abs=1e-12) and printed[0] == pytest.approx(1.25, abs=1e-12)


def test_ac03_magnitude_and_phase_are_eqs_6_7_with_atan2():
    """AC-03: (m_c, m_s) = (−1, −1): |m| = √2, ∠m = −135° (not +45°); the harmonic peaks at ψ = ∠m / i."""
    psi = np.linspace(0.0, 4.0 * math.pi, 513)
    phasor = sliding_phasors(-np.cos(psi) - np.sin(psi), psi).phasors[-1, 1]
    assert abs(phasor) == pytest.approx(math.sqrt(2.0), abs=1e-12)
    assert math.degrees(np.angle(phasor)) == pytest.approx(-135.0, abs=1e-9)
    peak = psi[np.argmax(-np.cos(psi[:257]) - np.sin(psi[:257]))]
    assert peak == pytest.approx(np.angle(phasor) % (2 * math.pi), abs=2 * math.pi / 256)


@pytest.mark.parametrize("samples_per_revolution", [100, 400])
def test_ac04_integration_is_in_azimuth_so_a_varying_speed_and_time_step_do_not_bias_it(samples_per_revolution):
    """AC-04: rotor speed ±10 % and a random time step, ≥ 100 samples per revolution: within 1e-3 relative."""
    psi = _varying_speed_azimuth(samples_per_revolution, 6)
    estimate = sliding_phasors(_signal(psi), psi).phasors
    assert np.abs(estimate[-1] - EXPECTED).max() / np.abs(EXPECTED).max() < 1e-3


def test_ac05_a_step_in_the_1p_amplitude_is_followed_linearly_and_reached_exactly_n_r_revolutions_later():
    """AC-05: amplitude 1 → 2 at ψ_step; the estimate moves linearly in azimuth and reaches 2 after exactly
    N_R = 2 revolutions: 12.12 s at 9.90 rpm."""
    rpm = 9.90
    omega = rpm * 2.0 * math.pi / 60.0
    t = np.arange(0.0, 40.0, 0.01)
    psi = omega * t
    step_time = 10.0
    m = np.where(t < step_time, 1.0, 2.0) * np.cos(psi)
    magnitude = np.abs(sliding_phasors(m, psi).phasors[:, 1])
    window = 2 * 60.0 / rpm  # 12.12 s
    assert window == pytest.approx(12.12, abs=0.005)
    after = np.searchsorted(t, step_time + window)
    assert np.all(magnitude[after:] == pytest.approx(2.0, abs=1e-8))  # window edge interpolated linearly
    assert magnitude[after - 2] < 2.0 - 1e-4
    for fraction in (0.25, 0.5, 0.75):  # linear in between
        assert magnitude[np.searchsorted(t, step_time + fraction * window)] == pytest.approx(1 + fraction, abs=0.01)


def test_the_streaming_estimator_equals_the_record_form_and_unwraps_a_wrapped_azimuth():
    """HarmonicEstimator, fed one sample at a time with ψ wrapped to [0, 2π), gives the record form's phasors."""
    psi = _varying_speed_azimuth(120, 5)
    values = np.column_stack((_signal(psi), 2.0 * np.sin(psi)))
    reference = sliding_phasors(values, psi)
    estimator = HarmonicEstimator(2)
    for k, (angle, sample) in enumerate(zip(psi % (2 * math.pi), values)):
        out = estimator.update(angle, sample)
        if k % 97 == 0 or k == psi.size - 1:
            np.testing.assert_allclose(out, reference.phasors[k], atol=1e-9)
            assert estimator.valid == reference.valid[k]
    assert estimator.valid


def test_bad_configuration_and_input_are_refused_naming_the_value():
    with pytest.raises(ConfigurationError, match="revolutions: must be finite and > 0"):
        HarmonicEstimator(1, revolutions=0.0)
    with pytest.raises(ConfigurationError, match="normalisation: must be one of"):
        sliding_phasors(np.ones(4), np.arange(4.0), normalisation="half")
    with pytest.raises(InputError, match="azimuth: must not turn backwards"):
        sliding_phasors(np.ones(4), np.array([0.0, 0.2, 0.1, 0.3]))
    with pytest.raises(InputError, match="values"):
        HarmonicEstimator(2).update(0.0, [1.0, math.nan])


def test_ac12_two_blade_pitch_law_is_antisymmetric_and_its_measured_phase_is_the_conjugate():
    """AC-12: θ^{1P} = 0.02∠30° (eq. 18) is the harmonic/1 demand c − j s = θ^{1P}, i.e. (c, s) = (Re, −Im);
    θ_2 = −θ_1 at every ψ, θ_1 peaks at ψ = −30°, and the estimator reads θ_1's 1P as 0.02∠−30°."""
    theta = 0.02 * np.exp(1j * math.radians(30.0))
    psi = np.linspace(0.0, 4.0 * math.pi, 721)
    pitch = mbc_inverse(theta.real, -theta.imag, psi, 1, 2)
    np.testing.assert_allclose(pitch[:, 1], -pitch[:, 0], atol=1e-15)
    np.testing.assert_allclose(pitch[:, 0], abs(theta) * np.cos(psi + np.angle(theta)), atol=1e-15)  # eq. 18
    assert math.degrees(psi[np.argmax(pitch[:360, 0])]) == pytest.approx(330.0, abs=0.5)
    measured = sliding_phasors(pitch[:, 0], psi).phasors[-1, 1]
    assert measured == pytest.approx(np.conj(theta), abs=1e-12)


def test_ac13_an_even_harmonic_on_two_blades_is_collective_like():
    """AC-13: θ_k = A cos(2ψ_k + φ) gives θ_2 = θ_1: a 2P pitch moves both blades together (no hub-y moment)."""
    psi = np.linspace(0.0, 2.0 * math.pi, 181)
    pitch = mbc_inverse(0.01 * math.cos(0.4), -0.01 * math.sin(0.4), psi, 2, 2)
    np.testing.assert_allclose(pitch[:, 1], pitch[:, 0], atol=1e-15)
    np.testing.assert_allclose(pitch[:, 0], 0.01 * np.cos(2 * psi + 0.4), atol=1e-15)
