"""Specification of hawt_analysis.comparison: runs compared with the first one."""
import json
import math

import pytest

from hawt_analysis.comparison import change_percent, compare_summaries
from hawt_analysis.fatigue import WohlerExponents
from hawt_analysis.summary import AnalysisOptions, summarize
from hawt_analysis.synthetic_run import synthetic_channels


@pytest.fixture(scope="module")
def runs():
    """A synthetic reference run and the same run with blade out-of-plane moments scaled by 0.8."""
    reference = synthetic_channels(duration=60.0, seed=3)
    reduced = {**reference, "root_moment_oop": 0.8 * reference["root_moment_oop"]}
    return reference, reduced


def test_scaling_a_load_by_0_8_shows_as_minus_20_percent_and_the_rest_unchanged(runs):
    """DEL and harmonic amplitudes scale with the load; untouched channels stay at 0 % change."""
    comparison = compare_summaries([summarize(run) for run in runs], ["cpc", "ipc"])
    assert comparison["reference"] == "cpc"
    assert comparison["del"]["root_moment_oop_2"]["change_percent"] == pytest.approx([0.0, -20.0])
    assert comparison["del"]["tower_base_fa_moment"]["change_percent"] == pytest.approx([0.0, 0.0])
    assert comparison["harmonics"]["root_moment_oop_1"]["change_percent"][1] == pytest.approx([-20.0] * 6)
    assert comparison["pitch"]["max_rate_rad_s"]["change_percent"] == pytest.approx([0.0, 0.0])
    assert comparison["warnings"] == []
    json.dumps(comparison, allow_nan=False)


