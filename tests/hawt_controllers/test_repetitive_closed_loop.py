"""Fratini 2019 R3, R4 and R8 (AC-18, AC-19, AC-21) on the NREL 5 MW, with ``hawt run repetitive`` (cores in process).

The scenarios are those ``./hawt bench repetitive`` prints (its functions). R3 and R4 are the
repetitive-PD collective controller's; R8 the repetitive IPC's: steady wind, shear 0.17, no tower
shadow, blade 1's flap root moment over the last 30 s of 90 s at 15 m/s against the baseline alone,
where with headroom the periodic flap load goes. At the thesis's 11.4 m/s (−94 % oscillation,
1P −92 %, 2P −63 %) this plant's blades touch its 0° pitch floor: the benchmark measures 1P −92 %
after 300 s with 2P and 3P grown; the suite leaves that run to it, for time.
"""
import sys
from pathlib import Path

import numpy as np
import pytest

from hawt_tools.graph_file import find_graph
from hawt_tools.graph_file import load_graph
from hawt_tools.in_process import build_run
from hawt_tools.graph_file import package_prefix

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
from bench_repetitive import REPETITIVE_PD, flap_loads, run_rows, speed_recovery, speed_ripple  # noqa: E402

pytestmark = pytest.mark.ros  # the graph's node classes come from the built workspace


def _change(wind_speed: str, duration: float) -> dict:
    base = flap_loads({"wind_speed": wind_speed, "repetitive_ipc": "false"}, duration, 30.0)
    learnt = flap_loads({"wind_speed": wind_speed, "learning_gain": "0.3", "proportional_gain": "0.1"}, duration, 30.0)
    return {key: learnt[key] / base[key] - 1.0 for key in ("oscillation", "1P", "2P", "rotor_speed")}


def test_with_pitch_headroom_at_15_m_s_the_periodic_flap_load_is_learnt_away():
    change = _change("15.0", 90.0)
    assert change["oscillation"] < -0.94 and change["1P"] < -0.92 and change["2P"] < -0.63, change
    assert abs(change["rotor_speed"]) < 0.01, change


def test_r3_after_a_wind_step_from_11_4_to_15_m_s_the_repetitive_pd_brings_the_speed_back_to_rated():
    """AC-18: the thesis's speed is back at rated after about 20 s; here within 1 % of 12.1 rpm after 30 s at
    most (24 s measured; the baseline PI: 20 s)."""
    assert speed_recovery(REPETITIVE_PD)["seconds"] < 30.0


def test_r4_a_1p_torque_disturbance_leaves_a_ripple_under_the_pi_that_the_repetitive_pd_removes():
    """AC-19: an unmeasured 4 kN*m 1P disturbance on the generator torque at 13 m/s: the PI leaves a 1P ripple of
    the rotor speed; the repetitive-PD removes most of it (-93 % measured); both keep the mean at rated. The PI's
    ripple is settled by 80 s (0.0790 rpm over its last 50 s, 0.0792 over the last 50 s of 150 s); the repetitive-PD
    learns for 150 s."""
    pi, repetitive = speed_ripple({}, 80.0), speed_ripple(REPETITIVE_PD)
    assert pi["1P"] > 0.05 and repetitive["1P"] < 0.2 * pi["1P"], (pi, repetitive)
    assert pi["mean"] == pytest.approx(12.1, abs=0.01) and repetitive["mean"] == pytest.approx(12.1, abs=0.01)


def test_the_repetitive_pd_and_the_baseline_swap_bumplessly_both_ways_in_turbulence():
    """hawt run repetitive with a schedule: cpc -> repetitive_cpc at step 3000, back at 6000 (15 m/s, class B): the
    collective command moves at each swap step by less than 0.02 deg (the rate limit allows 0.08 deg)."""
    run = build_run(load_graph(find_graph("repetitive"), {
        "duration": "62", "repetitive_ipc": "false", "wind_speed": "15.0", "wind_type": "turbulent", "seed": "2",
        "schedule": "['3000 +repetitive_cpc -cpc', '6000 +cpc -repetitive_cpc']"}, package_prefix))
    collective = []
    for _ in range(6200):
        run.step()
        collective.append(float(np.mean(run.command[0])))
    change = np.degrees(np.abs(np.diff(collective)))
    assert [e["detail"].split(";")[0] for e in run.events] == ["at step 3000: activate /wt1/repetitive_cpc",
                                                                 "at step 6000: activate /wt1/cpc"]
    assert change[2999] < 0.02 and change[5999] < 0.02, (change[2995:3005], change[5995:6005])


@pytest.mark.parametrize("gain, settles", [(0.02, True), (0.04, False)])
def test_the_refusal_of_a_learning_gain_predicts_whether_the_learnt_mean_settles(capsys, gain, settles):
    """g must stay below 2 K_P = 0.0377 (repetitive_cpc.check_values): hawt run refuses 0.04 with the factor and
    accepts 0.02. Stepped anyway by the cores (build_run checks nothing), 0.02 settles at rated after the 11.4 ->
    15 m/s step and 0.04 keeps oscillating."""
    from hawt_tools.cli import main

    argv = ["run", "repetitive", "cpc:=false", "repetitive_cpc:=true", "repetitive_ipc:=false", "duration:=0.1",
            "-p", f"repetitive_cpc.learning_gain:={gain}"]
    code = main(argv)
    err = capsys.readouterr().err
    assert (code == 0) == settles, err
    assert settles or "makes the learnt mean pitch diverge (factor |1 - g/K_P| = 1.12" in err
    rpm = run_rows({**REPETITIVE_PD, "repetitive_ipc": "false", "wind_type": "step", "step_speed": "15.0",
                    "step_time": "20.0", "shear_exponent": "0.0"}, 110.0,
                   {"/wt1/repetitive_cpc": [("learning_gain", gain)]})[:, 2]
    # Settling: 0.063 rpm peak-to-peak over the last 30 s on the plant with the blades' edgewise modes (the drivetrain
    # rings with them; below 0.05 with rigid-edgewise blades); a refused gain diverges.
    assert (np.ptp(rpm[-3000:]) < 0.1) == settles, np.ptp(rpm[-3000:])
