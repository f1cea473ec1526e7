"""Specification of hawt_plant.modal: generalized properties from the ElastoDyn data."""
import math
from dataclasses import replace

import numpy as np
import pytest

from hawt_plant.modal import (beam_first_mode, blade_edge_mode, blade_edgewise_frequency, blade_modal_properties,
                              polynomial_mode, tower_modal_properties, twisted_tip_angle)


def test_mode_shape_has_unit_tip_and_zero_root_slope(turbine):
    """phi(0) = phi'(0) = 0, phi(1) = 1; derivatives match finite differences."""
    x = np.linspace(0.0, 1.0, 1001)
    phi, d1, d2 = polynomial_mode(turbine.blade_structure.flap_mode_shape, x)
    assert phi[0] == d1[0] == 0.0 and phi[-1] == pytest.approx(1.0, abs=1e-4)
    np.testing.assert_allclose(np.gradient(phi, x)[1:-1], d1[1:-1], atol=1e-4)
    np.testing.assert_allclose(np.gradient(d1, x)[1:-1], d2[1:-1], atol=1e-3)


def test_a_mode_twisted_alike_along_the_span_deflects_along_its_principal_axis_turned_by_that_twist():
    """A constant structural twist turns the whole mode: the tip deflects at that angle (ElastoDyn's twisted shape
    functions); without twist it deflects along the principal axis."""
    s = np.linspace(0.0, 60.0, 601)
    curvature = polynomial_mode(np.array([0.6, 0.3, 0.1, 0.0, 0.0]), s / 60.0)[2]
    assert twisted_tip_angle(curvature, np.full_like(s, 0.2), s) == pytest.approx(0.2, abs=1e-12)
    assert twisted_tip_angle(curvature, np.zeros_like(s), s) == 0.0


def test_a_mode_takes_the_twist_where_it_bends():
    """The tip's angle weighs the twist by the curvature and its arm to the tip: a beam bending only over its inner
    half, twisted 0.3 rad there and 0 outside, deflects at 0.3 rad; one bending only over its outer half at 0."""
    s = np.linspace(0.0, 60.0, 6001)
    inner, twist = s <= 30.0, np.where(s <= 30.0, 0.3, 0.0)
    assert twisted_tip_angle(np.where(inner, 1.0, 0.0), twist, s) == pytest.approx(0.3, abs=2e-3)
    assert twisted_tip_angle(np.where(inner, 0.0, 1.0), twist, s) == pytest.approx(0.0, abs=2e-3)


def test_the_nrel_5mw_modes_tip_angles_lie_within_the_twist_where_they_bend(turbine):
    """The NREL 5 MW's structural twist falls from 13.3 deg at the root to 0 at the tip; its edgewise mode bends mostly
    near the root, its flap mode further out: the tips deflect 9.6 and 7.3 deg from the pitch's direction."""
    flap, edge = blade_modal_properties(turbine).twist_angle, blade_edge_mode(turbine).twist_angle
    assert 0.0 < flap < edge < math.radians(13.3)
    assert (math.degrees(flap), math.degrees(edge)) == pytest.approx((7.27, 9.63), abs=0.01)


def test_blade_mass_and_centre_of_mass_match_jonkman(turbine):
    """17 740 kg and 20.475 m from the root (Jonkman 2009 Table 2-1), within 1 %."""
    blade = blade_modal_properties(turbine)
    assert blade.mass == pytest.approx(17740.0, rel=0.01)
    assert blade.first_moment / blade.mass == pytest.approx(20.475, rel=0.01)


def test_blade_flap_frequency_is_near_jonkman_table_9_1(turbine):
    """Non-rotating first flap of the blade alone, 0.667-0.70 Hz (Jonkman 2009 Table 9-1), within 5 %."""
    frequency = blade_modal_properties(turbine).natural_frequency / (2 * math.pi)
    assert 0.667 * 0.95 <= frequency <= 0.70 * 1.05


