"""A live swap between harmonic IPC and repetitive IPC in a realtime graph that records, and back.

The repetitive graph runs 24 s of plant time in realtime at 15 m/s with --record, harmonic IPC 1P+2P
active; once the plant reports 8 s the test swaps them for the repetitive IPC (ramps of 2 s), at
16 s back again, waiting on the plant's progress lines, never on a clock. The bag must hold both
switches at their steps, the repetitive IPC's blade_pitch contributions, and a command that never
exceeds the actuator's 8 deg/s; hawt analyze shows the segments. The graph runs composed (every node a ROS node
in one process, on DDS; the recorder in its own), which costs a third of the CPU of separate processes in realtime;
a live switch across processes is `test_switching_realtime`'s.
"""
import math
import subprocess

import numpy as np
import pytest
from launched_graph import CLI, LaunchedGraph

from hawt_analysis.run_analysis import analyze_bag
from hawt_tools.controller_client import switch_controllers

pytestmark = pytest.mark.ros

SWITCHES = (("t=8.0 s", ["repetitive_ipc"], ["ipc_h1", "ipc_h2"]), ("t=16.0 s", ["ipc_h1", "ipc_h2"],
                                                                    ["repetitive_ipc"]))


@pytest.fixture(scope="module")
def session(tmp_path_factory):
    bag = tmp_path_factory.mktemp("repetitive_realtime") / "run.mcap"
    answers = []
    with LaunchedGraph(["repetitive", "--mode", "realtime", "--composed", "namespace:=rrt", "duration:=24",
                        "wind_speed:=15.0", "ipc_h1:=true", "ipc_h2:=true", "repetitive_ipc:=false",
                        "-p", "plant.report_period:=1", "--record", str(bag)]) as graph:
        for when, activate, deactivate in SWITCHES:
            graph.wait_for_line(when)
            answers.append(switch_controllers(activate, deactivate, ramp_time=2.0, namespace="rrt", timeout=30.0))
        assert graph.finish() == 0, graph.tail()
    analyze = subprocess.run([*CLI, "analyze", str(bag)], capture_output=True, text=True, timeout=300)
    info = subprocess.run([*CLI, "bag", "info", str(bag)], capture_output=True, text=True, timeout=300)
    return answers, analyze_bag(bag), analyze, info.stdout


def test_both_swaps_are_answered_and_recorded_at_their_steps(session):
    answers, analysis = session[:2]
    assert all(a.ok for a in answers), answers
    steps = {e["step"] for e in analysis.run.events if e["kind"] == "switch"}
    assert all(a.effective_step in steps for a in answers), (answers, sorted(steps))


def test_the_repetitive_ipc_contributed_and_the_command_never_exceeds_the_rate_limit(session):
    analysis, info = session[1], session[3]
    blade_pitch = [line for line in info.splitlines() if "/rrt/control/blade_pitch " in line]
    assert blade_pitch and int(blade_pitch[0].split("Count:")[1].split("|")[0]) > 500, info
    pitch = np.asarray(analysis.run.pitch_command["pitch"])
    steps = np.asarray(analysis.run.pitch_command["step"]).astype(np.int64)
    rates = np.abs(np.diff(pitch, axis=0)) / (0.01 * np.diff(steps)[:, None])
    assert rates.max() <= math.radians(8.0) * (1 + 1e-9)


def test_hawt_analyze_shows_a_segment_per_controller_set(session):
    analyze = session[2]
    assert analyze.returncode == 0, analyze.stderr
    assert len([s for s in session[1].summary["segments"]]) >= 3
