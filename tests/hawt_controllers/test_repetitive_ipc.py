"""The repetitive_ipc controller plug-in (Fratini 2019 §5.1 R8): one learning memory per blade on its flap moment.

A synthetic rotor stands in for the plant here (each blade's flap moment lags its own pitch by the
plant_lag as an azimuth, over a sheared 1P + 2P load); the NREL 5 MW closed loop is
tests/hawt_controllers/test_repetitive_closed_loop.py.
"""
import bisect
import math
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest

from hawt_controllers.plugins.controller import controller_parameters
from hawt_controllers.plugins.repetitive_ipc import RepetitiveIpcController
from hawt_core.parameter_table import ParameterError, default_values
from hawt_plant.turbine import nrel_5mw

K = -45.0e6
LAG = 0.43


def _plant(blades=3):
    return replace(nrel_5mw().description(0.01), blades=blades)


def _loads(psi, blades, pitch_history):
    """Flap moments of a sheared rotor whose blades respond to their own pitch ``LAG`` of azimuth later."""
    moments = []
    for i in range(blades):
        psi_i = psi + 2 * math.pi * i / blades
        moments.append(8.0e6 + 1.5e6 * math.cos(psi_i) + 0.4e6 * math.cos(2 * psi_i - 0.5)
                       + K * pitch_history(i, psi - LAG))
    return SimpleNamespace(root_moment_oop=moments, azimuth=psi % (2 * math.pi), pitch=[0.2] * blades)


def _run(controller, blades, revolutions, speed=1.27, dt=0.01):
    """Flap-moment peak to peak of blade 1 per revolution, in closed loop with the synthetic rotor."""
    issued = {i: ([], []) for i in range(blades)}

    def history(i, angle):
        angles, values = issued[i]
        j = bisect.bisect_right(angles, angle)
        if j == 0:
            return 0.0
        if j == len(angles):
            return values[-1]
        fraction = (angle - angles[j - 1]) / (angles[j] - angles[j - 1])
        return (1 - fraction) * values[j - 1] + fraction * values[j]

    psi, spans, current = 0.0, [], []
    for step in range(int(revolutions * 2 * math.pi / (speed * dt))):
        loads = _loads(psi, blades, history)
        contribution, = controller.update(step, loads)
        for i, value in enumerate(contribution.increment):
            issued[i][0].append(psi)
            issued[i][1].append(value)
        current.append(loads.root_moment_oop[0])
        if int((psi + speed * dt) / (2 * math.pi)) > int(psi / (2 * math.pi)):
            spans.append(np.ptp(current))
            current = []
        psi += speed * dt
    return np.array(spans)


@pytest.mark.parametrize("blades", [2, 3, 4])
def test_it_learns_the_sheared_rotors_periodic_flap_load_away_on_any_number_of_blades(blades):
    """From zero learning, active: blade 1's flap oscillation falls below 5 % within 15 revolutions."""
    controller = RepetitiveIpcController({"learning_gain": 0.5, "ramp_time": 0.0}, _plant(blades))
    controller.on_activate(None, (), None)
    spans = _run(controller, blades, 15)
    assert spans[-1] < 0.05 * spans[0], spans


def test_frozen_it_plays_its_memory_and_learns_no_more():
    controller = RepetitiveIpcController({"learning_gain": 0.5, "ramp_time": 0.0}, _plant())
    controller.on_activate(None, (), None)
    _run(controller, 3, 6)
    controller.reconfigure({**controller.values, "freeze": True})
    learnt = [m.memory.copy() for m in controller.memories]
    _run(controller, 3, 2)
    assert all(np.array_equal(m.memory, before) for m, before in zip(controller.memories, learnt))
    assert np.max(np.abs(learnt[0])) > 0.01


def test_a_deactivation_fades_the_increment_out_and_stops_the_learning():
    controller = RepetitiveIpcController({"learning_gain": 0.5, "ramp_time": 1.0}, _plant())
    controller.on_activate(0.0, (), None)
    _run(controller, 3, 6)
    controller.on_deactivate(None)
    loads = SimpleNamespace(root_moment_oop=[9.0e6, 8.0e6, 7.0e6], azimuth=0.3, pitch=[0.2] * 3)
    sizes = [max(map(abs, controller.update(k, loads)[0].increment)) for k in range(120)]
    assert sizes[0] > 0 and sizes[99:] == [0.0] * 21 and all(np.diff(sizes[:100]) <= 1e-12)
    assert all(m.frozen for m in controller.memories)


def test_a_learning_gain_that_would_diverge_is_refused_naming_the_harmonic():
    """Q identity with the shift 60 deg off the plant's lag: the refusal names the harmonic that grows."""
    values = {**default_values(controller_parameters(RepetitiveIpcController)), "q_filter": "identity",
              "shift": LAG + math.radians(60.0)}
    with pytest.raises(ParameterError, match=r"^learning_gain: .* diverges at harmonic \d+"):
        RepetitiveIpcController.check_values(values)
    RepetitiveIpcController.check_values({**values, "q_filter": "lowpass", "q_harmonics": 1})


def test_input_it_cannot_use_is_refused_by_name():
    controller = RepetitiveIpcController({}, _plant())
    with pytest.raises(ValueError, match="root_moment_oop"):
        controller.update(0, SimpleNamespace(root_moment_oop=[1.0, float("nan"), 2.0], azimuth=0.0, pitch=[0.1] * 3))
    with pytest.raises(ValueError, match="root_moment_oop: expected 3 blades"):
        controller.update(0, SimpleNamespace(root_moment_oop=[1.0, 2.0], azimuth=0.0, pitch=[0.1] * 3))
