"""Specification of hawt_controllers.laws.mbc3: Bir's (2008) multi-blade coordinate transformation of a periodic
linear model and its azimuth average.

The transformation is built here independently from its definition for B = 3 and 4 (blade i at
ψ_i = ψ + 2πi/B, q_i = q_0 + q_c cos ψ_i + q_s sin ψ_i (+ q_d (−1)^i), Bir's T = [[t, 0], [Ω t', t]] for a
displacement/rate pair); the isotropic rotor checks the known answer of the physics (the cyclic modes
whirl at ω ± Ω), and the output transform is checked against the signal transform of hawt_core.rotor.mbc.
"""
import doctest
import math

import numpy as np
import pytest

import hawt_controllers.laws.mbc3 as mbc3_module
from hawt_core.rotor.mbc import mbc_forward_sample
from hawt_controllers.laws.mbc3 import BladeGroups, LinearModel, azimuth_average, coleman_coordinates, mbc3

OMEGA = 12.1 * math.pi / 30  # rotor speed [rad/s]
AZIMUTHS = [0.0, 0.3, 1.1, 2.0 * math.pi / 3, 2.9, 4.4, 5.9]


def _t(psi, n_blades):
    """t(ψ), t' = dt/dψ, t'' for B = 3, 4: rows [1, cos ψ_i, sin ψ_i (, (−1)^i)]."""
    p = psi + 2.0 * np.pi * np.arange(n_blades) / n_blades
    one, zero = np.ones(n_blades), np.zeros(n_blades)
    t = [one, np.cos(p), np.sin(p)]
    t1 = [zero, -np.sin(p), np.cos(p)]
    t2 = [zero, -np.cos(p), -np.sin(p)]
    if n_blades == 4:
        t, t1, t2 = t + [(-1.0) ** np.arange(4)], t1 + [zero], t2 + [zero]
    return np.column_stack(t), np.column_stack(t1), np.column_stack(t2)


def _blade_names(base, n_blades):
    return [f"{base}_{i + 1}" for i in range(n_blades)]


def _rotor(n_blades):
    """A turbine-like layout: states (tower, flap_1..B, flap_rate_1..B, inflow_1..B, speed), inputs (pitch_1..B,
    torque), outputs interleaved (oop_1, ip_1, oop_2, ip_2, …, speed_out)."""
    b = n_blades
    flap, rate, inflow = tuple(range(1, 1 + b)), tuple(range(1 + b, 1 + 2 * b)), tuple(range(1 + 2 * b, 1 + 3 * b))
    states = ("tower", *_blade_names("flap", b), *_blade_names("flap_rate", b), *_blade_names("inflow", b), "speed")
    inputs = (*_blade_names("pitch", b), "torque")
    outputs = tuple(name for i in range(b) for name in (f"oop_{i + 1}", f"ip_{i + 1}")) + ("speed_out",)
    groups = BladeGroups(states=(flap, rate, inflow), rates=((1, 0),), inputs=(tuple(range(b)),),
                         outputs=(tuple(range(0, 2 * b, 2)), tuple(range(1, 2 * b, 2))))
    return states, inputs, outputs, groups


def _transforms(psi, n_blades, omega, groups, sizes):
    """T, Ṫ, T_u, T_y of the rotor layout, written out from the definition."""
    t, t1, t2 = _t(psi, n_blades)
    n, m, p = sizes
    flap, rate, inflow = groups.states
    big_t, big_t_dot = np.eye(n), np.zeros((n, n))
    for group in (flap, rate, inflow):
        big_t[np.ix_(group, group)] = t
        big_t_dot[np.ix_(group, group)] = omega * t1
    big_t[np.ix_(rate, flap)] = omega * t1
    big_t_dot[np.ix_(rate, flap)] = omega * omega * t2
    t_u = np.eye(m)
    t_u[np.ix_(groups.inputs[0], groups.inputs[0])] = t
    t_y = np.eye(p)
    for group in groups.outputs:
        t_y[np.ix_(group, group)] = t
    return big_t, big_t_dot, t_u, t_y


def _coleman_names(names, groups, n_blades):
    suffixes = ("collective", "cos", "sin", "diff")[:n_blades]
    renamed = list(names)
    for group in groups:
        base = names[group[0]][:-2]
        for position, suffix in zip(group, suffixes):
            renamed[position] = f"{base}_{suffix}"
    return tuple(renamed)


