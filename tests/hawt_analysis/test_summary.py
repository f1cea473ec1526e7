"""Specification of hawt_analysis.record and hawt_analysis.summary: the `hawt analyze` numbers."""
import json

import numpy as np
import pytest

from hawt_analysis.fatigue import damage_equivalent_load
from hawt_analysis.summary import AnalysisOptions, summarize
from hawt_analysis.synthetic_run import synthetic_channels

DESIGN_KEYS = {"duration_s", "del", "harmonics", "psd", "pitch", "rotor_speed", "power", "conventions"}


@pytest.fixture(scope="module")
def run():
    """Two minutes of a synthetic 3-bladed run at 100 Hz with every channel."""
    return synthetic_channels(duration=120.0, seed=2)


@pytest.fixture(scope="module")
def summary(run):
    return summarize(run)


def test_summary_is_strict_json_with_the_design_keys(summary):
    """The dict survives json.dumps without NaN and has every key of DESIGN §8."""
    assert DESIGN_KEYS <= set(json.loads(json.dumps(summary, allow_nan=False)))


def test_per_blade_channels_are_reported_per_blade_with_their_wohler_exponent(summary):
    """Blade-root moments appear as <field>_<blade> with m = 10; hub and tower moments with m = 4."""
    loads = summary["del"]
    assert {f"root_moment_oop_{i}" for i in (1, 2, 3)} | {f"root_moment_ip_{i}" for i in (1, 2, 3)} <= set(loads)
    assert all(loads[f"root_moment_{kind}_{i}"]["m"] == 10.0 for kind in ("oop", "ip") for i in (1, 2, 3))
    steel = ("hub_tilt_moment", "hub_yaw_moment", "tower_base_fa_moment", "tower_base_ss_moment")
    assert all(loads[name]["m"] == 4.0 for name in steel)
    assert summary["n_blades"] == 3


def test_del_entry_equals_the_fatigue_core_with_one_hertz_equivalent(run, summary):
    """Each DEL is damage_equivalent_load of the channel with N_eq = 1 Hz × (t_end − t_0)."""
    duration = run["time"][-1] - run["time"][0]
    expected = damage_equivalent_load(run["root_moment_oop"][:, 1], 10.0, duration)
    entry = summary["del"]["root_moment_oop_2"]
    assert entry["value"] == pytest.approx(expected.value, rel=1e-12)
    assert entry["n_eq"] == pytest.approx(duration) == pytest.approx(summary["duration_s"])


def test_harmonics_recover_the_synthetic_1p_of_the_blade_moments(summary):
    """The synthetic run's 1P of 2 MN·m (M_oop) and 5 MN·m (M_ip, gravity) come back within the turbulence."""
    harmonics = summary["harmonics"]
    assert harmonics["root_moment_oop_1"]["n"] == [1, 2, 3, 4, 5, 6]
    for blade in (1, 2, 3):
        assert harmonics[f"root_moment_oop_{blade}"]["amplitude"][0] == pytest.approx(2e6, rel=0.1)
        assert harmonics[f"root_moment_ip_{blade}"]["amplitude"][0] == pytest.approx(5e6, rel=0.02)


def test_psd_marks_the_rotor_harmonics_and_finds_the_1p_peak(run, summary):
    """Harmonic frequencies are n × mean rotor frequency and the blade moment's 1P peak is labelled 1."""
    one_p = run["rotor_speed"].mean() / (2 * np.pi)
    assert summary["psd"]["harmonic_frequencies_hz"] == pytest.approx([n * one_p for n in range(1, 7)])
    assert 1 in [peak["harmonic"] for peak in summary["psd"]["peaks"]["root_moment_oop_1"]]


def test_pitch_rotor_speed_and_power_statistics_are_reported(run, summary):
    """Pitch activity per blade and overall, rotor speed mean and std, power mean."""
    assert len(summary["pitch"]["max_rate_rad_s"]["per_blade"]) == 3
    assert summary["pitch"]["max_rate_rad_s"]["max"] == max(summary["pitch"]["max_rate_rad_s"]["per_blade"])
    assert summary["rotor_speed"]["mean"] == pytest.approx(run["rotor_speed"].mean())
    assert summary["rotor_speed"]["std"] == pytest.approx(run["rotor_speed"].std())
    assert summary["power"]["mean"] == pytest.approx(run["electrical_power"].mean())


def test_conventions_state_half_cycles_no_binning_no_mean_correction_and_one_hertz(summary):
    """The output says how cycles were counted, as DESIGN §8 asks."""
    conventions = summary["conventions"]
    assert "half cycles count 0.5" in conventions["cycle_counting"]
    assert (conventions["binning"], conventions["mean_correction"]) == ("none", "none")
    assert conventions["equivalent_frequency_hz"] == 1.0
    assert conventions["wohler_m"] == {"blade_root": 10.0, "steel": 4.0}


