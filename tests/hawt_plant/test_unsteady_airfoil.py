"""Specification of hawt_plant.unsteady_airfoil: the Hansen-Gaunaa-Madsen dynamic stall model, alone and in the
turbine model (ModelConfig.unsteady_airfoil)."""
import dataclasses
import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.special import hankel2

from hawt_plant.airfoil_table import ElementPolars
from hawt_plant.model import ModelConfig, TurbineModel, TurbineOutput
from hawt_plant.shear_wind import PowerLawWind
from hawt_plant.turbine import AirfoilPolar, UnsteadyAirfoilParameters
from hawt_plant.turbulence import TurbulenceSpec, generate_turbulence
from hawt_plant.unsteady_airfoil import UnsteadyAirfoil, separation_function, zero_lift_angle

SLOPE, ALPHA0 = 2.0 * math.pi, math.radians(-2.0)
CHORD, SPEED = 2.0, 40.0  # T_u = c / (2 V) = 25 ms
JONES = {"a1": 0.165, "a2": 0.335, "b1": 0.0455, "b2": 0.3}
"""Jones's two-term fit of Wagner's function (Hansen et al. 2004's constants)."""


def linear_airfoil(**lags) -> AirfoilPolar:
    """A thin-airfoil polar, cl = 2 pi (α - α0), up to 12° from α0, and flat beyond: attached flow below stall;
    ``lags`` the unsteady parameters beyond α0, cl_α, cd0 (default AeroDyn's)."""
    alpha = np.radians(np.linspace(-180.0, 180.0, 721))
    cl = SLOPE * np.clip(alpha - ALPHA0, -math.radians(12.0), math.radians(12.0))
    cl[np.abs(alpha) > math.radians(90.0)] = 0.0
    return AirfoilPolar(name="linear", alpha=alpha, cl=cl, cd=np.full(alpha.size, 0.01), cm=np.zeros(alpha.size),
                        unsteady=UnsteadyAirfoilParameters(alpha0=ALPHA0, lift_slope=SLOPE, cd0=0.01, **lags))


def one_element(airfoils, name, chord=CHORD):
    """The model of one element (B = N = 1) of airfoil ``name`` and its static polars."""
    polars = ElementPolars(airfoils, [name])
    return UnsteadyAirfoil(polars, airfoils, [name], np.array([chord]), 1), polars


def run(model, alpha, dt, speed=SPEED, pitching_rate=None):
    """Lift (circulatory + added mass), circulatory lift and drag for the angle-of-attack history ``alpha`` (and the
    section's pitching rate, default 0)."""
    rate = np.zeros(alpha.size) if pitching_rate is None else pitching_rate
    model.settle(np.array([[alpha[0]]]))
    rows = [model.step(np.array([[a]]), np.array([[speed]]), dt, pitching_rate=w) for a, w in zip(alpha[1:], rate[1:])]
    circulatory, added_mass, cd = (np.array([row[k][0, 0] for row in rows]) for k in range(3))
    return circulatory + added_mass, circulatory, cd


def complex_amplitude(signal, omega, t):
    """The complex amplitude X of the harmonic X exp(i omega t) in ``signal`` (least squares with a mean)."""
    basis = np.column_stack((np.ones_like(t), np.cos(omega * t), np.sin(omega * t)))
    _, c, s = np.linalg.lstsq(basis, signal, rcond=None)[0]
    return c - 1j * s


NODES = 19  # the NREL 5 MW's AeroDyn nodes


@pytest.fixture(scope="module")
def rotor(turbine):
    """The NREL 5 MW blade's unsteady airfoil model for three blades, and its static polars."""
    aero = turbine.blade_aerodynamics
    polars = ElementPolars(turbine.airfoils, aero.airfoil)
    return UnsteadyAirfoil(polars, turbine.airfoils, aero.airfoil, aero.chord, 3), polars


# ------------------------------------------------------------------ the static polar in steady flow