def test_runs_of_different_length_are_compared_with_a_warning_naming_both_lengths(runs):
    """A 60 s run against a 30 s one: figures still compared, one warning line names the runs and their lengths."""
    shorter = {name: values[: len(values) // 2] for name, values in runs[1].items()}
    comparison = compare_summaries([summarize(runs[0]), summarize(shorter)], ["long", "short"])
    (warning,) = comparison["warnings"]
    assert warning.startswith("the runs differ in length (long 60")
    assert "short 29.99 s" in warning and "cover different records" in warning


def test_change_against_a_zero_reference_is_none():
    """A change relative to 0 is undefined and reported as None (JSON null)."""
    assert change_percent([0.0, 1.0]) == [None, None]
    assert change_percent([2.0, 3.0, 1.0]) == [0.0, 50.0, -50.0]


def test_runs_with_different_wohler_exponents_are_not_compared(runs):
    """DELs of a channel with m = 10 in one run and m = 12 in another are refused, naming the channel."""
    other = summarize(runs[1], AnalysisOptions(wohler=WohlerExponents(blade_root=12.0)))
    with pytest.raises(ValueError, match=r"root_moment_oop_1: Wöhler exponent differs between runs \(\[10.0, 12.0\]\)"):
        compare_summaries([summarize(runs[0]), other], ["a", "b"])


def test_labels_must_match_the_summaries_and_be_unique(runs):
    """One unique label per run."""
    summary = summarize(runs[0])
    with pytest.raises(ValueError, match=r"labels: expected one label per summary \(2\), found 1"):
        compare_summaries([summary, summary], ["a"])
    with pytest.raises(ValueError, match="labels: expected unique labels"):
        compare_summaries([summary, summary], ["a", "a"])


def test_the_headline_gives_the_second_run_against_the_first_blades_averaged():
    from hawt_analysis.analysis_report import headline_text

    entry = lambda a, b: {"value": [a, b], "change_percent": [0.0, 100 * (b / a - 1)]}  # noqa: E731
    comparison = {"labels": ["baseline.mcap", "ipc.mcap"],
                  "del": {"root_moment_oop_1": entry(8.0, 4.0), "root_moment_oop_2": entry(8.0, 6.0),
                          "hub_tilt_moment": entry(3.0, 3.3), "hub_yaw_moment": entry(3.0, 2.7),
                          "tower_base_fa_moment": entry(15.0, 16.5)},
                  "pitch": {"travel_rad": entry(0.4, 4.0)},
                  "rotor_speed": {"mean": entry(1.29, 1.29)}, "power": {"mean": entry(5e6, 5e6)}}
    lines = headline_text(comparison).splitlines()
    assert lines[0] == "ipc.mcap against baseline.mcap:"
    assert "-37.5 % (mean of the blades)" in lines[1]
    assert "+10.0 % / -10.0 %" in lines[2] and "+10.0 % / n/a" in lines[3]
    assert "23 -> 229 deg" in lines[4] and "12.32 -> 12.32 rpm" in lines[5] and "5.00 -> 5.00 MW" in lines[6]


def _entry(*values: float) -> dict:
    return {"value": list(values), "change_percent": [None] * len(values)}


def test_the_compare_table_has_fixed_width_columns_and_a_percentage_only_against_a_reference_not_near_zero():
    """Each column as wide as its widest cell, cells two spaces apart (once `7.729e-050.0009144`); a change is a
    percentage where the reference is at least a tenth of the run's value, else the change in the row's unit (once
    `+13668.3 %` for an IPC's 1P pitch against a baseline that has next to none); the pitch rows say how the blades
    are combined."""
    from hawt_analysis.analysis_report import comparison_text

    deg = math.radians
    comparison = {"labels": ["baseline.mcap", "ipc.mcap"], "reference": "baseline.mcap",
                  "del": {"root_moment_oop_1": {**_entry(7.53e6, 4.365e6), "m": 10.0}},
                  "harmonics": {"pitch_1": {"n": [1, 2, 3],
                                            "amplitude": [[deg(0.02815), deg(7.729e-05), deg(0.01546)],
                                                          [deg(2.997), deg(0.0009144), deg(0.06575)]]}},
                  "pitch": {"travel_rad": _entry(deg(23.02), deg(246.5)),
                            "max_rate_rad_s": _entry(deg(0.6342), deg(8.0)),
                            "max_acceleration_rad_s2": _entry(deg(1.006), deg(32.68)),
                            "duty_cycle": _entry(0.7453, 0.9504)},
                  "rotor_speed": {"mean": _entry(1.29, 1.29)}, "power": None}
    assert comparison_text(comparison).splitlines()[1:] == [
        "quantity                                        baseline.mcap   ipc.mcap        change",
        "DEL root_moment_oop_1 [MN·m]                             7.53      4.365       -42.0 %",
        "1P pitch_1 [°]                                        0.02815      2.997      +2.969 °",
        "2P pitch_1 [°]                                      7.729e-05  0.0009144  +0.0008371 °",
        "3P pitch_1 [°]                                        0.01546    0.06575      +325.3 %",
        "pitch travel, sum of all blades [°]                     23.02      246.5      +223.5 °",
        "pitch largest rate of any blade [°/s]                  0.6342          8    +7.366 °/s",
        "pitch largest acceleration of any blade [°/s²]          1.006      32.68   +31.67 °/s²",
        "pitch duty cycle, mean of the blades [%]                74.53      95.04       +27.5 %",
        "rotor speed mean [rpm]                                  12.32      12.32        +0.0 %"]


@pytest.mark.parametrize("reference, value, factor, unit, text", [
    (7.53e6, 4.365e6, 1e-6, "MN·m", "-42.0 %"),
    (1.0, 10.0, 1.0, "°", "+900.0 %"),  # the reference a tenth of the value: still a percentage
    (1.0, 10.01, 1.0, "°", "+9.01 °"),  # under a tenth: near zero
    (0.0, 2.0, 1.0, "°", "+2 °"),
    (0.05, 0.95, 100.0, "%", "+90 pp"),  # a quantity in %: its change in percentage points
    (None, 1.0, 1.0, "°", ""),
])
def test_a_change_is_a_percentage_unless_the_reference_is_near_zero(reference, value, factor, unit, text):
    """The threshold: a reference under NEAR_ZERO (a tenth) of the value."""
    from hawt_analysis.analysis_report import change_text

    assert change_text(reference, value, factor, unit) == text
