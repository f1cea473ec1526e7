"""Holding a node's first messages until its writers are matched with every reader the graph lists.

A reader (the recorder, the loop assembler) that sees a writer is not yet seen by that writer: DDS
discovery is two-sided, and a reliable volatile writer sends only to readers it has matched. On a busy
machine the plant's first steps reach a controller before the controller's writer has matched the
recorder, and those contributions were missing from the bag. The gate keeps a node's messages until
each writer's matched count (``Publisher.get_subscription_count``: the middleware's matches) covers
every QoS-compatible subscription the graph lists on its topic, then publishes them in order. Once open
it stays open: it costs one graph query per message only until then.

A node of a recorded graph (``wait_for_recorder``, which ``hawt launch --record`` gives every node) also
waits until its graph lists the recorder's subscription on each of its topics: the plant starts once *it*
sees the recorder everywhere, and a node that answered step 0 before it had discovered the recorder's
subscription counted no reader to wait for (a stress run lost step 0 of ``control/pitch_command``).
"""
import time
from typing import Any, Callable, List, Mapping, Optional

from hawt_msgs.msg import ControlEvent
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

from hawt_core.node_role import HOLD_LIMIT
from hawt_node.events import EventPublisher
from hawt_node.recording import unrecorded_topics

__all__ = ["MatchedWriterGate", "can_match", "unmatched_writers"]


POLL_PERIOD = 0.005
"""Wall time [s] between two looks at the matches while messages are held."""


def can_match(writer: QoSProfile, reader: QoSProfile) -> bool:
    """DDS's request-offered rule for the two policies hawt sets: a reliable reader needs a reliable writer, a
    transient-local reader a transient-local writer (deadline and liveliness are left at their defaults, and
    rclpy reports a local profile's defaults differently from a discovered one's, so they are not compared)."""
    return not ((reader.reliability == ReliabilityPolicy.RELIABLE and writer.reliability != ReliabilityPolicy.RELIABLE)
                or (reader.durability == DurabilityPolicy.TRANSIENT_LOCAL
                    and writer.durability != DurabilityPolicy.TRANSIENT_LOCAL))


def unmatched_writers(node: Node, publishers: Mapping[str, Any]) -> List[str]:
    """The topics of ``publishers`` (topic → rclpy publisher) whose writer is matched with fewer readers than the
    QoS-compatible subscriptions ``node`` sees in the graph on that topic."""
    missing = []
    for topic, publisher in publishers.items():
        readers = [info for info in node.get_subscriptions_info_by_topic(topic)
                   if can_match(publisher.qos_profile, info.qos_profile)]
        if publisher.get_subscription_count() < len(readers):
            missing.append(topic)
    return missing


class MatchedWriterGate:
    """Publishes through ``publish`` once ``node``'s ``publishers`` are matched with every listed reader.

    ``send(message)`` publishes at once when the gate is open, else keeps the message; a timer of the
    node publishes what is kept, in order, when the writers match or after ``hold_limit`` seconds, then
    reports the topics whose readers were still unmatched as an ``unmatched_reader`` warning. With
    ``recorder`` (a node name), a topic the graph does not yet list that node's subscription on is unmatched.
    """

    def __init__(self, node: Node, publishers: Mapping[str, Any], publish: Callable[[Any], None],
                 events: EventPublisher, hold_limit: float = HOLD_LIMIT, recorder: Optional[str] = None) -> None:
        self.node = node
        self.publishers = publishers
        self.recorder = recorder
        self.publish = publish
        self.events = events
        self.hold_limit = hold_limit
        self.open = False
        self.held: List[Any] = []
        self.since: Optional[float] = None
        self.timer = None

    def send(self, message: Any) -> None:
        """Publish ``message`` now if the writers are matched, else keep it (a repeat of the last kept one
        is not kept twice)."""
        if self.open:
            self.publish(message)
            return
        if not self.held or self.held[-1] is not message:
            self.held.append(message)
        if self._try_open():
            self._release([])
        elif self.timer is None:
            self.since = time.monotonic()
            self.timer = self.node.create_timer(POLL_PERIOD, self._poll)

    def _unmatched(self) -> List[str]:
        unmatched = unmatched_writers(self.node, self.publishers)
        if self.recorder is not None:
            unmatched += [topic for topic in unrecorded_topics(self.node, self.publishers, self.recorder)
                          if topic not in unmatched]
        return unmatched

    def _try_open(self) -> bool:
        self.open = not self._unmatched()
        return self.open

    def _poll(self) -> None:
        if self._try_open():
            self._release([])
        elif time.monotonic() - self.since >= self.hold_limit:
            self.open = True
            self._release(self._unmatched())

    def _release(self, missing: List[str]) -> None:
        if self.timer is not None:
            self.node.destroy_timer(self.timer)
            self.timer = None
        held, self.held = self.held, []
        for message in held:
            self.publish(message)
        if missing:
            self.events(ControlEvent.WARN, "unmatched_reader", f"published after {self.hold_limit:g} s without a "
                        f"match with every reader the graph lists on {', '.join(missing)}: they may miss these "
                        f"first {len(held)} message(s)")
