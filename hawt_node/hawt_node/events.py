"""Publishing ``control/events``: every switch, saturation, rejected input and parameter change."""
from builtin_interfaces.msg import Time
from hawt_msgs.msg import ControlEvent
from rclpy.node import Node

from hawt_node.qos import EVENTS
from hawt_core.topics import EVENTS as EVENTS_TOPIC

__all__ = ["EventPublisher"]


class EventPublisher:
    """Publishes ControlEvent messages for one node and logs them at the matching level."""

    def __init__(self, node: Node) -> None:
        self._node = node
        self._publisher = node.create_publisher(ControlEvent, EVENTS_TOPIC, EVENTS)

    def __call__(self, level: int, kind: str, detail: str, step: int = 0, stamp: Time = None) -> None:
        msg = ControlEvent(step=step, source=self._node.get_fully_qualified_name(), level=level, kind=kind,
                           detail=detail)
        if stamp is not None:
            msg.header.stamp = stamp
        self._publisher.publish(msg)
        # rclpy ties a severity to each calling line ("Logger severity cannot be changed between
        # calls"), so each level is logged from a line of its own.
        logger, text = self._node.get_logger(), f"{kind}: {detail}"
        if level == ControlEvent.DEBUG:
            logger.debug(text)
        elif level == ControlEvent.INFO:
            logger.info(text)
        elif level == ControlEvent.WARN:
            logger.warning(text)
        else:
            logger.error(text)