def test_a_settled_element_returns_the_static_polar_bit_for_bit(rotor):
    """Constant angle of attack and speed from a settled start: every step gives the static cl, cd exactly."""
    model, polars = rotor
    alpha = np.radians(np.random.default_rng(1).uniform(-30.0, 40.0, (3, NODES)))
    cl, cd = model.settle(alpha)
    np.testing.assert_array_equal(cl, polars.coefficients(alpha)[0])
    speed = np.full((3, NODES), 30.0)
    for _ in range(50):
        circulatory, added_mass, cd_step = model.step(alpha, speed, 0.01)
        np.testing.assert_array_equal(circulatory + added_mass, cl)
        np.testing.assert_array_equal(cd_step, cd)


def test_after_a_change_the_states_settle_on_the_static_polar(rotor):
    """From one angle of attack to another, held: the coefficients converge on the static polar at the new one."""
    model, polars = rotor
    alpha = np.radians(np.random.default_rng(2).uniform(-20.0, 30.0, (3, NODES)))
    model.settle(alpha + math.radians(5.0))
    speed = np.full((3, NODES), 40.0)
    for _ in range(3000):  # 30 s: over 23 times the slowest lag T_u / b1 (root chord 4.65 m)
        circulatory, added_mass, cd = model.step(alpha, speed, 0.01)
    cl_static, cd_static = polars.coefficients(alpha)
    np.testing.assert_allclose(circulatory + added_mass, cl_static, atol=1e-9)
    np.testing.assert_allclose(cd, cd_static, atol=1e-9)


def test_elements_without_unsteady_parameters_stay_quasi_steady(rotor, turbine):
    """The cylinders (no unsteady section in their polar files) follow the static polar at every step."""
    model, polars = rotor
    cylinders = [k for k, name in enumerate(turbine.blade_aerodynamics.airfoil)
                 if turbine.airfoils[name].unsteady is None]
    assert cylinders == [0, 1, 2, 3]
    rng = np.random.default_rng(3)
    model.settle(np.zeros((3, NODES)))
    for _ in range(20):
        alpha = rng.uniform(-1.0, 1.0, (3, NODES))
        circulatory, added_mass, cd = model.step(alpha, rng.uniform(5.0, 20.0, (3, NODES)), 0.01)
        cl_static, cd_static = polars.coefficients(alpha)
        np.testing.assert_array_equal((circulatory + added_mass)[:, cylinders], cl_static[:, cylinders])
        np.testing.assert_array_equal(cd[:, cylinders], cd_static[:, cylinders])


def test_a_step_not_kept_leaves_the_states_as_they_were(rotor):
    """Trial steps (advance=False, the model's induction iterations before the last) change no state: after them,
    a kept step gives what it gives alone, and so does the step after it."""
    model, _ = rotor
    rng = np.random.default_rng(4)
    start = rng.uniform(-0.2, 0.4, (3, NODES))
    inputs = [(start + rng.uniform(-0.05, 0.05, (3, NODES)), rng.uniform(10.0, 80.0, (3, NODES))) for _ in range(2)]
    results = []
    for trials in (0, 3):
        model.settle(start)
        for _ in range(trials):
            model.step(inputs[0][0] + 0.1, inputs[0][1], 0.01, advance=False)
        results.append([model.step(alpha, speed, 0.01) for alpha, speed in inputs])
    for kept, after_trials in zip(*results):
        for a, b in zip(kept, after_trials):
            np.testing.assert_array_equal(a, b)


def test_separation_function_is_kirchhoffs_inverted_and_rebuilds_the_static_lift():
    """f_st = (2 sqrt(cl / (cl_α (α - α0))) - 1)^2 in [0, 1], and attached f_st + separated (1 - f_st) = cl."""
    alpha = np.radians(np.linspace(-40.0, 40.0, 801))
    f_true = np.clip(1.0 - np.abs(alpha) / math.radians(30.0), 0.0, 1.0)
    cl = SLOPE * alpha * ((1.0 + np.sqrt(f_true)) / 2.0) ** 2  # Kirchhoff's flat plate, α0 = 0
    f_st, attached, separated = separation_function(alpha, cl, 0.0, SLOPE)
    np.testing.assert_allclose(f_st, np.where(f_true > 1.0 - 1e-6, 1.0, f_true), atol=1e-9)
    np.testing.assert_allclose(attached * f_st + separated * (1.0 - f_st), cl, atol=1e-12)
    np.testing.assert_allclose(separated[f_st == 1.0], cl[f_st == 1.0] / 2.0)


