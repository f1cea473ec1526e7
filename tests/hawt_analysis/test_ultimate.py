"""Ultimate loads: IEC partial safety factors per DLC, the governing case per channel, and the 50-year extrapolation
checked on synthetic Gumbel maxima whose 50-year value is known."""
import math

import numpy as np
import pytest
from scipy import optimize, stats

from hawt_analysis.ultimate import (FIFTY_YEARS, fifty_year_load, governing_loads, partial_safety_factor,
                                    ultimate_loads)

TEN_MINUTES = 600.0
REDUCED_VARIATE = -math.log(-math.log1p(-TEN_MINUTES / FIFTY_YEARS))
"""y with exp(-exp(-y)) = 1 - P_e for a 10-minute run: F50 = μ + β·y for one bin holding all the time."""


@pytest.mark.parametrize("dlc, factor", [("1.1", 1.25), ("1.3", 1.35), ("1.4", 1.35), ("1.5", 1.35), ("2.1", 1.35),
                                         ("2.3", 1.1), ("6.1", 1.35), ("6.2", 1.1), ("8.1", 1.5)])
def test_each_dlc_takes_the_factor_of_its_design_situation(dlc, factor):
    """IEC 61400-1 Ed. 3 Tables 2 and 3: normal 1.35, abnormal 1.1, transport 1.5; 1.25 for extrapolated DLC 1.1."""
    assert partial_safety_factor(dlc) == factor


def test_a_fatigue_or_unknown_dlc_is_refused_naming_it():
    for dlc in ("1.2", "9.9"):
        with pytest.raises(ValueError, match=f"DLC '{dlc}' is not an ultimate-load case"):
            partial_safety_factor(dlc)


def test_the_governing_case_has_the_largest_factored_load_and_keeps_its_sign():
    """An abnormal case (γ_f 1.1) with the larger raw extreme loses to a normal one (1.35) whose factored load is
    larger; a minimum of larger magnitude than the maximum is the characteristic load, negative."""
    rows = [
        {"controller": "ipc", "case": "ecd_11", "dlc": "1.4", "max.flap": 10.0, "min.flap": -2.0, "max.tilt": 3.0,
         "min.tilt": -8.0},
        {"controller": "ipc", "case": "eog_grid", "dlc": "2.3", "max.flap": 12.0, "min.flap": 1.0, "max.tilt": 2.0,
         "min.tilt": -1.0},
        {"controller": "baseline", "case": "eog_grid", "dlc": "2.3", "max.flap": 14.0, "min.flap": 0.0,
         "max.tilt": 1.0, "min.tilt": -1.0},
    ]
    table = {(load.controller, load.channel): load for load in ultimate_loads(rows, ["flap", "tilt"])}
    assert table["ipc", "flap"].case == "ecd_11" and table["ipc", "flap"].design == pytest.approx(13.5)
    assert table["ipc", "tilt"].characteristic == -8.0 and table["ipc", "tilt"].design == pytest.approx(-10.8)
    assert table["baseline", "flap"].dlc == "2.3" and table["baseline", "flap"].design == pytest.approx(15.4)


def test_over_several_dlcs_each_channel_takes_the_largest_factored_load_and_names_its_dlc():
    """IEC 61400-1 §7.6.2: the design load is the largest over the load cases; a DLC that has none (NaN, an
    incomplete extrapolation) governs only a channel no other DLC has."""
    def entry(dlc, channel, design):
        return {"controller": "ipc", "channel": channel, "design": design, "dlc": dlc, "case": f"case of {dlc}"}

    extreme = [entry("1.3", "flap", 12.0e6), entry("1.3", "tilt", -3.0e6), entry("1.3", "yaw", math.nan)]
    fault = [entry("2.3", "flap", 11.0e6), entry("2.3", "tilt", -5.0e6), entry("2.3", "tower", 90.0e6)]
    governing = {e["channel"]: e for e in governing_loads([extreme, fault])}
    assert {channel: (e["dlc"], e["design"]) for channel, e in governing.items() if channel != "yaw"} == {
        "flap": ("1.3", 12.0e6), "tilt": ("2.3", -5.0e6), "tower": ("2.3", 90.0e6)}
    assert math.isnan(governing["yaw"]["design"])
    assert governing_loads([[entry("1.1", "yaw", math.nan)], [entry("1.4", "yaw", 2.0e6)]])[0]["dlc"] == "1.4"


def test_many_maxima_of_one_bin_give_the_known_fifty_year_value():
    """5000 ten-minute maxima drawn from Gumbel(μ=10, β=2), all the time in that bin: F50 = μ + β·y (y ≈ 14.8)
    within 1 %, inside its 90 % interval."""
    truth = 10.0 + 2.0 * REDUCED_VARIATE
    maxima = stats.gumbel_r.rvs(10.0, 2.0, size=5000, random_state=np.random.default_rng(1))
    result = fifty_year_load([maxima], [1.0], resamples=100)
    assert result.value == pytest.approx(truth, rel=0.01)
    assert result.low < truth < result.high


def test_over_bins_the_fifty_year_value_is_where_their_weighted_exceedance_meets_the_target():
    """Three bins with known Gumbel parameters and time fractions; the true value has Σ p_i (1 - G_i) = T/50 years.
    From 100 000 maxima per bin it is found within 0.5 %; from 6 seeds per bin, as a campaign has, the 90 %
    interval contains it in at least 80 % of 20 synthetic campaigns (17 of these 20 when written: the fit of 6
    maxima is biased low)."""
    locations, scales, p = np.array([8.0, 11.0, 9.5]), np.array([0.8, 1.2, 1.5]), np.array([0.3, 0.2, 0.1])
    truth = optimize.brentq(lambda load: np.dot(p, stats.gumbel_r.sf(load, locations, scales))
                            - TEN_MINUTES / FIFTY_YEARS, 0.0, 100.0, xtol=1e-12)
    many = [stats.gumbel_r.rvs(m, s, size=100_000, random_state=np.random.default_rng(2))
            for m, s in zip(locations, scales)]
    assert fifty_year_load(many, p, resamples=1).value == pytest.approx(truth, rel=0.005)
    rng = np.random.default_rng(3)
    covered = 0
    for campaign in range(20):
        maxima = [stats.gumbel_r.rvs(m, s, size=6, random_state=rng) for m, s in zip(locations, scales)]
        result = fifty_year_load(maxima, p, resamples=100, seed=campaign)
        covered += result.low <= truth <= result.high
    assert covered >= 16, covered


def test_maxima_without_spread_extrapolate_to_their_value():
    """A channel whose run maxima are all equal (it never moved) has that value as its 50-year value."""
    assert fifty_year_load([[2.5, 2.5, 2.5], [1.0, 1.0, 1.0]], [0.5, 0.5], resamples=10).value == pytest.approx(2.5)


@pytest.mark.parametrize("maxima, probabilities, message", [
    ([[1.0, 2.0]], [1.0], "bin 0: 2 maxima; a Gumbel fit needs at least 3"),
    ([[1.0, 2.0, float("nan")]], [1.0], "all finite"),
    ([[1.0, 2.0, 3.0]], [0.5, 0.5], "maxima of 1 bins but 2 bin probabilities"),
    ([[1.0, 2.0, 3.0]], [1.5], "must be non-negative and sum to at most 1"),
])
def test_bad_input_is_refused_naming_what_is_wrong(maxima, probabilities, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(")):
        fifty_year_load(maxima, probabilities)
