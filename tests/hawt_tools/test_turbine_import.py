"""hawt turbine import / show (issue 20 items 1-2): OpenFAST decks as hawt turbine definitions.

The decks are ROSCO's test cases in the installed ``rosco`` wheel (Examples/Test_Cases), found through the
distribution's files. The NREL 5 MW deck imported must give the shipped definition
(hawt_plant/turbines/nrel_5mw), field by field, within the tolerance each field states; the values the shipped
file takes from Jonkman et al. (2009) instead of the deck are listed with both numbers.
"""
import dataclasses
import math
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
import yaml

from hawt_bag.plant_run import load_plant_run
from hawt_bag.reader import BagReader
from hawt_controllers.design.tunings import TuningError, tuning_file
from hawt_plant.model import ModelConfig, TurbineModel
from hawt_plant.shear_wind import PowerLawWind
from hawt_plant.turbine import load_turbine, nrel_5mw, nrel_5mw_two_bladed_downwind, turbine_from
from hawt_plant.turbine_summary import format_summary, turbine_summary
from hawt_tools.cli import main
from hawt_tools.turbine_import import RIGID_TORSION_FREQUENCY, node_widths, import_deck, write_turbine

NREL_5MW = "NREL-5MW/NREL-5MW.fst"
IEA_15MW = "IEA-15-240-RWT/IEA-15-240-RWT-Monopile/IEA-15-240-RWT-Monopile.fst"
NREL_2P8 = "NREL_2p8_127/NREL-2p8-127.fst"
BAR_10 = "BAR_10/BAR_10.fst"


@pytest.fixture(scope="module")
def imported_5mw(imported_deck):
    return load_turbine(imported_deck(NREL_5MW) / "turbine.yaml")


EXACT = (0.0, 0.0, "copied verbatim")
DEGREES = (0.0, 5e-7, "deg x pi/180; the shipped file writes radians to 6 or 8 decimals")
MATCHES = {
    "environment.air_density": EXACT,
    "environment.gravity": EXACT,
    "rotor.number_of_blades": EXACT,
    "rotor.hub_radius": EXACT,
    "rotor.tip_radius": EXACT,
    "rotor.cone_angle": (0.0, 5e-9, "ElastoDyn PreCone(1) = -2.5 deg, negated; the shipped file writes 8 decimals"),
    "rotor.shaft_tilt": (0.0, 5e-9, "ElastoDyn ShftTilt = -5 deg, negated; the shipped file writes 8 decimals"),
    "rotor.overhang": EXACT,
    "rotor.hub_mass": EXACT,
    "rotor.hub_inertia": EXACT,
    "rotor.downwind": EXACT,
    "nacelle.mass": (0.0, 0.0, "NacMass; the deck's YawBrMass is 0"),
    "nacelle.cm_downwind": EXACT,
    "nacelle.cm_above_tower_top": EXACT,
    "nacelle.yaw_inertia": EXACT,
    "nacelle.shaft_above_tower_top": EXACT,
    "blade_aerodynamics.span": (0.0, 0.0, "AeroDyn's 19 nodes, as shipped"),
    "blade_aerodynamics.width": (0.0, 1e-5, "from the spans, as the shipped file derived them (5 decimals)"),
    "blade_aerodynamics.chord": EXACT,
    "blade_aerodynamics.twist": DEGREES,
    "blade_aerodynamics.airfoil": EXACT,
    "blade_structure.span_fraction": EXACT,
    "blade_structure.structural_twist": DEGREES,
    "blade_structure.mass_density": (0.0, 0.0, "BMassDen x AdjBlMs, the loader multiplies both"),
    "blade_structure.flap_stiffness": (0.0, 0.0, "FlpStff; AdjFlSt and FlStTunr(1) are 1"),
    "blade_structure.edge_stiffness": (0.0, 0.0, "EdgStff; AdjEdSt is 1"),
    "blade_structure.flap_mode_shape": EXACT,
    "blade_structure.flap_damping_ratio": (1e-12, 0.0, "BldFlDmp(1) / 100"),
    "blade_structure.edge_mode_shape": EXACT,
    "blade_structure.edge_damping_ratio": (1e-12, 0.0, "BldEdDmp(1) / 100"),
    "tower.height": EXACT,
    "tower.height_fraction": EXACT,
    "tower.mass_density": EXACT,
    "tower.fa_stiffness": EXACT,
    "tower.ss_stiffness": EXACT,
    "tower.fa_mode_shape": EXACT,
    "tower.ss_mode_shape": EXACT,
    "tower.fa_damping_ratio": (1e-12, 0.0, "TwrFADmp(1) / 100"),
    "tower.ss_damping_ratio": (1e-12, 0.0, "TwrSSDmp(1) / 100"),
    "tower.outline_elevation": EXACT,
    "tower.outline_diameter": EXACT,
    "tower.drag_coefficient": EXACT,
    "tower.base_height": EXACT,
    "tower.clamp_height": EXACT,
    "drivetrain.gearbox_ratio": EXACT,
    "drivetrain.gearbox_efficiency": (1e-12, 0.0, "GBoxEff / 100"),
    "drivetrain.generator_inertia": EXACT,
    "drivetrain.torsional_stiffness": EXACT,
    "drivetrain.torsional_damping": EXACT,
    "generator.efficiency": (1e-12, 0.0, "ServoDyn GenEff / 100"),
    "generator.rated_power": EXACT,
    "generator.rated_torque": (2e-6, 0.0, "DISCON.IN VS_RtTq = 4.30935e4 (6 digits); the shipped 43093.55 is "
                                          "Jonkman's VS_RtTq"),
    "generator.max_torque": (2e-6, 0.0, "DISCON.IN VS_MaxTq = 4.74029e4 (6 digits); the shipped 47402.91 is "
                                        "Jonkman's VS_MaxTq"),
    "pitch_actuator.min_angle": EXACT,
    "pitch_actuator.max_angle": (0.0, 1e-3, "DISCON.IN PC_MaxPit = 1.57; the shipped 90 deg = 1.570796 rad"),
    "pitch_actuator.natural_frequency": (0.0, 0.0, "DISCON.IN PA_Mode = 0: hawt's default, as the shipped file"),
    "pitch_actuator.damping_ratio": (0.0, 0.0, "DISCON.IN PA_Mode = 0: hawt's default, as the shipped file"),
    "schedule.cut_in_wind_speed": EXACT,
    "schedule.rated_wind_speed": EXACT,
    "schedule.cut_out_wind_speed": EXACT,
    "schedule.rated_rotor_speed": (1e-9, 0.0, "DISCON.IN PC_RefSpd / GBRatio = 122.90967 / 97"),
    "aerodynamics.tower_shadow": (0.0, 0.0, "AeroDyn15 TwrPotent = 1"),
    "aerodynamics.tower_drag": (0.0, 0.0, "AeroDyn15 TwrAero = True"),
    "aerodynamics.skewed_wake": (0.0, 0.0, "AeroDyn15 Skew_Mod = 1, SkewRedistr_Mod = default"),
    "aerodynamics.unsteady_airfoil": (0.0, 0.0, "AeroDyn15 UA_Mod = 3"),
    "aerodynamics.dynamic_inflow": (0.0, 0.0, "AeroDyn15 Wake_Mod = 1 with DBEMT_Mod = 2"),
    **{f"protection.{name}": (1e-6, 0.0, "neither has a protection section: the defaults from the same ratings")
       for name in ("rotor_speed_warning", "rotor_speed_trip", "generator_speed_warning", "generator_speed_trip",
                    "tower_top_acceleration_trip", "pitch_asymmetry_trip")},
}
"""Field of the definition -> (relative tolerance, absolute tolerance, why) of the import against the shipped."""

