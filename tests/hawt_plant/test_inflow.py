"""Specification of hawt_plant.inflow and the plant's wind parameters: every wind type is built from the plant's
settings, its parameters are bounded, and the IEC extreme conditions run in the plant."""
import math

import numpy as np
import pytest

from hawt_core.parameter_table import ParameterError, resolve_values
from hawt_plant.gusts import ExtremeOperatingGust
from hawt_plant.iec_extreme import DirectionChange, ExtremeWindShear
from hawt_plant.inflow import OPERATING_WIND_KINDS, WIND_KINDS, InflowSettings, make_wind
from hawt_plant.plant_setup import PARAMETERS, check_parameters
from hawt_plant.shear_wind import PowerLawWind

ROWS = {row.name: row for row in PARAMETERS}
HUB = (np.zeros(1), np.zeros(1), np.full(1, 90.0))


def _hub(wind, t: float) -> np.ndarray:
    return wind.velocity(t, *HUB)[:, 0]


def test_the_plant_offers_every_wind_kind_and_the_extreme_wind_only_to_a_shut_down_rotor():
    """wind_type takes every kind make_wind builds: the operating rotor's (the earlier five and the IEC EDC, ECD and
    EWS, both) and the EWM's (50- and 1-year), which only an idling or parked rotor runs in: with an operating rotor
    the EWM is refused in one line naming the remedy, before anything is built."""
    assert OPERATING_WIND_KINDS == (
        "steady", "turbulent", "bts", "step", "eog", "edc", "ecd", "ews_vertical", "ews_horizontal")
    assert ROWS["wind_type"].choices == WIND_KINDS == OPERATING_WIND_KINDS + ("ewm50", "ewm1")
    with pytest.raises(ParameterError, match="^wind_type: ewm50 is the extreme wind of a shut-down turbine: set rotor"):
        check_parameters(resolve_values(PARAMETERS, {"wind_type": "ewm50"}))
    check_parameters(resolve_values(PARAMETERS, {"wind_type": "ewm50", "rotor": "parked"}))


@pytest.mark.parametrize("name, bad", [("gust_sign", 0), ("gust_sign", 2), ("wind_class", "IV"),
                                       ("turbulence_model", "EWM"), ("step_time", -1.0)])
def test_the_new_wind_parameters_refuse_values_outside_their_choices_or_range(name, bad):
    """gust_sign is 1 or -1 (bounded to [-1, 1] like every number), wind_class I, II or III, turbulence_model NTM or
    ETM: anything else is a ParameterError naming the parameter, before a graph starts."""
    with pytest.raises(ParameterError, match=f"^{name}: "):
        ROWS[name].typed(bad)


@pytest.mark.parametrize("kind, expected_type", [("edc", DirectionChange), ("ecd", DirectionChange),
                                                 ("ews_vertical", ExtremeWindShear),
                                                 ("ews_horizontal", ExtremeWindShear),
                                                 ("eog", ExtremeOperatingGust), ("ewm50", PowerLawWind),
                                                 ("ewm1", PowerLawWind)])
def test_each_iec_kind_is_the_standards_condition_of_the_settings(kind, expected_type):
    """make_wind builds the condition at wind_speed from step_time, steady before it at the hub (the EWM: the wind
    class's V_e50 = 1.4 V_ref or V_e1 = 0.8 V_e50 whatever wind_speed says)."""
    wind = make_wind(InflowSettings(kind=kind, wind_speed=14.0, step_time=5.0, turbine_class="II"))
    assert isinstance(wind, expected_type)
    expected = {"ewm50": 1.4 * 42.5, "ewm1": 0.8 * 1.4 * 42.5}.get(kind, 14.0)
    np.testing.assert_allclose(_hub(wind, 4.0), [expected, 0.0, 0.0], atol=1e-12)


