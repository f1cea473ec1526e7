"""The controller base node built in this process: configure from plant/description, refusals, live parameters.

A test node plays the plant: it publishes plant/description (latched) and the measurements of
each step, and reads what the controller answers; both spin on one executor in this process.
"""
import math

import numpy as np
import pytest
import rclpy
from hawt_msgs.msg import BladeLoads, ControlEvent, ControllerSwitch, HarmonicPitch, PlantDescription, TurbineState
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter

from hawt_controllers.ros.controller_node import ControllerNode
from hawt_controllers.ros.mbc_node import MbcNode
from hawt_core.topics import BLADE_LOADS, EVENTS, PLANT_DESCRIPTION, SWITCHES, TURBINE_STATE, ipc_topic
from hawt_plant.turbine import nrel_5mw
from hawt_node.qos import CONTROL_LOOP_HISTORY, EVENTS as EVENTS_QOS, LATCHED

pytestmark = pytest.mark.ros


class FakePlant(Node):
    """Publishes the description and each step's measurements; keeps what comes back."""

    def __init__(self, context, blades: int = 3, dt: float = 0.01) -> None:
        super().__init__("fake_plant", namespace="cn", context=context)
        description = nrel_5mw().description(dt)
        fields = {**description.as_fields(), "blades": blades}
        self.create_publisher(PlantDescription, PLANT_DESCRIPTION, LATCHED).publish(PlantDescription(**fields))
        self.loads = self.create_publisher(BladeLoads, BLADE_LOADS, CONTROL_LOOP_HISTORY)
        self.state = self.create_publisher(TurbineState, TURBINE_STATE, CONTROL_LOOP_HISTORY)
        self.events, self.answers = [], {}
        self.create_subscription(ControlEvent, EVENTS, self.events.append, EVENTS_QOS)
        self.create_subscription(HarmonicPitch, ipc_topic(1), lambda m: self.answers.setdefault(m.step, m),
                                 CONTROL_LOOP_HISTORY)

    def send(self, step: int, oop=(1.2e6, 0.8e6, 1.0e6)) -> None:
        msg = BladeLoads(step=step, azimuth=0.3, rotor_speed=1.267, root_moment_oop=list(oop),
                         root_moment_ip=[0.0, 0.0, 0.0], pitch=[0.25, 0.25, 0.25])
        msg.header.stamp.nanosec = 10_000_000 * step
        self.loads.publish(msg)


@pytest.fixture
def graph():
    context = rclpy.Context()
    rclpy.init(context=context)
    executor = SingleThreadedExecutor(context=context)
    nodes = []

    def add(node):
        nodes.append(node)
        executor.add_node(node)
        return node

    def spin_until(condition, what: str, limit: int = 20000):
        for _ in range(limit):
            if condition():
                return
            executor.spin_once(timeout_sec=0.01)
        raise AssertionError(f"not reached: {what}")

    yield context, add, spin_until
    executor.shutdown()
    for node in nodes:
        node.destroy_node()
    rclpy.shutdown(context=context)


def _arguments(**parameters) -> list:
    arguments = ["--ros-args", "-r", "__ns:=/cn"]
    for name, value in parameters.items():
        arguments += ["-p", f"{name}:={value}"]
    return arguments


def test_a_blade_count_that_conflicts_with_plant_description_is_refused_at_configure(graph):
    """blade_sine with two amplitudes on a three-bladed plant stays unconfigured; one event names both values."""
    context, add, spin_until = graph
    plant = add(FakePlant(context))
    sine = add(ControllerNode("blade_sine", context=context, cli_args=_arguments(amplitudes="[0.01,0.01]")))
    spin_until(lambda: any(e.kind == "invalid_parameter" for e in plant.events), "the refusal event")
    refusal = next(e for e in plant.events if e.kind == "invalid_parameter")
    assert refusal.detail == "/cn/blade_sine: amplitudes: 2 entries conflict with plant/description blades 3"
    assert sine._state_machine.current_state[1] == "unconfigured"


def test_a_harmonic_the_transform_cannot_give_for_two_blades_is_refused(graph):
    """ipc of harmonic 1 on a two-bladed plant: refused at configure, naming n_blades (DESIGN §3: B = 2 is singular)."""
    context, add, spin_until = graph
    plant = add(FakePlant(context, blades=2))
    ipc = add(ControllerNode("ipc", context=context, cli_args=_arguments()))
    spin_until(lambda: any(e.kind == "invalid_parameter" for e in plant.events), "the refusal event")
    assert "n_blades: the MBC transform is singular for B=2" in plant.events[0].detail
    assert ipc._state_machine.current_state[1] == "unconfigured"


