"""The lqg_ipc plug-in around Selvam's law: bumpless take-over from the integrator IPC, weights set live (designed
and checked before they are accepted) and the wind estimate it publishes."""
import math

import numpy as np
import pytest

from hawt_analysis.wind_estimation import estimate_quality
from hawt_controllers.plugins.lqg_ipc import LqgIpcController
from hawt_core.parameter_table import ParameterError
from hawt_core.plant_description import PlantDescription
from hawt_plant.model import ModelConfig, TurbineModel
from hawt_plant.shear_wind import PowerLawWind
from hawt_plant.turbine import nrel_5mw
from hawt_tools.graph_file import find_graph
from hawt_tools.graph_file import load_graph
from hawt_tools.in_process import RunRecord, build_run
from hawt_tools.graph_file import package_prefix

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


def test_replacing_the_integrator_ipc_it_starts_from_its_output_and_blends_to_its_own():
    """The lqg graph in sheared turbulence with ipc_h1 active, lqg_ipc taking harmonic/1 over at step 2000 (a
    replacing switch: the outgoing stops at once): the first demand after the switch is the integrator's last, plus
    no more than the ramp's share of the way (1/200 per step at ramp_time 2 s), and the demand keeps moving by
    less per step than the integrator's own largest step until the ramp ends."""
    run = build_run(load_graph(find_graph("lqg"), {"lqg_ipc": "false", "ipc_h1": "true", "wind_type": "turbulent",
                                                   "duration": "30", "schedule": "['2000 +lqg_ipc -ipc_h1']"},
                               package_prefix))
    record = RunRecord()
    for _ in range(2400):
        run.step(record)
    demand = np.array([(r["cos"], r["sin"]) for r in sorted(record.rows["control/ipc/h1"], key=lambda r: r["step"])])
    integrator_step = np.abs(np.diff(demand[1000:2000], axis=0)).max()
    assert np.abs(demand[2000] - demand[1999]).max() < integrator_step
    assert np.abs(np.diff(demand[2000:2200], axis=0)).max() < 2 * integrator_step
    assert np.abs(demand[2250] - demand[1999]).max() > 10 * integrator_step  # it does move to its own


def test_without_a_controller_to_take_over_from_it_ramps_in_from_zero(sheared_loads):
    controller = LqgIpcController({"ramp_time": 1.0}, PLANT)
    controller.on_activate(None, (), sheared_loads[0])
    demands = _outputs(controller, sheared_loads[:150])
    assert np.abs(demands[0]).max() < 0.02 * np.abs(demands[100:]).max()


def test_live_weights_are_designed_for_every_operating_point_and_an_absurd_set_is_refused_with_its_reason():
    """Each weight has a range from 1e-9 to six decades above its tuning (within it every design succeeds); 1e30 is
    refused by it before any design."""
    controller = LqgIpcController({}, PLANT)
    before = controller.laws.designs
    assert len(before) == len(controller.models)
    with pytest.raises(ParameterError, match=r"inversion_walk: 1e\+30 is above its maximum 10000.0"):
        controller.check({**controller.values, "inversion_walk": 1e30})
    assert controller.laws.designs == before
    controller.check({**controller.values, "input_weight": 10.0})
    assert controller.laws.designs == before  # checked, not applied


def test_new_weights_take_over_at_a_step_and_keep_the_estimates(sheared_loads):
    controller = LqgIpcController({}, PLANT)
    controller.on_activate(None, (), sheared_loads[0])
    _outputs(controller, sheared_loads[:200])
    estimates = controller.laws.estimate.copy()
    gains = [design.k_lqr for design in controller.laws.designs]
    controller.reconfigure({**controller.values, "input_weight": 10.0})
    assert np.array_equal(controller.laws.estimate, estimates)
    assert all(not np.allclose(design.k_lqr, k) for design, k in zip(controller.laws.designs, gains))


def test_the_estimate_is_the_wind_and_states_of_the_law_in_use(sheared_loads):
    """In shear the estimated cos wind takes up the shear's 1P: it settles positive (more wind with the blade up)."""
    controller = LqgIpcController({}, PLANT)
    _outputs(controller, sheared_loads)
    estimate = controller.estimate()
    laws, active = controller.laws, controller.active_law
    assert [estimate["wind_cos"], estimate["wind_sin"]] == laws.wind[active].tolist()
    assert estimate["operating_wind_speed"] == controller.models[active].wind_speed
    assert np.array_equal(estimate["states"], laws.estimate[active, :laws.designs[active].states])
    assert estimate["wind_cos"] > 0.0


def test_the_estimator_follows_the_pitch_the_blades_have_when_the_rate_limit_cuts_the_demand():
    """Selvam's Table II weights demand more than the actuator's 8 deg/s on most steps of a turbulent run (the loop
    assembler limits the command). Told only its own contribution, the estimate's error was larger than the wind
    itself (error RMS 3.1 of 1.7 m/s in 120 s); with the actuator states set from the measured blade pitch it
    follows the wind: error RMS under 0.95 of the wind's (1.29 of 1.43 m/s, 0.90, over the last 50 s of 60). The
    plant's induction is quasi-steady, as the design's linear model has it (with the turbine's dynamic inflow the
    plant is further from the model: error RMS 1.33 of 1.43 m/s before the blade's slope and twist)."""
    table_ii = [("wind_walk", 10.0), ("measurement_noise", 0.01), ("input_weight", 0.8), ("inversion_walk", 0.01)]
    run = build_run(load_graph(find_graph("lqg"), {"wind_type": "turbulent", "duration": "60", "seed": "1"},
                               package_prefix), {"/wt1/lqg_ipc": table_ii,
                                                 "/wt1/plant": [("dynamic_inflow", "false")]})
    core = next(c.core for c in run.controllers if c.core.TYPE == "lqg_ipc")
    truth, estimate, command = [], [], []
    for _ in range(6000):
        run.step()
        truth.append((run.output.effective_wind_cos, run.output.effective_wind_sin))
        estimate.append((core.estimate()["wind_cos"], core.estimate()["wind_sin"]))
        command.append(run.command[0])
    rate = np.abs(np.diff(command, axis=0)).max(axis=1) / DT
    assert np.mean(rate > 0.99 * PLANT.max_pitch_rate) > 0.5  # the premise: the rate limit acts
    truth, estimate = np.array(truth), np.array(estimate)
    for axis in range(2):
        quality = estimate_quality(truth[1000:, axis], estimate[1000:, axis], 100.0)
        assert quality.error_rms < 0.95 * quality.truth_rms
