"""Specification of hawt_tools.openfast_case: a case's OpenFAST inputs written from the turbine's own deck.

The deck is the rosco wheel's NREL 5 MW (what the packaged turbine was checked against); what is written is read
back with openfast-io, as OpenFAST would read it. OpenFAST itself is the user's and is not run here.
"""
import math
import os
from pathlib import Path

import pytest
from openfast_io.FAST_writer import InputWriter_OpenFAST

from hawt_analysis.openfast_output import openfast_channel_names
from hawt_tools.openfast_case import (FIXED_BOTTOM, PLANT_UA_MODEL, CaseInputs, DeckNotFound, OpenFastFailed, deck_of,
                                      keep_deck, openfast_executable, read_deck, run_openfast, write_case)


def _inputs(**changes) -> CaseInputs:
    values = dict(duration=120.0, wind_speed=18.0, shear_exponent=0.2, rotor_speed=12.1 * math.pi / 30.0,
                  pitch=(0.26, 0.26, 0.26), azimuth=math.radians(30.0), tower_top=(0.22, -0.06),
                  discon_library=Path("/opt/rosco/libdiscon.so"), discon_input=Path("/tmp/case/DISCON.IN"),
                  channels=openfast_channel_names(3))
    return CaseInputs(**{**values, **changes})


def _write_deck(fst_vt: dict, folder: Path) -> None:
    writer = InputWriter_OpenFAST()
    writer.fst_vt, writer.FAST_runDirectory, writer.FAST_namingOut = fst_vt, str(folder), "NREL-5MW"
    writer.execute()


def test_the_packaged_turbine_has_the_rosco_wheels_deck():
    deck = deck_of("nrel_5mw")
    assert deck.name == "NREL-5MW.fst" and deck.is_file()


def test_a_turbine_without_a_deck_is_refused_with_how_to_get_one(tmp_path):
    (tmp_path / "turbine.yaml").write_text("")
    with pytest.raises(DeckNotFound, match=rf"turbine {tmp_path}: no OpenFAST deck\(s\) in {tmp_path}/openfast "
                                           rf"\(hawt turbine import DECK.fst -o {tmp_path} keeps one there\)"):
        deck_of(str(tmp_path))
    with pytest.raises(DeckNotFound, match="nrel_5mw_two_bladed: no OpenFAST deck"):
        deck_of("nrel_5mw_two_bladed")


def test_a_case_changes_what_it_sets_and_nothing_else(tmp_path):
    """TMax, the steady inflow at the hub, the initial state, the controller and the outputs as asked; the rigid
    base and no yaw DOF; every other input as the deck has it."""
    deck, _ = read_deck(deck_of("nrel_5mw"))
    written = write_case(deck_of("nrel_5mw"), tmp_path, "steady-18", _inputs())
    case, _ = read_deck(written.fst)
    assert written.hub_height == pytest.approx(90.0, abs=1e-3)
    assert case["Fst"]["TMax"] == 120.0 and case["Fst"]["OutFileFmt"] == 2
    inflow = case["InflowWind"]
    assert (inflow["WindType"], inflow["HWindSpeed"], inflow["PLExp"]) == (1, 18.0, 0.2)
    assert float(inflow["RefHt"]) == pytest.approx(90.0, abs=1e-3)
    assert float(inflow["WindVziList"][0]) == pytest.approx(90.0, abs=1e-3)
    elasto = case["ElastoDyn"]
    assert elasto["RotSpeed"] == pytest.approx(12.1)
    assert [elasto[f"BlPitch{i}"] for i in (1, 2, 3)] == pytest.approx([math.degrees(0.26)] * 3)
    assert (elasto["Azimuth"], elasto["TTDspFA"], elasto["TTDspSS"]) == pytest.approx((30.0, 0.22, -0.06))
    assert elasto["YawDOF"] is False
    assert case["ServoDyn"]["DLL_FileName"] == "/opt/rosco/libdiscon.so"
    assert case["ServoDyn"]["DLL_InFile"] == "/tmp/case/DISCON.IN"
    for channel in ("RootMyc1", "RootMxc3", "LSSTipMys", "YawBrTAxp", "TwrBsMxt", "GenPwr", "RtFldFxh",
                    "Wind1VelX"):
        assert any(case["outlist"][module].get(channel) for module in ("ElastoDyn", "AeroDyn", "ServoDyn",
                                                                        "InflowWind")), channel
    for module, key in (("ElastoDyn", "TipRad"), ("ElastoDyn", "FlapDOF1"), ("ElastoDyn", "EdgeDOF"),
                        ("AeroDyn", "Skew_Mod"), ("AeroDyn", "TwrPotent"),
                        ("Fst", "DT"), ("ElastoDyn", "GBRatio")):
        assert case[module][key] == deck[module][key], (module, key)
    assert "Fst TMax = 120" in written.changed and "ElastoDyn YawDOF = False" in written.changed
    assert all(case[module][key] == value for (module, key), value in FIXED_BOTTOM.items() if key in case[module])


