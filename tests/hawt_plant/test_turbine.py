"""Specification of hawt_plant.turbine: the NREL 5 MW definition and the checked loader."""
import math
import shutil
from pathlib import Path

import numpy as np
import pytest
import yaml

from hawt_plant.turbine import TurbineDefinitionError, load_turbine

PACKAGED = Path(__file__).resolve().parents[2] / "hawt_plant" / "hawt_plant" / "turbines" / "nrel_5mw"


@pytest.fixture
def editable_copy(tmp_path):
    """A copy of the packaged definition and a function that edits one key of it."""
    target = tmp_path / "nrel_5mw"
    shutil.copytree(PACKAGED, target)
    path = target / "turbine.yaml"

    def edit(keys, value):
        doc = yaml.safe_load(path.read_text())
        node = doc
        for key in keys[:-1]:
            node = node[key]
        if value is None:
            del node[keys[-1]]
        else:
            node[keys[-1]] = value
        path.write_text(yaml.safe_dump(doc))
        return path

    return edit


def test_nrel_5mw_hub_height_is_90_m(turbine):
    """Tower height, shaft height, overhang and tilt put the apex at 90 m (Jonkman 2009)."""
    assert turbine.hub_height == pytest.approx(90.0, abs=1e-3)


def test_nrel_5mw_geometry_matches_elastodyn(turbine):
    """Rotor radius, blade count, precone and tilt are the ElastoDyn values in SI units."""
    rotor = turbine.rotor
    assert (rotor.number_of_blades, rotor.tip_radius, rotor.hub_radius) == (3, 63.0, 1.5)
    assert rotor.cone_angle == pytest.approx(math.radians(2.5), rel=1e-6)
    assert rotor.shaft_tilt == pytest.approx(math.radians(5.0), rel=1e-6)
    assert turbine.blade_length == 61.5


def test_nrel_5mw_has_aerodyn_15s_19_nodes_and_their_trapezoidal_widths(turbine):
    """The AeroDyn 15 blade file's nodes, root and tip included, each acting halfway to its neighbours: the widths
    add up to the blade length."""
    aero = turbine.blade_aerodynamics
    assert aero.span.size == 19 and aero.span[0] == 0.0 and aero.span[-1] == pytest.approx(61.5, abs=1e-3)
    halfway = np.concatenate(([0.0], 0.5 * (aero.span[1:] + aero.span[:-1]), [61.5]))
    np.testing.assert_allclose(aero.width, np.diff(halfway), atol=1e-5)
    assert aero.airfoil[0] == "Cylinder1" and aero.airfoil[-1] == "NACA64_A17"


def test_a_node_outside_the_stretch_its_width_gives_it_is_rejected(editable_copy):
    """The widths tile the blade in the order of the nodes; a node must lie in its own stretch."""
    spans = [0.0, 1.3667, 4.1, 6.8333, 10.25, 14.35, 18.45, 22.55, 26.65, 30.75, 34.85, 38.95, 43.05, 47.15, 51.25,
             54.6667, 57.4, 61.0, 61.4999]
    path = editable_copy(["blade", "aerodynamics", "span"], spans)
    with pytest.raises(TurbineDefinitionError, match=r"blade\.aerodynamics\.span: expected each node inside the "
                                                     r"stretch"):
        load_turbine(path)


def test_nrel_5mw_airfoil_polars_cover_the_circle(turbine):
    """All eight polars run from -pi to pi in radians."""
    assert len(turbine.airfoils) == 8
    for polar in turbine.airfoils.values():
        assert polar.alpha[0] == pytest.approx(-math.pi) and polar.alpha[-1] == pytest.approx(math.pi)
        assert np.all(np.diff(polar.alpha) > 0.0)


def test_nrel_5mw_du21_polar_is_transcribed_in_radians(turbine):
    """DU21_A17 at 0 deg has cl 0.521 and cd 0.0057 as in AeroData/DU21_A17.dat."""
    polar = turbine.airfoils["DU21_A17"]
    assert np.interp(0.0, polar.alpha, polar.cl) == pytest.approx(0.521)
    assert np.interp(0.0, polar.alpha, polar.cd) == pytest.approx(0.0057)


