"""hawt analyze on a recorded run with an intruder on control/pitch_command: the pitch activity is that of the
commands the plant applied, and the intruder's refused commands are counted apart, naming it."""
import pytest
from builtin_interfaces.msg import Time
from hawt_msgs.msg import PitchCommand
from std_msgs.msg import Header

from hawt_analysis.run_analysis import analyze_bag
from hawt_bag.reader import BagReader
from hawt_faults.fault_runs import DT

pytestmark = pytest.mark.ros


def _feathered(plant_step: int) -> PitchCommand:
    """The intruder's command when the plant has sent ``plant_step``: for the step after it, so that the bag holds it
    before mbc's command of that step, with 86 deg and zero torque, stamped with the step's time and as well-formed
    as mbc's, so that only its publisher tells it apart."""
    step = plant_step + 1
    stamp = round(step * DT * 1e9)
    return PitchCommand(header=Header(stamp=Time(sec=stamp // 1_000_000_000, nanosec=stamp % 1_000_000_000)),
                        step=step, pitch=[1.5] * 3, collective=1.5, individual=[0.0] * 3, generator_torque=0.0)


def test_analyze_counts_an_intruders_commands_apart_from_the_applied_ones(launch, probe):
    """Lockstep baseline in turbulence, 20 s, twice: alone, and with a second publisher on control/pitch_command
    answering the plant's steps ahead of mbc (`_feathered`) from step 100 until the plant has reported it and 40
    commands are sent. The bag holds the intruder's commands in a channel of their own, and analyze gives the
    intruded run the commanded pitch activity (travel, rates, duty cycle, flags) of the run without it, and one
    refused_commands entry naming the intruder with the messages of its channel and their steps."""
    arguments = ("wind_type:=turbulent", "seed:=3", "duration:=20")
    alone = launch("baseline", "refused_alone", *arguments)
    alone.finish()
    namespace = "refused"
    intruder = probe(namespace)
    # The intruder offers volatile, mbc transient local: the recorder takes the intruder's commands through a second
    # subscription (hawt_bag.recorder's module notes)
    topic = f"/{namespace}/control/pitch_command"
    run = launch("baseline", namespace, *arguments)
    intruder.wait_until_recorded(run.launcher, margin=0)
    intruder.wait_for_step(100, run.launcher)
    intruder.publish_until({"control/pitch_command": _feathered},
                           lambda: intruder.reported("intruder") and intruder.published >= 40,
                           run.launcher, "the plant's intruder event and 40 commands sent")
    run.finish()

    with BagReader(run.bag) as reader:
        (command,) = [t for t in reader.info().topics if t.topic == topic]
    recorded = dict(command.publishers)
    assert set(recorded) == {f"/{namespace}/mbc", "/fault_probe"}, recorded
    expected, summary = analyze_bag(alone.bag).summary, analyze_bag(run.bag).summary
    assert summary["pitch_command"] == expected["pitch_command"]
    (refused,) = summary["refused_commands"]
    assert refused["publisher"] == "/fault_probe"
    assert refused["messages"] == recorded["/fault_probe"] <= intruder.published
    assert 100 <= refused["first_step"] <= refused["last_step"] <= 2000  # within the run's steps 0-2000 (20 s, 100 Hz)
    assert expected["refused_commands"] == [] and summary["warnings"] == []