DELIBERATE = {
    "generator.max_torque_rate": (15000.0, 40000.0, "Jonkman baseline VS_MaxRat; DISCON.IN VS_MaxRat"),
    "pitch_actuator.max_rate": (0.1396263, 0.1745, "Jonkman baseline 8 deg/s; DISCON.IN PC_MaxRat"),
    "schedule.min_rotor_speed": (0.7225663, 34.64286 / 97.0, "Jonkman's 6.9 rpm; DISCON.IN VS_MinOMSpd / GBRatio"),
    "schedule.optimal_tip_speed_ratio": (7.55, 7.5, "Jonkman's region 2; DISCON.IN VS_TSRopt"),
    "protection.pitch_rate_trip": (1.1 * 0.1396263, 1.1 * 0.1745, "the default, 1.1 x the actuator's rate limit "
                                                                   "(pitch_actuator.max_rate above)"),
}
"""Field -> (the shipped value, from Jonkman et al. 2009 or hawt's choice; the deck's value, which the import gives;
sources)."""


def _field(turbine, path: str):
    part, name = path.split(".")
    return getattr(getattr(turbine, part), name)


@pytest.mark.parametrize("path", sorted(MATCHES))
def test_the_nrel_5mw_deck_gives_the_shipped_definition_within_each_fields_tolerance(imported_5mw, path):
    """Each field of the imported NREL 5 MW equals the shipped one to its stated tolerance (MATCHES)."""
    rtol, atol, why = MATCHES[path]
    found, shipped = _field(imported_5mw, path), _field(nrel_5mw(), path)
    if isinstance(shipped, (bool, int, str, tuple)):
        assert found == shipped, why
    else:
        np.testing.assert_allclose(found, shipped, rtol=rtol, atol=atol, err_msg=why)


@pytest.mark.parametrize("path", sorted(DELIBERATE))
def test_the_shipped_values_from_jonkman_2009_are_the_only_other_differences(imported_5mw, path):
    """Where the shipped file takes a value from Jonkman et al. (2009), the import gives the deck's instead."""
    shipped, deck, _ = DELIBERATE[path]
    assert _field(nrel_5mw(), path) == pytest.approx(shipped, rel=1e-9)
    assert _field(imported_5mw, path) == pytest.approx(deck, rel=1e-6)


def test_every_field_of_the_definition_is_compared():
    """MATCHES and DELIBERATE cover every field of every part of a turbine (the airfoils are compared below, the
    aerodynamic options' sources in the next test: they are not compared values)."""
    turbine = nrel_5mw()
    fields = {f"{part.name}.{field.name}" for part in dataclasses.fields(turbine)
              if dataclasses.is_dataclass(getattr(turbine, part.name))
              for field in dataclasses.fields(getattr(turbine, part.name)) if field.compare}
    assert fields == set(MATCHES) | set(DELIBERATE)


def test_the_shipped_aerodynamic_options_name_the_sources_the_import_writes(imported_5mw):
    """The shipped NREL 5 MW's options follow the deck: their sources are the import's word for word (the unsteady
    airfoil's adds which model the plant runs)."""
    shipped, imported = nrel_5mw().aerodynamics.sources, imported_5mw.aerodynamics.sources
    for name in ("tower_shadow", "tower_drag", "skewed_wake", "dynamic_inflow"):
        assert shipped[name] == imported[name], name
    assert shipped["unsteady_airfoil"].startswith(imported["unsteady_airfoil"][:-1])