def test_nrel_5mw_limits_and_rated_values(turbine):
    """Pitch 0-90 deg at 8 deg/s, rated 5 MW at 12.1 rpm, gearbox 97."""
    assert turbine.pitch_actuator.max_angle == pytest.approx(math.pi / 2, rel=1e-6)
    assert turbine.pitch_actuator.max_rate == pytest.approx(math.radians(8.0), rel=1e-6)
    assert turbine.generator.rated_power == 5.0e6
    assert turbine.schedule.rated_rotor_speed == pytest.approx(12.1 * math.pi / 30, rel=1e-5)
    assert turbine.drivetrain.gearbox_ratio == 97.0


@pytest.mark.parametrize("base, clamp, kind", [(None, None, "ground"), (15.0, None, "rigid"),
                                               (15.0, -30.0, "flexible")])
def test_the_tower_stands_on_the_ground_a_rigid_base_or_a_flexible_one(editable_copy, base, clamp, kind):
    """Without base_height the tower is clamped on the ground; with it alone, on a rigid base that high; with a
    clamp_height below it, on a flexible base (its beam reaches down to the clamp)."""
    path = editable_copy(["tower", "base_height"], base) if base is not None else PACKAGED / "turbine.yaml"
    if clamp is not None:
        path = editable_copy(["tower", "clamp_height"], clamp)
    tower = load_turbine(path).tower
    assert tower.base_kind == kind
    assert (tower.base_height, tower.clamp_height) == (base or 0.0, clamp if clamp is not None else base or 0.0)
    assert tower.length == tower.height - tower.clamp_height


@pytest.mark.parametrize("key, value, message", [
    ("base_height", 87.6, r"tower\.base_height: expected a value below the tower top \(height 87\.6\), found 87\.6"),
    ("base_height", -1.0, r"tower\.base_height: expected a value >= 0"),
    ("clamp_height", 1.0, r"tower\.clamp_height: expected a value <= 0"),
])
def test_a_base_at_or_above_the_top_or_a_clamp_above_the_base_is_refused(editable_copy, key, value, message):
    """The base is below the tower top, on or above the ground; the clamp at or below the base."""
    with pytest.raises(TurbineDefinitionError, match=message):
        load_turbine(editable_copy(["tower", key], value))


def test_missing_key_is_named_with_its_file(editable_copy):
    """A missing key gives an error naming the file and the dotted key."""
    path = editable_copy(["generator", "max_torque"], None)
    with pytest.raises(TurbineDefinitionError, match=r"turbine\.yaml: generator\.max_torque: missing"):
        load_turbine(path)


def test_wrong_array_length_is_named(editable_copy):
    """An array of the wrong length names the key and both lengths."""
    path = editable_copy(["blade", "aerodynamics", "chord"], [3.0] * 16)
    with pytest.raises(TurbineDefinitionError, match=r"blade\.aerodynamics\.chord: expected 19 values, found 16"):
        load_turbine(path)


def test_widths_that_do_not_tile_the_blade_are_rejected(editable_copy):
    """Element widths must add up to the blade length."""
    path = editable_copy(["blade", "aerodynamics", "width"], [4.0] * 19)
    with pytest.raises(TurbineDefinitionError, match=r"blade\.aerodynamics\.width: widths add up to"):
        load_turbine(path)


def test_mass_distribution_is_checked_against_the_stated_blade_mass(editable_copy):
    """A blade mass far from the integrated distribution is reported."""
    path = editable_copy(["blade", "structure", "reference_mass"], 20000.0)
    with pytest.raises(TurbineDefinitionError, match=r"reference_mass: the distributed properties give"):
        load_turbine(path)