def test_the_zero_lift_angle_is_the_polars_nearest_the_files(turbine):
    """α0 is where the static lift crosses zero, nearest the polar file's "zero Cn angle" (DU21: -4.12° for -5.06°)."""
    polar = turbine.airfoils["DU21_A17"]
    alpha0 = zero_lift_angle(polar, polar.unsteady.alpha0)
    assert math.degrees(alpha0) == pytest.approx(-4.125, abs=0.01)
    assert np.interp(alpha0, polar.alpha, polar.cl) == pytest.approx(0.0, abs=1e-12)


# ------------------------------------------------------------------ attached flow: the indicial and frequency responses


@pytest.mark.parametrize("lags", [{}, JONES], ids=["aerodyn-defaults", "jones"])
def test_a_step_in_attached_flow_follows_the_indicial_function(lags):
    """After a step Δα the circulatory lift is cl_α (α_1 - α0 - Δα (A1 exp(-b1 s) + A2 exp(-b2 s))), s = 2 V t / c,
    with the airfoil's A1, A2, b1, b2 (AeroDyn's defaults, or Jones's): exactly as the model sees the step (linear
    over one step), and within 1 % of Δcl as the step shrinks."""
    p = linear_airfoil(**lags)
    A1, A2, B1, B2 = p.unsteady.a1, p.unsteady.a2, p.unsteady.b1, p.unsteady.b2
    model, _ = one_element({"linear": p}, "linear")
    dt, start, end = 0.001, math.radians(2.0), math.radians(4.0)
    alpha = np.concatenate(([start], np.full(400, end)))
    _, circulatory, _ = run(model, alpha, dt)
    t = dt * np.arange(1, alpha.size)
    s = 2.0 * SPEED * t / CHORD
    rates = np.array([B1, B2]) * 2.0 * SPEED / CHORD
    ramp = (np.expm1(rates * dt) / (rates * dt))[:, None] * np.exp(-np.outer(rates, t))  # the step over one dt
    exact = SLOPE * (end - ALPHA0 - (end - start) * (A1 * ramp[0] + A2 * ramp[1]))
    np.testing.assert_allclose(circulatory, exact, rtol=1e-12)
    indicial = SLOPE * (end - ALPHA0 - (end - start) * (A1 * np.exp(-B1 * s) + A2 * np.exp(-B2 * s)))
    assert np.max(np.abs(circulatory - indicial)) < 0.01 * SLOPE * (end - start)
    assert s[-1] > 12.0 and circulatory[-1] == pytest.approx(SLOPE * (end - ALPHA0), rel=0.05)


def test_the_added_mass_follows_the_sections_rotation_not_the_inflow():
    """A step of α from the inflow (ω = 0: a gust, the tower's shadow) gives no added-mass lift (AeroDyn's UA_Mod 4);
    a section turning nose-up at ω gives π T_u ω = π (c / 2) ω / V while it turns."""
    model, _ = one_element({"linear": linear_airfoil()}, "linear")
    dt, delta, omega = 0.001, math.radians(2.0), 0.5
    cl, circulatory, _ = run(model, np.array([0.0, delta, delta, delta]), dt)
    np.testing.assert_array_equal(cl - circulatory, 0.0)
    cl, circulatory, _ = run(model, np.full(4, delta), dt, pitching_rate=np.array([0.0, omega, omega, 0.0]))
    tu_omega = CHORD / 2.0 * omega / SPEED
    np.testing.assert_allclose(cl - circulatory, [math.pi * tu_omega, math.pi * tu_omega, 0.0], atol=1e-15)