def test_the_nrel_5mw_polars_are_the_shipped_ones(imported_5mw):
    """The deck's Airfoils/*.dat (AeroDyn 15) hold the shipped polars' AeroData/*.dat (v13) rows: coefficients
    verbatim, angles to the shipped file's 7 decimals of radians."""
    shipped = nrel_5mw().airfoils
    assert sorted(imported_5mw.airfoils) == sorted(shipped)
    for name, polar in imported_5mw.airfoils.items():
        np.testing.assert_allclose(polar.alpha, shipped[name].alpha, rtol=0.0, atol=5e-8, err_msg=name)
        for column in ("cl", "cd", "cm"):
            np.testing.assert_array_equal(getattr(polar, column), getattr(shipped[name], column), err_msg=name)


UNSTEADY_FROM_V13 = {"DU21_A17": (-4.2, -5.0609, 0.006, 0.0057), "DU40_A17": (-3.2, -1.343, 0.03, 0.0113)}
"""Airfoil -> (alpha0 [deg] and Cd0 of the deck's AeroDyn 15 UA table; the v13 header's zero-Cn angle and minimum
CD, which the shipped polars carry)."""


def test_the_unsteady_parameters_are_the_decks_ua_tables(imported_5mw):
    """The plant's unsteady-airfoil parameters come from each table's UA coefficients: the lift slopes (C_nalpha)
    are the shipped ones; alpha0 and Cd0 are the AeroDyn 15 files' values, not the v13 headers' that the shipped
    polars read, and differ from them (e.g. DU40: Cd0 0.03 against 0.0113); the cylinders have none (C_nalpha 0)."""
    shipped = nrel_5mw().airfoils
    for name, polar in imported_5mw.airfoils.items():
        if shipped[name].unsteady is None:
            assert polar.unsteady is None, name
            continue
        assert polar.unsteady.lift_slope == shipped[name].unsteady.lift_slope
    for name, (alpha0, v13_alpha0, cd0, v13_cd0) in UNSTEADY_FROM_V13.items():
        found, expected = imported_5mw.airfoils[name].unsteady, shipped[name].unsteady
        assert (math.degrees(found.alpha0), found.cd0) == pytest.approx((alpha0, cd0))
        assert (math.degrees(expected.alpha0), expected.cd0) == pytest.approx((v13_alpha0, v13_cd0))


def test_the_unsteady_lags_are_the_decks_and_default_to_aerodyns(imported_5mw, imported_deck):
    """A1, A2, b1, b2, T_p, T_f0 come from each UA table: the DU tables' numbers, NACA64's "Default" as AeroDyn's
    defaults (the same values on this deck), written to the airfoil file with where each came from."""
    for name, polar in imported_5mw.airfoils.items():
        if polar.unsteady is not None:
            p = polar.unsteady
            assert (p.a1, p.a2, p.b1, p.b2, p.pressure_lag, p.separation_lag) == (0.3, 0.7, 0.14, 0.53, 1.7, 3.0), name
    folder = imported_deck(NREL_5MW) / "airfoils"
    assert "  b1: 0.14  # b1 (\"Default\": AeroDyn's)" in (folder / "NACA64_A17.yaml").read_text()
    assert "  b1: 0.14  # b1\n" in (folder / "DU21_A17.yaml").read_text()


OPTIONS = ("tower_shadow", "tower_drag", "skewed_wake", "unsteady_airfoil", "dynamic_inflow")

DECK_AERODYNAMICS = {
    NREL_5MW: ((True, True, True, True, True), [
        "UA_Mod = 3 (B-L Minnema/Pierce): the plant's unsteady airfoil is Hansen-Gaunaa-Madsen's (UA_Mod = 4) in its "
        "place", "DBEMT_Mod = 2 (time-dependent tau1): the plant's dynamic inflow is Øye's filter"]),
    IEA_15MW: ((True, True, True, True, True), [
        "UA_Mod = 3 (B-L Minnema/Pierce)", "UAStartRad = 0.1, UAEndRad = 1", "AIDrag = True, TIDrag = True: the "
        "plant's induction leaves the drag out", "the tower's downstream shadow (IEA-15-240-RWT-Monopile_AeroDyn15.dat "
        "TwrShadow = 1): the blades of the upwind rotor stay ahead of the tower"]),
    NREL_2P8: ((False, False, True, True, True), [
        "NREL-2p8-127_AeroDyn15.dat TwrPotent = 0", "NREL-2p8-127_AeroDyn15.dat TwrAero = False",
        "AIDrag = True, TIDrag = True"]),
}
"""Deck -> (its options in OPTIONS' order; what turbine.yaml must say about them: sources, approximations, what
is not modelled). All three: Wake_Mod 1 with DBEMT_Mod 2, Skew_Mod 1, UA_Mod 3; the IEA 15 MW also has the
downstream tower shadow and UA from 10 % of the radius, the 2.8-127 no tower influence or drag; both these put the
drag into the induction."""


@pytest.mark.parametrize("deck", sorted(DECK_AERODYNAMICS))
def test_each_deck_gives_the_aerodynamic_options_of_its_aerodyn_input(imported_deck, deck):
    """The imported definition's options are its AeroDyn input's (DECK_AERODYNAMICS), each with the AeroDyn file and
    switch as its source, and the file lists what the plant does differently."""
    options, lines = DECK_AERODYNAMICS[deck]
    text = (imported_deck(deck) / "turbine.yaml").read_text()
    aerodynamics = load_turbine(imported_deck(deck) / "turbine.yaml").aerodynamics
    assert tuple(getattr(aerodynamics, name) for name in OPTIONS) == options
    assert all(re.match(r"\S+_AeroDyn15\.dat ", aerodynamics.sources[name]) for name in OPTIONS), aerodynamics.sources
    for line in lines:
        assert line in text, line