def test_live_parameters_are_checked_by_the_law_and_applied_at_the_next_step(graph):
    """A valid integral gain is accepted and applied from the next step (parameter_change event names the step);
    a NaN, max_amplitude = 0 (which the law refuses) and a gain of 1e30 (beyond the table's 1e-5) are rejected with
    the reason, the node stays up."""
    context, add, spin_until = graph
    plant = add(FakePlant(context))
    ipc = add(ControllerNode("ipc", context=context, cli_args=_arguments(ramp_time=0.0, lowpass_order=0)))
    spin_until(lambda: ipc._state_machine.current_state[1] == "active", "ipc active")
    plant.send(0)
    spin_until(lambda: 0 in plant.answers, "the answer of step 0")
    result, = ipc.set_parameters([Parameter("integral_gain", value=2e-8)])
    assert result.successful
    nan, = ipc.set_parameters([Parameter("integral_gain", value=math.nan)])
    assert not nan.successful and "integral_gain" in nan.reason
    zero, = ipc.set_parameters([Parameter("max_amplitude", value=0.0)])
    assert not zero.successful and "max_amplitude" in zero.reason
    absurd, = ipc.set_parameters([Parameter("integral_gain", value=1e30)])
    assert not absurd.successful and "integral_gain" in absurd.reason and "1e-05" in absurd.reason
    plant.send(1)
    spin_until(lambda: 1 in plant.answers, "the answer of step 1")
    change = [e for e in plant.events if e.kind == "parameter_change"]
    assert change and change[0].detail == "integral_gain=2e-08 (from step 1)" and change[0].step == 1
    # the integral doubled its slope: I(1) - I(0) = 2e-8 * e * dt with the same error e as step 0's 1e-8 * e * dt
    first, second = plant.answers[0], plant.answers[1]
    assert np.isclose(second.cos - first.cos, 2 * first.cos, rtol=1e-9)


def test_a_repeated_step_is_answered_again_without_advancing_the_law(graph):
    """The plant resends step 0: the same answer again, and step 1 continues from step 0's state."""
    context, add, spin_until = graph
    plant = add(FakePlant(context))
    ipc = add(ControllerNode("ipc", context=context, cli_args=_arguments(ramp_time=0.0, lowpass_order=0)))
    spin_until(lambda: ipc._state_machine.current_state[1] == "active", "ipc active")
    seen = []
    plant.create_subscription(HarmonicPitch, ipc_topic(1), seen.append, CONTROL_LOOP_HISTORY)
    plant.send(0)
    spin_until(lambda: len(seen) == 1, "one answer")
    plant.send(0)
    spin_until(lambda: len(seen) == 2, "the answer again")
    assert (seen[0].cos, seen[0].sin) == (seen[1].cos, seen[1].sin)
    plant.send(1)
    spin_until(lambda: len(seen) == 3, "step 1")
    assert np.isclose(seen[2].cos, 2 * seen[0].cos, rtol=1e-9)


def _ipc_in_handover_at_step_3(graph, plant: FakePlant, name: str) -> ControllerNode:
    """The 1P ipc ``name``, configured and knowing the switch that hands harmonic/1 from ipc_a (active) to ipc_b at
    step 3, which ``plant`` publishes."""
    context, add, spin_until = graph
    switch = ControllerSwitch(step=3, activate=["/cn/ipc_b"], activate_interfaces=["harmonic/1"],
                              deactivate=["/cn/ipc_a"], deactivate_interfaces=["harmonic/1"], ramp_time=0.0)
    plant.create_publisher(ControllerSwitch, SWITCHES, LATCHED).publish(switch)
    node = add(ControllerNode("ipc", context=context, cli_args=_arguments(active=name == "ipc_a", lowpass_order=0)
                              + ["-r", f"__node:={name}"]))
    spin_until(lambda: node.switches is not None and node.switches.pending, f"{name} configured, switch known")
    return node


