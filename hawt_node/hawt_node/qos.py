"""Quality-of-service profiles of the control loop (DESIGN.md §4)."""
from rclpy.event_handler import SubscriptionEventCallbacks
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

__all__ = ["CONTROL_LOOP", "CONTROL_LOOP_HISTORY", "EVENTS", "LATCHED", "NO_QOS_EVENTS"]

#: Measurements and commands: reliable, keep the last sample only.
CONTROL_LOOP = QoSProfile(
    history=HistoryPolicy.KEEP_LAST,
    depth=1,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.VOLATILE,
)

#: What a control-loop publisher keeps: reliable like CONTROL_LOOP, but a reader that falls
#: behind (a recorder, a test, a plot) by up to this many samples still gets every one of them,
#: and a transient-local reader that joins late (a respawned recorder) gets the last ones sent.
#: Depth and durability offered do not stop a volatile reader from matching, so controllers
#: still read with CONTROL_LOOP (latest only, nothing from before they joined).
CONTROL_LOOP_HISTORY = QoSProfile(
    history=HistoryPolicy.KEEP_LAST,
    depth=2000,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)

#: Events: reliable, deep enough not to drop bursts, kept for a recorder that joins late.
EVENTS = QoSProfile(
    history=HistoryPolicy.KEEP_LAST,
    depth=100,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)

LATCHED = QoSProfile(
    history=HistoryPolicy.KEEP_LAST,
    depth=100,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)
"""Switches and controller states: a node that starts later still receives what was published before."""

NO_QOS_EVENTS = SubscriptionEventCallbacks(use_default_callbacks=False)
"""A subscription without rclpy's default QoS event handlers (incompatible QoS and type, which only log), for a node
spun by rclpy's SingleThreadedExecutor that takes a sample every step (the recorder, the launcher's event node): that
executor rebuilds its wait set for every wait, two or three handlers per subscription (a 20 s realtime switching
graph's recorder spent most of its CPU there)."""