def test_the_edgewise_estimate_is_near_fasts_first_edgewise_modes(turbine):
    """The Rayleigh-Ritz estimate of the standing blade's first edgewise mode is within 2 % of FAST's first
    asymmetric edgewise modes, 1.0793 and 1.0898 Hz (Jonkman 2009 Table 9-1), and the same estimate over the flap
    stiffness gives the flap mode's frequency within 0.5 % (the basis holds the flap mode shape)."""
    assert 1.0793 * 0.98 <= blade_edgewise_frequency(turbine) <= 1.0898 * 1.02
    flap = replace(turbine, blade_structure=replace(turbine.blade_structure,
                                                    edge_stiffness=turbine.blade_structure.flap_stiffness))
    assert blade_edgewise_frequency(flap) == pytest.approx(
        blade_modal_properties(turbine).natural_frequency / (2 * math.pi), rel=0.005)


def test_rotation_stiffens_the_flap_mode(turbine):
    """At rated speed the centrifugal stiffening raises the flap frequency by a few percent."""
    blade = blade_modal_properties(turbine)
    omega = turbine.schedule.rated_rotor_speed
    rotating = math.sqrt((blade.stiffness + blade.centrifugal_stiffness * omega**2) / blade.modal_mass)
    assert 1.02 < rotating / blade.natural_frequency < 1.10


def test_rotor_inertia_matches_the_elastodyn_summary(turbine):
    """Hub plus three coned blades: 38 677 040 kg m^2 (ROSCO NREL5MW.yaml rotor_inertia) within 1 %."""
    blade = blade_modal_properties(turbine)
    rh = turbine.rotor.hub_radius
    about_apex = blade.second_moment + 2 * rh * blade.first_moment + rh**2 * blade.mass
    inertia = turbine.rotor.hub_inertia + 3 * math.cos(turbine.rotor.cone_angle) ** 2 * about_apex
    assert inertia == pytest.approx(38_677_040.613, rel=0.01)


def test_gravity_softens_the_tower(turbine):
    """The gravity stiffness makes the tower softer with a heavier top mass."""
    light = tower_modal_properties(turbine, "fa", 1.0)
    heavy = tower_modal_properties(turbine, "fa", 350_000.0)
    assert heavy.stiffness < light.stiffness
    assert heavy.top_slope == light.top_slope > 0.0


def test_a_rigid_base_raises_the_tower_without_changing_its_mode(turbine):
    """The same tower clamped on a rigid base 15 m high: its mode is unchanged, and so are the moments about its base
    (where the plant takes the tower-base moments), which does not move."""
    tower = turbine.tower
    raised = replace(turbine, tower=replace(tower, height=tower.height + 15.0, base_height=15.0, clamp_height=15.0))
    assert raised.tower.base_kind == "rigid" and turbine.tower.base_kind == "ground"
    top = 350_000.0
    ground, rigid = tower_modal_properties(turbine, "fa", top), tower_modal_properties(raised, "fa", top)
    for name in ("modal_mass", "modal_first_moment", "modal_height_moment", "mass_above_base", "stiffness",
                 "top_slope"):
        assert getattr(rigid, name) == pytest.approx(getattr(ground, name), rel=1e-12)
    assert rigid.base_shape == ground.base_shape == 0.0


def test_on_a_flexible_base_the_base_moments_cover_the_tower_above_its_base_which_moves_with_the_mode(turbine):
    """The NREL 5 MW's tower with its lowest 20 m as a flexible base (clamp at 0, base at 20 m): the mass and the
    moments for the tower-base loads are those of the tower above 20 m, about 20 m; the base moves phi(base)."""
    tower, top = turbine.tower, 350_000.0
    on_base = replace(turbine, tower=replace(tower, base_height=20.0))
    assert on_base.tower.base_kind == "flexible"
    whole, flexible = tower_modal_properties(turbine, "fa", top), tower_modal_properties(on_base, "fa", top)
    h = np.linspace(20.0, tower.height, 20001)
    x = h / tower.height
    mu = np.interp(x, tower.height_fraction, tower.mass_density)
    phi = polynomial_mode(tower.fa_mode_shape, x)[0]
    assert flexible.mass_above_base == pytest.approx(np.trapezoid(mu, h), rel=1e-6)
    assert flexible.modal_first_moment == pytest.approx(np.trapezoid(mu * phi, h), rel=1e-6)
    assert flexible.modal_height_moment == pytest.approx(np.trapezoid(mu * phi * (h - 20.0), h), rel=1e-6)
    assert flexible.base_shape == pytest.approx(polynomial_mode(tower.fa_mode_shape, np.array(20.0 / tower.height))[0])
    assert flexible.modal_mass == whole.modal_mass and flexible.stiffness == whole.stiffness


