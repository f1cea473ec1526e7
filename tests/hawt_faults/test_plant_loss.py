"""The plant lost mid-run in realtime: the controllers step only on plant messages, so they stop and hold."""
import numpy as np
import pytest

from hawt_faults.fault_runs import (ACTUATOR, assert_pitch_within_limits, assert_plant_published_no_nan,
                                    graph_outliving, read_recording)

pytestmark = pytest.mark.ros

HARMONICS = (1, 2, 3)
CONTROLLER_TOPICS = ("control/collective", *(f"control/ipc/h{n}" for n in HARMONICS))
IN_FLIGHT = 5
"""Answers of the last plant steps that may still arrive after the plant's last message."""


def test_cpc_and_ipc_publish_nothing_after_the_plant_dies_so_nothing_winds_up(launch, probe, tmp_path):
    """Realtime IPC graph, plant SIGKILLed: no controller output follows except answers in flight; last ones finite."""
    namespace = "plant_lost"
    watcher = probe(namespace, HARMONICS)
    run = launch(str(graph_outliving(tmp_path, "ipc", "plant")), namespace, "mode:=realtime", "duration:=60")
    for topic in CONTROLLER_TOPICS:
        watcher.wait_for_answer(200, run.launcher, topic)
    watcher.wait_until_recorded(run.launcher)
    run.kill("plant")
    for _ in range(25):
        watcher.spin(0.1)
    # Answers in flight may still come (on a busy machine one came 0.5 s after the kill), nothing beyond them.
    last_sent = watcher.steps["plant/blade_loads"]
    assert all(watcher.steps[topic] <= last_sent + IN_FLIGHT for topic in CONTROLLER_TOPICS), \
        f"a controller published during the plant's absence: {watcher.steps}"
    run.interrupt()
    output = run.finish()

    assert "/plant_lost/plant ended (killed by SIGKILL)" in output
    recording = read_recording(run.bag, namespace, HARMONICS)
    last_step, last_sent = recording.loads.fields["step"].max(), recording.loads.log_time.max()
    for columns in (recording.collective, *recording.ipc.values()):
        steps = columns.fields["step"]
        # A SIGKILLed plant's last messages may reach the controllers but not the recorder.
        assert steps.max() <= last_step + IN_FLIGHT, f"{columns.topic} answered a step the plant never sent"
        # Recorded after the plant's last message: at most the answers in flight. Which steps they answer is not
        # checked: the recorder takes each topic from its own queue, so on a busy machine an answer published in time
        # can be logged after later messages of other topics (a fresh-clone run logged IPC's answer to step 254 after
        # the plant's step 273, and nothing else late).
        late = steps[columns.log_time > last_sent]
        assert len(late) <= IN_FLIGHT, \
            f"{columns.topic} published steps {late.tolist()} after the plant's last step {last_step}"
    collective = recording.collective.fields
    assert np.isfinite(collective["pitch"][-1]) and ACTUATOR.min_angle <= collective["pitch"][-1] <= ACTUATOR.max_angle
    assert np.isfinite(collective["generator_torque"][-1])
    for columns in recording.ipc.values():
        assert np.isfinite(columns.fields["cos"][-1]) and np.isfinite(columns.fields["sin"][-1])
    assert_plant_published_no_nan(recording)
    assert_pitch_within_limits(recording)
