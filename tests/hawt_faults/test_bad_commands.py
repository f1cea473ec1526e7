"""Bad commands injected into a running realtime graph are refused with events and never applied."""
import math

import numpy as np
import pytest
from hawt_msgs.msg import ControlEvent, PitchCommand

from hawt_faults.fault_runs import assert_pitch_within_limits, assert_plant_published_no_nan, read_recording

pytestmark = pytest.mark.ros

FEATHERED = [1.5] * 3
"""A valid pitch [rad] far from the operating point's 15 deg: applied for even a few steps, it would show."""


def test_nan_wrong_length_future_and_stale_commands_are_refused_and_never_applied(launch, probe):
    """Realtime baseline: three refusals (invalid_input), two stale bursts (one stale_input each); pitch undisturbed.
    The test stops the run (Ctrl-C) after the last burst; its duration only bounds it (20 s of plant time once ran
    out on a busy machine before the second burst had ended)."""
    namespace = "bad_commands"
    injector = probe(namespace)
    run = launch("baseline", namespace, "mode:=realtime", "duration:=300",  # the probe may command (a source)
                 "-p", "plant.command_sources:=['mbc', '/fault_probe']")
    injector.wait_until_recorded(run.launcher)
    injector.wait_for_step(300, run.launcher)  # the injected commands are numbered from the plant's step
    step = injector.plant_step
    for command, reason in ((lambda k: PitchCommand(step=k, pitch=[math.nan, 0.26, 0.26], generator_torque=4e4),
                             "not finite"),
                            (lambda k: PitchCommand(step=k, pitch=[0.26, 0.26], generator_torque=4e4),
                             "expected 3 values"),
                            (lambda k: PitchCommand(step=k + 10_000, pitch=FEATHERED, generator_torque=4e4),
                             "step ahead of the plant")):
        injector.publish_until({"control/pitch_command": command}, lambda: injector.reported("invalid_input", reason),
                               run.launcher, reason)
    for burst in (1, 2):
        burst_end = injector.plant_step + 100
        injector.publish_until({"control/pitch_command": lambda k: PitchCommand(step=k - 50, pitch=FEATHERED,
                                                                                generator_torque=0.0)},
                               lambda: injector.plant_step >= burst_end, run.launcher, f"stale burst {burst}")
        # the plant has reported this burst, and 1.5 s (more than stale_burst_gap) pass before the next one
        injector.wait_while_launched(lambda: sum(e.kind == "stale_input" for e in injector.events) >= burst,
                                     run.launcher, f"the report of stale burst {burst}")
        injector.wait_for_step(burst_end + 150, run.launcher)
    run.interrupt()
    run.finish()
    injector.take_what_arrived()

    recording = read_recording(run.bag, namespace)
    refused = [event["detail"] for event in recording.events_of("invalid_input")]
    reasons = ("(not finite: pitch [nan, 0.26, 0.26], generator_torque 40000.0)", "(pitch: expected 3 values, found 2)",
               "(step ahead of the plant's step ")
    assert all(any(reason in detail for detail in refused) for reason in reasons), refused
    assert all(any(reason in detail for reason in reasons) for detail in refused), refused
    stale = recording.events_of("stale_input")
    assert len(stale) == 2 and all(event["level"] == ControlEvent.WARN for event in stale)
    assert all(event["level"] == ControlEvent.ERROR for event in recording.events_of("invalid_input"))
    steps, pitch = recording.measured_pitch()
    after = pitch[steps >= step]
    assert np.all(np.abs(after - pitch[steps == step]) < math.radians(0.5)), \
        f"the pitch moved to {np.degrees(after.max()):.2f} deg from {np.degrees(pitch[steps == step].max()):.2f} deg"
    with_nan = [row for row in recording.commands.fields["pitch"] if not np.all(np.isfinite(row))]
    assert with_nan and all(list(row[1:]) == [0.26, 0.26] for row in with_nan), "every NaN command is the injected one"
    assert not recording.events_of("watchdog")
    assert recording.events_of("interrupted") and int(recording.loads.fields["step"].max()) == injector.plant_step
    assert_plant_published_no_nan(recording)
    assert_pitch_within_limits(recording)
