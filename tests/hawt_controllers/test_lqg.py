"""LQG IPC with wind-estimate feedforward (Selvam et al. 2009): the notes' acceptance checks 16-19 on this plant's
Coleman-frame linear model at 18 m/s, and checks 12, 15, 20 and 21 on the shipped linear models
(data/linear_nrel5mw.npz) at 13, 18 and 24 m/s."""
import dataclasses
import math

import numpy as np
import pytest

from hawt_controllers.laws.collective import load_baseline_config
from hawt_core.exceptions import ConfigurationError
from hawt_controllers.laws.coleman_models import load_models
from hawt_controllers.design.linear_models import collective_loop_gain, linearize_at, stability_margins
from hawt_controllers.laws.lqg_design import LqgWeights, controllability_rank, design_lqg, observability_rank
from hawt_controllers.laws.lqg_ipc import LqgIpc, closed_loop_response, rotor_speed_response

DT = 0.01
IPC_H1 = (1.1793209854830301e-08, 0.42587361125278206)  # ipc_h1 of data/ipc_nrel5mw.yaml: k_i, phi_1
TABLE_II = LqgWeights(measurement_noise=0.01, wind_walk=0.1 / DT, input_weight=0.8, inversion_walk=0.01)
"""Selvam's Table II read as in the notes (Q_w 0.1 per step), in this module's units."""


@pytest.fixture(scope="module")
def model():
    return linearize_at(18.0)


@pytest.fixture(scope="module")
def design(model):
    return design_lqg(model.model, DT)


SPEEDS = (13.0, 18.0, 24.0)


@pytest.fixture(scope="module")
def shipped():
    """The shipped linear models by wind speed."""
    from hawt_controllers.plugins.lqg_ipc import DEFAULT_MODELS

    return {m.wind_speed: m for m in load_models(DEFAULT_MODELS)}


@pytest.mark.parametrize("speed, gain_margin, phase_margin", [(13.0, 2.43, 21.9), (18.0, 2.92, 38.1),
                                                              (24.0, 3.12, 57.4)])
def test_check_12_the_baseline_collective_loop_has_selvam_s_gain_margin_and_his_phase_margin_only_at_24_m_s(
        shipped, speed, gain_margin, phase_margin):
    """Check 12 asks GM >= 2 and PM >= 45 deg of the collective PI. This project's is Jonkman's baseline (PI on the
    0.25 Hz low-passed generator speed, gain-scheduled at the operating pitch), here on the model's collective pitch
    command -> generator speed (pitch actuator, drivetrain, blades' edgewise modes and tower included) with the torque
    held: GM 2.43, 2.92, 3.12 and PM 21.9, 38.1, 57.4 deg at 13, 18, 24 m/s. A finding: Selvam's GM is met, his PM
    only at 24 m/s (the speed filter alone takes 20-24 deg at the crossovers). (Before the nacelle's roll twisted the
    shaft: GM 2.44, 2.94, 3.17, PM 21.9, 38.2, 57.4 deg; before the elements' inflow took the
    deflected blade's slope: GM 2.34, 2.92, 3.17; before the blade modes took the structural twist: GM 2.37, 2.96, 3.23,
    PM 21.2, 37.9, 57.3 deg. With the tower damped at the deck's
    ratio of the mode with the rotor on top rather than ElastoDyn's of the tower alone: GM 2.37, 2.98, 3.27. With the
    blades rigid edgewise: GM
    2.41, 3.19, 3.51, PM 21.2, 38.3, 57.5 deg; with edgewise modes not turning with the pitch, GM 2.40, 3.14, 3.50. On the plant before it took AeroDyn 15's nodes: GM 2.45,
    3.18, 3.49 with phase crossovers at 0.17, 0.23, 0.26 Hz, PM 21.6, 38.4, 57.5 deg with gain crossovers at 0.09,
    0.11, 0.11 Hz; closing the region-3 torque law T = P/ω_f as well gave GM 2.33, 3.11, 3.44 and PM 15.3, 32.9,
    52.0 deg.)"""
    omega = np.geomspace(1e-3, 100.0, 2000)
    gm, pm = stability_margins(collective_loop_gain(shipped[speed], load_baseline_config(), omega))
    assert gm == pytest.approx(gain_margin, abs=0.01) and gm >= 2.0
    assert math.degrees(pm) == pytest.approx(phase_margin, abs=0.1) and pm > 0.0
    assert (math.degrees(pm) >= 45.0) == (speed == 24.0)


