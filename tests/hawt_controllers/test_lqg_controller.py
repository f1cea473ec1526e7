"""The lqg_ipc plug-in around Selvam's law: bumpless take-over from the integrator IPC, weights set live (designed
and checked before they are accepted) and the wind estimate it publishes."""
import math

import numpy as np
import pytest

from hawt_controllers.controller import HarmonicContribution
from hawt_controllers.lqg_controller import LqgIpcController
from hawt_core.parameter_table import ParameterError
from hawt_core.plant_description import PlantDescription
from hawt_plant.model import ModelConfig, TurbineModel
from hawt_plant.shear_wind import PowerLawWind
from hawt_plant.turbine import nrel_5mw

DT = 0.01
PLANT = PlantDescription("nrel_5mw", DT, 3, 12.1 * math.pi / 30, 5e6, 43093.55, 97.0, 0.0, math.pi / 2,
                         8 * math.pi / 180)


@pytest.fixture(scope="module")
def sheared_loads():
    """Four seconds of the plant's output in sheared 18 m/s wind, commands held."""
    model = TurbineModel(nrel_5mw(), PowerLawWind(18.0, shear_exponent=0.2), ModelConfig())
    first = model.output
    return [model.step(first.pitch.copy(), first.generator_torque) for _ in range(400)]


def _outputs(controller, loads):
    return np.array([[c.cos, c.sin] for k, out in enumerate(loads) for c in controller.update(k, out)])


def test_replacing_the_integrator_ipc_it_starts_from_its_output_and_blends_to_its_own(sheared_loads):
    """Taking over harmonic/1 (ramp 0, as a replacing switch gives it), the first demand is the outgoing output,
    it moves by no more than 1/200 of the gap per step (ramp_time 2 s at 10 ms), and after the ramp it is its own
    law's demand: that of a controller active from the start, whose estimators were told the same applied pitch."""
    outgoing = HarmonicContribution(1, 0.02, -0.01, 0.4)
    controller = LqgIpcController({}, PLANT)
    controller.on_activate(0.0, (outgoing,), sheared_loads[0])
    demands = _outputs(controller, sheared_loads[:300])
    assert demands[0] == pytest.approx([0.02, -0.01], abs=2e-4)
    gap = np.abs(demands[0] - demands[250]).max()
    assert np.abs(np.diff(demands[:200], axis=0)).max() < gap / 100
    assert not np.allclose(demands[250], demands[0], atol=1e-3)


def test_without_a_controller_to_take_over_from_it_ramps_in_from_zero(sheared_loads):
    controller = LqgIpcController({"ramp_time": 1.0}, PLANT)
    controller.on_activate(None, (), sheared_loads[0])
    demands = _outputs(controller, sheared_loads[:150])
    assert np.abs(demands[0]).max() < 0.02 * np.abs(demands[100:]).max()


def test_live_weights_are_designed_for_every_operating_point_and_a_failing_set_is_refused_with_its_reason():
    controller = LqgIpcController({}, PLANT)
    before = [law.design for law in controller.laws]
    with pytest.raises(ParameterError, match="the LQG design fails with these weights"):
        controller.check({**controller.values, "inversion_walk": 1e30})
    assert [law.design for law in controller.laws] == before
    controller.check({**controller.values, "input_weight": 10.0})
    assert [law.design for law in controller.laws] == before  # checked, not applied


def test_new_weights_take_over_at_a_step_and_keep_the_estimates(sheared_loads):
    controller = LqgIpcController({}, PLANT)
    controller.on_activate(None, (), sheared_loads[0])
    _outputs(controller, sheared_loads[:200])
    estimates = [law.estimate.copy() for law in controller.laws]
    gains = [law.design.k_lqr for law in controller.laws]
    controller.reconfigure({**controller.values, "input_weight": 10.0})
    assert all(np.array_equal(law.estimate, e) for law, e in zip(controller.laws, estimates))
    assert all(not np.allclose(law.design.k_lqr, k) for law, k in zip(controller.laws, gains))


def test_the_estimate_is_the_wind_and_states_of_the_law_in_use(sheared_loads):
    """In shear the estimated cos wind takes up the shear's 1P: it settles positive (more wind with the blade up)."""
    controller = LqgIpcController({}, PLANT)
    _outputs(controller, sheared_loads)
    estimate = controller.estimate()
    law = controller.laws[controller.active_law]
    assert (estimate["wind_cos"], estimate["wind_sin"]) == law.wind
    assert estimate["operating_wind_speed"] == controller.models[controller.active_law].wind_speed
    assert np.array_equal(estimate["states"], law.estimate[:law.design.states])
    assert estimate["wind_cos"] > 0.0
