"""Load transfer along the chain (Zalkind & Pao eqs. 8–17, 20): acceptance checks AC-06 … AC-09, AC-14 and
AC-15 of literature/notes/seed001_zalkind.md §6."""
import math

import numpy as np
import pytest

from hawt_analysis.load_transfer import (fit_transfer, fit_transfer_by_region, hub_to_main_bearing,
                                         main_bearing_from_hub_1p, main_bearing_to_hub, operating_region)
from hawt_core.rotor.harmonic_estimator import sliding_phasors
from hawt_plant.shear_wind import PowerLawWind

PSI = np.arange(0, 2 * 256 + 1) * (2.0 * math.pi / 256)  # two revolutions, uniform in azimuth


def _harmonic(phasor, order, psi=PSI):
    """The time-domain harmonic Re{conj(m) e^{j i ψ}} = m_c cos iψ + m_s sin iψ of a phasor m = m_c + j m_s."""
    return phasor.real * np.cos(order * psi) + phasor.imag * np.sin(order * psi)


def _main_bearing_phasors(hub_y_1p, hub_z_1p):
    """Estimated 0P…4P of the main-bearing moments, from hub loads holding only these 1P phasors (eq. 13)."""
    main_y, main_z = hub_to_main_bearing(_harmonic(hub_y_1p, 1), _harmonic(hub_z_1p, 1), PSI)
    return sliding_phasors(np.column_stack((main_y, main_z)), PSI).phasors[-1]


@pytest.mark.parametrize("seed", range(5))
def test_ac06_hub_1p_reaches_the_main_bearing_as_0p_and_2p_by_eqs_14_15_16_corrected_17(seed):
    """AC-06: only 0P and 2P at the main bearing; eqs. 14, 15, 17 and the corrected 16 hold to machine precision."""
    rng = np.random.default_rng(seed)
    hub_y, hub_z = rng.normal(size=2) + 1j * rng.normal(size=2)
    (y0, y1, y2, y3, y4), (z0, z1, z2, z3, z4) = _main_bearing_phasors(hub_y, hub_z)
    assert max(abs(v) for v in (y1, y3, y4, z1, z3, z4)) < 1e-12
    closed = main_bearing_from_hub_1p(hub_y, hub_z)
    assert abs(y0 - closed.y0) < 1e-12 and abs(y2 - closed.y2) < 1e-12  # (14), (15)
    assert abs(z0 - closed.z0) < 1e-12 and abs(z2 - closed.z2) < 1e-12  # (16) corrected, (17)


def test_ac06_erratum_eq_16_as_printed_does_not_hold():
    """Regression record of the erratum: ½ Re{m_hz + j m_hy} (as printed) misses the simulated m_mz^{0P}."""
    hub_y, hub_z = 0.8 - 1.3j, 0.5 + 0.9j
    simulated = _main_bearing_phasors(hub_y, hub_z)[1, 0].real
    assert abs(0.5 * (hub_z + 1j * hub_y).real - simulated) == pytest.approx(1.3)  # off by Im m_hy^{1P}
    assert 0.5 * (hub_z - 1j * hub_y).real == pytest.approx(simulated, abs=1e-12)


def test_main_bearing_to_hub_inverts_eq_13():
    psi = np.linspace(0.0, 7.0, 50)
    y, z = np.sin(3 * psi) + 2.0, np.cos(psi) - 1.0
    np.testing.assert_allclose(main_bearing_to_hub(*hub_to_main_bearing(y, z, psi), psi), (y, z), atol=1e-14)


def test_ac07_the_control_condition_removes_the_main_bearing_2p_and_leaves_a_constant_load():
    """AC-07: m_hy^{1P} = j m_hz^{1P} (eq. 20) with m_hz^{1P} = 0.7 − 0.4j: no 2P on either axis, and the
    main-bearing load is the constant (Re m_hy^{1P}, Re m_hz^{1P}) = (0.4, 0.7)."""
    hub_z = 0.7 - 0.4j
    hub_y = 1j * hub_z
    closed = main_bearing_from_hub_1p(hub_y, hub_z)
    assert abs(closed.y2) < 1e-15 and abs(closed.z2) < 1e-15
    main_y, main_z = hub_to_main_bearing(_harmonic(hub_y, 1), _harmonic(hub_z, 1), PSI)
    np.testing.assert_allclose(main_y, 0.4, atol=1e-14)
    np.testing.assert_allclose(main_z, 0.7, atol=1e-14)


def test_ac08_a_constant_fixed_frame_moment_satisfies_the_condition_in_the_hub_frame():
    """AC-08: a constant (G_y, G_z) = (2.0, −0.5) seen in the rotating hub frame has 1P phasors m_hy^{1P} =
    j m_hz^{1P} = G_y + j G_z = 2 − 0.5j (a gravity or mass-offset moment needs no pitch)."""
    hub_y, hub_z = main_bearing_to_hub(np.full(PSI.size, 2.0), np.full(PSI.size, -0.5), PSI)
    phasors = sliding_phasors(np.column_stack((hub_y, hub_z)), PSI).phasors[-1]
    assert phasors[0, 1] == pytest.approx(2.0 - 0.5j, abs=1e-12)
    assert 1j * phasors[1, 1] == pytest.approx(2.0 - 0.5j, abs=1e-12)