def _aerodyn(**changes):
    """AeroDyn inputs as openfast-io reads the NREL 5 MW's, with ``changes``."""
    return {"Wake_Mod": 1, "DBEMT_Mod": 0, "tau1_const": 4.0, "TwrPotent": 1, "TwrShadow": 0, "TwrAero": True,
            "Skew_Mod": 1, "SkewMomCorr": False, "SkewRedistr_Mod": "default", "SkewRedistrFactor": '"default"',
            "UA_Mod": 0, "UAStartRad": 0.0, "UAEndRad": 1.0, "TipLoss": True, "HubLoss": True, "TanInd": True,
            "AIDrag": False, "TIDrag": False, "BEM_Mod": 1, "SectAvg": False, **changes}


@pytest.mark.parametrize("changes, downwind, options, line", [
    ({}, False, {}, None),
    ({"UA_Mod": 4}, False, {"unsteady_airfoil": True}, "UA_Mod = 4 (B-L HGM 4-states): the plant's unsteady "
                                                       "airfoil is its model"),
    ({"UA_Mod": 3}, False, {"unsteady_airfoil": True}, "UA_Mod = 3 (B-L Minnema/Pierce): the plant's unsteady "
                                                       "airfoil is Hansen-Gaunaa-Madsen's (UA_Mod = 4) in its place"),
    ({"TwrPotent": 2}, False, {}, "TwrPotent = 2 (potential flow with Bak's correction): the plant's tower shadow is "
                                  "the baseline potential flow"),
    ({"TwrPotent": 0, "TwrAero": False}, False, {"tower_shadow": False, "tower_drag": False}, None),
    ({"TwrPotent": 0, "TwrShadow": 1}, True, {}, "TwrPotent = 0, TwrShadow = 1: behind the tower the plant has the "
                                                 "baseline potential flow and Powles' wake together"),
    ({"TwrShadow": 1}, True, {}, None),
    ({"Skew_Mod": 0}, False, {"skewed_wake": False}, None),
    ({"SkewRedistr_Mod": 0}, False, {"skewed_wake": False}, None),
    ({"SkewRedistr_Mod": 2}, False, {}, "SkewRedistr_Mod = 2 (vortex cylinder): the plant's skewed wake is Pitt & "
                                        "Peters'"),
    ({"SkewRedistrFactor": 1.0}, False, {}, "SkewRedistrFactor = 1: the plant's Pitt & Peters constant is 15 pi/32"),
    ({"SkewMomCorr": True}, False, {}, "the skew momentum correction (AD.dat SkewMomCorr = True)"),
    ({"DBEMT_Mod": 2}, False, {"dynamic_inflow": True}, "DBEMT_Mod = 2 (time-dependent tau1): the plant's dynamic "
                                                        "inflow is Øye's filter on each element's axial induction"),
    ({"DBEMT_Mod": 1}, False, {"dynamic_inflow": True}, "not the constant tau1 = 4 s"),
    ({"DBEMT_Mod": -1}, False, {}, "DBEMT_Mod = -1 (frozen wake, for linearisation): the plant's induction is "
                                   "quasi-steady"),
    ({"Wake_Mod": 2, "DBEMT_Mod": 2}, False, {"dynamic_inflow": True}, "Wake_Mod = 2 (DBEMT): the plant's dynamic "
                                                                       "inflow is Øye's"),
    ({"Wake_Mod": 3}, False, {}, "Wake_Mod = 3 (OLAF free vortex wake): the plant's induction is BEM's"),
    ({"Wake_Mod": 0}, False, {}, "Wake_Mod = 0 (no induction): the plant's induction is BEM's"),
    ({"TipLoss": False, "TanInd": False}, False, {}, "TipLoss = False, TanInd = False: the plant's BEM always has "
                                                     "Prandtl's tip and hub losses and the tangential induction"),
    ({"AIDrag": True, "TIDrag": True}, False, {}, "AIDrag = True, TIDrag = True: the plant's induction leaves the "
                                                  "drag out"),
    ({"SectAvg": True}, False, {}, "sector averaging (AD.dat SectAvg = True)"),
], ids=["the deck's switches", "UA_Mod 4", "UA_Mod 3", "Bak correction", "no tower influence",
        "downwind wake only", "downwind potential and wake", "no skew model", "no skew redistribution", "vortex cylinder", "skew factor", "skew momentum",
        "DBEMT tau1 varying", "DBEMT tau1 constant", "frozen wake", "legacy Wake_Mod 2", "OLAF", "no induction",
        "no tip loss", "drag in the induction", "sector average"])
def test_each_aerodyn_switch_maps_to_an_option_and_says_where_the_plant_differs(changes, downwind, options, line):
    """From the NREL 5 MW's inputs without UA and DBEMT (tower shadow, drag and skewed wake on, nothing to list):
    each change gives its options and the one line that says what the plant does instead."""
    from hawt_tools.turbine_import import aerodynamic_options

    mapping = aerodynamic_options(_aerodyn(**changes), downwind, "AD.dat")
    expected = {**dict.fromkeys(OPTIONS[:3], True), "unsteady_airfoil": False, "dynamic_inflow": False, **options}
    assert {name: item.value for name, item in mapping.section.items()} == expected
    assert all(item.in_file and item.source.startswith("AD.dat ") for item in mapping.section.values())
    listed = [*mapping.approximations, *mapping.not_modelled]
    if line is None:
        assert listed == [], listed
    else:
        assert len(listed) == 1 and line in listed[0], listed


