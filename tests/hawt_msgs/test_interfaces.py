"""Every hawt_msgs message and service crosses a real process boundary over DDS unchanged."""
import json
import math
import subprocess
import sys
import time
from pathlib import Path

import hawt_msgs.msg
import pytest
import rclpy
from hawt_msgs.srv import ListControllers, SwitchControllers
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy

from message_samples import MESSAGE_TYPES, filled
from ros_echo import LISTING

pytestmark = pytest.mark.ros


@pytest.fixture(scope="module")
def echo_process():
    process = subprocess.Popen([sys.executable, str(Path(__file__).resolve().parent.parent / "ros_echo.py")])
    yield process
    process.terminate()
    try:
        process.wait(timeout=30)
    except subprocess.TimeoutExpired:  # it did not end on SIGTERM in time (once, in a fresh-clone run): no orphan
        process.kill()
        process.wait(timeout=10)


@pytest.fixture(scope="module")
def node(echo_process):
    rclpy.init()
    node = Node("interfaces_test")
    yield node
    node.destroy_node()
    rclpy.shutdown()


def _round_trip(node: Node, kind, sent: list, timeout: float = 15.0) -> list:
    qos = QoSProfile(depth=50, reliability=ReliabilityPolicy.RELIABLE)
    received = []
    subscription = node.create_subscription(kind, f"echo_out/{kind.__name__}", received.append, qos)
    publisher = node.create_publisher(kind, f"echo_in/{kind.__name__}", qos)
    try:
        deadline = time.monotonic() + timeout
        # Both directions are matched once a warm-up message has come back; send it until it does.
        while not received and time.monotonic() < deadline:
            publisher.publish(kind())
            end = time.monotonic() + 0.2
            while not received and time.monotonic() < end:
                rclpy.spin_once(node, timeout_sec=0.02)
        for _ in range(10):
            rclpy.spin_once(node, timeout_sec=0.01)
        received.clear()
        for msg in sent:
            publisher.publish(msg)
        while len(received) < len(sent) and time.monotonic() < deadline:
            rclpy.spin_once(node, timeout_sec=0.05)
        return received
    finally:
        node.destroy_publisher(publisher)
        node.destroy_subscription(subscription)


@pytest.mark.parametrize("type_name", MESSAGE_TYPES)
def test_every_message_field_round_trips_between_processes(node, type_name):
    """Each field of each message, with arrays of B = 2 and B = 3, comes back from another process unchanged."""
    kind = getattr(hawt_msgs.msg, type_name)
    sent = [filled(kind, index, blades) for index, blades in enumerate((2, 3, 3, 2))]
    received = _round_trip(node, kind, sent)
    assert received == sent


def test_nan_wind_speed_estimate_survives_the_round_trip(node):
    """The 'no estimate' NaN of CollectivePitch arrives as NaN."""
    sent = hawt_msgs.msg.CollectivePitch(pitch=0.1, wind_speed_estimate=math.nan, region=25)
    received, = _round_trip(node, hawt_msgs.msg.CollectivePitch, [sent])
    assert math.isnan(received.wind_speed_estimate) and received.pitch == 0.1 and received.region == 25


def _call(node: Node, kind, name: str, request):
    client = node.create_client(kind, name)
    try:
        assert client.wait_for_service(timeout_sec=15.0), f"{name} not available"
        future = client.call_async(request)
        rclpy.spin_until_future_complete(node, future, timeout_sec=15.0)
        return future.result()
    finally:
        node.destroy_client(client)


def test_switch_controllers_request_and_response_round_trip(node):
    """SwitchControllers carries its lists, strictness and ramp time, and its response comes back."""
    request = SwitchControllers.Request(activate=["ipc_h1", "ipc_h2"], deactivate=["ipc_h3"],
                                        strictness=SwitchControllers.Request.STRICT, ramp_time=2.5)
    response = _call(node, SwitchControllers, "echo/switch_controllers", request)
    assert response.ok
    assert json.loads(response.message) == {"activate": ["ipc_h1", "ipc_h2"], "deactivate": ["ipc_h3"],
                                            "strictness": 2, "ramp_time": 2.5}
    assert response.effective_step == 2**63 + 2


def test_list_controllers_response_round_trips(node):
    """ListControllers' names, types, states and claimed interfaces arrive in order."""
    response = _call(node, ListControllers, "echo/list_controllers", ListControllers.Request())
    assert {"names": list(response.names), "types": list(response.types), "states": list(response.states),
            "interfaces": list(response.interfaces)} == LISTING
