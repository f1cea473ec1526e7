"""Faults injected into the plant (hawt_plant.faults) in closed loop, in process: what the controllers and the safety
system do, and what the run records. Steady 18 m/s, tens of seconds simulated."""
import numpy as np
import pytest

from hawt_plant.turbine import nrel_5mw
from hawt_tools.in_process import RunRecord

TURBINE = nrel_5mw()
RATED = TURBINE.schedule.rated_rotor_speed
DT = 0.01


def _run(graph: str, faults: str, seconds: float):
    """``graph`` at steady 18 m/s with the plant's ``faults`` for ``seconds``, stepped in process and recorded."""
    from hawt_tools.graph_file import find_graph
    from hawt_tools.graph_file import load_graph
    from hawt_tools.in_process import build_run
    from hawt_tools.graph_file import package_prefix
    from hawt_tools.node_parameters import parse_overrides

    loaded = load_graph(find_graph(graph), {"wind_speed": "18.0"}, package_prefix)
    run = build_run(loaded, parse_overrides(loaded, [f"plant.faults:={faults}"]))
    record = RunRecord()
    for _ in range(int(round(seconds / DT))):
        run.step(record)
    columns = {topic: {name: np.asarray([row[name] for row in rows]) for name in rows[0]}
               for topic, rows in record.rows.items()}
    return run, columns


def _events(run, kind: str):
    return [event for event in run.events if event["kind"] == kind]


def test_a_dead_blade_root_sensor_fades_the_ipc_out_with_an_event_and_no_nan_reaches_the_plant():
    """ipc graph, blade 2's load sensor dead at 10 s: a WARN fault event at step 1000; each IPC controller reports the
    NaN at step 1000, once, and says it fades out; its demand falls linearly from its last one to 0 over its 5 s ramp
    (not held), so the individual pitch is 0 from 15 s; no command is NaN;
    the collective controller, which reads generator speed and pitch, keeps the rotor at rated speed."""
    run, topics = _run("ipc", "['load_dead blade=2 at=10']", 20)
    (fault,) = _events(run, "fault")
    assert (fault["step"], fault["level"]) == (1000, 30) and "blade 2 dead" in fault["detail"]
    refused = _events(run, "invalid_input")
    assert sorted(e["source"] for e in refused) == ["/wt1/ipc_h1", "/wt1/ipc_h2", "/wt1/ipc_h3"]
    assert all(e["step"] == 1000 and "NaN" in e["detail"] and "fading out" in e["detail"] for e in refused)
    loads = topics["plant/blade_loads"]["root_moment_oop"]
    assert np.isnan(loads[1000:, 1]).all() and np.isfinite(loads[:1000]).all()
    command = topics["control/pitch_command"]
    assert np.isfinite(command["pitch"]).all() and np.isfinite(command["generator_torque"]).all()
    individual = np.abs(command["individual"])
    assert individual[900:1000].max() > np.radians(1.0)  # IPC was working before
    assert individual[1500:].max() == 0.0  # faded out over its 5 s ramp
    h1 = topics["control/ipc/h1"]
    demand = np.hypot(h1["cos"], h1["sin"])
    fade = 1.0 - np.arange(1, 501) * DT / 5.0  # linear, over the controller's ramp_time 5 s, from the last demand
    np.testing.assert_allclose(demand[1000:1500], fade * demand[999], rtol=1e-9, atol=1e-15)
    speed = topics["plant/blade_loads"]["rotor_speed"]
    assert np.abs(speed[1000:] / RATED - 1.0).max() < 0.02


