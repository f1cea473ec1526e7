"""Specification of hawt_plant.bem: induction, steady solution and NREL 5 MW performance."""
import math

import numpy as np
import pytest

from hawt_plant.bem import (induction_factors, pitch_sensitivity, prandtl_loss, rotor_performance, skewed_wake_factor,
                            solve_inflow_angle)


def test_power_coefficient_peaks_near_tsr_75_at_048(turbine, blade):
    """Cp(lambda) at 0 deg pitch peaks near lambda = 7.5 with Cp = 0.48 within 5 % (Jonkman 2009 ch. 7)."""
    ratios = np.arange(5.0, 10.01, 0.25)
    cp = [rotor_performance(turbine, 8.0, tsr * 8.0 / 63.0, 0.0, blade).power_coefficient for tsr in ratios]
    assert 7.0 <= ratios[int(np.argmax(cp))] <= 8.0
    assert max(cp) == pytest.approx(0.48, rel=0.05)


def test_power_at_rated_wind_and_speed_is_rated_shaft_power(turbine, blade):
    """At 11.4 m/s, 12.1 rpm and 0 deg the rotor gives the rated 5.3 MW shaft power within 5 %."""
    performance = rotor_performance(turbine, 11.4, 12.1 * math.pi / 30.0, 0.0, blade)
    assert performance.power == pytest.approx(5.0e6 / 0.944, rel=0.05)
    assert performance.tip_speed_ratio == pytest.approx(7.0, abs=0.01)


def test_the_equilibrium_pitch_sensitivity_is_the_slope_of_the_steady_power(turbine, blade):
    """With the induction re-solved, dP/dtheta is the central difference of rotor_performance's power; with the
    wake frozen it is steeper (the induction would relieve part of the change): 18 m/s, rated speed, 15 deg."""
    speed, pitch, step = 1.26711, math.radians(15.0), 1e-4
    slope = (rotor_performance(turbine, 18.0, speed, pitch + step, blade).power
             - rotor_performance(turbine, 18.0, speed, pitch - step, blade).power) / (2 * step)
    equilibrium = pitch_sensitivity(turbine, 18.0, speed, pitch, frozen_wake=False, blade=blade)
    frozen = pitch_sensitivity(turbine, 18.0, speed, pitch, frozen_wake=True, blade=blade)
    assert equilibrium == pytest.approx(slope, rel=1e-6)
    assert frozen < equilibrium < 0.0


def test_feathering_reduces_power_and_thrust(turbine, blade):
    """More pitch to feather, less power and thrust at rated speed in 18 m/s."""
    low, high = (rotor_performance(turbine, 18.0, 1.26711, math.radians(p), blade) for p in (10.0, 15.0))
    assert high.power < low.power and high.thrust < low.thrust


def test_steady_solution_balances_blade_element_and_momentum_thrust(turbine, blade):
    """In the momentum region each annulus' blade-element thrust equals 4 pi r rho V^2 F a (1 - a) dr."""
    speed, omega = 8.0, 7.5 * 8.0 / 63.0
    vx = np.full(blade.radius.shape, speed * math.cos(turbine.rotor.cone_angle))
    vy = omega * blade.radius
    phi = solve_inflow_angle(vx, vy, 0.0, blade)
    cl, _ = blade.polars.coefficients(phi - blade.twist)
    loss = prandtl_loss(np.sin(phi), blade)
    a, a_prime, _, _ = induction_factors(phi, cl, loss, blade.local_solidity)
    w2 = (vx * (1 - a)) ** 2 + (vy * (1 + a_prime)) ** 2
    element = 3 * 0.5 * w2 * blade.chord * cl * np.cos(phi)
    momentum = 4 * math.pi * blade.radius * vx**2 * loss * a * (1 - a)
    region = (a > 0.05) & (a < 0.38)
    assert region.sum() >= 8
    np.testing.assert_allclose(element[region], momentum[region], rtol=1e-6)


def test_buhl_correction_joins_momentum_theory_at_k_two_thirds():
    """The high-induction branch is continuous with a = k/(1+k) at k = 2/3 (a = 0.4 when F = 1)."""
    phi = np.array([0.2, 0.2])
    sin2 = math.sin(0.2) ** 2
    solidity = 1.0
    k = np.array([2 / 3 - 1e-9, 2 / 3 + 1e-9])
    cl = k * 4.0 * sin2 / (solidity * math.cos(0.2))
    a, _, k_found, _ = induction_factors(phi, cl, np.ones(2), np.full(2, solidity))
    np.testing.assert_allclose(k_found, k)
    np.testing.assert_allclose(a, 0.4, atol=1e-8)