def test_the_blade_mass_the_import_states_is_the_deck_distributions(imported_deck):
    """The deck states no blade mass: the import's reference mass and centre of gravity are the trapezoidal
    integrals of BMassDen x AdjBlMs over the 49 stations, 0.74 % and 0.16 % from Jonkman's 17 740 kg and 20.475 m
    (ElastoDyn integrates over its 17 elements); the loader allows 2 %."""
    structure = yaml.safe_load((imported_deck(NREL_5MW) / "turbine.yaml").read_text())["blade"]["structure"]
    assert structure["reference_mass"] == pytest.approx(17740.0, rel=0.008)
    assert structure["reference_cg_from_root"] == pytest.approx(20.475, rel=0.002)


def test_every_value_written_names_its_source_file_and_key(imported_deck):
    """Each value line of the written turbine.yaml ends in a comment naming where it comes from."""
    lines = (imported_deck(NREL_5MW) / "turbine.yaml").read_text().splitlines()
    values = [line for line in lines if not line.startswith("#") and not line.rstrip().endswith(":")]
    assert len(values) > 60
    for line in values:
        assert re.search(r"(  # |source: \").*(\.dat|\.fst|DISCON\.IN|from the spans|hawt's default)", line), line


def test_each_aerodyn_node_acts_halfway_to_its_neighbours():
    """AeroDyn 15's trapezoidal rule: the root and tip nodes get half a spacing, the others half of each side's."""
    assert node_widths(np.array([0.0, 1.0, 3.0, 4.0]), 4.0).tolist() == [0.5, 1.5, 1.5, 0.5]
    assert node_widths(np.array([0.5, 2.0]), 4.0).tolist() == [1.25, 2.75]


@pytest.mark.parametrize("deck, blades, rated_power, hub_height", [
    (IEA_15MW, 3, 15e6, 150.0),  # the tower's base 15 m above the sea, on its monopile
    (NREL_2P8, 3, 2.8e6, 88.05),
])
def test_other_decks_import_load_and_a_plant_steps_on_them(imported_deck, deck, blades, rated_power, hub_height):
    """The IEA 15 MW (monopile deck) and the NREL 2.8-127 load, and the plant holds its operating point for 3 s
    below and above rated with the commands held, above rated also with its unsteady airfoil option: finite
    outputs, the rotor speed within 2 %."""
    turbine = load_turbine(imported_deck(deck) / "turbine.yaml")
    assert turbine.rotor.number_of_blades == blades and turbine.generator.rated_power == rated_power
    assert turbine.hub_height == pytest.approx(hub_height, abs=0.05)
    rated = turbine.schedule.rated_wind_speed
    for wind_speed, unsteady in ((rated - 3.0, False), (rated + 4.0, False), (rated + 4.0, True)):
        model = TurbineModel(turbine, PowerLawWind(wind_speed, hub_height=turbine.hub_height, shear_exponent=0.2),
                             ModelConfig(unsteady_airfoil=unsteady))
        first = out = model.output
        for _ in range(300):
            out = model.step(first.pitch, first.generator_torque)
        values = [getattr(out, field.name) for field in dataclasses.fields(out)]
        assert all(np.all(np.isfinite(value)) for value in values)
        assert out.rotor_speed == pytest.approx(first.rotor_speed, rel=0.02)


def test_the_iea_15mw_stands_on_its_monopile_as_a_flexible_base_at_the_decks_heights(imported_deck):
    """The monopile deck's tower stands on SubDyn's monopile (clamped at the mudline, 30 m below the sea, up to
    TowerBsHt = 15 m): the plant's tower is one beam from -30 m to the top, the hub at the deck's 150 m. Its first
    modes are that beam's: 0.182 Hz with the rotor and nacelle a point mass (the summary's), against 0.17 Hz in the
    IEA 15 MW report (Gaertner et al. 2020) and 0.181 Hz from WISDEM's current model (IEA-15-240-RWT issue 247);
    well below 2P at rated speed (0.252 Hz), where the tower clamped at its base (0.256 Hz) stood. (With their
    rotary inertia the plant's fore-aft mode is at 0.172 Hz; OpenFAST v5 on the deck, parked, without aerodynamics
    and water, rings at 0.174 Hz.) The beam's mass below the base is the monopile's steel. The import's
    approximations and the summary say what the tower stands on."""
    turbine = load_turbine(imported_deck(IEA_15MW) / "turbine.yaml")
    assert "#   - the tower stands on the deck's monopile, a flexible base (IEA-15-240-RWT-Monopile_SubDyn.dat: 18 " \
        "members from -30 m, clamped, to TowerBsHt = 15 m)" in (imported_deck(IEA_15MW) / "turbine.yaml").read_text()
    assert "the tower stands on a flexible base: its substructure, from its clamp at -30 m to the tower's base at " \
        "15 m" in format_summary(turbine_summary(turbine))
    tower = turbine.tower
    assert (tower.base_kind, tower.base_height, tower.clamp_height) == ("flexible", 15.0, -30.0)
    assert turbine.hub_height == pytest.approx(150.0, abs=0.05)
    summary = turbine_summary(turbine)
    assert summary.tower_fa_frequency == pytest.approx(0.181, rel=0.02)
    assert summary.tower_ss_frequency == pytest.approx(0.181, rel=0.02)
    assert summary.tower_fa_frequency == pytest.approx(0.17, rel=0.08)
    assert summary.tower_fa_frequency < 0.75 * 2 * turbine.schedule.rated_rotor_speed / (2 * np.pi)
    heights = tower.clamp_height + tower.height_fraction * tower.length
    below = heights < tower.base_height - 1e-6
    # SubDyn: D = 10 m, XsecT 55.3 .. 41.1 mm over nine 5 m sections, steel 7800 kg/m^3
    thickness = np.array([0.055341, 0.053449, 0.051509, 0.049527, 0.047517, 0.045517, 0.043527, 0.042242, 0.041058])
    steel = 7800.0 * np.pi / 4.0 * (10.0**2 - (10.0 - 2.0 * thickness) ** 2) * 5.0
    assert np.trapezoid(tower.mass_density[below], heights[below]) == pytest.approx(steel.sum(), rel=1e-4)