@pytest.mark.parametrize("sign", [1, -1])
def test_gust_sign_turns_the_direction_changes_and_the_shear_its_way(sign):
    """gust_sign +1 turns the EDC and ECD towards +y (v > 0) and makes the EWS faster above the hub and at +y."""
    def settings(kind):
        return InflowSettings(kind=kind, wind_speed=14.0, step_time=0.0, gust_sign=sign)

    for kind in ("edc", "ecd"):
        assert np.sign(_hub(make_wind(settings(kind)), 20.0)[1]) == sign
    top, left = (np.zeros(1), np.zeros(1), np.full(1, 150.0)), (np.zeros(1), np.full(1, 60.0), np.full(1, 90.0))
    vertical, horizontal = make_wind(settings("ews_vertical")), make_wind(settings("ews_horizontal"))
    assert np.sign(vertical.velocity(6.0, *top)[0, 0] - vertical.velocity(20.0, *top)[0, 0]) == sign
    assert np.sign(horizontal.velocity(6.0, *left)[0, 0] - 14.0) == sign


def test_the_rotor_diameter_and_turbulence_class_reach_the_edc_and_ews():
    """The EDC's theta_e and the EWS's amplitude take D = 2 rotor_radius and the turbulence class's sigma_1."""
    settings = InflowSettings(kind="edc", wind_speed=14.0, rotor_radius=120.0, turbulence_class="C", step_time=0.0)
    theta_e = 4.0 * math.atan(0.12 * (0.75 * 14.0 + 5.6) / (14.0 * (1.0 + 0.1 * 240.0 / 42.0)))
    assert make_wind(settings).direction_change == pytest.approx(theta_e)
    ews = make_wind(InflowSettings(kind="ews_vertical", wind_speed=14.0, rotor_radius=120.0, turbulence_class="C"))
    assert ews.amplitude == pytest.approx(2.5 + 0.2 * 6.4 * 0.12 * (0.75 * 14.0 + 5.6) * (240.0 / 42.0) ** 0.25)


def _baseline(wind_type: str, *overrides: str):
    from hawt_tools.graph_file import find_graph
    from hawt_tools.graph_file import load_graph
    from hawt_tools.in_process import build_run
    from hawt_tools.graph_file import package_prefix
    from hawt_tools.node_parameters import parse_overrides

    graph = load_graph(find_graph("baseline"), {"wind_speed": "18.0", "wind_type": wind_type}, package_prefix)
    return build_run(graph, parse_overrides(graph, ["plant.step_time:=0.5", *overrides]))


def _stepped(run, steps: int):
    for _ in range(steps):
        run.step(None)
    return run.output


@pytest.fixture(scope="module")
def steady_output():
    """The baseline graph in steady 18 m/s wind after 3 s."""
    return _stepped(_baseline("steady"), 300)


@pytest.mark.parametrize("kind", ["edc", "ecd", "ews_vertical", "ews_horizontal"])
def test_each_transient_runs_in_the_baseline_graph_in_process(kind, steady_output):
    """hawt run baseline wind_type:=KIND: 2.5 s into the condition the blade-effective wind (the wind the plant samples
    on the blades, in multi-blade coordinates) and the blade loads have left the steady wind's, and stay finite."""
    output = _stepped(_baseline(kind), 300)
    effective = [output.effective_wind_mean, output.effective_wind_cos, output.effective_wind_sin]
    steady = [steady_output.effective_wind_mean, steady_output.effective_wind_cos, steady_output.effective_wind_sin]
    assert np.abs(np.subtract(effective, steady)).max() > 0.1
    assert np.all(np.isfinite(output.root_moment_oop))
    assert np.abs(output.root_moment_oop - steady_output.root_moment_oop).max() > 1e4


def test_a_direction_change_reaches_the_rotor_as_a_lateral_wind_that_moves_the_hub_moments_its_way():
    """An EDC at 18 m/s (theta_e 26.1 deg, class B) is a lateral wind v = V sin theta at the rotor: 6.5 s after its
    start the hub yaw and tilt moments have moved from the steady wind's in opposite directions for the two signs
    (means over 20-25 s of runs whose EDC starts at 5 s: yaw 0.45 -> -0.10 / +1.08 MN m, tilt 2.15 -> 0.61 / 3.06
    MN m, with the skewed wake)."""
    moments = {}
    for name, run in (("steady", _baseline("steady")), (1, _baseline("edc", "plant.gust_sign:=1")),
                      (-1, _baseline("edc", "plant.gust_sign:=-1"))):
        output = _stepped(run, 700)
        moments[name] = np.array([output.hub_yaw_moment, output.hub_tilt_moment])
    assert np.all(moments[1] < moments["steady"] - 2e5) and np.all(moments[-1] > moments["steady"] + 2e5)
