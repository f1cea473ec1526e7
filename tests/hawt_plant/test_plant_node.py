"""The plant node in a real graph: lockstep runs are bit-identical, bad commands are never applied."""
import math
import subprocess
import sys
import time

import numpy as np
import pytest
import rclpy
from hawt_msgs.msg import BladeLoads, ControlEvent, PitchCommand
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy

pytestmark = pytest.mark.ros

_QOS = QoSProfile(depth=5000, reliability=ReliabilityPolicy.RELIABLE)


@pytest.fixture(scope="module")
def node():
    rclpy.init()
    node = Node("plant_node_test")
    yield node
    node.destroy_node()
    rclpy.shutdown()


def _run_baseline(node: Node, hawt_cli, namespace: str, *arguments: str, busy: bool = False) -> dict:
    """Run the baseline graph under ``namespace`` and collect its blade loads by step."""
    received = {}
    subscription = node.create_subscription(BladeLoads, f"/{namespace}/plant/blade_loads",
                                            lambda m: received.setdefault(m.step, m), _QOS)
    hog = subprocess.Popen([sys.executable, "-c", "while True: pass"]) if busy else None
    launcher = subprocess.Popen([*hawt_cli, "launch", "baseline", f"namespace:={namespace}", *arguments],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        while launcher.poll() is None:
            rclpy.spin_once(node, timeout_sec=0.01)
        for _ in range(50):
            rclpy.spin_once(node, timeout_sec=0.01)
        assert launcher.returncode == 0, launcher.stdout.read()
    finally:
        if hog is not None:
            hog.kill()
        node.destroy_subscription(subscription)
    return received


def _fields(msg: BladeLoads) -> tuple:
    return (msg.header.stamp.sec, msg.header.stamp.nanosec, msg.azimuth, msg.rotor_speed,
            tuple(msg.root_moment_oop), tuple(msg.root_moment_ip), tuple(msg.pitch))


def test_two_lockstep_runs_give_bit_identical_blade_loads_even_with_a_busy_core(node, hawt_cli):
    """Same graph, same wind: every step's blade loads are equal to the bit, the second run beside a CPU hog."""
    first = _run_baseline(node, hawt_cli, "det1", "duration:=4", "-p", "plant.wait_for_subscribers:=3")
    second = _run_baseline(node, hawt_cli, "det2", "duration:=4", "-p", "plant.wait_for_subscribers:=3", busy=True)
    common = sorted(set(first) & set(second))
    assert len(common) >= 0.95 * 400
    assert [_fields(first[k]) for k in common] == [_fields(second[k]) for k in common]
    assert len({_fields(first[k]) for k in common}) == len(common), "the loads change from step to step"


def test_a_bad_pitch_command_is_not_applied_and_is_reported(node, hawt_cli):
    """NaN, wrong length and out-of-range commands are refused on control/events; the plant holds the last valid one."""
    events, loads = [], {}
    node.create_subscription(ControlEvent, "/bad/control/events", events.append, _QOS)
    node.create_subscription(BladeLoads, "/bad/plant/blade_loads", lambda m: loads.setdefault(m.step, m), _QOS)
    publisher = node.create_publisher(PitchCommand, "/bad/control/pitch_command", _QOS)
    plant = subprocess.Popen([sys.executable, "-c", "from hawt_plant.plant_node import main; main()", "--ros-args", "-r", "__ns:=/bad",
                              "-p", "duration:=0.05", "-p", "resend_period:=0.2",
                              "-p", "wait_for_subscribers:=1", "-p", "command_sources:=['/plant_node_test']"],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        deadline = time.monotonic() + 30
        while 0 not in loads and time.monotonic() < deadline:
            rclpy.spin_once(node, timeout_sec=0.05)
        start = loads[0]
        bad = [PitchCommand(step=0, pitch=[math.nan, 0.2, 0.2], generator_torque=4e4),
               PitchCommand(step=1, pitch=[0.2, 0.2], generator_torque=4e4),
               PitchCommand(step=2, pitch=[0.2, 2.0, 0.2], generator_torque=4e4),
               PitchCommand(step=3, pitch=[0.2, 0.2, 0.2], generator_torque=-1.0)]
        for step, command in enumerate(bad):
            while step not in loads and time.monotonic() < deadline:
                rclpy.spin_once(node, timeout_sec=0.05)
            publisher.publish(command)
        while plant.poll() is None and time.monotonic() < deadline:
            rclpy.spin_once(node, timeout_sec=0.05)
        for _ in range(20):
            rclpy.spin_once(node, timeout_sec=0.02)
    finally:
        plant.kill()
    rejected = [e for e in events if e.kind == "invalid_input"]
    reasons = [e.detail.split(" not applied (")[1] for e in rejected]
    assert len(reasons) == 4
    for reason, start_of_reason in zip(reasons, ("not finite: pitch [nan", "pitch: expected 3 values, found 2",
                                                 "pitch [0.2, 2.0, 0.2] outside [0.0, 1.5", "generator_torque -1.0 outside")):
        assert reason.startswith(start_of_reason)
    assert all(e.level == ControlEvent.ERROR for e in rejected)
    # the held command is the operating point's: pitch moves only by the actuator's settling, never to 0.2 rad
    assert all(np.allclose(loads[k].pitch, start.pitch, atol=1e-3) for k in loads)


def test_the_plant_node_resolves_its_aerodynamic_options_as_the_in_process_runner_does(node):
    """Declared on a ROS node, 'turbine' takes the turbine's option and an override (a bool, through the dynamically
    typed descriptor) replaces it: the model's options are make_plant's for the same values."""
    from rclpy.parameter import Parameter

    from hawt_core.parameter_table import resolve_values
    from hawt_plant.plant_node import PlantNode
    from hawt_plant.plant_setup import PARAMETERS, make_plant

    overrides = {"skewed_wake": False, "dynamic_inflow": True}
    plant = PlantNode(context=node.context, namespace="aero_options",
                      parameter_overrides=[Parameter(name, value=value) for name, value in overrides.items()])
    try:
        assert (plant.values["skewed_wake"], plant.values["unsteady_airfoil"]) == (False, "turbine")
        assert plant.model.config == make_plant(resolve_values(PARAMETERS, overrides))[1].config
        assert (plant.model.config.skewed_wake, plant.model.config.unsteady_airfoil,
                plant.model.config.dynamic_inflow) == (False, True, True)
    finally:
        plant.destroy_node()
