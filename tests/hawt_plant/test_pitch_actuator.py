"""Specification of hawt_plant.pitch_actuator: second-order actuator with rate and angle limits."""
import math
from dataclasses import replace

import numpy as np
import pytest

from hawt_plant.pitch_actuator import DiscretePitchActuator
from hawt_plant.turbine import nrel_5mw


@pytest.fixture(scope="module")
def parameters():
    return nrel_5mw().pitch_actuator


def run(actuator, command, steps, angle=0.0):
    angles, rates = np.full(3, angle), np.zeros(3)
    history = []
    for _ in range(steps):
        angles, rates = actuator.step(angles, rates, np.asarray(command, dtype=float))
        history.append(angles.copy())
    return np.array(history), rates


def test_small_step_follows_the_exact_second_order_response(parameters):
    """Below the rate limit the response is the analytic step response of w, zeta."""
    w, zeta, dt = parameters.natural_frequency, parameters.damping_ratio, 0.01
    history, _ = run(DiscretePitchActuator(parameters, dt), np.full(3, 0.001), 100)
    t = dt * np.arange(1, 101)
    wd = w * math.sqrt(1 - zeta**2)
    exact = 0.001 * (1 - np.exp(-zeta * w * t) * (np.cos(wd * t) + zeta * w / wd * np.sin(wd * t)))
    np.testing.assert_allclose(history[:, 0], exact, atol=1e-12)


def test_large_step_is_limited_to_8_deg_per_second(parameters):
    """A 20 deg step moves at most max_rate dt per step and arrives after about 2.5 s."""
    dt = 0.01
    history, _ = run(DiscretePitchActuator(parameters, dt), np.full(3, math.radians(20.0)), 400)
    assert np.max(np.diff(history[:, 0])) <= parameters.max_rate * dt * (1 + 1e-12)
    assert history[200, 0] < math.radians(20.0) - 0.01
    assert history[-1, 0] == pytest.approx(math.radians(20.0), abs=1e-4)


def test_angle_stays_within_the_limits(parameters):
    """Commands at the stops never overshoot them, and the rate is zero there."""
    fast = replace(parameters, max_rate=10.0)
    history, rates = run(DiscretePitchActuator(fast, 0.01), np.zeros(3), 200, angle=0.3)
    assert history.min() >= fast.min_angle
    assert history[-1, 0] == 0.0 and np.all(rates == 0.0)


def test_blades_move_independently(parameters):
    """Each blade follows its own command."""
    history, _ = run(DiscretePitchActuator(parameters, 0.01), [0.0, 0.01, 0.02], 300)
    np.testing.assert_allclose(history[-1], [0.0, 0.01, 0.02], atol=1e-6)


def test_time_step_must_be_positive(parameters):
    """dt <= 0 is rejected by name."""
    with pytest.raises(ValueError, match="dt"):
        DiscretePitchActuator(parameters, 0.0)