def test_the_stability_margins_of_a_loop_with_known_crossovers():
    """L = 2/(s + 1)^3: the phase is -180 deg at ω = √3, where |L| = 1/4 (GM 4); |L| = 1 at ω = √(2^(2/3) - 1),
    where the phase is -3 atan(ω) (PM π - 3 atan(ω)). A loop that never reaches 1 has an infinite phase margin."""
    omega = np.geomspace(1e-2, 1e2, 2000)
    gm, pm = stability_margins(2.0 / (1j * omega + 1.0) ** 3)
    assert gm == pytest.approx(4.0, rel=1e-4)
    assert pm == pytest.approx(math.pi - 3.0 * math.atan(math.sqrt(2.0 ** (2.0 / 3.0) - 1.0)), abs=1e-4)
    assert stability_margins(0.5 / (1j * omega + 1.0))[1] == math.inf


@pytest.mark.parametrize("speed", SPEEDS)
def test_check_15_the_integrator_ipc_removes_a_constant_tilt_yaw_load_and_does_not_reduce_from_1p_on(shipped, speed):
    """Check 15, the conventional IPC: a constant cos/sin wind leaves no steady-state cos/sin moment (0.83-0.90 MN m
    per m/s without IPC); from 1P to the Nyquist frequency |u -> M| is at most 29 % above no IPC (at 1.5P; 26 % at
    13 m/s, 28 % at 18 m/s) and nowhere more than 1.5 % below it (1.2 % at 1.6 Hz, beside the drivetrain's torsion at
    1.66-1.73 Hz), except at the blades' edgewise whirl modes (backward 0.91 Hz, forward 1.31 Hz in the Coleman frame,
    0.8-1.7 % damped), where the loop shifts those resonances: there it is down to 0.991, 0.978 and 0.854 times no IPC
    at 13, 18 and 24 m/s (the last at the forward whirl, yaw axis): Selvam's "no reduction, and even a slight increase"
    (check 19 asks >= no IPC at 1P, 2P and 3P) holds away from them. (With the blade modes not turned by the
    structural twist, the whirls 0.5-1 % damped: down to 0.977, 0.950 and 0.639 there, 0.99 elsewhere; with the blades
    rigid edgewise the ratio stayed above 0.99 everywhere.)"""
    design = design_lqg(shipped[speed].model, DT)
    assert np.abs(closed_loop_response(design, [0.0], "integrator", *IPC_H1)).max() < 1e-12
    assert np.abs(closed_loop_response(design, [0.0], "none")).max() > 0.8
    omega = np.geomspace(shipped[speed].rotor_speed, math.pi / DT, 400)
    ratio = np.abs(closed_loop_response(design, omega, "integrator", *IPC_H1)) \
        / np.abs(closed_loop_response(design, omega, "none"))
    hertz = omega / (2 * math.pi)
    whirl = ((hertz > 0.85) & (hertz < 0.97)) | ((hertz > 1.2) & (hertz < 1.6))
    for axis in (0, 1):
        assert 0.985 <= ratio[~whirl, axis, axis].min() and ratio[:, axis, axis].max() <= 1.35
        assert 0.8 <= ratio[whirl, axis, axis].min()