@pytest.mark.parametrize("graph, node, topic", [
    ("lqg", "lqg_ipc", "control/ipc/h1"),
    ("repetitive", "repetitive_ipc", "control/blade_pitch"),
])
def test_a_dead_blade_root_sensor_fades_lqg_and_repetitive_ipc_out_as_it_does_the_ipc(graph, node, topic):
    """Blade 2's load sensor dead at 10 s: the LQG (Selvam) and the repetitive IPC (Fratini) report the refused
    input once and say they fade out; their demand falls linearly from the last one to 0 over their 2 s ramp, not
    held, so the individual pitch is 0 from 12 s, and no command is NaN."""
    run, topics = _run(graph, "['load_dead blade=2 at=10']", 14)
    (refused,) = [e for e in _events(run, "invalid_input") if e["source"] == f"/wt1/{node}"]
    assert refused["step"] == 1000 and "NaN" in refused["detail"] and "fading out" in refused["detail"]
    command = topics["control/pitch_command"]
    assert np.isfinite(command["pitch"]).all() and np.isfinite(command["individual"]).all()
    individual = np.abs(command["individual"])
    assert individual[900:1000].max() > np.radians(0.1)  # working before
    assert individual[1200:].max() == 0.0  # faded out over its 2 s ramp
    rows = topics[topic]
    demand = np.hypot(rows["cos"], rows["sin"]) if "cos" in rows else np.abs(rows["increment"]).max(axis=1)
    fade = 1.0 - np.arange(1, 201) * DT / 2.0
    np.testing.assert_allclose(demand[1000:1200], fade * demand[999], rtol=1e-9, atol=1e-15)


def test_a_grid_loss_at_18_m_s_is_seen_by_the_grid_monitor_which_shuts_the_turbine_down():
    """baseline, grid lost at 5 s: an ERROR fault event at step 500; the protection's grid monitor sees the loss at the
    end of that step and trips (step 501), feathering every blade at the actuator's rate limit; the generator, off the
    grid, has no torque from that step on; the rotor, its load gone at once, speeds up to 1.04 x rated until the
    blades have feathered enough, short of the protection's warning level (1.12 x rated)."""
    run, topics = _run("baseline", "['grid_loss at=5']", 20)
    (fault,) = _events(run, "fault")
    assert (fault["step"], fault["level"]) == (500, 40)
    (trip,) = _events(run, "protection_trip")
    assert trip["step"] == 501 and trip["detail"].startswith("grid loss: the generator is off the network")
    torque = topics["plant/state"]["generator_torque"]
    assert torque[500] > 0.9 * TURBINE.generator.rated_torque
    assert np.all(torque[501:] == 0.0)
    pitch = topics["plant/blade_loads"]["pitch"]
    np.testing.assert_allclose(np.diff(pitch[600:1000], axis=0), TURBINE.pitch_actuator.max_rate * DT, rtol=1e-2)
    speed = topics["plant/blade_loads"]["rotor_speed"]
    assert 1.02 * RATED < speed[500:].max() < 1.06 * RATED and _events(run, "protection_warning") == []


def test_a_pitch_runaway_to_feather_on_one_blade_trips_the_pitch_asymmetry_protection_which_feathers_all():
    """baseline, blade 1's actuator runs to feather at 5 s: an ERROR fault event at step 500; blade 1 moves at the
    actuator's rate limit; the protection trips on pitch asymmetry within 3 s and feathers the other blades at the
    rate limit; the rotor does not overspeed."""
    run, topics = _run("baseline", "['pitch_runaway blade=1 to=feather at=5']", 15)
    (fault,) = _events(run, "fault")
    assert (fault["step"], fault["level"]) == (500, 40)
    (trip,) = _events(run, "protection_trip")
    assert trip["detail"].startswith("pitch asymmetry ") and 500 < trip["step"] < 800
    pitch = topics["plant/blade_loads"]["pitch"]
    rate = np.diff(pitch[:, 0]) / DT
    assert rate[520:trip["step"]].min() == pytest.approx(TURBINE.pitch_actuator.max_rate, rel=1e-9)
    assert np.all(np.diff(pitch[trip["step"] + 50:, 1]) > 0.0) and pitch[-1, 1] > pitch[trip["step"], 1] + 0.5
    assert topics["plant/blade_loads"]["rotor_speed"].max() < 1.01 * RATED


