"""Quality-of-service profiles of the control loop (DESIGN.md §4)."""
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

__all__ = ["CONTROL_LOOP", "CONTROL_LOOP_HISTORY", "EVENTS", "LATCHED"]

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