@pytest.mark.parametrize("n_blades", [3, 4])
def test_mbc3_of_the_rotating_model_of_a_constant_coleman_model_is_that_model_at_every_azimuth(n_blades):
    """Round trip: A(ψ) = (T A_c + Ṫ) T⁻¹, B(ψ) = T B_c T_u⁻¹, C(ψ) = T_y C_c T⁻¹, D = T_y D_c T_u⁻¹ is periodic in
    ψ, and mbc3 gives back A_c, B_c, C_c, D_c with the Coleman names at every azimuth; so does their average."""
    states, inputs, outputs, groups = _rotor(n_blades)
    n, m, p = len(states), len(inputs), len(outputs)
    rng = np.random.default_rng(7)
    a_c, b_c = rng.normal(size=(n, n)), rng.normal(size=(n, m))
    c_c, d_c = rng.normal(size=(p, n)), rng.normal(size=(p, m))
    transformed = []
    for psi in AZIMUTHS:
        t, t_dot, t_u, t_y = _transforms(psi, n_blades, OMEGA, groups, (n, m, p))
        rotating = LinearModel((t @ a_c + t_dot) @ np.linalg.inv(t), t @ b_c @ np.linalg.inv(t_u),
                               t_y @ c_c @ np.linalg.inv(t), t_y @ d_c @ np.linalg.inv(t_u), states, inputs, outputs)
        coleman = mbc3(rotating, psi, OMEGA, groups)
        for name, expected in zip("abcd", (a_c, b_c, c_c, d_c)):
            np.testing.assert_allclose(getattr(coleman, name), expected, atol=1e-10, err_msg=f"{name} at ψ={psi}")
        transformed.append(coleman)
    assert transformed[0].states == _coleman_names(states, groups.states, n_blades)
    assert transformed[0].inputs == _coleman_names(inputs, groups.inputs, n_blades)
    assert transformed[0].outputs[:6] == ("oop_collective", "ip_collective", "oop_cos", "ip_cos", "oop_sin", "ip_sin")
    assert transformed[0].states[1:4] == ("flap_collective", "flap_cos", "flap_sin")
    assert transformed[0].states[0] == "tower" and transformed[0].inputs[-1] == "torque"
    average = azimuth_average(transformed)
    np.testing.assert_allclose(average.a, a_c, atol=1e-10)
    np.testing.assert_allclose(average.d, d_c, atol=1e-10)
    assert not np.allclose(rotating.a, a_c)  # the rotating-frame model differs: the check is not vacuous


def _isotropic_rotor(n_blades, omega_b, zeta):
    """B identical uncoupled blades q̈_i = −ω² q_i − 2ζω q̇_i + u_i; states (q_1..B, qdot_1..B), outputs q."""
    eye, zero = np.eye(n_blades), np.zeros((n_blades, n_blades))
    a = np.block([[zero, eye], [-omega_b ** 2 * eye, -2.0 * zeta * omega_b * eye]])
    model = LinearModel(a, np.vstack([zero, eye]), np.hstack([eye, zero]), zero,
                        (*_blade_names("q", n_blades), *_blade_names("qdot", n_blades)),
                        _blade_names("u", n_blades), _blade_names("y", n_blades))
    blades = tuple(range(n_blades))
    groups = BladeGroups(states=(blades, tuple(range(n_blades, 2 * n_blades))), rates=((1, 0),),
                         inputs=(blades,), outputs=(blades,))
    return model, groups


def test_isotropic_three_bladed_rotor_has_the_textbook_coleman_equations():
    """Substituting q_i = q_0 + q_c cos ψ_i + q_s sin ψ_i into q̈_i = −ω² q_i − 2ζω q̇_i + u_i (Ω constant):

        q̈_c = −(ω² − Ω²) q_c − 2ζωΩ q_s − 2ζω q̇_c − 2Ω q̇_s + u_c
        q̈_s = 2ζωΩ q_c − (ω² − Ω²) q_s + 2Ω q̇_c − 2ζω q̇_s + u_s,

    the collective as one blade; inputs and outputs map one-to-one. The same at every azimuth."""
    w, zeta = 2.0 * math.pi * 0.7, 0.05
    model, groups = _isotropic_rotor(3, w, zeta)
    stiffness = np.array([[-w * w, 0, 0],
                          [0, -(w * w - OMEGA ** 2), -2 * zeta * w * OMEGA],
                          [0, 2 * zeta * w * OMEGA, -(w * w - OMEGA ** 2)]])
    damping = np.array([[-2 * zeta * w, 0, 0], [0, -2 * zeta * w, -2 * OMEGA], [0, 2 * OMEGA, -2 * zeta * w]])
    expected = np.block([[np.zeros((3, 3)), np.eye(3)], [stiffness, damping]])
    for psi in AZIMUTHS:
        coleman = mbc3(model, psi, OMEGA, groups)
        np.testing.assert_allclose(coleman.a, expected, atol=1e-12)
        np.testing.assert_allclose(coleman.b, np.vstack([np.zeros((3, 3)), np.eye(3)]), atol=1e-12)
        np.testing.assert_allclose(coleman.c, np.hstack([np.eye(3), np.zeros((3, 3))]), atol=1e-12)
    assert coleman.states == ("q_collective", "q_cos", "q_sin", "qdot_collective", "qdot_cos", "qdot_sin")
    assert coleman.inputs == ("u_collective", "u_cos", "u_sin")