def test_check_16_the_augmented_model_is_observable_and_the_plant_controllable(design):
    n = design.states
    assert observability_rank(design.a_est, design.c_est) == n + 2  # turbine states and the two wind states
    assert observability_rank(design.plant.a, design.plant.c) == n
    assert controllability_rank(design.plant.a, design.plant.b_theta) == n
    assert controllability_rank(design.a_est, design.b_est) == n  # the wind states are not controllable
    assert np.min(np.abs(np.linalg.eigvals(design.plant.a) - 1.0)) > 1e-3  # no pole at z = 1


def _simulate(design, weights_design, wind, steps):
    """The design plant driven by the cos/sin wind ``wind`` (steps x 2) in closed loop with the FB-FF law."""
    p, law = design.plant, LqgIpc([weights_design])
    x, estimates = np.zeros(design.states), []
    theta = np.zeros(2)
    for k in range(steps):
        y = (p.c @ x + p.d_theta @ theta + p.d_u @ wind[k]) * 1e6
        theta = np.degrees(law.step(*y)[0])
        x = p.a @ x + p.b_theta @ theta + p.b_u @ wind[k]
        estimates.append(law.wind[0])
    return np.array(estimates)


def test_check_17_the_wind_estimate_follows_a_step_with_no_steady_state_error(design, model):
    steps = 3000
    wind = np.zeros((steps, 2))
    wind[100:, 0] = 1.0
    estimate = _simulate(design, design, wind, steps)
    assert estimate[-1, 0] == pytest.approx(1.0, abs=1e-3)
    assert estimate[-1, 1] == pytest.approx(0.0, abs=1e-3)
    faster = design_lqg(model.model, DT, LqgWeights(wind_walk=10 * design.weights.wind_walk))
    quick = _simulate(design, faster, wind, steps)

    def rise(series):
        return int(np.argmax(series[:, 0] >= 0.9))

    assert rise(quick) < rise(estimate)  # a larger Q_w tracks faster


def test_check_18_the_sdmi_inverse_is_stable_and_inverts_g_at_low_frequency(design):
    a, b, c, d = design.inverse
    assert np.max(np.abs(np.linalg.eigvals(a))) < 1.0
    p = design.plant
    z = np.exp(1j * 0.01 * DT)
    g = p.c @ np.linalg.solve(z * np.eye(p.a.shape[0]) - p.a, p.b_theta) + p.d_theta
    g_inv = c @ np.linalg.solve(z * np.eye(a.shape[0]) - a, b) + d
    assert np.allclose(g_inv @ g, np.eye(2), atol=0.02)


def test_check_19_the_closed_loop_from_the_wind_to_the_moments_has_selvam_s_shape(model):
    """Figs 6-7 in shape, with Selvam's weights: FB-FF below no IPC at 3P; the integrator IPC lower at very low
    frequency and not below no IPC from 1P on. (The default weights give up the 3P reduction: with these the
    law's pitch rate is at the actuator's limit almost all the time in a turbulent run.)"""
    design = design_lqg(model.model, DT, TABLE_II)
    rotor = model.rotor_speed
    omega = np.array([0.01, rotor, 2 * rotor, 3 * rotor])
    none = np.abs(closed_loop_response(design, omega, "none"))
    integrator = np.abs(closed_loop_response(design, omega, "integrator", *IPC_H1))
    lqg = np.abs(closed_loop_response(design, omega, "lqg"))
    for axis in (0, 1):
        assert lqg[3, axis, axis] < none[3, axis, axis]
        assert integrator[0, axis, axis] < lqg[0, axis, axis]
        assert np.all(integrator[1:, axis, axis] >= none[1:, axis, axis])


def _pitch_activity(design, omega, controller, *gains):
    """The largest cyclic pitch per unit cos/sin wind [deg per m/s] (2-norm over the wind's direction)."""
    return np.linalg.norm(closed_loop_response(design, omega, controller, *gains, output="pitch"), 2, axis=(1, 2))