FAULTS = "['azimuth_offset angle=0.3 at=2', 'load_dead blade=2 at=4', 'pitch_stuck blade=3 at=6', 'grid_loss at=8']"


@pytest.mark.parametrize("graph, entries, refusal", [
    ("baseline", "['grid_loss at=1', 'pitch_stuck blade=2 at=0.005']",
     "entry 'pitch_stuck blade=2 at=0.005': at: 0.005 s is not a whole number of steps of dt 0.01 s"),
    ("two_bladed", "['load_dead blade=3 at=1']", "entry 'load_dead blade=3 at=1': blade: expected 1..2, found 3"),
], ids=["not a whole step", "a blade the turbine does not have"])
def test_a_bad_faults_entry_is_refused_before_the_run_in_one_line(hawt_cli, graph, entries, refusal):
    """`hawt run` (and `hawt launch`, through the same parameter check): exit 2, one line naming the entry."""
    import subprocess

    result = subprocess.run([*hawt_cli, "run", graph, "duration:=1", "-p", f"plant.faults:={entries}"],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 2
    assert result.stderr.strip() == f"hawt run: -p plant.faults: {refusal}"


@pytest.mark.ros
def test_faults_give_the_lockstep_graph_and_hawt_run_the_same_run_and_events_at_their_steps(hawt_cli, tmp_path):
    """ipc graph, 10 s of turbulence with an azimuth offset, a dead load sensor, a stuck actuator and a grid loss:
    plant/blade_loads, plant/state and control/pitch_command of `hawt launch` (one process per node) and `hawt run`
    are equal in every field at every step, and each bag has the four fault events at their steps and each IPC
    controller's one report of the dead sensor."""
    import subprocess

    from hawt_bag.step_comparison import step_differences
    from hawt_faults.fault_runs import read_recording

    bags = {}
    for command in ("launch", "run"):
        bags[command] = tmp_path / f"{command}.mcap"
        result = subprocess.run([*hawt_cli, command, "ipc", "wind_type:=turbulent", "duration:=10", "seed:=3", "-p",
                                 f"plant.faults:={FAULTS}", "--record", str(bags[command])], capture_output=True,
                                text=True, timeout=600)
        assert result.returncode == 0, result.stderr[-3000:]
        recording = read_recording(bags[command], "wt1")
        faults = recording.events_of("fault")
        assert [(e["step"], e["level"]) for e in faults] == [(200, 30), (400, 30), (600, 40), (800, 40)], faults
        # each IPC controller reports the dead sensor once, at its first refused step, in both engines
        refused = recording.events_of("invalid_input")
        assert sorted((e["source"].rsplit("/", 1)[-1], e["step"]) for e in refused) == \
            [("ipc_h1", 400), ("ipc_h2", 400), ("ipc_h3", 400)], refused
    topics = ("/wt1/plant/blade_loads", "/wt1/plant/state", "/wt1/control/pitch_command")
    assert step_differences(bags["launch"], bags["run"], topics) == []


def test_a_bag_with_a_dead_sensor_is_analysed_up_to_it_and_says_so(hawt_cli, tmp_path):
    """hawt analyze of a run whose blade 2 sensor died at 10 s: the steps before the NaN are analysed, and a warning
    says where the NaN starts and in which channel (it stopped at 'root_moment_oop: NaN at sample 1000')."""
    import subprocess

    bag = tmp_path / "dead.mcap"
    ran = subprocess.run([*hawt_cli, "run", "ipc", "duration:=20", "-p", "plant.faults:=['load_dead blade=2 at=10']",
                          "--record", str(bag)], capture_output=True, text=True, timeout=300)
    assert ran.returncode == 0, ran.stderr[-3000:]
    analysed = subprocess.run([*hawt_cli, "analyze", str(bag)], capture_output=True, text=True, timeout=300)
    assert analysed.returncode == 0, analysed.stderr[-3000:]
    assert "NaN from step 1000 (t=10.00 s) in root_moment_oop" in analysed.stderr
    assert "steps 0..999" in analysed.stdout