def test_a_replacing_controller_waits_for_the_outgoing_output_of_the_step_before(graph):
    """ipc_b replaces ipc_a on harmonic/1 at step 3. The loads of step 3 reach ipc_b before ipc_a's output of
    step 2 (a busy machine may deliver them so): ipc_b answers nothing until that output is there, then starts
    from it — not from the step 1 output it already had — so the handover is the same on every run."""
    context, add, spin_until = graph
    plant = add(FakePlant(context))
    outgoing = plant.create_publisher(HarmonicPitch, ipc_topic(1), CONTROL_LOOP_HISTORY)
    incoming = _ipc_in_handover_at_step_3(graph, plant, "ipc_b")
    for step, cos in ((0, 0.01), (1, 0.02)):
        outgoing.publish(HarmonicPitch(step=step, harmonic=1, cos=cos, sin=0.0))
        plant.send(step)
        spin_until(lambda: incoming.answer.last is not None and incoming.answer.last.step == step, f"step {step}")
    plant.send(2)
    spin_until(lambda: incoming.answer.last.step == 2, "step 2")
    plant.send(3)
    spin_until(lambda: incoming.deferred is not None and incoming.deferred.step == 3, "step 3 held for the handover")
    assert 3 not in plant.answers
    outgoing.publish(HarmonicPitch(step=2, harmonic=1, cos=0.05, sin=-0.01))
    spin_until(lambda: 3 in plant.answers, "ipc_b's answer of step 3")
    assert abs(plant.answers[3].cos - 0.05) < 1e-3 and abs(plant.answers[3].sin + 0.01) < 1e-3
    assert any(e.kind == "switch" and "from the outgoing controller's last output" in e.detail for e in plant.events)


def test_a_controller_handed_over_at_a_step_it_never_saw_reports_the_switch_at_that_step(graph):
    """ipc_a hands harmonic/1 over to ipc_b at step 3. From step 3 on nothing of ipc_a is used, so the plant does not
    wait for it: a busy node may next see step 5. It answered nothing from step 3 on, so the switch took effect at
    step 3, and it says so, not that it came late; step 5 gets no output from it."""
    context, add, spin_until = graph
    plant = add(FakePlant(context))
    outgoing = _ipc_in_handover_at_step_3(graph, plant, "ipc_a")
    for step in (0, 1, 2, 5):
        plant.send(step)
        spin_until(lambda: outgoing.answer.last is not None and outgoing.answer.last.step == step, f"step {step}")
    spin_until(lambda: any(e.kind == "switch" for e in plant.events), "ipc_a's switch event")
    switches = [e for e in plant.events if e.kind == "switch"]
    assert [(e.step, e.level, e.detail) for e in switches] == [
        (3, ControlEvent.INFO, "deactivated at step 3, handing over")]
    assert sorted(plant.answers) == [0, 1, 2]


def test_with_await_schedule_no_step_is_answered_before_the_schedule_so_a_switch_at_step_0_is_on_time(graph):
    """An inactive ipc with await_schedule (hawt launch sets it in a graph with a controller_manager): step 0, sent
    again and again, gets no answer while the schedule is missing; once the schedule (activate it at step 0) is
    there, step 0 is answered by the active controller. Without the wait it would have answered step 0 inactive,
    and a resent step is never recomputed: the switch would have come one step late."""
    from hawt_msgs.msg import ControllerSchedule
    from hawt_core.topics import SCHEDULE

    context, add, spin_until = graph
    plant = add(FakePlant(context))
    ipc = add(ControllerNode("ipc", context=context, cli_args=_arguments(active=False, await_schedule=True, ramp_time=0.0)
                      + ["-r", "__node:=ipc_h1"]))
    spin_until(lambda: ipc.switches is not None and plant.loads.get_subscription_count() == 1, "ipc configured")
    sends = 0

    def sent_again() -> bool:
        nonlocal sends
        plant.send(0)
        sends += 1
        return sends == 50

    spin_until(sent_again, "step 0 sent 50 times")
    assert plant.answers == {} and ipc.answer.last is None
    switch = ControllerSwitch(step=0, activate=["/cn/ipc_h1"], activate_interfaces=["harmonic/1"], ramp_time=0.0)
    plant.create_publisher(ControllerSchedule, SCHEDULE, LATCHED).publish(ControllerSchedule(switches=[switch]))
    spin_until(lambda: ipc.switches.has_schedule, "the schedule received")
    plant.send(0)
    spin_until(lambda: 0 in plant.answers, "the answer of step 0")
    assert ipc._state_machine.current_state[1] == "active"


def test_the_schedule_is_published_in_one_message_once_the_controllers_it_names_have_announced(graph):
    """controller_manager with schedule ['5 +ipc_b']: nothing on controller_manager/schedule while ipc_b is unknown
    (it cannot be planned); once ipc_b announces itself, one latched message with the switch of step 5."""
    from hawt_controllers.ros.controller_manager_node import ControllerManagerNode
    from hawt_msgs.msg import ControllerSchedule
    from hawt_core.topics import SCHEDULE

    context, add, spin_until = graph
    plant = add(FakePlant(context))
    schedules = []
    plant.create_subscription(ControllerSchedule, SCHEDULE, schedules.append, LATCHED)
    manager = add(ControllerManagerNode(context=context, cli_args=_arguments(schedule="['5 +ipc_b']")))
    spin_until(lambda: manager.dt is not None, "the manager has the plant's description")
    for _ in range(20):
        manager._run_schedule()  # what its timer does: ipc_b has not announced, so nothing is planned
    assert schedules == [] and manager.schedule
    add(ControllerNode("ipc", context=context, cli_args=_arguments(active=False) + ["-r", "__node:=ipc_b"]))
    spin_until(lambda: schedules and manager.schedule_timer.is_canceled(), "the schedule, published once")
    schedule, = schedules
    switch, = schedule.switches
    assert (switch.step, list(switch.activate), list(switch.activate_interfaces)) == (5, ["/cn/ipc_b"],
                                                                                        ["harmonic/1"])