@pytest.mark.parametrize("speed", SPEEDS)
def test_check_20_fb_ff_pitches_more_than_the_integrator_ipc_from_3p_on_with_selvam_s_weights(shipped, speed):
    """Check 20 with Table II, the weights of Selvam's claim: from 3P to the Nyquist frequency FB-FF's cyclic pitch per
    unit wind is at least 2.6 times the integrator IPC's (at 3P: 5.0, 4.4, 4.2 times at 13, 18, 24 m/s; the least,
    2.6, at 24 m/s at the backward edgewise whirl, 0.91 Hz, where the integrator's pitch resonates), and the ratio
    grows to about 2000 at the Nyquist frequency, where FB-FF still pitches 0.8 deg per m/s and the integrator has
    rolled off (1.4-1.8 times at 1P)."""
    design = design_lqg(shipped[speed].model, DT, TABLE_II)
    omega = np.geomspace(3 * shipped[speed].rotor_speed, math.pi / DT, 300)
    ratio = _pitch_activity(design, omega, "lqg") / _pitch_activity(design, omega, "integrator", *IPC_H1)
    assert ratio.min() > 2.5 and ratio[-1] > 1000


@pytest.mark.parametrize("speed, at_3p", [(13.0, 1.33), (18.0, 1.13), (24.0, 1.04)])
def test_check_20_with_the_default_weights_fb_ff_pitches_about_as_the_integrator_ipc_at_3p(shipped, speed, at_3p):
    """The defaults (tuned for the actuator's rate limit) give up Selvam's high-frequency pitch: at 3P FB-FF's cyclic
    pitch per unit wind is 1.33, 1.13, 1.04 times the integrator IPC's at 13, 18, 24 m/s; it exceeds it by more only above about 8P (30 times at the Nyquist frequency, at
    0.003 deg per m/s: 1/300 of Table II's)."""
    design = design_lqg(shipped[speed].model, DT)
    omega = np.array([3 * shipped[speed].rotor_speed, math.pi / DT])
    ratio = _pitch_activity(design, omega, "lqg") / _pitch_activity(design, omega, "integrator", *IPC_H1)
    assert ratio[0] == pytest.approx(at_3p, abs=0.01)
    assert _pitch_activity(design, omega[1:], "lqg")[0] < 0.01


@pytest.mark.parametrize("speed", SPEEDS)
@pytest.mark.parametrize("controller, weights, collective, cyclic", [
    ("integrator", LqgWeights(), 0.04, 0.10), ("lqg", LqgWeights(), 0.04, 0.10), ("lqg", TABLE_II, 0.07, 0.20)])
def test_check_21_ipc_leaves_the_rotor_speed_s_response_to_the_wind_below_0_3_hz_nearly_unchanged(
        shipped, speed, controller, weights, collective, cyclic):
    """Check 21 on the whole Coleman model (every state; the laws are designed on the tilt/yaw design states only), the
    laws closed on its cos/sin channels (stably: rotor_speed_response refuses an unstable loop), 1 mHz to 0.3 Hz. The
    collective pitch and the generator torque are held, as in the design model: the rotor speed's response is the
    open loop's, damped by the aerodynamics only.

    - The collective wind -> rotor speed changes by at most 3.4 % with the integrator IPC, 2.9 % with FB-FF and the
      default weights, 6.7 % with Table II (each largest at 0.3 Hz, the band's top).
    - The cos/sin wind reaches the rotor speed through the shear's couplings only: at most 16.2 % of the collective
      wind's response without IPC (at 13 m/s; 15 % with the tower damped more, before it took ElastoDyn's damping).
      IPC changes that by up to 2.6 times itself, but by at most 8.6 % (integrator, defaults) and 19 % (Table II) of
      the collective wind's response at that frequency.
    """
    model = shipped[speed]
    design = design_lqg(model.model, DT, weights)
    gains = IPC_H1 if controller == "integrator" else ()
    omega = 2 * math.pi * np.geomspace(1e-3, 0.3, 200)
    none = rotor_speed_response(model.model, design, omega, "none")[:, 0, :]
    assert np.max(np.abs(none[:, 1:]) / np.abs(none[:, :1])) < 0.17
    change = np.abs(rotor_speed_response(model.model, design, omega, controller, *gains)[:, 0, :] - none) \
        / np.abs(none[:, :1])
    assert change[:, 0].max() < collective
    assert change[:, 1:].max() < cyclic


