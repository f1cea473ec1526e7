"""Ctrl-C on a recorded realtime run: every node flushes what it sent before it exits, so nothing is lost, and the
bag says the run was interrupted."""
import pytest
from hawt_msgs.msg import ControlEvent

from hawt_faults.fault_runs import read_recording

pytestmark = pytest.mark.ros

HARMONICS = (1, 2, 3)
IN_FLIGHT = 2
"""Steps the plant may have sent that the controllers had not answered yet when the signal came."""


def test_an_interrupted_recording_holds_every_topic_up_to_the_plants_last_step(launch, probe):
    """Realtime IPC graph interrupted mid-run: each controller topic's last recorded step is the plant's last one
    (less the answers in flight). (Realtime controllers may skip a step whose inputs the next step overtook.)"""
    namespace = "interrupted"
    watcher = probe(namespace, HARMONICS)
    run = launch("ipc", namespace, "mode:=realtime", "duration:=60")
    watcher.wait_until_recorded(run.launcher, margin=300)
    run.interrupt()
    output = run.finish()

    assert "stopped: interrupted" in output
    recording = read_recording(run.bag, namespace, HARMONICS)
    last_step = int(recording.loads.fields["step"].max())
    (interrupted,) = recording.events_of("interrupted")  # the launcher says so in the bag, at the plant's step
    assert interrupted["source"] == "/hawt_launch" and interrupted["level"] == ControlEvent.WARN
    assert 0 < interrupted["step"] <= last_step and "stopped the graph: interrupted" in interrupted["detail"]
    for columns in (recording.commands, recording.collective, *recording.ipc.values()):
        last = int(columns.fields["step"].max())
        assert last >= last_step - IN_FLIGHT, f"{columns.topic}: last recorded step {last}, the plant sent {last_step}"
