"""Spatial repetitive control (Fratini 2019 §4.2, eqs. 4.4, 4.6): the learning memory on a synthetic periodic plant.

The plant moves the measurement at azimuth ψ by k times the output issued at ψ − λ (a blade
whose flap moment lags its pitch by λ) on top of a disturbance periodic in azimuth, as a
sheared rotor gives; the error is e = r − y. The convergence condition of
:func:`convergence_problem` must predict what the simulation does.
"""
import math

import numpy as np
import pytest

from hawt_core.exceptions import ConfigurationError
from hawt_controllers.laws.repetitive import AzimuthMemory, RepetitiveConfig, convergence_problem, learning_factors

K = -40.0e6  # dM/dθ [N·m/rad]
LAG = math.radians(25.0)


def disturbance(psi):
    return 2.0e6 * np.cos(psi) + 0.8e6 * np.sin(2 * psi + 0.3) + 0.3e6 * np.cos(3 * psi - 1.0)


def simulate(config, revolutions=30, speed=1.27, dt=0.01, speed_variation=0.0, lag=LAG):
    """RMS error per revolution, the memory, and the error of the last whole revolution by azimuth."""
    memory = AzimuthMemory(config, 1.0 / K)
    steps = int(revolutions * 2 * math.pi / (speed * (1 - speed_variation)) / dt) + 1
    angles, outputs = np.empty(steps), np.empty(steps)
    psi, error, rms, current, last = 0.0, 0.0, [], [], ([], [])
    for k in range(steps):
        issued_at = psi - lag
        applied = np.interp(issued_at, angles[:k], outputs[:k]) if k and issued_at >= angles[0] else 0.0
        error = -(K * applied + disturbance(psi))
        angles[k], outputs[k] = psi, memory.step(psi, error)
        current.append((psi, error))
        omega = speed * (1 + speed_variation * math.sin(0.37 * k * dt))
        if int((psi + omega * dt) / (2 * math.pi)) > int(psi / (2 * math.pi)):
            last = tuple(zip(*current))
            rms.append(math.sqrt(np.mean(np.square(last[1]))))
            current = []
        psi += omega * dt
    return np.array(rms), memory, np.array(last)


def harmonic(signal, n):
    """Amplitude of harmonic n of the revolution in ``signal`` (rows: azimuths, values)."""
    psi, values = signal
    return abs(2 * np.mean(values * np.exp(-1j * n * psi)))


def test_with_the_shift_at_the_plant_lag_the_error_falls_every_revolution_to_nothing():
    """δ = λ, Q = identity, g = 0.5: each harmonic's factor is 1 − g; the error falls monotonically (AC-19's
    'removes it within a few revolutions') and the memory holds the inverse of the disturbance."""
    config = RepetitiveConfig(learning_gain=0.5, shift=LAG)
    assert convergence_problem(config, LAG) is None
    assert np.allclose(learning_factors(config, LAG), 0.5)
    rms, memory, _ = simulate(config)
    assert np.allclose(rms[2:6] / rms[1:5], 0.5, atol=0.02), rms  # the predicted factor, revolution by revolution
    learning = rms[rms > 2e-3 * rms[0]]  # until the floor of the bins' interpolation
    assert np.all(np.diff(learning) < 0) and rms[-1] < 1e-3 * rms[0]
    psi = np.linspace(0, 2 * np.pi, 72, endpoint=False)
    assert np.allclose(memory.memory, -disturbance(psi + LAG) / K, atol=0.02 * 2.0e6 / 40.0e6)


def test_a_shift_that_misses_the_lag_is_refused_and_does_diverge():
    """δ − λ = 60° with Q = identity: harmonics where n·60° turns the correction round grow; the refusal says
    which, and the simulation's error grows."""
    config = RepetitiveConfig(learning_gain=0.5, shift=LAG + math.radians(60.0))
    problem = convergence_problem(config, LAG)
    assert problem is not None and "diverges at harmonic" in problem
    rms, _, _ = simulate(config, revolutions=40)
    assert rms[-1] > 3 * rms[1]