def test_a_closed_loop_that_is_not_stable_has_no_frequency_response(shipped):
    """An integrator IPC of the wrong sign (or ten times the gain) destabilises the loop: refused, not evaluated."""
    design = design_lqg(shipped[18.0].model, DT)
    for gain in (-IPC_H1[0], 10 * IPC_H1[0]):
        with pytest.raises(ValueError, match="unstable"):
            closed_loop_response(design, [1.0], "integrator", gain, IPC_H1[1])


def test_the_law_stepped_equals_the_controller_of_the_closed_loop(design):
    """LqgIpc.step and closed_loop_response's controller are the same system: a response to random moments."""
    from hawt_controllers.laws.lqg_ipc import _lqg_controller

    rng = np.random.default_rng(1)
    moments = rng.normal(scale=1e5, size=(200, 2))
    law = LqgIpc([design])
    stepped = np.array([law.step(*m)[0] for m in moments])
    a, b, c, d = _lqg_controller(design)
    state, expected = np.zeros(a.shape[0]), []
    for m in moments / 1e6:
        expected.append(c @ state + d @ m)
        state = a @ state + b @ m
    assert np.allclose(stepped, np.radians(expected), rtol=1e-9, atol=1e-15)


def test_laws_stepped_together_are_each_law_stepped_alone(design, model):
    """A schedule's laws step as one LqgIpc (one batched product per matrix): each row is what that design's law
    alone gives; a design of other dimensions is refused, naming it."""
    other = design_lqg(model.model, DT, LqgWeights(input_weight=10 * design.weights.input_weight))
    together, alone = LqgIpc([design, other]), [LqgIpc([design]), LqgIpc([other])]
    rng = np.random.default_rng(2)
    for moments in rng.normal(scale=1e5, size=(100, 2)):
        stepped = together.step(*moments)
        for row, law in zip(stepped, alone):
            assert np.allclose(row, law.step(*moments)[0], rtol=1e-12, atol=1e-18)
    assert np.allclose(together.wind, [law.wind[0] for law in alone], rtol=1e-12, atol=1e-15)
    with pytest.raises(ValueError, match="design 1 has other dimensions than design 0"):
        LqgIpc([design, dataclasses.replace(other, ff_a=np.zeros((1, 1)))])


@pytest.mark.parametrize("field", ["measurement_noise", "wind_walk", "input_weight", "inversion_walk"])
def test_a_weight_that_is_not_positive_is_refused_by_name(field):
    with pytest.raises(ConfigurationError, match=field):
        LqgWeights(**{field: 0.0})
    with pytest.raises(ConfigurationError, match=field):
        LqgWeights(**{field: math.nan})


def test_the_shipped_linear_models_are_what_hawt_linearize_gives(model):
    """data/linear_nrel5mw.npz is written by `hawt linearize`, not edited: its 18 m/s model is today's."""
    from hawt_controllers.laws.coleman_models import load_models
    from hawt_controllers.plugins.lqg_ipc import DEFAULT_MODELS

    shipped = {m.wind_speed: m for m in load_models(DEFAULT_MODELS)}[18.0]
    assert shipped.model.states == model.model.states and shipped.model.inputs == model.model.inputs
    # Each entry within 1e-8 of its row's largest: a trim one ulp apart (fresh-clone CI: rotor speed ...098 against
    # ...099 rad/s) moves the finite-difference entries that are nearly 0 by up to 2e-10 of their row's scale; any
    # change of the model's physics moves them by far more.
    for name in ("a", "b", "c", "d"):
        today = getattr(model.model, name)
        scale = np.abs(today).max(axis=1, keepdims=True)
        assert np.all(np.abs(getattr(shipped.model, name) - today) <= 1e-8 * scale), name


