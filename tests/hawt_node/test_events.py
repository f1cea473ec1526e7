"""EventPublisher: every event goes out on control/events and into the node's log, whatever its level."""
import pytest
import rclpy
from hawt_msgs.msg import ControlEvent
from rclpy.node import Node

from hawt_node.events import EventPublisher

pytestmark = pytest.mark.ros


def test_one_publisher_logs_events_of_every_level_one_after_the_other():
    """ERROR then INFO then WARN then DEBUG from one publisher: rclpy's one-severity-per-call-site rule is not hit."""
    context = rclpy.Context()
    rclpy.init(context=context)
    try:
        node = Node("events_test", context=context)
        events = EventPublisher(node)
        for level in (ControlEvent.ERROR, ControlEvent.INFO, ControlEvent.WARN, ControlEvent.DEBUG, ControlEvent.ERROR):
            events(level, "test", f"level {level}")
        node.destroy_node()
    finally:
        rclpy.shutdown(context=context)