def test_non_numeric_value_is_rejected(editable_copy):
    """A string where a number belongs names the key."""
    path = editable_copy(["rotor", "tip_radius"], "sixty-three")
    with pytest.raises(TurbineDefinitionError, match=r"rotor\.tip_radius: expected a finite number"):
        load_turbine(path)


def test_missing_airfoil_file_is_named(editable_copy, tmp_path):
    """An element referring to an airfoil without a polar file names that file."""
    (tmp_path / "nrel_5mw" / "airfoils" / "DU21_A17.yaml").unlink()
    path = editable_copy(["name"], "edited")
    with pytest.raises(TurbineDefinitionError, match=r"DU21_A17\.yaml: cannot read the file"):
        load_turbine(path)


def test_nrel_5mw_unsteady_parameters_are_the_polar_file_headers(turbine):
    """DU40_A17's unsteady section holds the header of AeroData/DU40_A17.dat: "Zero Cn angle of attack" -1.3430 deg,
    "Cn slope for zero lift" 7.4888, "Minimum CD value" 0.0113; the cylinders (zero slope there) have none."""
    unsteady = turbine.airfoils["DU40_A17"].unsteady
    assert unsteady.alpha0 == pytest.approx(math.radians(-1.3430), rel=1e-9)
    assert (unsteady.lift_slope, unsteady.cd0) == (7.4888, 0.0113)
    assert turbine.airfoils["Cylinder1"].unsteady is None and turbine.airfoils["Cylinder2"].unsteady is None
    assert all(polar.unsteady is not None for name, polar in turbine.airfoils.items() if "Cylinder" not in name)


def test_nrel_5mw_unsteady_lags_are_the_aerodyn_15_decks(turbine):
    """Every NREL 5 MW airfoil with an unsteady section carries the OpenFAST deck's A1 0.3, A2 0.7, b1 0.14, b2 0.53,
    T_p 1.7, T_f0 3 (Airfoils/*.dat; NACA64's "Default", AeroDyn's defaults, the same values)."""
    for name, polar in turbine.airfoils.items():
        if polar.unsteady is not None:
            p = polar.unsteady
            assert (p.a1, p.a2, p.b1, p.b2, p.pressure_lag, p.separation_lag) == (0.3, 0.7, 0.14, 0.53, 1.7, 3.0), name


@pytest.mark.parametrize("edit, message", [
    (("  a1: 0.3  # A1\n", ""), None),
    (("  b1: 0.14", "  b_1: 0.14"), r"unsteady\.b_1: no such parameter \(expected alpha0, lift_slope, cd0, a1, a2"),
    (("  a1: 0.3", "  a1: 0.5"), r"unsteady\.a2: expected a1 \+ a2 <= 1, found 0\.5 \+ 0\.7"),
    (("  separation_lag: 3.0", "  separation_lag: 0"), r"unsteady\.separation_lag: expected a value > 0"),
], ids=["absent-is-aerodyn-default", "misspelled", "weights-over-one", "zero-lag"])
def test_unsteady_lags_are_optional_and_checked(editable_copy, tmp_path, edit, message):
    """A1, A2, b1, b2, T_p, T_f0 may be left out (AeroDyn's defaults); a misspelled, out-of-range or inconsistent
    one names the file and the key."""
    path = tmp_path / "nrel_5mw" / "airfoils" / "DU21_A17.yaml"
    text = path.read_text()
    assert edit[0] in text
    path.write_text(text.replace(*edit))
    if message is None:
        assert load_turbine(editable_copy(["name"], "edited")).airfoils["DU21_A17"].unsteady.a1 == 0.3
        return
    with pytest.raises(TurbineDefinitionError, match=r"DU21_A17\.yaml: " + message):
        load_turbine(editable_copy(["name"], "edited"))