def _lqg_run(arguments, steps):
    from hawt_tools.graph_file import find_graph
    from hawt_tools.graph_file import load_graph
    from hawt_tools.in_process import RunRecord, build_run
    from hawt_tools.graph_file import package_prefix

    run = build_run(load_graph(find_graph("lqg"), arguments, package_prefix))
    record = RunRecord()
    for _ in range(steps):
        run.step(record)
    return run, record


def _one_p(record, last):
    from hawt_core.rotor.mbc import mbc_forward_sample

    rows = record.rows["plant/blade_loads"][-last:]
    harmonics = [mbc_forward_sample(r["root_moment_oop"], r["azimuth"], 1) for r in rows]
    return float(np.hypot(np.mean([h.cos for h in harmonics]), np.mean([h.sin for h in harmonics])))


def test_the_lqg_graph_removes_the_1p_blade_load_of_the_shear_within_the_actuator_s_rate_limit():
    """hawt run lqg, steady sheared 18 m/s: the lqg_ipc plug-in takes the mean 1P blade-root moment (the shear's)
    down by more than 90 % against the graph with it inactive, and the commanded pitch never moves faster
    than the 8 deg/s limit (the defaults respect it)."""
    steps = 3000
    _, with_lqg = _lqg_run({"duration": "30"}, steps)
    _, without = _lqg_run({"duration": "30", "lqg_ipc": "false"}, steps)
    assert _one_p(with_lqg, 500) < 0.1 * _one_p(without, 500)
    pitch = np.array([r["pitch"] for r in with_lqg.rows["control/pitch_command"]])
    assert np.all(np.isfinite(pitch))
    assert np.abs(np.diff(pitch, axis=0)).max() <= math.radians(8.0) * DT * (1 + 1e-9)
    assert not any(r["flags"] & 2 for r in with_lqg.rows["control/pitch_command"][1:])  # FLAG_RATE_SATURATED


def test_lqg_ipc_and_the_integrator_ipc_swap_on_harmonic_1_at_a_step():
    run, record = _lqg_run({"duration": "30", "schedule": "['1500 +ipc_h1 -lqg_ipc']"}, 2000)
    assert [e["step"] for e in run.events if e["kind"] == "switch"] == [1500]
    pitch = np.array([r["pitch"] for r in record.rows["control/pitch_command"]])
    assert np.abs(np.diff(pitch, axis=0)).max() <= math.radians(8.0) * DT * (1 + 1e-9)
    harmonic = record.rows["control/ipc/h1"]
    assert {r["step"] for r in harmonic} >= set(range(1500, 2000))  # ipc_h1 answers from the switch on


@pytest.mark.parametrize("words, message", [
    (["--wind-speed", "18.5"], "18.5 m/s is not in"),
    (["--input-weight", "-1"], "input_weight: expected a finite value > 0"),
    (["--linear-models", "/nonexistent.npz"], "no such file"),
])
def test_design_lqg_bad_input_is_one_line_and_exit_2(words, message, capsys):
    from hawt_tools import cli

    assert cli.main(["design", "lqg", *words]) == 2
    error = capsys.readouterr().err.strip()
    assert message in error and "\n" not in error


def test_design_lqg_prints_the_checks_and_the_closed_loop(capsys, tmp_path):
    from hawt_tools import cli

    plot = tmp_path / "lqg.png"
    assert cli.main(["design", "lqg", "--plot", str(plot)]) == 0
    out = capsys.readouterr().out
    assert "rank 18 of 18" in out and "rank 16 of 16" in out and "FB-FF (LQG)" in out
    assert plot.stat().st_size > 10_000
