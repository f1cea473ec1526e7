"""Controller switches in the real graph: at their step, bumpless, recorded, and the same in every lockstep run.

The switching graph (plant, cpc, mbc, ipc_h1, ipc_h2, ipc_h1_retuned, ipc_h4, blade_sine, controller_manager)
runs 30 s in lockstep, each node its own process, with a schedule given in steps:
CPC -> +IPC-1P (step 600) -> +IPC-2P (1200) -> swap IPC-1P for the retuned one (1800) -> all IPC off (2400).
"""
import math
import subprocess
import sys

import numpy as np
import pytest

from hawt_bag.reader import BagReader
from hawt_analysis.run_analysis import analyze_bag
from hawt_bag.topic_columns import read_topic_columns

pytestmark = pytest.mark.ros

DT = 0.01
RAMP_STEPS = 100
SWITCH_STEPS = (600, 1200, 1800, 2400)
SCHEDULE = "['600 +ipc_h1', '1200 +ipc_h2', '1800 +ipc_h1_retuned -ipc_h1', '2400 -ipc_h1_retuned -ipc_h2']"
MAX_RATE = math.radians(8.0)


def _run(path, engine: str = "launch"):
    """The switching graph with SCHEDULE, recorded: ``launch`` (the lockstep ROS graph) or ``run`` (in process)."""
    result = subprocess.run([sys.executable, "-m", "hawt_tools.cli", engine, "switching", "namespace:=sw",
                             "duration:=30", f"schedule:={SCHEDULE}", f"ramp_time:={RAMP_STEPS * DT}",
                             "--record", str(path), "-p", "plant.wait_for_subscribers:=4"],
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    with BagReader(path) as reader:
        topics = {name: read_topic_columns(reader, f"/sw/{name}").fields
                  for name in ("plant/blade_loads", "control/pitch_command")}
    return topics, analyze_bag(path)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("switching")
    return [_run(folder / "launched.mcap"), _run(folder / "ran.mcap", "run")]


def test_each_switch_is_an_event_at_the_step_it_was_scheduled_for(runs):
    """Every IPC node reports its switch at the scheduled step: 1 + 1 + 2 + 2 events at 600, 1200, 1800, 2400."""
    _, analysis = runs[0]
    events = [(e["step"], e["source"]) for e in analysis.run.events if e["kind"] == "switch"
              and not e["source"].endswith("controller_manager")]
    assert sorted(events) == [(600, "/sw/ipc_h1"), (1200, "/sw/ipc_h2"), (1800, "/sw/ipc_h1"),
                              (1800, "/sw/ipc_h1_retuned"), (2400, "/sw/ipc_h1_retuned"), (2400, "/sw/ipc_h2")]


def _per_step(fields: dict) -> dict:
    """One row per step (a step the plant sent again after resend_period is recorded twice, identically)."""
    _, first = np.unique(np.asarray(fields["step"]), return_index=True)
    return {name: np.asarray(values)[first] for name, values in fields.items() if not name.startswith("header")}


def test_a_lockstep_switch_schedule_gives_bit_identical_runs(runs):
    """Same schedule in steps, same seed: every blade-load and pitch-command field of the lockstep graph is equal bit
    for bit to the in-process engine's (`hawt run`, one thread, no scheduling to race): the graph's switches land
    where the schedule puts them, whatever the processes' timing."""
    (first, _), (second, _) = runs
    for topic in first:
        a, b = _per_step(first[topic]), _per_step(second[topic])
        assert a["step"].size == 3000
        for field in a:
            assert np.array_equal(a[field], b[field]), f"{topic}.{field}"


def test_no_switch_moves_the_pitch_faster_than_the_actuator_limit(runs):
    """The commanded pitch never changes faster than 8 deg/s, at a switch or anywhere else."""
    command = runs[0][0]["control/pitch_command"]
    pitch, steps = np.asarray(command["pitch"]), np.asarray(command["step"])
    rates = np.abs(np.diff(pitch, axis=0)) / DT
    row = int(np.argmax(rates.max(axis=1)))
    around = slice(max(row - 3, 0), row + 4)
    assert rates.max() <= MAX_RATE * (1 + 1e-9), \
        f"rows {around}: steps {steps[around].tolist()}, pitch {pitch[around].tolist()}"


def test_the_ipc_contribution_follows_the_switches(runs):
    """No IPC before step 600, IPC while a controller is on, none again once the last one has ramped out."""
    command = runs[0][0]["control/pitch_command"]
    steps, individual = np.asarray(command["step"]), np.abs(np.asarray(command["individual"]))
    assert individual[steps < 600].max() == 0.0
    assert individual[(steps > 800) & (steps < 2400)].max() > math.radians(0.5)
    assert individual[steps >= 2400 + RAMP_STEPS].max() == 0.0


def test_swapping_a_controller_hands_over_without_a_jump(runs):
    """At the swap the IPC part changes no more than at the steps around it (bumpless transfer)."""
    command = runs[0][0]["control/pitch_command"]
    steps, individual = np.asarray(command["step"]), np.asarray(command["individual"])
    change = np.abs(np.diff(individual, axis=0)).max(axis=1)
    around = change[(steps[1:] > 1750) & (steps[1:] < 1850) & (steps[1:] != 1800)]
    assert change[steps[1:] == 1800][0] <= 1.5 * around.max()


def test_analysis_shows_the_loads_between_switches(runs):
    """hawt analyze's segments: the 1P of M_oop falls once IPC-1P is on and comes back when all IPC is off."""
    _, analysis = runs[0]
    segments = analysis.summary["segments"]
    assert [s["first_step"] for s in segments] == [0, *SWITCH_STEPS]

    def oop_1p(segment):
        return np.mean([dict(zip(h["n"], h["amplitude"]))[1] for name, h in segment["harmonics"].items()
                        if name.startswith("root_moment_oop")])

    cpc, with_1p2p, off = oop_1p(segments[0]), oop_1p(segments[2]), oop_1p(segments[4])
    assert with_1p2p < 0.3 * cpc and off > 0.5 * cpc