def test_a_contributor_still_starting_at_the_first_step_is_waited_for_not_lost(graph):
    """mbc with cpc and an ipc_h1 that waits for a schedule nobody has published yet: step 0 goes unanswered by
    ipc_h1 for longer than input_timeout (0.2 s here), which is not a loss while no command has gone out (the nodes
    are starting: start_timeout); once ipc_h1 answers, step 0's command includes it and no contribution_lost."""
    import time

    from hawt_controllers.ros.mbc_node import MbcNode
    from hawt_msgs.msg import ControllerSchedule, PitchCommand
    from hawt_core.topics import PITCH_COMMAND, SCHEDULE

    context, add, spin_until = graph
    plant = add(FakePlant(context))
    commands = []
    plant.create_subscription(PitchCommand, PITCH_COMMAND, commands.append, CONTROL_LOOP_HISTORY)
    add(ControllerNode("cpc", context=context, cli_args=_arguments()))
    ipc = add(ControllerNode("ipc", context=context, cli_args=_arguments(await_schedule=True, ramp_time=0.0)
                      + ["-r", "__node:=ipc_h1"]))
    mbc = add(MbcNode(context=context, cli_args=_arguments(controllers="[cpc, ipc_h1]", input_timeout=0.2)))
    spin_until(lambda: ipc.switches is not None and mbc.assembler is not None and mbc.expected <= mbc.announced
               and plant.loads.get_subscription_count() >= 3, "the graph configured")

    def send_step_0() -> None:
        plant.state.publish(TurbineState(step=0, generator_speed=122.9, generator_torque=43093.0))
        plant.send(0)

    send_step_0()
    spin_until(lambda: mbc.loads is not None, "mbc has step 0")
    spin_until(lambda: time.monotonic() - mbc.loads_received > 0.5, "more than input_timeout without ipc_h1")
    assert commands == [] and not any(e.kind == "contribution_lost" for e in plant.events)
    plant.create_publisher(ControllerSchedule, SCHEDULE, LATCHED).publish(ControllerSchedule())
    spin_until(lambda: ipc.switches.has_schedule, "ipc_h1 has the schedule")
    send_step_0()  # the plant resends an unanswered step
    spin_until(lambda: commands, "step 0's command")
    assert commands[0].step == 0 and any(abs(v) > 0.0 for v in commands[0].individual)
    assert not any(e.kind == "contribution_lost" for e in plant.events)


def test_the_loop_assemblers_live_limits_may_narrow_the_turbines_never_widen_them(graph):
    """mbc on the NREL 5 MW's description (0..90 deg, 8 deg/s): max_pitch_rate 1 rad/s (57 deg/s) and min_pitch
    -0.5 rad are refused, naming the turbine's value, and the assembler keeps the turbine's limits; 4 deg/s is
    accepted and applied."""
    context, add, spin_until = graph
    add(FakePlant(context))
    mbc = add(MbcNode(context=context, cli_args=_arguments()))
    spin_until(lambda: mbc.assembler is not None, "mbc has the plant's description")
    turbine = nrel_5mw().pitch_actuator
    assert (mbc.assembler.limits.min_angle, mbc.assembler.limits.max_angle, mbc.assembler.limits.max_rate) == \
        (turbine.min_angle, turbine.max_angle, turbine.max_rate)
    for name, value, beyond in (("max_pitch_rate", 1.0, "max_pitch_rate 1 beyond the turbine's 0.139626"),
                                ("min_pitch", -0.5, "min_pitch -0.5 beyond the turbine's 0")):
        result, = mbc.set_parameters([Parameter(name, value=value)])
        assert not result.successful and result.reason.startswith(beyond) and "never widen" in result.reason
    assert mbc.assembler.limits.max_rate == turbine.max_rate and mbc.assembler.limits.min_angle == 0.0
    narrower, = mbc.set_parameters([Parameter("max_pitch_rate", value=math.radians(4.0))])
    assert narrower.successful and mbc.assembler.limits.max_rate == pytest.approx(math.radians(4.0))