def test_options_change_exponents_and_binning(run):
    """Options reach the cores: m = 12 for blades, 4 for steel, and 64 rainflow bins."""
    from hawt_analysis.fatigue import WohlerExponents

    options = AnalysisOptions(wohler=WohlerExponents(blade_root=12.0), rainflow_bins=64)
    summary = summarize(run, options)
    assert summary["del"]["root_moment_ip_3"]["m"] == 12.0
    assert summary["conventions"]["binning"] == "64 bins, ranges at upper bin edges"


def test_a_run_with_only_the_required_channels_has_empty_sections(run):
    """time, azimuth and rotor_speed suffice; absent loads give empty sections, absent pitch and power None."""
    summary = summarize({name: run[name] for name in ("time", "azimuth", "rotor_speed")})
    assert (summary["del"], summary["harmonics"], summary["pitch"], summary["power"]) == ({}, {}, None, None)
    assert summary["n_blades"] is None


def _with(run, **changes):
    return {**{name: run[name] for name in ("time", "azimuth", "rotor_speed", "pitch", "hub_tilt_moment")}, **changes}


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"hub_tilt_moment": np.r_[np.zeros(10), np.nan, np.zeros(11990)]}, "hub_tilt_moment: NaN at sample 10"),
        ({"hub_tilt_moment": np.zeros(12000)}, "hub_tilt_moment: expected 12001 samples like time, found 12000"),
        ({"root_moment_oop": np.zeros((12001, 3)), "pitch": np.zeros((12001, 2))}, "pitch: expected B=3 blades like root"),
        ({"root_moment_oop": np.zeros(12001)}, r"root_moment_oop: expected 2-D array \(samples, blades\)"),
        ({"blade_loads": np.zeros(12001)}, "blade_loads: unknown channel"),
        ({"time": np.r_[np.arange(12000) * 0.01, 130.0]}, "time: sampling not uniform"),
    ],
)
def test_bad_input_raises_value_error_naming_the_channel(run, changes, message):
    """NaN, mismatched lengths or blade counts, wrong shapes, unknown names and gaps in time are refused by name."""
    with pytest.raises(ValueError, match=message):
        summarize(_with(run, **changes))


def test_missing_required_channel_is_named(run):
    """A record without azimuth cannot be analysed and says so."""
    with pytest.raises(ValueError, match="azimuth: required channel missing"):
        summarize({"time": run["time"], "rotor_speed": run["rotor_speed"]})


def test_a_record_of_less_than_one_revolution_has_no_harmonics_and_says_how_far_the_rotor_turned():
    """Three seconds hold less than one revolution at 12 rpm (as a parked rotor's record holds none): no harmonics can
    be fitted, so there are none; the loads' DELs are there, and the text says why the harmonics are missing."""
    from hawt_analysis.analysis_report import analysis_text

    summary = summarize(synthetic_channels(duration=3.0))
    assert summary["harmonics"] == {} and 0.6 < summary["revolutions"] < 0.61 and summary["del"]
    assert "no harmonics (the rotor turned 0.61 revolutions, less than one)" in analysis_text(summary)


def test_the_segments_table_keeps_its_columns_apart_whatever_the_values_width():
    """The loads between switches are a table of fixed-width columns: an amplitude printed in 8 characters
    (0.008228) stays apart from its neighbour (a new user read "0.017440.008228"), and a segment under one
    revolution shows "-" in each column."""
    from hawt_analysis.analysis_report import analysis_text

    summary = summarize(synthetic_channels(duration=3.0))
    harmonics = {name: {"n": [1, 2, 3], "amplitude": [17440.0, 8228.0, 1234.5]}
                 for name in ("root_moment_oop_1", "root_moment_oop_2", "root_moment_oop_3", "hub_tilt_moment",
                              "hub_yaw_moment")}
    summary["segments"] = [{"first_step": 0, "last_step": 999, "start_s": 0.0, "harmonics": harmonics},
                           {"first_step": 1000, "last_step": 1050, "start_s": 10.0, "harmonics": None}]
    lines = analysis_text(summary).splitlines()
    header = lines.index(next(line for line in lines if line.startswith("steps")))
    assert lines[header].split() == ["steps", "from", "[s]", "M_oop", "1P", "2P", "3P", "tilt", "3P", "yaw", "3P"]
    assert lines[header + 1].split() == ["0..999", "0.0", "0.01744", "0.008228", "0.001234", "0.001234", "0.001234"]
    assert lines[header + 2].split() == ["1000..1050", "10.0", "-", "-", "-", "-", "-"]