def test_invalid_unsteady_parameter_is_named(editable_copy, tmp_path):
    """A negative lift slope in a polar's unsteady section names the file and the key."""
    path = tmp_path / "nrel_5mw" / "airfoils" / "DU21_A17.yaml"
    path.write_text(path.read_text().replace("lift_slope: 6.2047", "lift_slope: -6.2047"))
    with pytest.raises(TurbineDefinitionError, match=r"DU21_A17\.yaml: unsteady\.lift_slope: expected a value > 0"):
        load_turbine(editable_copy(["name"], "edited"))


def test_the_packaged_nrel_5mw_takes_the_options_of_its_aerodyn_deck(turbine):
    """NRELOffshrBsline5MW_Onshore_AeroDyn15.dat: TwrPotent 1, TwrAero True, Skew_Mod 1 and UA_Mod 3 give tower
    shadow, tower drag, skewed wake and unsteady airfoil; Wake_Mod 1 with DBEMT_Mod 2 (OpenFAST 4's dynamic BEMT)
    gives dynamic inflow. Each source names the deck's switch."""
    options = turbine.aerodynamics
    assert (options.tower_shadow, options.tower_drag, options.skewed_wake, options.unsteady_airfoil,
            options.dynamic_inflow) == (True, True, True, True, True)
    for name, key in (("tower_shadow", "TwrPotent = 1"), ("tower_drag", "TwrAero = True"),
                      ("skewed_wake", "Skew_Mod = 1"), ("unsteady_airfoil", "UA_Mod = 3"),
                      ("dynamic_inflow", "Wake_Mod = 1 (BEMT), DBEMT_Mod = 2")):
        assert options.sources[name].startswith(f"NRELOffshrBsline5MW_Onshore_AeroDyn15.dat {key}"), name


def test_the_two_bladed_variants_keep_the_decks_options_and_the_downwind_one_says_why_its_shadow_is_on():
    """Derived from turbine.yaml, both variants have its options; the downwind rotor's tower shadow (potential flow
    and Powles' wake) names hawt's reason instead of TwrPotent."""
    from hawt_plant.turbine import nrel_5mw, nrel_5mw_two_bladed, nrel_5mw_two_bladed_downwind

    base = nrel_5mw().aerodynamics
    for variant in (nrel_5mw_two_bladed(), nrel_5mw_two_bladed_downwind()):
        assert variant.aerodynamics == base
    downwind = nrel_5mw_two_bladed_downwind().aerodynamics.sources
    assert "Powles' wake" in downwind["tower_shadow"] and downwind["skewed_wake"] == base.sources["skewed_wake"]


def test_a_definition_without_an_aerodynamics_section_keeps_hawts_defaults(editable_copy):
    """An older file loads unchanged: tower shadow and tower drag on, the rest off, each source saying so."""
    from hawt_plant.turbine import NO_SECTION, AerodynamicOptions

    options = load_turbine(editable_copy(["aerodynamics"], None)).aerodynamics
    assert options == AerodynamicOptions(tower_shadow=True, tower_drag=True, skewed_wake=False,
                                         unsteady_airfoil=False, dynamic_inflow=False)
    assert set(options.sources.values()) == {NO_SECTION}


def test_an_option_given_as_true_or_false_names_the_file_and_key_as_its_source(editable_copy):
    """``dynamic_inflow: true`` without a source: on, its source the definition's file and key; an option left
    out of the section keeps hawt's default."""
    editable_copy(["aerodynamics", "tower_drag"], None)
    options = load_turbine(editable_copy(["aerodynamics", "dynamic_inflow"], True)).aerodynamics
    assert options.dynamic_inflow and options.sources["dynamic_inflow"] == "turbine.yaml aerodynamics.dynamic_inflow"
    assert options.tower_drag and options.sources["tower_drag"].startswith("hawt's default")