@pytest.mark.parametrize("blades, expected", [(2, {0: 1.0, 2: 1.097679, 4: 0.053852}),
                                              (3, {0: 1.5, 3: 0.348891})])
def test_ac09_blade_harmonics_reach_the_fixed_frame_tilt_only_at_multiples_of_b(blades, expected):
    """AC-09: identical blades with harmonics {0P: 5; 1P: 1.0 + 0.3j; 2P: 0.2 + 0.1j; 3P: 0.05 + 0.02j;
    4P: 0.01}; tilt = Σ_k M_k cos ψ_k: B = 2 gives 0P, 2P, 4P; B = 3 gives 0P and 3P (1e-6)."""
    blade = {0: 5.0, 1: 1.0 + 0.3j, 2: 0.2 + 0.1j, 3: 0.05 + 0.02j, 4: 0.01}
    tilt = np.zeros(PSI.size)
    for k in range(blades):
        psi_k = PSI + 2.0 * math.pi * k / blades
        tilt += sum(_harmonic(complex(m), i, psi_k) for i, m in blade.items()) * np.cos(psi_k)
    magnitudes = np.abs(sliding_phasors(tilt, PSI, max_harmonic=5).phasors[-1])
    np.testing.assert_allclose(magnitudes, [expected.get(i, 0.0) for i in range(6)], atol=1e-6)


def test_ac14_the_complex_affine_fit_recovers_the_map_and_refuses_a_single_point():
    """AC-14: noise-free m_2 = a_1 m_1 + a_0 over N ≥ 2 points: recovered exactly; N = 1 is singular."""
    gain, offset = 0.8 - 0.35j, -1.2 + 0.4j
    m1 = np.array([1.0 + 2.0j, -0.5 + 0.1j, 3.0 - 1.0j, 0.2 + 0.2j])
    fit = fit_transfer(m1, gain * m1 + offset)
    assert fit.gain == pytest.approx(gain, abs=1e-12) and fit.offset == pytest.approx(offset, abs=1e-12)
    assert fit.residual_rms < 1e-12 and fit.points == 4
    two = fit_transfer(m1[:2], gain * m1[:2] + offset)
    assert two.gain == pytest.approx(gain, abs=1e-12)
    with pytest.raises(ValueError, match="m1: the fit needs N >= 2 operating points"):
        fit_transfer(m1[:1], m1[:1])
    with pytest.raises(ValueError, match="singular"):
        fit_transfer([1.0 + 1j, 1.0 + 1j], [0.0, 1.0])


def test_ac14_ac18_regions_ii_and_iii_are_fitted_separately_by_the_collective_pitch():
    """AC-14/AC-18: points with the collective pitch above fine pitch are region III and get their own fit."""
    m1 = np.array([1.0, 2.0, 3.0, 1.0 + 1j, 2.0 + 1j, 4.0 + 1j])
    pitch = np.radians([0.0, 0.0, 0.2, 3.0, 8.0, 14.0])
    m2 = np.where(operating_region(pitch) == 2, 2.0 * m1 + 1.0, -0.5j * m1)
    fits = fit_transfer_by_region(m1, m2, pitch)
    assert operating_region(pitch).tolist() == [2, 2, 2, 3, 3, 3]
    assert fits[2].gain == pytest.approx(2.0) and fits[2].offset == pytest.approx(1.0)
    assert fits[3].gain == pytest.approx(-0.5j) and abs(fits[3].offset) < 1e-12
    assert set(fit_transfer_by_region(m1[:4], m2[:4], pitch[:4])) == {2}


def test_ac15_power_law_shear_over_the_sumr_rotor():
    """AC-15: z_h = 142.4 m, R = 106.8 m, α = 0.14: u/u_h = 1.0815 at 249.2 m and 0.8236 at 35.6 m."""
    wind = PowerLawWind(10.0, hub_height=142.4, shear_exponent=0.14)
    u = wind.velocity(0.0, np.zeros(2), np.zeros(2), np.array([249.2, 35.6]))[0] / 10.0
    np.testing.assert_allclose(u, [1.0815, 0.8236], atol=5e-5)


def test_a_record_has_the_rotating_hub_moments_of_its_main_bearing_moments():
    """make_record adds hub_rotating_y/z_moment (eq. 13 inverted) wherever hub tilt, yaw and azimuth are recorded,
    so bags recorded before these channels have them; summarize gives their DELs (steel, m = 4)."""
    from hawt_analysis.record import make_record
    from hawt_analysis.summary import summarize

    time = np.arange(2001) * 0.01
    azimuth = np.mod(1.3 * time, 2 * math.pi)
    tilt, yaw = 2.0 + np.cos(2 * azimuth), -0.5 + 0.3 * np.sin(2 * azimuth)
    channels = {"time": time, "azimuth": azimuth, "rotor_speed": np.full(time.size, 1.3),
                "hub_tilt_moment": tilt, "hub_yaw_moment": yaw}
    record = make_record(channels)
    expected = main_bearing_to_hub(tilt, yaw, azimuth)
    np.testing.assert_allclose(record.scalars["hub_rotating_y_moment"], expected[0], atol=1e-12)
    np.testing.assert_allclose(record.scalars["hub_rotating_z_moment"], expected[1], atol=1e-12)
    assert summarize(channels)["del"]["hub_rotating_y_moment"]["m"] == 4.0