def test_buhl_correction_reaches_one_at_high_loading():
    """With Buhl's empirical relation the induction rises towards 1, never beyond, at very high k."""
    phi = np.full(4, 0.1)
    cl = np.array([1.0, 10.0, 100.0, 1e4])
    a, _, _, _ = induction_factors(phi, cl, np.ones(4), np.full(4, 0.2))
    assert np.all(np.diff(a) > 0.0) and np.all(a < 1.0) and a[-1] > 0.99


def test_prandtl_loss_vanishes_at_the_tip_and_is_one_mid_span(blade):
    """F is near 1 mid-span, falls towards the tip and is 0 at the tip node and the root node (the hub)."""
    loss = prandtl_loss(np.full(blade.radius.shape, math.sin(0.1)), blade)
    assert loss[9] == pytest.approx(1.0, abs=1e-3)
    assert loss[-2] < 0.7 and np.all(np.diff(loss[9:]) < 0.0)
    assert loss[0] == 0.0 and loss[-1] == 0.0


def test_a_node_at_the_tip_or_the_hub_sees_only_its_rotation_as_in_aerodyn(turbine, blade):
    """Where the loss factor is 0 (the NREL 5 MW's root node at the hub and its tip node at 61.4999 m) AeroDyn 15
    takes a = 1 and a' = 0, so the inflow angle is 0 (measured with OpenFAST v5 at 8 m/s, 9 rpm: AxInd 1, TnInd 0,
    Phi 0 at the tip node); the nodes inside keep momentum theory's induction."""
    speed = 9.0 * math.pi / 30.0
    phi = solve_inflow_angle(np.full(blade.radius.shape, 8.0), speed * blade.radius, 0.0, blade)
    cl, _ = blade.polars.coefficients(phi - blade.twist)
    a, a_prime, _, _ = induction_factors(phi, cl, prandtl_loss(np.sin(phi), blade), blade.local_solidity)
    assert (phi[0], phi[-1], a[0], a[-1], a_prime[0], a_prime[-1]) == (0.0, 0.0, 1.0, 1.0, 0.0, 0.0)
    assert np.all((phi[1:-1] > 0.0) & (a[1:-1] < 0.5))


def test_parked_rotor_has_the_undisturbed_inflow_angle(blade):
    """Without rotation (vy = 0) the inflow angle is 90 deg and finite everywhere."""
    phi = solve_inflow_angle(np.full(blade.radius.shape, 10.0), np.zeros(blade.radius.shape), 0.0, blade)
    np.testing.assert_allclose(phi, math.pi / 2)


def test_tiled_blade_gives_every_row_the_loss_of_the_blade(blade):
    """A blade tiled for 3 blades evaluates a (3, N) inflow angle row by row like the blade itself."""
    tiled = blade.tiled(3)
    assert tiled.radius.shape == (3, blade.radius.size) and tiled.loss_exponents.shape == (2, 3, blade.radius.size)
    phi = np.linspace(0.9, 0.05, blade.radius.size) + np.array([[0.0], [0.01], [0.02]])
    loss = prandtl_loss(np.sin(phi), tiled)
    np.testing.assert_array_equal(loss, [prandtl_loss(np.sin(row), blade) for row in phi])


@pytest.mark.parametrize("a, chi0, tip_ratio, cos_azimuth", [(0.3, 0.1, 0.75, 1.0), (0.2, 0.3, 0.5, -0.4),
                                                             (0.0, -0.2, 1.0, 0.7)])
def test_skewed_wake_factor_is_pitt_and_peters_form(a, chi0, tip_ratio, cos_azimuth):
    """a_skew/a = 1 + (15π/32) tan(χ/2) (r/R) cos(ψ - ψ_d), χ = (1 + 0.6 a) χ_0 (AeroDyn SkewMod 2)."""
    chi = (1 + 0.6 * a) * chi0
    expected = 1 + 15 * math.pi / 32 * math.tan(chi / 2) * tip_ratio * cos_azimuth
    assert skewed_wake_factor(np.array(a), chi0, np.array(tip_ratio), np.array(cos_azimuth)) == pytest.approx(expected)


def test_skewed_wake_factor_is_one_without_skew_and_holds_chi_at_a_right_angle():
    assert np.all(skewed_wake_factor(np.array([0.1, 0.3]), 0.0, np.array([0.5, 1.0]), np.array([1.0, -1.0])) == 1.0)
    held = skewed_wake_factor(np.array(0.3), 1.5, np.array(1.0), np.array(1.0))
    assert held == pytest.approx(1 + 15 * math.pi / 32)  # tan(π/4) = 1