@pytest.mark.parametrize("key, value, message", [
    ("skewed_wake", "yes", r"aerodynamics\.skewed_wake: expected true or false, or \{value: true or false, "
                           r"source: text\}, found 'yes'"),
    ("skewed_wake", {"value": True}, r"aerodynamics\.skewed_wake: expected true or false"),
    ("skew", True, r"aerodynamics\.skew: no such option \(expected tower_shadow, tower_drag, skewed_wake, "
                   r"unsteady_airfoil, dynamic_inflow\)"),
], ids=["not a boolean", "no source", "unknown option"])
def test_a_bad_aerodynamic_option_is_named_with_its_file_and_key(editable_copy, key, value, message):
    """A value that is not true/false (or {value, source}), or an option the plant does not have."""
    with pytest.raises(TurbineDefinitionError, match=rf"turbine\.yaml: {message}"):
        load_turbine(editable_copy(["aerodynamics", key], value))


def test_a_protection_section_sets_the_levels_it_names_and_the_rest_keep_their_defaults(editable_copy, turbine):
    """``protection: {rotor_speed_trip: 1.45, pitch_asymmetry_trip: 0.1}``: those two levels, every other one the
    default from the turbine's ratings (what a definition without the section gets)."""
    limits = load_turbine(editable_copy(["protection"], {"rotor_speed_trip": 1.45, "pitch_asymmetry_trip": 0.1})
                          ).protection
    assert (limits.rotor_speed_trip, limits.pitch_asymmetry_trip) == (1.45, 0.1)
    assert limits.generator_speed_trip == turbine.protection.generator_speed_trip
    assert limits.rotor_speed_warning == turbine.protection.rotor_speed_warning


@pytest.mark.parametrize("section, message", [
    ({"rotor_overspeed": 1.5}, r"protection\.rotor_overspeed: unknown protection level \(expected one of: "
                               r"rotor_speed_warning, rotor_speed_trip, "),
    ({"rotor_speed_trip": -1.0}, r"protection\.rotor_speed_trip: expected a value > 0.0, found -1.0"),
    ({"generator_speed_warning": 200.0, "generator_speed_trip": 150.0},
     r"protection\.generator_speed_warning: expected a value <= generator_speed_trip \(150.0\), found 200.0"),
], ids=["misspelled", "negative", "warning above trip"])
def test_a_bad_protection_level_is_named_with_its_file_and_key(editable_copy, section, message):
    """A misspelled level, a level that is not positive, a warning above its trip."""
    with pytest.raises(TurbineDefinitionError, match=rf"turbine\.yaml: {message}"):
        load_turbine(editable_copy(["protection"], section))


def test_a_definition_read_once_is_kept_until_a_file_it_reads_changes(tmp_path, monkeypatch):
    """The parsed definition is kept in $HAWT_CACHE_DIR/turbines, keyed by the folder's definition and polar files:
    loaded again it is the same turbine, its options' sources included; a changed polar is read again; an unreadable
    kept file is parsed again, not trusted."""
    monkeypatch.setenv("HAWT_CACHE_DIR", str(tmp_path / "cache"))
    folder = tmp_path / "nrel_5mw"
    shutil.copytree(PACKAGED, folder)
    first = load_turbine(folder / "turbine.yaml")
    kept = list((tmp_path / "cache" / "turbines").glob("*.pickle"))
    assert len(kept) == 1
    again = load_turbine(folder / "turbine.yaml")
    assert np.array_equal(again.blade_aerodynamics.chord, first.blade_aerodynamics.chord)
    assert dict(again.aerodynamics.sources) == dict(first.aerodynamics.sources)
    assert again.aerodynamics == first.aerodynamics and sorted(again.airfoils) == sorted(first.airfoils)
    polar = sorted((folder / "airfoils").glob("*.yaml"))[-1]
    polar.write_text(polar.read_text() + "\n# edited\n")
    load_turbine(folder / "turbine.yaml")
    assert len(list((tmp_path / "cache" / "turbines").glob("*.pickle"))) == 2
    kept[0].write_bytes(b"not a pickle")
    polar.write_text(polar.read_text().replace("\n# edited\n", ""))
    assert np.array_equal(load_turbine(folder / "turbine.yaml").blade_aerodynamics.chord,
                          first.blade_aerodynamics.chord)