def test_a_deck_without_a_substructure_model_stands_on_a_rigid_base(rosco_case, tmp_path):
    """The monopile deck with SubDyn off (CompSub = 0): the tower is clamped at TowerBsHt, a rigid base, the hub
    still at 150 m; its first modes are the tower's alone with the deck's TwFAM1Sh (0.256 Hz), and the import says
    why the base is rigid."""
    deck = shutil.copytree(rosco_case(IEA_15MW).parent, tmp_path / "IEA-15-240-RWT-Monopile")
    (tmp_path / "IEA-15-240-RWT").symlink_to(rosco_case("IEA-15-240-RWT/IEA-15-240-RWT"))  # the shared blade files
    _set(deck / "IEA-15-240-RWT-Monopile.fst", "CompSub", "0")
    imported = import_deck(deck / "IEA-15-240-RWT-Monopile.fst")
    turbine = load_turbine(write_turbine(imported, tmp_path / "out"))
    assert (turbine.tower.base_kind, turbine.tower.base_height, turbine.tower.clamp_height) == ("rigid", 15.0, 15.0)
    assert turbine.hub_height == pytest.approx(150.0, abs=0.05)
    assert turbine_summary(turbine).tower_fa_frequency == pytest.approx(0.256, abs=0.0005)
    assert any(line.startswith("the tower stands on a rigid base 15 m high (IEA-15-240-RWT-Monopile_ElastoDyn.dat "
                               "TowerBsHt; IEA-15-240-RWT-Monopile.fst CompSub = 0: no SubDyn substructure)")
               for line in imported.approximations)


def test_a_rigid_drivetrain_is_kept_at_a_torsion_the_plant_integrates(imported_deck):
    """The IEA 15 MW's DTTorSpr (ElastoDyn DrTrDOF = False) gives a 31 Hz torsion the plant's 0.01 s step cannot
    integrate: the import lowers it to a 10 Hz torsion (its rotor inertia integrated over the ElastoDyn stations,
    the summary's on the plant's fine grid: 1e-5 apart) and says so."""
    turbine = load_turbine(imported_deck(IEA_15MW) / "turbine.yaml")
    assert turbine_summary(turbine).drivetrain_frequency == pytest.approx(RIGID_TORSION_FREQUENCY, rel=1e-4)
    text = (imported_deck(IEA_15MW) / "turbine.yaml").read_text()
    assert "DrTrDOF = False (rigid): lowered to the stiffness of a 10 Hz torsion" in text


def test_a_downwind_deck_keeps_elastodyns_signs_and_marks_the_rotor_downwind(rosco_case, tmp_path):
    """OverHang > 0 is a downwind rotor: cone, tilt and overhang keep ElastoDyn's signs (the format's downwind
    convention, as two_bladed_downwind.yaml) and the rotor's position is downwind."""
    deck = shutil.copytree(rosco_case("NREL-5MW"), tmp_path / "deck")
    elastodyn = deck / "NRELOffshrBsline5MW_Onshore_ElastoDyn.dat"
    for key, value in (("OverHang", "5.0191"), ("PreCone(1)", "2.5"), ("PreCone(2)", "2.5"), ("PreCone(3)", "2.5"),
                       ("ShftTilt", "5")):
        _set(elastodyn, key, value)
    rotor = load_turbine(write_turbine(import_deck(deck / "NREL-5MW.fst"), tmp_path / "out")).rotor
    shipped = nrel_5mw_two_bladed_downwind()
    assert rotor.downwind and shipped.rotor.downwind
    for name in ("cone_angle", "shaft_tilt", "overhang"):
        assert getattr(rotor, name) == pytest.approx(getattr(shipped.rotor, name), abs=5e-9)


def _set(path: Path, key: str, value: str) -> None:
    """Replace the value of the setting ``key`` (the line's second word) in a deck's file."""
    lines = path.read_text().splitlines()
    index = next(k for k, line in enumerate(lines) if line.split()[1:2] == [key])
    lines[index] = f"{value}   {key}   - set by the test"
    path.write_text("\n".join(lines) + "\n")