def test_the_beam_mode_is_the_best_shape_of_elastodyns_basis(turbine):
    """beam_first_mode on the NREL 5 MW's tower: a shape adding up to 1 (unit top) whose frequency, evaluated by
    tower_modal_properties, is the one returned, and below that of the deck's own TwFAM1Sh (Rayleigh-Ritz gives
    the lowest over the basis); within 3 % of it."""
    tower, top = turbine.tower, 350_000.0
    shape, frequency = beam_first_mode(tower.height_fraction, tower.mass_density, tower.fa_stiffness, tower.length,
                                       top, turbine.environment.gravity)
    assert shape.sum() == pytest.approx(1.0)

    def hertz(coefficients: np.ndarray) -> float:
        mode = tower_modal_properties(replace(turbine, tower=replace(tower, fa_mode_shape=coefficients)), "fa", top)
        return math.sqrt(mode.stiffness / (mode.modal_mass + top)) / (2.0 * math.pi)

    assert hertz(shape) == pytest.approx(frequency, rel=1e-9)
    assert frequency < hertz(tower.fa_mode_shape) < 1.03 * frequency


def test_the_beam_mode_of_a_uniform_beam_is_the_cantilevers(turbine):
    """A uniform cantilever without top mass or gravity: 1.8751^2 sqrt(EI / (mu L^4)) / (2 pi) (Euler-Bernoulli) to
    within 1e-4."""
    fraction = np.array([0.0, 1.0])
    shape, frequency = beam_first_mode(fraction, np.full(2, 5000.0), np.full(2, 4e11), 80.0, 0.0, 0.0)
    assert frequency == pytest.approx(1.87510407**2 * math.sqrt(4e11 / (5000.0 * 80.0**4)) / (2 * math.pi), rel=1e-4)


def test_unknown_tower_direction_is_rejected(turbine):
    """Only 'fa' and 'ss' exist."""
    with pytest.raises(ValueError, match="direction"):
        tower_modal_properties(turbine, "yaw", 1.0)


def test_the_towers_structural_damping_is_elastodyns_on_the_tower_alone(turbine):
    """ElastoDyn (CTSS) gives the deck's damping ratio to the tower's own mode: c = 2 zeta sqrt(k_bending m_tower).
    The NREL 5 MW parked in still air (0.01 m/s; no tower drag or shadow), its tower top pushed 0.2 m sideways: the
    side-side mode decays at c omega / (2 k) of critical, within 5 %, which with the rotor and nacelle on top is
    under half the deck's 1 % (as OpenFAST's 0.65 % at 18 m/s with the rotor's aerodynamic damping; plant 0.65 %)."""
    from scipy.signal import find_peaks

    from hawt_plant.model import ModelConfig, TurbineModel
    from hawt_plant.shear_wind import PowerLawWind

    model = TurbineModel(turbine, PowerLawWind(0.01),
                         ModelConfig(rotor="parked", tower_drag=False, tower_shadow=False))
    output = model.reset_to_operating_point(tower_offset=(0.0, 0.2))
    side = np.array([model.step(output.pitch.copy(), 0.0).tower_top_ss_disp for _ in range(4000)])
    side -= side[-1000:].mean()
    peaks, _ = find_peaks(side)
    peaks = peaks[side[peaks] > 0][:8]
    ratio = -np.polyfit(np.arange(peaks.size), np.log(side[peaks]), 1)[0] / (2.0 * math.pi)
    omega = 2.0 * math.pi / (0.01 * np.mean(np.diff(peaks)))
    top = turbine.rotor.hub_mass + turbine.nacelle.mass + 3 * blade_modal_properties(turbine).mass
    ss = tower_modal_properties(turbine, "ss", top)
    assert ratio == pytest.approx(ss.damping * omega / (2.0 * ss.stiffness), rel=0.05)
    assert ratio < 0.5 * turbine.tower.ss_damping_ratio
