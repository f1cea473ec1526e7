"""Quality-of-service profiles of the control loop (DESIGN.md §4)."""
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

__all__ = ["CONTROL_LOOP", "EVENTS"]

#: Measurements and commands: reliable, keep the last sample only.
CONTROL_LOOP = QoSProfile(
    history=HistoryPolicy.KEEP_LAST,
    depth=1,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.VOLATILE,
)

#: Events: the ROS default (reliable, keep last 10), deep enough not to drop bursts.
EVENTS = QoSProfile(
    history=HistoryPolicy.KEEP_LAST,
    depth=100,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.VOLATILE,
)