@pytest.mark.parametrize("k", [0.05, 0.1, 0.3])
def test_pitching_in_attached_flow_has_the_frequency_response_of_the_state_space_model(k):
    """α = α_m + â sin(ω t) by turning the section (ω = α') at reduced frequency k = ω c / (2 V): the lift's complex
    amplitude is cl_α â C_J(k) (1 + i k) + i π k â, C_J(k) = 1 - A1 i k / (i k + b1) - A2 i k / (i k + b2) (the
    model's continuous response to the three-quarter-chord angle α_34 = α + T_u α'), within 0.5 % in amplitude and
    0.3° in phase; with Jones's constants C_J is Theodorsen's C(k) within 0.02, the known error of his fit."""
    p = linear_airfoil(**JONES)
    A1, A2, B1, B2 = p.unsteady.a1, p.unsteady.a2, p.unsteady.b1, p.unsteady.b2
    model, _ = one_element({"linear": p}, "linear")
    dt, amplitude = 0.001, math.radians(2.0)
    omega = k * 2.0 * SPEED / CHORD
    t = dt * np.arange(round(12 * 2 * math.pi / omega / dt) + 1)
    alpha = math.radians(3.0) + amplitude * np.sin(omega * t)
    cl, circulatory, _ = run(model, alpha, dt, pitching_rate=amplitude * omega * np.cos(omega * t))
    last = t[1:] > t[-1] - 4 * 2 * math.pi / omega  # four periods after eight
    jones = 1.0 - A1 * 1j * k / (1j * k + B1) - A2 * 1j * k / (1j * k + B2)
    expected = (SLOPE * jones * (1.0 + 1j * k) + 1j * math.pi * k) * amplitude * -1j  # sin = Re(-i exp(i ω t))
    found = complex_amplitude(cl[last], omega, t[1:][last])
    assert abs(found) == pytest.approx(abs(expected), rel=0.005)
    assert math.degrees(np.angle(found / expected)) == pytest.approx(0.0, abs=0.3)
    circulation = complex_amplitude(circulatory[last], omega, t[1:][last]) / (SLOPE * amplitude * (1 + 1j * k) * -1j)
    theodorsen = hankel2(1, k) / (hankel2(1, k) + 1j * hankel2(0, k))
    assert abs(circulation - theodorsen) < 0.02


# ------------------------------------------------------------------ dynamic stall


def test_pitching_through_stall_overshoots_the_static_maximum_in_a_hysteresis_loop(turbine):
    """NACA64_A17 pitching 12° ± 8° at k = 0.1 (c = 2 m, V = 40 m/s): the lift peaks over 10 % above the
    static maximum, and at 16° it is higher on the upstroke than on the downstroke (the loop)."""
    model, polars = one_element(turbine.airfoils, "NACA64_A17")
    dt, k = 0.01, 0.1
    omega = k * 2.0 * SPEED / CHORD
    t = dt * np.arange(2001)
    alpha = math.radians(12.0) + math.radians(8.0) * np.sin(omega * t)
    cl, _, _ = run(model, alpha, dt)
    static_max = polars.coefficients(np.radians(np.linspace(0.0, 30.0, 3001))[:, None])[0].max()
    last = t[1:] > t[-1] - 2 * 2 * math.pi / omega
    assert cl[last].max() > 1.10 * static_max
    rising = np.gradient(alpha[1:]) > 0.0
    near = np.abs(alpha[1:] - math.radians(16.0)) < math.radians(0.3)
    assert cl[last & near & rising].mean() - cl[last & near & ~rising].mean() > 0.2


# ------------------------------------------------------------------ in the turbine model


def simulate(model, steps):
    """Hold the initial commands for ``steps`` steps; outputs stacked per field."""
    first = model.output
    outputs = [model.step(first.pitch.copy(), first.generator_torque) for _ in range(steps)]
    return {f.name: np.array([getattr(o, f.name) for o in outputs]) for f in dataclasses.fields(TurbineOutput)}