def test_a_deck_with_another_unsteady_airfoil_model_runs_the_plants(tmp_path):
    """The NREL 5 MW deck's UA_Mod 3 (Beddoes-Leishman) becomes UA_Mod 4, the model the plant has, and the case says
    so with the deck's value; a deck without unsteady aerodynamics keeps UA_Mod 0."""
    assert read_deck(deck_of("nrel_5mw"))[0]["AeroDyn"]["UA_Mod"] == 3
    written = write_case(deck_of("nrel_5mw"), tmp_path / "ua", "steady-8", _inputs())
    assert read_deck(written.fst)[0]["AeroDyn"]["UA_Mod"] == PLANT_UA_MODEL == 4
    assert any(line.startswith("AeroDyn UA_Mod = 4 (was 3") for line in written.changed)
    quasi_steady = tmp_path / "quasi_steady"
    deck, _ = read_deck(deck_of("nrel_5mw"))
    deck["AeroDyn"]["UA_Mod"] = 0
    _write_deck(deck, quasi_steady)
    written = write_case(quasi_steady / "NREL-5MW.fst", tmp_path / "qs", "steady-8", _inputs())
    assert read_deck(written.fst)[0]["AeroDyn"]["UA_Mod"] == 0
    assert not any("UA_Mod" in line for line in written.changed)


def test_a_monopile_deck_runs_on_a_rigid_base_with_its_platform_fixed(tmp_path, rosco_case):
    """The IEA 15 MW monopile deck: substructure, waves and sea state off and every platform DOF too; with the
    platform DOFs left on and nothing holding the platform, OpenFAST v5 let the turbine drift and struck the tower
    within 20 s (hawt validate on the imported turbine)."""
    deck = rosco_case("IEA-15-240-RWT/IEA-15-240-RWT-Monopile/IEA-15-240-RWT-Monopile.fst")
    fixed, switched = read_deck(deck)  # the deck has its platform DOFs on: read_deck turns them off and says so
    assert fixed["ElastoDyn"]["PtfmPDOF"] is False and "ElastoDyn PtfmPDOF = False" in switched
    written = write_case(deck, tmp_path, "steady-18", _inputs())
    case, _ = read_deck(written.fst)
    assert all(case[module][key] == value for (module, key), value in FIXED_BOTTOM.items())
    assert "ElastoDyn PtfmPDOF = False" in written.changed and "Fst CompSub = 0 (was 1)" in written.changed


def test_a_turbulent_case_reads_the_plants_field_from_a_bts_file(tmp_path):
    field = tmp_path / "field.bts"
    written = write_case(deck_of("nrel_5mw"), tmp_path / "case", "turbulent-18", _inputs(bts_file=field))
    inflow = read_deck(written.fst)[0]["InflowWind"]
    assert inflow["WindType"] == 3 and Path(inflow["FileName_BTS"]) == field.resolve()


def test_an_unknown_output_channel_is_refused(tmp_path):
    with pytest.raises(ValueError, match="output channel RootMyc9: no module"):
        write_case(deck_of("nrel_5mw"), tmp_path, "x", _inputs(channels=("RootMyc9",)))


def test_an_imported_turbine_keeps_a_copy_of_its_deck_that_validate_finds(tmp_path):
    copy = keep_deck(deck_of("nrel_5mw"), tmp_path)
    assert copy == tmp_path / "openfast" / "NREL-5MW.fst"
    assert deck_of(str(tmp_path)) == copy
    (original, _), (kept, _) = read_deck(deck_of("nrel_5mw")), read_deck(copy)
    assert kept["ElastoDyn"]["TipRad"] == original["ElastoDyn"]["TipRad"]
    assert kept["AeroDyn"]["UA_Mod"] == original["AeroDyn"]["UA_Mod"]
    assert all(Path(p).is_relative_to(tmp_path) or not Path(p).is_absolute()
               for p in (kept["Fst"]["EDFile"], kept["Fst"]["AeroFile"]))


