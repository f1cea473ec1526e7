"""An IPC process killed mid-run: its contribution fades out, the loop goes on, and it comes back when respawned.

A lockstep graph (plant, cpc, mbc, ipc_h1, ipc_h2 with ``respawn``) is recorded; ipc_h2's
process is killed with SIGKILL once the plant has passed t = 5 s, and the graph is stopped (Ctrl-C) once ipc_h2
answers again and the plant has gone 2 s on.
"""
import math
import os
import signal
import subprocess

import numpy as np
import pytest

from launched_graph import LaunchedGraph, last_sent_step, returned_and_ran_on

from hawt_analysis.run_analysis import analyze_bag

pytestmark = pytest.mark.ros

GRAPH = """\
launch:
- node: {pkg: hawt_plant, exec: plant, name: plant, namespace: lost, on_exit: shutdown,
         param: [{name: duration, value: 60.0}, {name: report_period, value: 1.0}]}
- node: {pkg: hawt_controllers, exec: cpc, name: cpc, namespace: lost}
- node: {pkg: hawt_controllers, exec: mbc, name: mbc, namespace: lost, param: [{name: controllers, value: [cpc, ipc_h1, ipc_h2]}]}
- node: {pkg: hawt_controllers, exec: ipc, name: ipc_h1, namespace: lost,
         param: [{from: $(turbine-tuning nrel_5mw ipc)}]}
- node: {pkg: hawt_controllers, exec: ipc, name: ipc_h2, namespace: lost, respawn: true, respawn_delay: 1.0,
         param: [{from: $(turbine-tuning nrel_5mw ipc)}]}
"""


def _pid_of(launcher: int, node_name: str) -> int:
    found = subprocess.run(["pgrep", "-P", str(launcher), "-f", f"__node:={node_name}( |$)"],
                           capture_output=True, text=True).stdout.split()
    assert len(found) == 1, found
    return int(found[0])


@pytest.fixture(scope="module")
def launched(tmp_path_factory):
    """The recorded graph, ipc_h2 killed at t = 5 s, stopped with Ctrl-C once it is back and the plant 2 s on (the
    run's 60 s is only the limit); the analysis of the bag and the plant's last step sent."""
    folder = tmp_path_factory.mktemp("ipc_lost")
    graph, bag = folder / "graph.yaml", folder / "run.mcap"
    graph.write_text(GRAPH)
    with LaunchedGraph([str(graph), "--record", str(bag), "-p", "plant.wait_for_subscribers:=3"]) as launch:
        launch.wait_for_line("t=5.0 s")
        os.kill(_pid_of(launch.process.pid, "ipc_h2"), signal.SIGKILL)
        launch.wait_until(lambda: returned_and_ran_on(list(launch.lines)), "ipc_h2 back and the plant 2 s on")
        launch.process.send_signal(signal.SIGINT)
        assert launch.finish() == 0, launch.tail()
    return analyze_bag(bag), last_sent_step(launch.lines)


@pytest.fixture(scope="module")
def run(launched):
    """The analysis of the bag."""
    return launched[0]


def test_the_run_goes_on_with_every_step(launched):
    """The loop goes on after the loss and the return, and the bag holds every step up to the plant's last."""
    analysis, last_sent = launched
    assert analysis.summary["bag"]["last_step"] == last_sent > 700


def test_the_lost_controller_is_reported_and_its_return_too(run):
    """control/events holds contribution_lost for control/ipc/h2 and, after the respawn, contribution_returned."""
    steps = {kind: [e["step"] for e in run.run.events if e["kind"] == kind and e["detail"].startswith("control/ipc/h2")]
             for kind in ("contribution_lost", "contribution_returned")}
    assert steps["contribution_lost"] and steps["contribution_returned"] \
        and steps["contribution_returned"][0] > steps["contribution_lost"][0]


def test_every_command_stays_finite_within_limits_and_rate(run):
    """No NaN, pitch within 0..90 deg, no step faster than 8 deg/s, through the loss and the return."""
    pitch = np.asarray(run.run.pitch_command["pitch"])
    assert np.all(np.isfinite(pitch)) and pitch.min() >= 0.0 and pitch.max() <= math.radians(90.0)
    assert (np.abs(np.diff(pitch, axis=0)) / 0.01).max() <= math.radians(8.0) * (1 + 1e-9)


def test_the_commands_are_flagged_while_the_contribution_fades(run):
    """FLAG_STALE_IPC marks the steps the lost controller's demand was faded in."""
    flags = np.asarray(run.run.pitch_command["flags"]).astype(int)
    assert np.count_nonzero(flags & 8) > 0
