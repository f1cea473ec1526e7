"""The plant's protection trips whatever the controllers do: overspeed, tower-top acceleration, pitch asymmetry.

A collective controller stuck at fine pitch (the baseline tuning with zero gains and a 0.001 rad pitch ceiling) is the
active controller at 18 m/s: the rotor runs away, and the protection trips on overspeed below 1.2 x rated speed, in
every engine, then feathers at the actuator's rate with the generator torque off.
"""
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
import yaml
from hawt_msgs.msg import ControlEvent

from hawt_bag.step_comparison import step_differences
from hawt_faults.fault_runs import ACTUATOR, DT, read_recording
from hawt_plant.turbine import nrel_5mw

PACKAGED = Path(__file__).resolve().parents[2] / "hawt_plant" / "hawt_plant" / "turbines" / "nrel_5mw"
BASELINE = Path(__file__).resolve().parents[2] / "hawt_controllers" / "hawt_controllers" / "data" / \
    "nrel5mw_baseline.yaml"
RATED = nrel_5mw().schedule.rated_rotor_speed
TORQUE_RATE = nrel_5mw().generator.max_torque_rate


@pytest.fixture
def stuck_at_fine_pitch(tmp_path) -> str:
    """``cpc.controller_file:=`` a baseline tuning whose pitch loop does nothing: gains 0, pitch at most 0.001 rad."""
    tuning = yaml.safe_load(BASELINE.read_text())
    tuning["parameters"].update(proportional_gain=0.0, integral_gain=0.0, max_pitch=0.001)
    path = tmp_path / "stuck.yaml"
    path.write_text(yaml.safe_dump(tuning))
    return f"cpc.controller_file:={path}"


def _overspeed_trip_feathered_the_turbine(bag: Path, namespace: str) -> int:
    """One ERROR protection_trip naming an overspeed below 1.2 x rated; from its step on, every blade pitches towards
    feather at the actuator's rate and the generator torque falls at its rate limit to 0 (reached where the run
    lasted long enough after the trip). Returns the trip's step."""
    recording = read_recording(bag, namespace)
    (trip,) = recording.events_of("protection_trip")
    assert trip["level"] == ControlEvent.ERROR and "overspeed: " in trip["detail"], trip
    assert "feathering to 1.5708 rad" in trip["detail"]
    steps, pitch = recording.measured_pitch()
    state_steps, first = np.unique(recording.state.fields["step"], return_index=True)
    speed = recording.loads.fields["rotor_speed"][np.unique(recording.loads.fields["step"], return_index=True)[1]]
    at = trip["step"]
    assert speed[steps < at].max() < 1.2 * RATED
    rise = pitch[-1] - pitch[steps == at][0]
    assert np.all(rise > 0.8 * ACTUATOR.max_rate * (steps[-1] - at) * DT), rise
    torque = recording.state.fields["generator_torque"][first]
    after = torque[state_steps >= at]
    assert torque[state_steps < at].min() > 0.0 and np.all(np.diff(after) <= 0.0)
    at_its_rate = after[0] - 0.8 * TORQUE_RATE * (state_steps[-1] - at) * DT
    assert 0.0 <= torque[-1] <= max(0.0, at_its_rate), (torque[-1], at_its_rate)
    return at


@pytest.mark.ros
def test_a_controller_stuck_at_fine_pitch_trips_the_protection_in_lockstep_and_in_process_alike(
        hawt_cli, tmp_path, stuck_at_fine_pitch):
    """The lockstep graph (one process per node) and `hawt run`, 10 s at 18 m/s: the same overspeed trip, and the
    plant's topics equal in every field at every step (a tripped lockstep plant still steps on its controllers'
    answers, not applying them)."""
    bags = {}
    for command in ("launch", "run"):
        bags[command] = tmp_path / f"{command}.mcap"
        result = subprocess.run([*hawt_cli, command, "baseline", "duration:=10", "-p", stuck_at_fine_pitch,
                                 "--record", str(bags[command])], capture_output=True, text=True, timeout=300)
        assert result.returncode == 0, result.stderr[-3000:]
    assert "protection_trip at t=" in result.stderr and "generator overspeed" in result.stderr
    trips = [_overspeed_trip_feathered_the_turbine(bag, "wt1") for bag in bags.values()]
    assert trips[0] == trips[1]
    assert step_differences(bags["launch"], bags["run"], ("/wt1/plant/blade_loads", "/wt1/plant/state")) == []
    compared = subprocess.run([*hawt_cli, "compare", str(bags["run"]), str(bags["launch"])], capture_output=True,
                              text=True, timeout=300)  # a tripped run compared is said to be one
    assert compared.returncode == 0, compared.stderr[-3000:]
    assert f"{bags['launch']}: protection_trip at t=" in compared.stderr


@pytest.mark.ros
def test_a_controller_stuck_at_fine_pitch_trips_the_protection_in_realtime(launch, stuck_at_fine_pitch):
    """The realtime graph, 8 s at 18 m/s: the overspeed trip and the feathering, as in lockstep."""
    run = launch("baseline", "protect_rt", "mode:=realtime", "duration:=8", "-p", stuck_at_fine_pitch)
    run.finish()
    _overspeed_trip_feathered_the_turbine(run.bag, "protect_rt")


@pytest.mark.parametrize("graph, level, value, cause", [
    ("ipc", "pitch_asymmetry_trip", 0.02, "pitch asymmetry "),
    ("baseline", "tower_top_acceleration_trip", 0.15, "tower-top acceleration "),
], ids=["pitch asymmetry", "tower-top acceleration"])
def test_a_turbines_own_protection_levels_trip_in_process(hawt_cli, tmp_path, graph, level, value, cause):
    """The plant of a copy of the NREL 5 MW whose ``protection`` section lowers one level below what the graph does in
    turbulence (IPC spreads the pitch by more than 1.1 deg; the tower top accelerates by more than 0.15 m/s^2):
    `hawt run` trips on it, names it, and feathers."""
    turbine = tmp_path / "turbine"
    shutil.copytree(PACKAGED, turbine)
    definition = yaml.safe_load((turbine / "turbine.yaml").read_text())
    definition["protection"] = {level: value}
    (turbine / "turbine.yaml").write_text(yaml.safe_dump(definition))
    bag = tmp_path / "run.mcap"
    result = subprocess.run([*hawt_cli, "run", graph, "-p", f"plant.turbine_file:={turbine}", "wind_type:=turbulent",
                             "duration:=30",
                             "--record", str(bag)], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr[-3000:]
    recording = read_recording(bag, "wt1")
    (trip,) = recording.events_of("protection_trip")
    assert trip["detail"].startswith(cause), trip
    steps, pitch = recording.measured_pitch()
    assert np.all(pitch[-1] > pitch[steps == trip["step"]][0]), "the blades did not pitch towards feather"