def test_the_option_is_off_by_default_and_off_builds_no_dynamic_stall(turbine):
    """ModelConfig() has no unsteady airfoil; the default and the explicit False give bit-identical runs."""
    assert ModelConfig().unsteady_airfoil is False
    runs = [simulate(TurbineModel(turbine, PowerLawWind(11.4, shear_exponent=0.2), config), 200)
            for config in (ModelConfig(), ModelConfig(unsteady_airfoil=False))]
    for name, values in runs[0].items():
        np.testing.assert_array_equal(values, runs[1][name], err_msg=name)


def test_in_axisymmetric_steady_flow_the_unsteady_model_stays_at_the_steady_values(turbine):
    """Uniform wind along the shaft, no tilt, cone, shadow or gravity (which swings the blades edgewise once a
    revolution): with dynamic stall the run stays at the quasi-steady model's values (no drift over 20 s)."""
    axisymmetric = replace(turbine, rotor=replace(turbine.rotor, shaft_tilt=0.0, cone_angle=0.0),
                           environment=replace(turbine.environment, gravity=0.0))
    runs = [simulate(TurbineModel(axisymmetric, PowerLawWind(18.0, shear_exponent=0.0),
                                  ModelConfig(tower_shadow=False, unsteady_airfoil=on)), 2000) for on in (False, True)]
    for name in ("root_moment_oop", "aero_torque", "rotor_thrust", "rotor_speed", "tower_top_fa_disp"):
        scale = np.max(np.abs(runs[0][name]))
        np.testing.assert_allclose(runs[1][name], runs[0][name], atol=1e-6 * scale, err_msg=name)


def test_in_steady_sheared_wind_the_unsteady_model_stays_near_the_quasi_steady_one(turbine):
    """NREL 5 MW (tilt, cone, tower shadow) in steady sheared wind at 18 m/s, commands held: over each of five
    revolutions dynamic stall changes the mean blade-root moment and aerodynamic torque by under 0.5 % and the
    rotor speed by under 0.1 %, and it adds no drift to these means (the tower passage's dip itself differs): from
    the second revolution to the fifth they move as the quasi-steady model's settle (its aerodynamic torque by 0.11 %),
    within 0.1 %."""
    runs = [simulate(TurbineModel(turbine, PowerLawWind(18.0, shear_exponent=0.2),
                                  ModelConfig(unsteady_airfoil=on)), 3000) for on in (False, True)]
    revolution = round(2.0 * math.pi / runs[0]["rotor_speed"][0] / 0.01)
    means = [{name: run[name][: 5 * revolution].reshape(5, revolution, -1).mean(axis=(1, 2))
              for name in ("root_moment_oop", "aero_torque", "rotor_speed")} for run in runs]
    for name, quasi_steady in means[0].items():
        tolerance = 1e-3 if name == "rotor_speed" else 5e-3
        np.testing.assert_allclose(means[1][name], quasi_steady, rtol=tolerance, err_msg=name)
        drift = [run_means[name][-1] - run_means[name][1] for run_means in means]
        assert abs(drift[1] - drift[0]) < 1e-3 * abs(quasi_steady[1]), name


def test_a_turbulent_run_with_dynamic_stall_stays_finite_and_close_to_quasi_steady(turbine):
    """20 s of IEC turbulence at 18 m/s: every output finite, the root moment's standard deviation within 25 % of
    the quasi-steady model's."""
    wind = generate_turbulence(TurbulenceSpec(mean_speed=18.0, turbulence_class="B", n_y=5, n_z=5, duration=20.0))
    runs = [simulate(TurbineModel(turbine, wind, ModelConfig(unsteady_airfoil=on)), 2000) for on in (False, True)]
    for name, values in runs[1].items():
        assert np.all(np.isfinite(values)), name
    std = [run["root_moment_oop"].std() for run in runs]
    assert std[1] == pytest.approx(std[0], rel=0.25)