def test_hawt_turbine_import_and_show_print_what_was_converted_and_the_summary(hawt_cli, rosco_case, tmp_path):
    """``hawt turbine import`` writes DIR/turbine.yaml and its airfoils and lists what is not modelled; ``hawt
    turbine show DIR`` prints the rated values, the plant's Cp-max and optimal tip-speed ratio, and first modes."""
    result = subprocess.run([*hawt_cli, "turbine", "import", str(rosco_case(NREL_5MW)), "-o", str(tmp_path / "n5")],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert "8 airfoil polars" in result.stdout and "not modelled:" in result.stdout
    assert "BldFl2Sh, BldFlDmp(2)" in result.stdout and "BldEdgSh" not in result.stdout
    assert sorted(path.stem for path in (tmp_path / "n5" / "airfoils").iterdir()) == sorted(nrel_5mw().airfoils)
    show = subprocess.run([*hawt_cli, "turbine", "show", str(tmp_path / "n5")], capture_output=True, text=True,
                          timeout=120)
    assert show.returncode == 0, show.stderr
    text = show.stdout
    assert "rated: 5 MW electrical, rotor 12.10 rpm" in text and "wind 11.40 m/s" in text
    cp, tsr = (float(x) for x in re.search(r"Cp-max ([\d.]+) at tip-speed ratio ([\d.]+)", text).groups())
    assert 0.48 < cp < 0.50 and 7.3 < tsr < 8.0
    fa = float(re.search(r"tower fore-aft ([\d.]+) Hz", text).group(1))
    flap = float(re.search(r"blade flap ([\d.]+) Hz", text).group(1))
    # Jonkman et al. (2009) Table 9-1 (FAST): the summary's tower mode has no rotary inertia of the rotor and
    # nacelle (5 % high), its flap mode no coupling with the edgewise mode (2 % low).
    assert fa == pytest.approx(0.324, rel=0.06) and flap == pytest.approx(0.6993, rel=0.05)
    assert "  skewed_wake on: NRELOffshrBsline5MW_Onshore_AeroDyn15.dat Skew_Mod = 1" in text
    assert "  dynamic_inflow on: NRELOffshrBsline5MW_Onshore_AeroDyn15.dat Wake_Mod = 1 (BEMT), DBEMT_Mod = 2" in text


def test_hawt_turbine_show_of_an_unknown_turbine_says_what_it_looked_for_in_one_line(hawt_cli, tmp_path):
    """A turbine that is neither packaged nor a folder here is named as ``hawt run`` names it: the packaged names and
    the path looked at, one line, exit 2."""
    show = subprocess.run([*hawt_cli, "turbine", "show", "iea16"], capture_output=True, text=True, timeout=60,
                          cwd=tmp_path)
    assert show.returncode == 2 and show.stdout == ""
    assert show.stderr.strip().splitlines() == [
        f"hawt turbine: show: turbine 'iea16': no packaged turbine of that name (packaged: nrel_5mw, "
        f"nrel_5mw_two_bladed, nrel_5mw_two_bladed_downwind) and no folder or file {tmp_path / 'iea16'}"]


def test_an_imported_turbine_carries_its_rosco_input_and_runs_rosco_wherever_its_folder_is(rosco_case, tmp_path):
    """``hawt turbine import`` copies the deck's DISCON.IN (ServoDyn DLL_InFile) and the Cp/Ct/Cq file it names into
    the folder, PerfFileName rewritten to the file's name and every other line byte for byte the deck's. The folder,
    its cpc designed (the rosco graph holds cpc to swap to) and moved elsewhere, runs ``hawt run rosco
    turbine:=MOVED``: in steady 18 m/s ROSCO holds the IEA 15 MW at its rated speed and power."""
    folder = tmp_path / "iea15"
    assert main(["turbine", "import", str(rosco_case(IEA_15MW)), "-o", str(folder)]) == 0
    deck = rosco_case(IEA_15MW).with_name("IEA-15-240-RWT-Monopile_DISCON.IN").read_bytes().splitlines(True)
    copy = (folder / "DISCON.IN").read_bytes().splitlines(True)
    changed = [line for line, original in zip(copy, deck) if line != original]
    assert len(copy) == len(deck) and len(changed) == 1
    assert changed[0].split()[:3] == [b'"Cp_Ct_Cq.IEA15MW.txt"', b"!", b"PerfFileName"]
    assert (folder / "Cp_Ct_Cq.IEA15MW.txt").read_bytes() == \
        rosco_case("IEA-15-240-RWT/IEA-15-240-RWT/Cp_Ct_Cq.IEA15MW.txt").read_bytes()
    assert main(["design", "cpc", "--turbine", str(folder)]) == 0
    moved = shutil.move(folder, tmp_path / "elsewhere")
    bag = tmp_path / "rosco.mcap"
    assert main(["run", "rosco", f"turbine:={moved}", "duration:=5", "--record", str(bag)]) == 0
    with BagReader(bag) as reader:
        channels = load_plant_run(reader).channels
    rated = turbine_from(str(moved)).description(0.01)
    assert channels["time"][-1] == pytest.approx(5.0, abs=0.011)
    assert channels["rotor_speed"] == pytest.approx(rated.rated_rotor_speed, rel=0.005)
    assert channels["electrical_power"] == pytest.approx(rated.rated_power, rel=0.005)


def test_a_turbine_folder_without_its_discon_input_names_the_import_that_writes_it(tmp_path):
    with pytest.raises(TuningError, match=rf"no discon tuning {tmp_path}/DISCON.IN; write it with: hawt turbine "
                                          rf"import DECK.fst -o {tmp_path} \(it copies the deck's DISCON.IN"):
        tuning_file(str(tmp_path), "discon")


def _copy_5mw(tmp_path: Path, case) -> Path:
    return shutil.copytree(case("NREL-5MW"), tmp_path / "NREL-5MW") / "NREL-5MW.fst"


def _without_tower_file(tmp_path: Path, case) -> Path:
    fst = _copy_5mw(tmp_path, case)
    (fst.parent / "NRELOffshrBsline5MW_Onshore_ElastoDyn_Tower.dat").unlink()
    return fst


def _without_an_airfoil(tmp_path: Path, case) -> Path:
    fst = _copy_5mw(tmp_path, case)
    (fst.parent / "Airfoils" / "DU21_A17.dat").unlink()
    return fst


def _with_aerodisk(tmp_path: Path, case) -> Path:
    fst = _copy_5mw(tmp_path, case)
    _set(fst, "CompAero", "1")
    return fst


def _with_reynolds_polars(tmp_path: Path, case) -> Path:
    fst = _copy_5mw(tmp_path, case)
    _set(fst.parent / "NRELOffshrBsline5MW_Onshore_AeroDyn15.dat", "AFTabMod", "2")
    return fst


def _with_setting(file: str, key: str, value: str):
    """A deck maker: the NREL 5 MW with ``key`` of its ``file`` set to ``value``."""
    def make(tmp_path: Path, case) -> Path:
        fst = _copy_5mw(tmp_path, case)
        _set(fst.parent / file, key, value)
        return fst

    return make


ELASTODYN = "NRELOffshrBsline5MW_Onshore_ElastoDyn.dat"


def _without_the_cp_file(tmp_path: Path, case) -> Path:
    fst = _copy_5mw(tmp_path, case)
    (fst.parent / "Cp_Ct_Cq.NREL5MW.txt").unlink()
    return fst


def _with_a_negative_blade_mass_density(tmp_path: Path, case) -> Path:
    """The NREL 5 MW with the BMassDen (third column) of the blade's third station negated."""
    fst = _copy_5mw(tmp_path, case)
    blade = fst.parent / "NRELOffshrBsline5MW_Blade.dat"
    lines = blade.read_text().splitlines()
    index = next(k for k, line in enumerate(lines) if line.split()[:1] == ["1.951000000000000E-02"])
    words = lines[index].split()
    lines[index] = "  ".join(words[:2] + ["-" + words[2]] + words[3:])
    blade.write_text("\n".join(lines) + "\n")
    return fst


@pytest.mark.parametrize("make_deck, message", [
    (_without_tower_file, "NRELOffshrBsline5MW_Onshore_ElastoDyn.dat: TwrFile: "
                          "NRELOffshrBsline5MW_Onshore_ElastoDyn_Tower.dat: no such file"),
    (_without_an_airfoil, "NRELOffshrBsline5MW_Onshore_AeroDyn15.dat: AFNames(7): Airfoils/DU21_A17.dat: no such "
                          "file"),
    (_with_aerodisk, "NREL-5MW.fst: CompAero: 1 (AeroDisk) is not supported"),
    (_with_reynolds_polars, "NRELOffshrBsline5MW_Onshore_AeroDyn15.dat: AFTabMod: 2 is not supported"),
    (lambda tmp_path, case: case(BAR_10), "BAR_10.fst: CompElast: 2 (BeamDyn blades) is not supported"),
    (_with_setting(ELASTODYN, "GBRatio", "0"), f"{ELASTODYN}: GBRatio: expected a value > 0, found 0\n"),
    (_with_setting(ELASTODYN, "GBRatio", "-97"), f"{ELASTODYN}: GBRatio: expected a value > 0, found -97\n"),
    (_with_setting(ELASTODYN, "TowerHt", "0"), f"{ELASTODYN} TowerHt: expected a value > 0.0, found 0 "
                                                 "(tower.height of the turbine definition)\n"),
    (_with_a_negative_blade_mass_density, "NRELOffshrBsline5MW_Blade.dat: BMassDen: expected values > 0, found "
                                          "-773.363 (value 3 of 49)\n"),
    (_without_the_cp_file, "DISCON.IN: PerfFileName: Cp_Ct_Cq.NREL5MW.txt: no such file\n"),
    (_with_setting("NRELOffshrBsline5MW_Onshore_ServoDyn.dat", "PCMode", "0"),
     "NRELOffshrBsline5MW_Onshore_ServoDyn.dat: PCMode: 0 is not supported: the limits and rated values come from the "
     "ROSCO controller's DISCON.IN (PCMode = 5)\n"),
], ids=["missing tower file", "missing airfoil", "AeroDisk", "polars over Reynolds number", "BeamDyn blades",
        "no gearbox ratio", "a negative gearbox ratio", "no tower", "a negative blade mass density",
        "the DISCON.IN's Cp file missing", "no ROSCO controller"])
def test_a_bad_deck_is_refused_with_one_line_naming_the_file_and_key(hawt_cli, rosco_case, tmp_path, make_deck,
                                                                     message):
    """A missing file, an option the plant cannot honour, a value out of its range: exit 2, one line on stderr
    naming file and key (and the value and the range allowed), and nothing written (the values the import computes
    with are checked where they are read, the others by the definition's checks before it is written)."""
    result = subprocess.run([*hawt_cli, "turbine", "import", str(make_deck(tmp_path, rosco_case)), "-o",
                             str(tmp_path / "out")], capture_output=True, text=True, timeout=120)
    assert result.returncode == 2 and len(result.stderr.strip().splitlines()) == 1, result.stderr
    assert result.stderr.startswith(f"hawt turbine: {message}"), result.stderr
    assert not (tmp_path / "out").exists()


def test_a_plant_on_the_imported_nrel_5mw_runs_as_on_the_shipped_one(imported_5mw):
    """The plant on the imported NREL 5 MW starts at the shipped one's operating point at 8 and 14 m/s within
    1 % (below rated the schedule's tip-speed ratio, 7.5 against 7.55, gives a rotor speed 0.7 % lower)."""
    for wind_speed in (8.0, 14.0):
        outputs = [TurbineModel(turbine, PowerLawWind(wind_speed, shear_exponent=0.2)).output
                   for turbine in (imported_5mw, nrel_5mw())]
        assert outputs[0].rotor_speed == pytest.approx(outputs[1].rotor_speed, rel=0.01)
        assert outputs[0].electrical_power == pytest.approx(outputs[1].electrical_power, rel=0.01)
        assert math.isclose(outputs[0].pitch[0], outputs[1].pitch[0], abs_tol=math.radians(0.2))
