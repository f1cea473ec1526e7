"""Specification of hawt validate's cases, figures and checks (hawt_tools.validation) and its command line.

The OpenFAST runs themselves are the benchmark of issue 29 (``hawt validate nrel_5mw --openfast PATH``), not a test:
OpenFAST is the user's.
"""
import math

import numpy as np
import pytest

from hawt_analysis.synthetic_run import synthetic_channels
from hawt_tools.cli import main
from hawt_tools.validation import (DEFAULT_CASES, STEADY_CHECKS, TURBULENT_CHECKS, Check, case_figures,
                                   compare_figures, not_like_for_like, parse_case)


def test_the_default_cases_are_issue_29s():
    assert [c.name for c in DEFAULT_CASES] == ["steady-8", "steady-11.4", "steady-18", "turbulent-18"]
    turbulent = DEFAULT_CASES[-1]
    assert turbulent.turbulent and turbulent.duration == 600.0 and turbulent.turbulence_class == "B"
    assert all(c.shear_exponent == 0.2 and c.analysed < c.duration for c in DEFAULT_CASES)


def test_a_case_on_the_command_line_is_kind_and_speed():
    case = parse_case("steady-13")
    assert (case.wind_speed, case.turbulent, case.duration) == (13.0, False, 160.0)
    shorter = parse_case("turbulent-15", duration=300.0)
    assert shorter.turbulent and shorter.duration == 300.0 and shorter.analysed == pytest.approx(270.0)
    with pytest.raises(ValueError, match=r"--case 'gusty-13': expected steady-V or turbulent-V"):
        parse_case("gusty-13")
    with pytest.raises(ValueError, match=r"--case steady-45: 45 m/s is outside the plant's 3..30 m/s"):
        parse_case("steady-45")
    with pytest.raises(ValueError, match=r"--duration 5: expected at least 20 s"):
        parse_case("steady-13", duration=5.0)


def test_the_checks_are_issue_29s_tolerances():
    steady = {c.key: c for c in STEADY_CHECKS}
    assert steady["power_mean"].tolerance == 0.02 and steady["pitch_mean"] == Check("pitch_mean", 0.3, True)
    assert steady["root_oop_1p"].tolerance == 0.10 and steady["hub_yaw_3p"].tolerance == 0.15
    assert steady["tower_fa_mean"].tolerance == 0.05 and steady["tower_ss_3p"].tolerance == 0.25
    assert {c.key for c in TURBULENT_CHECKS} >= {"root_oop_del", "hub_tilt_del", "hub_yaw_del", "tower_fa_del",
                                                 "tower_ss_del"}


def test_a_difference_is_relative_to_openfast_or_absolute_in_degrees():
    hawt = {"power_mean": 5.1e6, "pitch_mean": math.radians(14.7)}
    openfast = {"power_mean": 5.0e6, "pitch_mean": math.radians(14.3)}
    power, pitch = compare_figures(hawt, openfast, (Check("power_mean", 0.02), Check("pitch_mean", 0.3, True)))
    assert (power["hawt"], power["openfast"], power["difference"], power["within"]) == pytest.approx(
        (5.1, 5.0, 0.02, True))
    assert pitch["unit"] == "deg" and pitch["difference"] == pytest.approx(0.4) and not pitch["within"]


def test_the_report_says_when_the_towers_are_not_like_for_like():
    """A tower on the ground is; one on a flexible substructure is not, against OpenFAST's deck on a rigid base: the
    report says so, naming the clamp and the base."""
    from dataclasses import replace

    from hawt_plant.turbine import nrel_5mw

    turbine = nrel_5mw()
    assert not_like_for_like(turbine) == []
    monopile = replace(turbine, tower=replace(turbine.tower, base_height=15.0, clamp_height=-30.0))
    [note] = not_like_for_like(monopile)
    assert "flexible substructure (the beam clamped at -30 m, the tower's base at 15 m)" in note
    assert "rigid base" in note


def test_a_runs_figures_are_hawts_analysis_of_its_channels():
    """The means are the channels' means, the blade-root 1P the 2 MN*m the synthetic run was made with."""
    channels = synthetic_channels(duration=60.0)
    figures = case_figures(channels)
    assert figures["pitch_mean"] == pytest.approx(float(np.mean(channels["pitch"])))
    assert figures["thrust_mean"] == pytest.approx(float(np.mean(channels["rotor_thrust"])))
    assert figures["root_oop_1p"] == pytest.approx(2e6, rel=0.05)
    assert figures["root_oop_del"] > 0 and figures["tower_fa_del"] > 0
    same = compare_figures(figures, figures, STEADY_CHECKS)
    assert all(row["within"] and row["difference"] == 0.0 for row in same)


@pytest.mark.parametrize("arguments, message", [
    (["validate", "nrel_5mw"], "no OpenFAST executable: give --openfast PATH or set $HAWT_OPENFAST"),
    (["validate", "nrel_5mw", "--openfast", "/nonexistent/openfast"], "--openfast /nonexistent/openfast: no such "
                                                                       "file"),
    (["validate", "nrel_5mw", "--openfast", "/bin/true", "--case", "windy-9"], "expected steady-V or turbulent-V"),
    (["validate", "nrel_5mw_two_bladed", "--openfast", "/bin/true"], "nrel_5mw_two_bladed: no OpenFAST deck"),
    (["validate", "/nonexistent/turbine", "--openfast", "/bin/true"], "/nonexistent/turbine"),
    (["validate", "nrel_5mx", "--openfast", "/bin/true"], "turbine 'nrel_5mx': no packaged turbine of that name "
                                                          "(packaged: nrel_5mw, "),
])
def test_bad_input_is_one_line_and_exit_2_before_anything_runs(arguments, message, capsys, monkeypatch, tmp_path):
    monkeypatch.delenv("HAWT_OPENFAST", raising=False)
    monkeypatch.chdir(tmp_path)
    assert main(arguments) == 2
    _, err = capsys.readouterr()
    assert err.count("\n") == 1 and message in err, err
    assert not list(tmp_path.iterdir())  # no report folder left behind


def test_an_imported_turbine_runs_hawts_side_with_the_rosco_input_the_import_kept(tmp_path, capsys):
    """hawt turbine import keeps the deck and its ROSCO input; the validation graph (no cpc tuning needed) then runs
    ROSCO on that turbine, and validate finds the deck, with no hand edit."""
    from hawt_tools.openfast_case import deck_of

    folder = tmp_path / "nrel5mw"
    assert main(["turbine", "import", str(deck_of("nrel_5mw")), "-o", str(folder)]) == 0
    assert deck_of(str(folder)) == folder / "openfast" / "NREL-5MW.fst"
    assert main(["run", "validation", f"turbine:={folder}", "duration:=1"]) == 0
    assert "finished 100 steps" in capsys.readouterr().out
