"""LQG IPC with wind-estimate feedforward (Selvam et al. 2009): the notes' acceptance checks 16-19 on this plant's
Coleman-frame linear model at 18 m/s."""
import math

import numpy as np
import pytest

from hawt_controllers.exceptions import ConfigurationError
from hawt_controllers.linear_models import linearize_at
from hawt_controllers.lqg_design import LqgWeights, controllability_rank, design_lqg, observability_rank
from hawt_controllers.lqg_ipc import LqgIpc, closed_loop_response

DT = 0.01
IPC_H1 = (1.1793209854830301e-08, 0.42587361125278206)  # ipc_h1 of config/ipc_nrel5mw.yaml: k_i, phi_1
TABLE_II = LqgWeights(measurement_noise=0.01, wind_walk=0.1 / DT, input_weight=0.8, inversion_walk=0.01)
"""Selvam's Table II read as in the notes (Q_w 0.1 per step), in this module's units."""


@pytest.fixture(scope="module")
def model():
    return linearize_at(18.0)


@pytest.fixture(scope="module")
def design(model):
    return design_lqg(model.model, DT)


def test_check_16_the_augmented_model_is_observable_and_the_plant_controllable(design):
    n = design.states
    assert observability_rank(design.a_est, design.c_est) == n + 2  # turbine states and the two wind states
    assert observability_rank(design.plant.a, design.plant.c) == n
    assert controllability_rank(design.plant.a, design.plant.b_theta) == n
    assert controllability_rank(design.a_est, design.b_est) == n  # the wind states are not controllable
    assert np.min(np.abs(np.linalg.eigvals(design.plant.a) - 1.0)) > 1e-3  # no pole at z = 1


def _simulate(design, weights_design, wind, steps):
    """The design plant driven by the cos/sin wind ``wind`` (steps x 2) in closed loop with the FB-FF law."""
    p, law = design.plant, LqgIpc(weights_design)
    x, estimates = np.zeros(design.states), []
    theta = np.zeros(2)
    for k in range(steps):
        y = (p.c @ x + p.d_theta @ theta + p.d_u @ wind[k]) * 1e6
        theta = np.degrees(law.step(*y))
        x = p.a @ x + p.b_theta @ theta + p.b_u @ wind[k]
        estimates.append(law.wind)
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


def test_the_law_stepped_equals_the_controller_of_the_closed_loop(design):
    """LqgIpc.step and closed_loop_response's controller are the same system: a response to random moments."""
    from hawt_controllers.lqg_ipc import _lqg_controller

    rng = np.random.default_rng(1)
    moments = rng.normal(scale=1e5, size=(200, 2))
    law = LqgIpc(design)
    stepped = np.array([law.step(*m) for m in moments])
    a, b, c, d = _lqg_controller(design)
    state, expected = np.zeros(a.shape[0]), []
    for m in moments / 1e6:
        expected.append(c @ state + d @ m)
        state = a @ state + b @ m
    assert np.allclose(stepped, np.radians(expected), rtol=1e-9, atol=1e-15)


@pytest.mark.parametrize("field", ["measurement_noise", "wind_walk", "input_weight", "inversion_walk"])
def test_a_weight_that_is_not_positive_is_refused_by_name(field):
    with pytest.raises(ConfigurationError, match=field):
        LqgWeights(**{field: 0.0})
    with pytest.raises(ConfigurationError, match=field):
        LqgWeights(**{field: math.nan})


def test_the_shipped_linear_models_are_what_hawt_linearize_gives(model):
    """config/linear_nrel5mw.npz is written by `hawt linearize`, not edited: its 18 m/s model is today's."""
    from hawt_controllers.linear_models import load_models
    from hawt_controllers.lqg_controller import DEFAULT_MODELS

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
    from hawt_tools.cli import find_graph
    from hawt_tools.graph_file import load_graph
    from hawt_tools.in_process import RunRecord, build_run
    from hawt_tools.launcher import package_prefix

    run = build_run(load_graph(find_graph("lqg"), arguments, package_prefix))
    record = RunRecord()
    for _ in range(steps):
        run.step(record)
    return run, record


def _one_p(record, last):
    from hawt_controllers.mbc import mbc_forward_sample

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
    assert "rank 14 of 14" in out and "rank 12 of 12" in out and "FB-FF (LQG)" in out
    assert plot.stat().st_size > 10_000
