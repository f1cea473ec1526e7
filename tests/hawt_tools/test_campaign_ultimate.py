"""An ultimate-load campaign's table: DLC 1.3 names the case with the largest factored extreme, DLC 1.1 extrapolates
every bin's run maxima to their 50-year value; both from the campaign's per-case rows."""
import math
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

from hawt_analysis.campaign_report import ultimate_text
from hawt_analysis.lifetime import WindDistribution
from hawt_tools.campaign import ultimate_table
from hawt_tools.campaign_file import Campaign, ControllerConfig

CONTROLLERS = (ControllerConfig("baseline", "baseline"), ControllerConfig("ipc", "ipc"))


def _campaign(dlc: str, speeds=(11.0, 17.0), seeds=(1, 2, 3)) -> Campaign:
    return Campaign(Path("ultimate.yaml"), speeds, seeds, CONTROLLERS, duration=600.0, dlc=dlc,
                    site=WindDistribution(10.0))


def _row(controller: str, speed: float, seed: int, flap: float, flap_min: float = 0.0) -> dict:
    return {"controller": controller, "wind_speed": speed, "seed": seed, "max.root_moment_oop_1": flap,
            "min.root_moment_oop_1": flap_min, "max.hub_tilt_moment": 1.0e6, "min.hub_tilt_moment": -2.0e6}


def test_dlc_1_3_names_the_case_whose_extreme_governs_with_the_normal_factor():
    rows = [_row("baseline", 11.0, 1, 9.0e6), _row("baseline", 17.0, 2, 11.0e6, -1.0e6), _row("ipc", 11.0, 3, 8.0e6)]
    table = {(e["controller"], e["channel"]): e for e in ultimate_table(_campaign("1.3"), rows)}
    flap = table["baseline", "root_moment_oop_1"]
    assert (flap["case"], flap["factor"], flap["design"]) == ("17 m/s seed 2", 1.35, pytest.approx(1.35 * 11.0e6))
    assert table["ipc", "hub_tilt_moment"]["characteristic"] == -2.0e6  # the minimum's magnitude is the larger
    text = ultimate_text(list(table.values()))
    assert "ultimate loads, DLC 1.3: design load = γ_f 1.35 × characteristic load" in text
    assert "blade 1 root out-of-plane design [MN·m]" in text and "-27.3 %" in text  # ipc 8 against 11 MN·m


def test_dlc_1_1_extrapolates_each_controllers_bin_maxima_to_fifty_years():
    """Maxima drawn from a Gumbel distribution per bin: the characteristic load is the 50-year value of the fit
    (above every maximum run), γ_f 1.25, its interval named; a controller missing a case gets NaN."""
    rng = np.random.default_rng(4)
    rows = [_row(name, speed, seed, float(stats.gumbel_r.rvs(8e6 if speed < 15 else 10e6, 5e5, random_state=rng)))
            for name in ("baseline", "ipc") for speed in (11.0, 17.0) for seed in (1, 2, 3)]
    rows = rows[:-1]  # ipc at 17 m/s seed 3 missing
    table = {(e["controller"], e["channel"]): e for e in ultimate_table(_campaign("1.1"), rows)}
    flap = table["baseline", "root_moment_oop_1"]
    assert flap["factor"] == 1.25 and flap["characteristic"] > max(r["max.root_moment_oop_1"] for r in rows)
    assert flap["design"] == pytest.approx(1.25 * flap["characteristic"])
    assert flap["basis"].startswith("50-year value, 90% interval ")
    assert math.isnan(table["ipc", "root_moment_oop_1"]["design"])


def test_a_transient_dlcs_governing_case_is_named_by_its_gust_and_its_trip():
    rows = [_row("baseline", 13.0, 1, 9.0e6), {**_row("baseline", 13.0, 2, 12.0e6), "trips": "protection_trip at t=45.27 s"}]
    (flap,) = [e for e in ultimate_table(_campaign("1.4", speeds=(13.0,), seeds=(1, 2)), rows)
               if e["channel"] == "root_moment_oop_1"]
    assert (flap["case"], flap["factor"]) == ("13 m/s ECD -, tripped: protection_trip at t=45.27 s", 1.35)


def test_a_fatigue_campaign_has_no_ultimate_table():
    assert ultimate_table(_campaign("1.2"), [_row("baseline", 11.0, 1, 9.0e6)]) == []