def test_the_lowpass_q_makes_the_same_shift_converge_and_removes_the_harmonics_it_keeps():
    """The same mis-shift with Q keeping harmonics 0..1: every factor < 1, the error settles; the 1P part of
    the disturbance (the largest) is removed. Above Q's cut, eq. 4.4's unfiltered L·e stays in the memory:
    the error there settles at d_n / (1 + g exp(i n (δ − λ))), here 3P doubled (n (δ − λ) = 180°)."""
    config = RepetitiveConfig(learning_gain=0.5, shift=LAG + math.radians(60.0), q_filter="lowpass",
                              q_harmonics=1)
    assert convergence_problem(config, LAG) is None
    rms, _, last = simulate(config, revolutions=40)
    assert np.ptp(rms[-5:]) < 0.01 * rms[-1]
    assert harmonic(last, 1) < 0.01 * 2.0e6
    assert harmonic(last, 3) == pytest.approx(2 * 0.3e6, rel=0.05)


def test_the_smoother_of_eq_4_6_has_unit_gain_at_0p_and_attenuates_high_harmonics():
    config = RepetitiveConfig(q_filter="smoother", smoothing=0.25, bins=72)
    q = config.q_response()
    assert q[0] == pytest.approx(1.0) and q[-1] == pytest.approx(0.0) and np.all(np.diff(q) <= 0)


@pytest.mark.parametrize("dt, variation", [(0.02, 0.0), (0.005, 0.0), (0.01, 0.1)])
def test_the_memory_is_indexed_by_azimuth_so_dt_and_a_varying_speed_learn_the_same(dt, variation):
    """Azimuth-domain indexing: halving or doubling dt, or a ±10 % speed variation, learns the same memory."""
    config = RepetitiveConfig(learning_gain=0.5, shift=LAG)
    _, reference, _ = simulate(config, revolutions=25)
    _, other, _ = simulate(config, revolutions=25, dt=dt, speed_variation=variation)
    scale = np.max(np.abs(reference.memory))
    assert np.max(np.abs(other.memory - reference.memory)) < 0.03 * scale


def test_memory_is_bounded_in_size_and_value_over_1e5_steps():
    """10⁵ steps of an error far too large for the actuator: the memory stays 72 bins, clipped at its bounds."""
    config = RepetitiveConfig(learning_gain=1.0, shift=0.0, lower=-0.05, upper=0.05)
    memory = AzimuthMemory(config, 1.0 / K)
    for k in range(100_000):
        memory.step(0.013 * k, 1.0e9)
    assert memory.memory.shape == (72,) and len(memory._sums) == 72
    assert np.all(np.abs(memory.memory) <= 0.05) and memory.revolutions > 200


def test_a_frozen_memory_plays_on_and_learns_again_from_what_it_sees_after_it_resumes():
    memory = AzimuthMemory(RepetitiveConfig(learning_gain=0.5), 1.0)
    memory.reset([0.1] * 72)
    memory.freeze(True)
    for k in range(2000):
        assert memory.step(0.01 * k, 5.0) == pytest.approx(0.1)
    memory.freeze(False)
    for k in range(2000, 2000 + 300):  # half a revolution: only the bins passed since the resume learn
        memory.step(0.01 * k, 5.0)
    learnt = np.isclose(memory.memory, 0.1 + 2.5)
    assert 0 < learnt.sum() < 72 and np.allclose(memory.memory[~learnt], 0.1)
    for k in range(2300, 2300 + 340):  # one revolution and a bin after the resume: every bin has learnt once
        memory.step(0.01 * k, 5.0)
    assert np.allclose(memory.memory, 0.1 + 2.5)


@pytest.mark.parametrize("field, config", [
    ("bins", RepetitiveConfig(bins=2)),
    ("learning_gain", RepetitiveConfig(learning_gain=float("nan"))),
    ("q_filter", RepetitiveConfig(q_filter="lowpas")),
    ("q_harmonics", RepetitiveConfig(bins=8, q_harmonics=5)),
    ("smoothing", RepetitiveConfig(smoothing=0.7)),
    ("lower", RepetitiveConfig(lower=0.1, upper=0.1)),
])
def test_a_configuration_it_cannot_use_is_refused_naming_the_field(field, config):
    with pytest.raises(ConfigurationError, match=f"^{field}:"):
        AzimuthMemory(config, 1.0)
