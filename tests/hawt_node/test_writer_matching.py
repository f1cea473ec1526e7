"""MatchedWriterGate: a node's first messages reach every reader the graph lists, in order, or a warning says
why not."""
from typing import List

import pytest
from hawt_msgs.msg import ControlEvent
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import Int32, String

from hawt_core.topics import EVENTS
from hawt_node.events import EventPublisher
from hawt_node.qos import CONTROL_LOOP, CONTROL_LOOP_HISTORY, EVENTS as EVENTS_QOS
from hawt_node.writer_matching import MatchedWriterGate, can_match, unmatched_writers
from ros_probe import ProbeNode

pytestmark = pytest.mark.ros

TOPIC = "/writer_matching_test"


def _listed(probe: ProbeNode, count: int) -> bool:
    return len(probe.node.get_subscriptions_info_by_topic(TOPIC)) >= count


def test_messages_sent_before_the_writer_matches_a_listed_reader_all_arrive_in_order():
    reader, writer = ProbeNode("gate_reader", background=True), ProbeNode("gate_writer")
    received: List[int] = []
    try:
        reader.node.create_subscription(Int32, TOPIC, lambda m: received.append(m.data), CONTROL_LOOP_HISTORY)
        publisher = writer.node.create_publisher(Int32, TOPIC, CONTROL_LOOP_HISTORY)
        gate = MatchedWriterGate(writer.node, {TOPIC: publisher}, publisher.publish, EventPublisher(writer.node))
        writer.wait_until(lambda: _listed(writer, 1), "the reader in the graph")
        messages = [Int32(data=k) for k in range(50)]
        for message in messages:
            gate.send(message)
        writer.wait_until(lambda: gate.open and not gate.held, "the gate open")
        gate.send(Int32(data=50))
        writer.wait_until(lambda: len(received) >= 51, "51 messages at the reader")
        writer.spin(0.1)
        assert received == list(range(51))
        assert unmatched_writers(writer.node, {TOPIC: publisher}) == []
    finally:
        for probe in (reader, writer):
            probe.close()


def test_a_reader_that_never_matches_holds_the_messages_only_up_to_the_limit_and_is_reported():
    """A reader of another type on the topic is listed by the graph but never matched by the middleware."""
    reader, writer = ProbeNode("gate_reader", background=True), ProbeNode("gate_writer")
    other = ProbeNode("gate_reader_of_strings", background=True)
    received: List[int] = []
    events: List[ControlEvent] = []
    try:
        reader.node.create_subscription(Int32, TOPIC, lambda m: received.append(m.data), CONTROL_LOOP_HISTORY)
        other.node.create_subscription(String, TOPIC, lambda m: None, CONTROL_LOOP_HISTORY)
        reader.node.create_subscription(ControlEvent, EVENTS, events.append, EVENTS_QOS)
        publisher = writer.node.create_publisher(Int32, TOPIC, CONTROL_LOOP_HISTORY)
        gate = MatchedWriterGate(writer.node, {TOPIC: publisher}, publisher.publish, EventPublisher(writer.node),
                                 hold_limit=0.5)
        writer.wait_until(lambda: _listed(writer, 2), "both readers in the graph")
        writer.wait_until(lambda: publisher.get_subscription_count() == 1, "the Int32 reader matched")
        messages = [Int32(data=k) for k in range(3)]
        for message in messages:
            gate.send(message)
        gate.send(messages[-1])  # a repeated step's answer, sent again while held: kept once
        assert received == [] and len(gate.held) == 3
        writer.wait_until(lambda: len(received) == 3 and events, "the held messages and the warning")
        assert received == [0, 1, 2]
        assert events[0].kind == "unmatched_reader" and events[0].level == ControlEvent.WARN
        assert TOPIC in events[0].detail and "3 message(s)" in events[0].detail
        assert gate.open and unmatched_writers(writer.node, {TOPIC: publisher}) == [TOPIC]
    finally:
        for probe in (reader, other, writer):
            probe.close()


def test_a_reader_counts_only_if_dds_can_match_it_by_reliability_and_durability():
    reliable_volatile = CONTROL_LOOP
    best_effort = QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT)
    transient_local = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    assert can_match(reliable_volatile, reliable_volatile)
    assert can_match(reliable_volatile, best_effort)
    assert not can_match(best_effort, reliable_volatile)
    assert not can_match(reliable_volatile, transient_local)
    assert can_match(transient_local, reliable_volatile)
    assert can_match(CONTROL_LOOP_HISTORY, transient_local), "a respawned recorder gets the loop's history"


def test_a_recorded_node_holds_its_messages_until_the_recorder_subscribes_to_its_topic():
    """No reader the graph lists is enough while the recorder has not subscribed yet (wait_for_recorder)."""
    writer = ProbeNode("gate_writer")
    recorder = None
    received: List[int] = []
    try:
        publisher = writer.node.create_publisher(Int32, TOPIC, CONTROL_LOOP_HISTORY)
        gate = MatchedWriterGate(writer.node, {TOPIC: publisher}, publisher.publish, EventPublisher(writer.node),
                                 hold_limit=600.0, recorder="gate_recorder")
        for k in range(3):
            gate.send(Int32(data=k))
        writer.spin(0.2)
        assert not gate.open and len(gate.held) == 3
        recorder = ProbeNode("gate_recorder", background=True)
        recorder.node.create_subscription(Int32, TOPIC, lambda m: received.append(m.data), CONTROL_LOOP_HISTORY)
        writer.wait_until(lambda: len(received) == 3, "the held messages at the recorder")
        assert received == [0, 1, 2] and gate.open
    finally:
        for probe in (writer, recorder):
            if probe is not None:
                probe.close()