@pytest.mark.parametrize("n_blades, harmonics", [(3, [1]), (4, [1]), (5, [1, 2])])
def test_isotropic_rotor_whirling_modes_split_by_the_rotor_speed(n_blades, harmonics):
    """Undamped (ζ = 0): the collective (and for even B the differential) mode stays at ±ω, the cyclic pair of
    harmonic n splits to ±(ω + nΩ) and ±(ω − nΩ) — the progressive and regressive whirl."""
    w = 2.0 * math.pi * 0.7
    model, groups = _isotropic_rotor(n_blades, w, 0.0)
    frequencies = [w] * (n_blades - 2 * len(harmonics)) + [w + sign * n * OMEGA for n in harmonics for sign in (1, -1)]
    expected = np.sort([sign * f for f in frequencies for sign in (1, -1)])
    for psi in AZIMUTHS:
        eigenvalues = np.linalg.eigvals(mbc3(model, psi, OMEGA, groups).a)
        np.testing.assert_allclose(eigenvalues.real, 0.0, atol=1e-9)
        np.testing.assert_allclose(np.sort(eigenvalues.imag), expected, atol=1e-9)


def test_damped_isotropic_rotor_cyclic_eigenvalues_are_the_blade_eigenvalues_shifted_by_j_omega():
    """With damping the cyclic eigenvalues are λ ± jΩ, λ = −ζω ± jω√(1 − ζ²) the blade's; modes() reports
    the collective at (ω/2π, ζ) and the whirling modes at |λ ± jΩ|/2π with damping ζω/|λ ± jΩ|."""
    w, zeta = 2.0 * math.pi * 0.7, 0.08
    model, groups = _isotropic_rotor(3, w, zeta)
    coleman = mbc3(model, 0.8, OMEGA, groups)
    blade = complex(-zeta * w, w * math.sqrt(1 - zeta * zeta))
    expected = [blade, blade.conjugate(), blade + 1j * OMEGA, blade.conjugate() - 1j * OMEGA,
                blade - 1j * OMEGA, blade.conjugate() + 1j * OMEGA]
    eigenvalues = np.linalg.eigvals(coleman.a)
    by_frequency = np.argsort(eigenvalues.imag)
    np.testing.assert_allclose(eigenvalues[by_frequency], sorted(expected, key=lambda e: e.imag), atol=1e-9)
    whirl = [abs(blade - 1j * OMEGA), abs(blade), abs(blade + 1j * OMEGA)]
    np.testing.assert_allclose(coleman.modes(), [[r / (2 * math.pi), zeta * w / r] for r in whirl], rtol=1e-9)
    np.testing.assert_allclose(coleman.modes()[1], [w / (2 * math.pi), zeta], rtol=1e-9)


def test_modes_of_real_eigenvalues_report_the_corner_frequency_and_unit_damping():
    """A real eigenvalue λ is reported as (|λ|/2π, −sign λ), zero as (0, 0); rows sorted by frequency."""
    model = LinearModel(np.diag([-3.0, 2.0, 0.0]), np.zeros((3, 0)), np.zeros((0, 3)), np.zeros((0, 0)),
                        ("lag", "unstable", "integrator"), (), ())
    np.testing.assert_allclose(model.modes(), [[0.0, 0.0], [2 / (2 * math.pi), -1.0], [3 / (2 * math.pi), 1.0]])


