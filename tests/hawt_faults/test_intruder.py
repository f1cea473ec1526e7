"""Only the graph's command source commands the plant: another publisher on control/pitch_command is refused
(identified by its publisher GID), reported as an intruder, and changes nothing of the run."""
import math
import re

import numpy as np
import pytest
from hawt_msgs.msg import CollectivePitch, ControlEvent, HarmonicPitch, PitchCommand

from hawt_bag.step_comparison import step_differences
from hawt_faults.fault_runs import assert_plant_finished, read_recording, run_in_process

pytestmark = pytest.mark.ros

FEATHERED = [1.5] * 3
"""The intruder's pitch [rad] (86 deg), with zero torque: applied for even one step, it would show."""


def _intrude(intruder, run, until_step: int, commands: int = 0) -> None:
    """The intruder answers every plant step it sees, from the plant's current step to ``until_step``, until the
    plant has reported it and until it has sent ``commands`` commands: the plant may discover the intruder's publisher
    only after its first commands (a fresh-clone run's lockstep plant had run past step 400 before, and no intruder
    event came), and a lockstep plant may run the steps faster than a busy intruder sends (a fresh-clone CI
    run's plant refused only 8)."""
    intruder.publish_until({"control/pitch_command": lambda step: PitchCommand(step=step, pitch=FEATHERED,
                                                                               generator_torque=0.0)},
                           lambda: (intruder.plant_step >= until_step and intruder.reported("intruder")
                                    and intruder.published >= commands), run.launcher,
                           f"plant step {until_step}, the plant's intruder event and {commands} commands sent")


def _the_intruder_was_refused_and_named(recording, namespace: str) -> int:
    """Checks the intruder event and the finished event's count; returns how many commands the plant refused."""
    (event,) = recording.events_of("intruder")
    assert event["level"] == ControlEvent.ERROR and event["source"] == f"/{namespace}/plant"
    assert " from /fault_probe refused: only " f"/{namespace}/mbc may command this plant" in event["detail"]
    (finished,) = recording.events_of("finished")
    refused = re.search(r"(\d+) commands from 1 intruders refused", finished["detail"])
    assert refused, finished["detail"]
    return int(refused.group(1))


def test_an_intruder_in_lockstep_is_refused_named_and_changes_nothing(launch, probe, hawt_cli, tmp_path):
    """Lockstep baseline in turbulence with a second publisher answering every step with 86 deg and zero torque from
    step 100 to 400 (and until the plant reports it and 40 commands are sent). The intruder's commands never answer
    a step: the plant topics are equal in every field at every step to the same run without it (`hawt run`, equal
    to the lockstep graph), and so are the loop assembler's commands. The run is 30 s long: the plant does not wait
    for the probe, whose discovery of a 6 s run (under a second of wall time in lockstep) a busy machine once delayed
    past the run's end."""
    arguments = ("wind_type:=turbulent", "seed:=3", "duration:=30")
    alone = run_in_process(hawt_cli, tmp_path, "baseline", "alone_ls", *arguments)
    namespace = "intruder_ls"
    intruder = probe(namespace)
    run = launch("baseline", namespace, *arguments)
    intruder.wait_until_recorded(run.launcher, margin=0)
    intruder.wait_for_step(100, run.launcher)
    _intrude(intruder, run, 400, commands=40)
    run.finish()

    recording = read_recording(run.bag, namespace)
    refused = _the_intruder_was_refused_and_named(recording, namespace)
    plant = ("plant/blade_loads", "plant/state")
    assert step_differences(alone, run.bag, [f"/alone_ls/{t}" for t in plant],
                            [f"/{namespace}/{t}" for t in plant]) == []
    # The plant saw the intruder at many steps. The bag may hold fewer: the recorder records a publisher from its
    # discovery on, which a busy machine once delayed to the intruder's last command.
    assert refused > 10, f"{refused} of {intruder.published} commands refused"
    commands = read_recording(alone, "alone_ls").commands.fields, recording.commands.fields
    sourced = [np.asarray(c["generator_torque"]) != 0.0 for c in commands]  # the intruder's rows have 0 torque
    for name in ("step", "pitch", "generator_torque"):
        first, second = (np.asarray(c[name])[keep] for c, keep in zip(commands, sourced))
        assert np.array_equal(np.unique(first, axis=0), np.unique(second, axis=0)), name
    assert_plant_finished(recording, 30.0)


