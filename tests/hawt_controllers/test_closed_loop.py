"""Closed loop of the cores on the NREL 5 MW model: the load reductions the IPC literature reports.

Steady 18 m/s, shear alpha = 0.2, tower shadow, 100 Hz, composed exactly as the graph composes
them: the plug-in controllers (``cpc`` -> collective_pitch + generator_torque, ``ipc`` of harmonic n ->
harmonic/<n>, built from the plant's description) and the one loop assembler
(hawt_controllers.plugins.loop_assembly: inverse MBC + sum + limits), with the shipped tuning
(data/ipc_nrel5mw.yaml). The ROS graph runs the same cores (test_plant_node.py, the graph
tests); here the loop runs in one process so a 60 s run takes seconds.
"""
import math

import numpy as np
import pytest
import yaml

from hawt_analysis.harmonics import harmonic_amplitudes
from hawt_controllers.laws.collective import load_baseline_config
from hawt_controllers.plugins.controller import CollectiveContribution
from hawt_controllers.plugins.cpc import CollectivePitchController
from hawt_controllers.plugins.ipc import HarmonicIpcController
from hawt_controllers.design.ipc_design import DEFAULT_FILE
from hawt_controllers.plugins.loop_assembly import LoopAssembler
from hawt_plant.model import TurbineModel
from hawt_plant.shear_wind import PowerLawWind
from hawt_plant.turbine import nrel_5mw

DT = 0.01
RATED_SPEED = 12.1 * math.pi / 30


def _ipc(harmonic: int, plant) -> HarmonicIpcController:
    values = yaml.safe_load(DEFAULT_FILE.read_text())[f"/**/ipc_h{harmonic}"]["ros__parameters"]
    controller = HarmonicIpcController(values, plant)
    controller.on_activate(0.0, (), None)
    return controller


def _run(harmonics, duration=60.0, settle=30.0) -> dict:
    turbine = nrel_5mw()
    plant = turbine.description(DT)
    model = TurbineModel(turbine, PowerLawWind(18.0, hub_height=turbine.hub_height, shear_exponent=0.2))
    out = model.reset_to_operating_point()
    controllers = [CollectivePitchController({}, plant), *(_ipc(n, plant) for n in harmonics)]
    assert [c.claims() for c in controllers] == [("collective_pitch", "generator_torque"),
                                                 *((f"harmonic/{n}",) for n in harmonics)]
    assembler = LoopAssembler(plant.blades, load_baseline_config().pitch_limits, plant.dt)
    previous = np.asarray(out.pitch)
    rows = []
    for step in range(int(duration / DT)):
        contributions = [c for controller in controllers for c in controller.update(step, out, out)]
        collective = next(c for c in contributions if isinstance(c, CollectiveContribution))
        command = assembler.assemble(collective.pitch, [(c, 1.0) for c in contributions if c is not collective],
                                     out.azimuth, previous)
        previous = command.pitch
        out = model.step(command.pitch, collective.generator_torque)
        if out.time >= settle:
            rows.append((out.azimuth, out.rotor_speed, out.electrical_power, out.hub_tilt_moment,
                         out.hub_yaw_moment, *out.root_moment_oop, *out.pitch))
    r = np.array(rows)
    oop = harmonic_amplitudes(r[:, 5], r[:, 0], harmonics=(1, 2, 3)).amplitude
    hub = harmonic_amplitudes(r[:, 3:5], r[:, 0], harmonics=(3,)).amplitude
    rates = np.abs(np.diff(r[:, 8:11], axis=0)) / DT
    return {"speed": r[:, 1], "power": r[:, 2], "oop": np.asarray(oop).ravel(), "hub_3p": np.asarray(hub).ravel(),
            "max_rate": rates.max()}


@pytest.fixture(scope="module")
def runs():
    return {name: _run(harmonics) for name, harmonics in (("cpc", ()), ("1p", (1,)), ("1p2p", (1, 2)))}


def test_collective_control_alone_holds_rated_speed_and_power(runs):
    """CPC alone: rotor speed within 1 % and electrical power within 2 % of rated (12.1 rpm, 5 MW)."""
    assert np.all(np.abs(runs["cpc"]["speed"] / RATED_SPEED - 1) < 0.01)
    assert np.all(np.abs(runs["cpc"]["power"] / 5e6 - 1) < 0.02)


def test_1p_ipc_cuts_the_1p_out_of_plane_moment_by_90_percent(runs):
    """Adding IPC-1P removes at least 90 % of the 1P amplitude of M_oop (shear makes it)."""
    assert runs["1p"]["oop"][0] <= 0.1 * runs["cpc"]["oop"][0]


def test_2p_ipc_cuts_2p_blade_loads_and_3p_hub_moments(runs):
    """Adding IPC-2P removes at least 80 % of the 2P of M_oop and 50 % of the 3P of hub tilt and yaw."""
    assert runs["1p2p"]["oop"][1] <= 0.2 * runs["cpc"]["oop"][1]
    assert np.all(runs["1p2p"]["hub_3p"] <= 0.5 * runs["cpc"]["hub_3p"])


def test_no_pitch_rate_beyond_the_actuator_limit(runs):
    """The measured blade pitch never moves faster than 8 deg/s."""
    for run in runs.values():
        assert run["max_rate"] <= math.radians(8.0) * 1.001