@pytest.mark.parametrize("n_blades", [3, 4])
def test_coleman_outputs_of_a_blade_moment_group_are_the_forward_transform_of_the_signals(n_blades):
    """For any state x and input u at ψ: ŷ = C_c z + D_c û with x = T z, u = T_u û gives, on the moment group,
    the mean, cos and sin of hawt_core.rotor.mbc.mbc_forward_sample(y_blades, ψ, 1), y = C(ψ) x + D(ψ) u."""
    states, inputs, outputs, groups = _rotor(n_blades)
    n, m, p = len(states), len(inputs), len(outputs)
    rng = np.random.default_rng(3)
    for psi in AZIMUTHS:
        model = LinearModel(rng.normal(size=(n, n)), rng.normal(size=(n, m)), rng.normal(size=(p, n)),
                            rng.normal(size=(p, m)), states, inputs, outputs)
        x, u = rng.normal(size=n), rng.normal(size=m)
        t, _, t_u, _ = _transforms(psi, n_blades, OMEGA, groups, (n, m, p))
        coleman = mbc3(model, psi, OMEGA, groups)
        y_hat = dict(zip(coleman.outputs, coleman.c @ np.linalg.solve(t, x) + coleman.d @ np.linalg.solve(t_u, u)))
        y = model.c @ x + model.d @ u
        expected = mbc_forward_sample(y[list(groups.outputs[0])], psi, 1)
        actual = (y_hat["oop_collective"], y_hat["oop_cos"], y_hat["oop_sin"])
        np.testing.assert_allclose(actual, tuple(expected), rtol=1e-10, atol=1e-12)
        assert y_hat["speed_out"] == pytest.approx(y[-1], rel=1e-10, abs=1e-12)


@pytest.mark.parametrize("n_blades", [5, 6])
def test_higher_harmonic_coordinates_are_the_forward_transform_of_their_harmonic(n_blades):
    """B >= 5 carries cos_n, sin_n for n up to (B − 1)/2 (named cos2, sin2, …); even B also the alternating part
    (1/B) Σ (−1)^i y_i (named diff), so the B coordinates describe every blade pattern."""
    rng = np.random.default_rng(5)
    names = _blade_names("moment", n_blades)
    model = LinearModel(-np.eye(1), np.zeros((1, 0)), rng.normal(size=(n_blades, 1)), np.zeros((n_blades, 0)),
                        ("tower",), (), names)
    psi, x = 1.3, np.array([0.7])
    coleman = mbc3(model, psi, OMEGA, BladeGroups(outputs=(tuple(range(n_blades)),)))
    y_hat = dict(zip(coleman.outputs, coleman.c @ x))
    y = model.c @ x
    for n, suffix in ((1, ""), (2, "2")):
        components = mbc_forward_sample(y, psi, n)
        assert y_hat["moment_collective"] == pytest.approx(components.mean, abs=1e-12)
        assert y_hat[f"moment_cos{suffix}"] == pytest.approx(components.cos, abs=1e-12)
        assert y_hat[f"moment_sin{suffix}"] == pytest.approx(components.sin, abs=1e-12)
    if n_blades == 6:
        assert y_hat["moment_diff"] == pytest.approx(np.mean(y * (-1.0) ** np.arange(6)), abs=1e-12)
    assert len(coleman.outputs) == n_blades and coleman.outputs == tuple(f"moment_{s}" for s in
                                                                         coleman_coordinates(n_blades))


def test_coleman_names_are_the_common_part_of_the_blade_names_plus_the_coordinate():
    """flap_1.. → flap_*, b1_edge.. → b_edge_*; B = 4 adds diff, B = 6 cos2, sin2 and diff."""
    assert coleman_coordinates(4) == ("collective", "cos", "sin", "diff")
    assert coleman_coordinates(6) == ("collective", "cos", "sin", "cos2", "sin2", "diff")
    names = ("b1_edge", "b2_edge", "b3_edge", "b4_edge")
    model = LinearModel(np.zeros((0, 0)), np.zeros((0, 4)), np.zeros((0, 0)), np.zeros((0, 4)), (), names, ())
    coleman = mbc3(model, 0.0, OMEGA, BladeGroups(inputs=((0, 1, 2, 3),)))
    assert coleman.inputs == ("b_edge_collective", "b_edge_cos", "b_edge_sin", "b_edge_diff")


def _three_blade_model(states=("flap_1", "flap_2", "flap_3")):
    return LinearModel(-np.eye(3), np.zeros((3, 0)), np.zeros((0, 3)), np.zeros((0, 0)), states, (), ())