def test_an_intruder_in_realtime_is_refused_named_and_never_applied(launch, probe):
    """Realtime baseline, steady 18 m/s: an intruder sends 86 deg and zero torque for 300 steps; the pitch stays
    within 0.5 deg of where it was, the torque never drops to zero, and the safety system is not tripped."""
    namespace = "intruder_rt"
    intruder = probe(namespace)
    run = launch("baseline", namespace, "mode:=realtime", "duration:=10")
    intruder.wait_until_recorded(run.launcher)
    intruder.wait_for_step(300, run.launcher)
    start = intruder.plant_step
    _intrude(intruder, run, start + 300)
    run.finish()

    recording = read_recording(run.bag, namespace)
    _the_intruder_was_refused_and_named(recording, namespace)
    steps, pitch = recording.measured_pitch()
    after = pitch[steps >= start]
    assert np.all(np.abs(after - pitch[steps == start]) < math.radians(0.5)), \
        f"the pitch moved to {np.degrees(after.max()):.2f} deg"
    state = recording.state.fields
    assert np.all(np.asarray(state["generator_torque"])[np.asarray(state["step"]) >= start] > 1e4)
    assert not recording.events_of("watchdog") and not recording.events_of("invalid_input")
    assert_plant_finished(recording, 10.0)


CONTRIBUTION_INTRUDERS = {
    "control/collective": lambda step: CollectivePitch(step=step, pitch=0.0, generator_torque=0.0),
    "control/ipc/h1": lambda step: HarmonicPitch(step=step, harmonic=1, cos=0.5, sin=0.0)}
"""What an intruder on each contribution topic sends for a plant step: the collective at fine pitch with zero torque
(the rotor would run away), and a 1P demand of cos 0.5 rad (28.6 deg of IPC)."""


@pytest.mark.parametrize("mode", ["lockstep", "realtime"])
def test_intruders_on_the_contribution_topics_are_refused_by_the_loop_assembler(launch, probe, hawt_cli, tmp_path,
                                                                               mode):
    """The ipc graph in turbulence: a second publisher answers every step on the collective (pitch 0, torque 0) and on
    the 1P demand (cos 0.5 rad) from step 100 until mbc has reported both and 40 messages are sent on each. mbc reads
    only the claimants of a contribution topic: it names the intruder once per topic (an ERROR intruder event each),
    and nothing of it reaches the plant. In lockstep the plant's topics are equal in every field at every step to a
    run without it (`hawt run`, equal to the lockstep graph); in realtime the pitch command never comes near the
    intruder's (no step's individual pitch above 10 deg, the torque never 0) and nothing trips."""
    namespace = f"contribution_{mode}"
    arguments = ("wind_type:=turbulent", "seed:=3", f"mode:={mode}", "duration:=" + ("10" if mode == "lockstep" else
                                                                                     "12"))
    alone = run_in_process(hawt_cli, tmp_path, "ipc", f"{namespace}_alone", *arguments) if mode == "lockstep" else None
    intruder = probe(namespace)
    run = launch("ipc", namespace, *arguments)
    intruder.wait_until_recorded(run.launcher, margin=0)
    intruder.wait_for_step(100, run.launcher)
    intruder.publish_until(CONTRIBUTION_INTRUDERS, lambda: all(intruder.reported("intruder", f"{topic} step ")
                                                               for topic in CONTRIBUTION_INTRUDERS)
                           and intruder.published >= 40 * len(CONTRIBUTION_INTRUDERS), run.launcher,
                           "mbc's intruder event on each contribution topic")
    run.finish()

    recording = read_recording(run.bag, namespace)
    events = recording.events_of("intruder")
    assert sorted(topic for topic in CONTRIBUTION_INTRUDERS for event in events
                  if f"{topic} step " in event["detail"]) == sorted(CONTRIBUTION_INTRUDERS), events
    for event in events:
        assert event["level"] == ControlEvent.ERROR and event["source"] == f"/{namespace}/mbc"
        assert " from /fault_probe refused: only " in event["detail"]
    assert not recording.events_of("protection_trip") and not recording.events_of("watchdog")
    if alone is not None:
        plant = ("plant/blade_loads", "plant/state")
        assert step_differences(alone, run.bag, [f"/{namespace}_alone/{t}" for t in plant],
                                [f"/{namespace}/{t}" for t in plant]) == []
    commands = recording.commands.fields
    assert np.abs(np.asarray(commands["individual"])).max() < math.radians(10.0)
    assert np.asarray(commands["generator_torque"])[np.asarray(commands["step"]) > 50].min() > 0.0
