"""Near rated wind the baseline graph settles (issue 13): Jonkman's collective PI on this plant grows a 0.05 Hz limit
cycle just above rated; with K_I x 0.4 near rated (hawt_controllers.laws.collective.integral_gain_factor) steady wind
at 10.5, 11.4 and 12.5 m/s settles to a pitch standard deviation below 0.05 deg (measured 0, 0, 0.005 deg over the
last 60 s of 120 s: at 11.4 m/s in uniform wind the plant holds fine pitch)."""
import dataclasses

import numpy as np
import pytest
import yaml

from hawt_controllers.laws.collective import load_baseline_config
from hawt_tools.graph_file import find_graph
from hawt_tools.graph_file import load_graph
from hawt_tools.in_process import build_run
from hawt_tools.graph_file import package_prefix

SECONDS, SETTLED = 120, 60


def _pitch_std(wind_speed: float, overrides=()) -> float:
    """The collective pitch's standard deviation [deg] from SETTLED s to the end of SECONDS s of steady wind, no
    shear."""
    run = build_run(load_graph(find_graph("baseline"), {"wind_speed": str(wind_speed), "shear_exponent": "0.0",
                                                         "duration": str(SECONDS)}, package_prefix), overrides)
    pitch = []
    for _ in range(SECONDS * 100):
        run.step()
        pitch.append(np.mean(run.output.pitch))
    return float(np.degrees(np.std(pitch[SETTLED * 100:])))


@pytest.mark.parametrize("wind_speed", [10.5, 11.4, 12.5])
def test_steady_wind_near_rated_settles(wind_speed):
    assert _pitch_std(wind_speed) < 0.05


def test_with_jonkmans_integral_gain_just_above_rated_the_limit_cycle_returns(tmp_path):
    """The same run with the factor set to 1 (Jonkman's DISCON) at 11.42 m/s, just above where this plant reaches rated
    power in uniform wind (at 11.4 m/s it holds fine pitch): pitch std 0.13 deg against 0.018 with the factor. (Before
    the elements' inflow took the deflected blade's slope the plant pitched 1.25 deg at 11.4 m/s and the cycle there
    had 0.51 deg; at 11.44 and 11.46 m/s it now has 0.10 and 0.02, at 11.5-12 m/s none: the cycle lives where the
    pitch leaves fine pitch.)"""
    jonkman = dataclasses.replace(load_baseline_config(), near_rated_integral_factor=1.0)
    path = tmp_path / "jonkman.yaml"
    path.write_text(yaml.safe_dump({"source": "test", "parameters": dataclasses.asdict(jonkman)}))
    assert _pitch_std(11.42, {"/wt1/cpc": [("controller_file", str(path))]}) > 0.1