@pytest.mark.parametrize("groups, message", [
    (dict(states=((0, 1),)), r"B >= 3 blades, found groups of 2"),
    (dict(states=((0, 1, 2),), inputs=((0, 1),)), r"inputs\[0\]: expected B=3 indices \(the length of states\[0\]\)"),
    (dict(), r"no blade group"),
    (dict(states=((0, 1, 2), (2, 3, 4))), r"states\[1\]: index 2 is already in states\[0\]"),
    (dict(states=((0, 1, -2),)), r"states\[0\]: expected indices >= 0"),
    (dict(states=((0, 1, 2.5),)), r"states\[0\]: expected a tuple of integer indices"),
    (dict(states=((0, 1, 2), (3, 4, 5)), rates=((1, 1),)), r"rates\[0\]: expected \(rate group, displacement group\)"),
    (dict(states=((0, 1, 2), (3, 4, 5)), rates=((1, 2),)), r"rates\[0\]: .*below 2"),
    (dict(states=((0, 1, 2), (3, 4, 5), (6, 7, 8)), rates=((1, 0), (2, 1))), r"rates\[1\]: state group 1 is already"),
])
def test_bad_blade_groups_are_refused_naming_the_group(groups, message):
    with pytest.raises(ValueError, match=message):
        BladeGroups(**groups)


def test_mbc3_refuses_groups_outside_the_model_and_names_with_nothing_in_common():
    with pytest.raises(ValueError, match=r"groups.states\[0\]: index 3 out of range for a model of 3 states"):
        mbc3(_three_blade_model(), 0.0, OMEGA, BladeGroups(states=((1, 2, 3),)))
    with pytest.raises(ValueError, match=r"groups.states\[0\]: the names \['x', 'y', 'z'\] have nothing in common"):
        mbc3(_three_blade_model(("x", "y", "z")), 0.0, OMEGA, BladeGroups(states=((0, 1, 2),)))
    with pytest.raises(ValueError, match=r"rotor_speed: must be finite"):
        mbc3(_three_blade_model(), 0.0, math.nan, BladeGroups(states=((0, 1, 2),)))


@pytest.mark.parametrize("fields, message", [
    (dict(a=np.zeros((3, 2))), r"a: expected shape \(3, 3\) for 3 states, 0 inputs and 0 outputs, found \(3, 2\)"),
    (dict(a=np.full((3, 3), np.nan)), r"a: NaN"),
    (dict(states=("f", "g", "f")), r"states: duplicate names \['f'\]"),
    (dict(states="fgh"), r"states: expected a sequence of names"),
    (dict(inputs=("", )), r"inputs: expected non-empty strings"),
])
def test_bad_linear_models_are_refused_naming_the_field(fields, message):
    arguments = dict(a=-np.eye(3), b=np.zeros((3, 0)), c=np.zeros((0, 3)), d=np.zeros((0, 0)),
                     states=("f", "g", "h"), inputs=(), outputs=())
    if "inputs" in fields:
        arguments.update(b=np.zeros((3, 1)), d=np.zeros((0, 1)))
    arguments.update(fields)
    with pytest.raises(ValueError, match=message):
        LinearModel(**arguments)


def test_azimuth_average_refuses_models_with_different_names_and_no_models():
    with pytest.raises(ValueError, match=r"models\[1\].states: expected the names of models\[0\]"):
        azimuth_average([_three_blade_model(), _three_blade_model(("edge_1", "edge_2", "edge_3"))])
    with pytest.raises(ValueError, match=r"models: need at least one model"):
        azimuth_average([])


def test_azimuth_average_is_the_element_wise_mean():
    """Bir's averaging: (A(ψ_1) + … + A(ψ_k)) / k, and the same for B, C, D."""
    first = _three_blade_model()
    second = LinearModel(np.arange(9.0).reshape(3, 3), first.b, first.c, first.d, first.states, (), ())
    np.testing.assert_allclose(azimuth_average([first, second]).a, (first.a + second.a) / 2)


def test_linear_model_is_immutable_and_converts_to_scipy():
    model = _three_blade_model()
    with pytest.raises(ValueError):
        model.a[0, 0] = 1.0
    assert model.state_space().A.shape == (3, 3)


def test_docstring_examples_hold():
    result = doctest.testmod(mbc3_module)
    assert result.attempted > 0 and result.failed == 0
