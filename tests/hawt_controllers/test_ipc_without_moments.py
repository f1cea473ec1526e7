"""HarmonicIpc.hold and the ipc plug-in without usable moments (a dead blade-root load sensor, issue 34): the demand
fades out over ramp_time instead of being held, and fades back in when the moments return."""
import math

import numpy as np
import pytest

from hawt_controllers.plugins.controller import update_or_hold
from hawt_controllers.laws.ipc import HarmonicIpc, HarmonicIpcConfig
from hawt_controllers.plugins.ipc import HarmonicIpcController
from hawt_plant.turbine import nrel_5mw

DT = 0.05
CONFIG = HarmonicIpcConfig(harmonic=1, integral_gain=1e-8, lowpass_order=0, max_amplitude=1.0, ramp_time=1.0)


def _integrated() -> tuple[HarmonicIpc, float]:
    ipc = HarmonicIpc(CONFIG, DT)
    ipc.activate(ramp_time=0.0)
    for _ in range(10):
        out = ipc.step(2.0e6, 0.0, DT)
    return ipc, out.cos


def test_without_moments_the_demand_falls_linearly_to_zero_over_ramp_time_with_the_integrator_held():
    ipc, last = _integrated()
    faded = [ipc.hold(DT).cos for _ in range(25)]
    assert faded[:20] == pytest.approx([last * (1.0 - (j + 1) * DT / CONFIG.ramp_time) for j in range(20)], abs=1e-15)
    assert faded[19:] == [0.0] * 6
    assert ipc.active  # still switched on: only the measurement factor fell


def test_when_the_moments_return_the_demand_fades_back_in_from_the_held_integrator():
    ipc, last = _integrated()
    for _ in range(25):
        ipc.hold(DT)
    back = [ipc.step(0.0, 0.0, DT).cos for _ in range(25)]
    assert back[:20] == pytest.approx([last * (j + 1) * DT / CONFIG.ramp_time for j in range(20)], abs=1e-15)
    assert back[19:] == pytest.approx([last] * 6)


def test_the_ipc_plug_in_answers_a_nan_moment_with_a_fading_demand_and_the_reason():
    """update_or_hold, as every engine calls it: the refusal names the NaN, the contribution is the faded one."""
    controller = HarmonicIpcController({"integral_gain": 1e-8, "lowpass_order": 0, "ramp_time": 1.0},
                                       nrel_5mw().description(DT))
    controller.on_activate(0.0, (), None)

    class Loads:
        azimuth, rotor_speed, pitch = 0.0, 1.0, np.full(3, 0.2)
        root_moment_oop = np.array([2e6, 0.0, 0.0])

    held = ()
    for k in range(10):
        held, refusal = update_or_hold(controller, k, Loads, None, held)
    assert refusal is None
    Loads.root_moment_oop = np.array([2e6, math.nan, 0.0])
    (faded,), refusal = update_or_hold(controller, 10, Loads, None, held)
    assert "NaN" in refusal
    assert (faded.cos, faded.sin) == pytest.approx((0.95 * held[0].cos, 0.95 * held[0].sin), rel=1e-12)