def test_the_kept_deck_and_its_rosco_input_move_with_the_turbine_folder(tmp_path):
    """The ROSCO input becomes the turbine's discon tuning with its Cp/Ct/Cq file beside it by name, and the copy's
    ServoDyn names it relatively: the folder moved elsewhere still gives ROSCO its performance table."""
    from hawt_controllers.discon.rosco_input import read_settings
    from hawt_controllers.design.tunings import tuning_file

    keep_deck(deck_of("nrel_5mw"), tmp_path / "before")
    (tmp_path / "before").rename(tmp_path / "after")
    folder = tmp_path / "after"
    discon = tuning_file(str(folder), "discon")
    assert discon == folder / "DISCON.IN"
    performance = read_settings(discon)["PerfFileName"].strip('"')
    assert performance == "Cp_Ct_Cq.NREL5MW.txt" and (folder / performance).is_file()
    kept, _ = read_deck(deck_of(str(folder)))
    assert kept["ServoDyn"]["DLL_InFile"].endswith("DISCON.IN")
    assert (folder / "openfast" / kept["ServoDyn"]["DLL_InFile"]).resolve() == discon.resolve()


def test_the_executable_comes_from_the_option_or_the_environment_else_one_line(tmp_path, monkeypatch):
    monkeypatch.delenv("HAWT_OPENFAST", raising=False)
    with pytest.raises(ValueError, match=r"^no OpenFAST executable: give --openfast PATH or set \$HAWT_OPENFAST$"):
        openfast_executable(None)
    with pytest.raises(ValueError, match=r"--openfast .*/none: no such file"):
        openfast_executable(str(tmp_path / "none"))
    plain = tmp_path / "openfast"
    plain.write_text("")
    with pytest.raises(ValueError, match=r"HAWT_OPENFAST .*/openfast: not executable"):
        monkeypatch.setenv("HAWT_OPENFAST", str(plain))
        openfast_executable(None)
    plain.chmod(0o755)
    assert openfast_executable(None) == plain.resolve()


def _stand_in(tmp_path: Path, script: str) -> Path:
    """An executable that prints what OpenFAST prints (the runner's plumbing, without a simulation)."""
    path = tmp_path / "openfast"
    path.write_text("#!/bin/sh\n" + script)
    path.chmod(0o755)
    return path


def test_the_runner_reports_openfasts_progress_and_keeps_its_output(tmp_path):
    executable = _stand_in(tmp_path, 'for t in 5 10; do echo " Time: $t of 10 seconds."; done\n'
                                     'echo "  OpenFAST terminated normally."\n')
    (tmp_path / "case.fst").write_text("")
    seen = []
    run_openfast(executable, tmp_path / "case.fst", lambda t, total: seen.append((t, total)))
    assert seen[-1] == (10.0, 10.0)
    assert "terminated normally" in (tmp_path / "case.log").read_text()


def test_a_failed_openfast_is_one_error_with_its_last_lines(tmp_path):
    executable = _stand_in(tmp_path, 'echo "FAST_InitializeAll:InflowWind_Init: FF wind array boundaries violated"\n'
                                     'echo "Aborting OpenFAST."\nexit 1\n')
    (tmp_path / "case.fst").write_text("")
    with pytest.raises(OpenFastFailed, match=r"OpenFAST failed on .*case.fst \(exit 1; its output: .*case.log\): "
                                             r"FAST_InitializeAll.*boundaries violated \| Aborting OpenFAST."):
        run_openfast(executable, tmp_path / "case.fst")
    assert os.path.getsize(tmp_path / "case.log") > 0


def test_a_program_that_exits_0_saying_nothing_is_asked_whether_it_is_openfast(tmp_path):
    """--openfast /bin/true (a new user's slip): the error says the program printed nothing and asks whether it is
    OpenFAST, where it ended on an empty colon."""
    (tmp_path / "case.fst").write_text("")
    with pytest.raises(OpenFastFailed, match=r"\(exit 0; its output: .*case.log\): it printed nothing: is /bin/true "
                                             r"OpenFAST\?$"):
        run_openfast(Path("/bin/true"), tmp_path / "case.fst")
