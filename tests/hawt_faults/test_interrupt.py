"""Ctrl-C on a recorded realtime run: every node flushes what it sent before it exits, so nothing is lost, and the
bag says the run was interrupted."""
import pytest
from hawt_msgs.msg import ControlEvent
from launched_graph import last_sent_step

from hawt_faults.fault_runs import read_recording

pytestmark = pytest.mark.ros

HARMONICS = (1, 2, 3)


def test_an_interrupted_recording_holds_every_step_each_node_sent(launch, probe):
    """Realtime IPC graph interrupted mid-run: each topic of the loop is recorded up to the last step its node sent,
    the plant's as it says when it stops, the controllers' and the loop assembler's as a reader of their topics in
    this test received them. (Realtime nodes do not wait for each other: a controller behind the plant when the signal
    comes never answers the steps it had not taken yet; on a busy machine the loop assembler once stopped 10 steps
    short of the plant.)"""
    namespace = "interrupted"
    watcher = probe(namespace, HARMONICS)
    # The test interrupts the run; its duration only bounds it (60 s once ran out under load before the probe had
    # seen the loop closed).
    run = launch("ipc", namespace, "mode:=realtime", "duration:=300")
    watcher.wait_until_recorded(run.launcher, margin=300)
    run.interrupt()
    output = run.finish()
    watcher.take_what_arrived()

    assert "stopped: interrupted" in output
    recording = read_recording(run.bag, namespace, HARMONICS)
    last_step = int(recording.loads.fields["step"].max())
    assert last_step == last_sent_step(output.splitlines()) == watcher.plant_step
    (interrupted,) = recording.events_of("interrupted")  # the launcher says so in the bag, at the plant's step
    assert interrupted["source"] == "/hawt_launch" and interrupted["level"] == ControlEvent.WARN
    assert 0 < interrupted["step"] <= last_step and "stopped the graph: interrupted" in interrupted["detail"]
    for topic, columns in (("control/pitch_command", recording.commands), ("control/collective", recording.collective),
                           *((f"control/ipc/h{n}", recording.ipc[n]) for n in HARMONICS)):
        last = int(columns.fields["step"].max())
        assert last == watcher.steps[topic], f"{topic}: last recorded step {last}, its node sent {watcher.steps[topic]}"
