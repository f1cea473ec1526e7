"""What the launcher has to say on ``control/events``: a node that died or is respawned, an interruption, a stop.

No node of the graph can report its own death, and the plant's ``finished`` event is missing when the graph is
stopped from outside (Ctrl-C, ``--duration`` of wall time). So ``hawt launch --record`` runs one more ROS node in
its own process, ``/hawt_launch``, which publishes these on the ``control/events`` of each namespace concerned,
stamped with the step and time of that namespace's latest ``plant/state`` (subscribed best effort, keep last 1: it
adds no reader the plant waits for; kept serialized and read only for an event, with no middleware event handlers or
parameter services beside it: this node takes every step's sample, and its executor's cost per sample grows with
what it waits on). Each event waits up to ``MATCH_WAIT`` for its writer to match every reader the graph lists (the
recorder) and for a first ``plant/state`` (on a busy machine this node once discovered the plant only after its
first 250 steps), ``HEAR_WAIT`` for the latter while the graph lists a publisher of ``plant/state`` (its samples are
on their way: an event at step 0 was once seen beside two busy loops), then goes out, at step 0 if the plant never
published; the launcher publishes it before it stops any node and waits until every matched reader has acknowledged
it, so the recorder has it when it stops.
"""
import threading
import time
from typing import Dict, Iterable, Tuple

import rclpy
from builtin_interfaces.msg import Time
from hawt_msgs.msg import ControlEvent, TurbineState
from rclpy.duration import Duration
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message
from rclpy.signals import SignalHandlerOptions

from hawt_core.topics import EVENTS, TURBINE_STATE
from hawt_node.qos import EVENTS as EVENTS_QOS, NO_QOS_EVENTS
from hawt_node.writer_matching import unmatched_writers

__all__ = ["HEAR_WAIT", "LaunchEvents", "MATCH_WAIT", "NODE_NAME"]

NODE_NAME = "hawt_launch"
MATCH_WAIT = 5.0
"""Wall time [s] an event waits at most for its writer to match the graph's readers of control/events and for
the namespace's first plant/state."""
HEAR_WAIT = 30.0
"""Wall time [s] an event waits at most for the namespace's first plant/state while the graph lists its publisher."""

_LATEST = QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT)


class LaunchEvents:
    """The launcher's ``/hawt_launch`` node (own context, executor thread) publishing ControlEvent messages.

    Call ``events(namespace, level, kind, detail)``; ``close()`` when the recorder has stopped.
    """

    def __init__(self, namespaces: Iterable[str]) -> None:
        self.context = rclpy.Context()
        # no arguments: the launcher's own (namespace:=wt1, …) would be read as ROS remap rules
        rclpy.init(args=[], context=self.context, signal_handler_options=SignalHandlerOptions.NO)
        self.node = Node(NODE_NAME, context=self.context, start_parameter_services=False)
        self.latest: Dict[str, Tuple[int, Time]] = {}
        self.received: Dict[str, bytes] = {}  # namespace: its latest plant/state, serialized
        self.publishers = {}
        for namespace in sorted(set(namespaces)):
            prefix = namespace.rstrip("/")
            self.latest[namespace] = (0, Time())
            self.publishers[namespace] = self.node.create_publisher(ControlEvent, f"{prefix}/{EVENTS}", EVENTS_QOS)
            self.node.create_subscription(TurbineState, f"{prefix}/{TURBINE_STATE}",
                                          lambda data, ns=namespace: self._heard(ns, data), _LATEST, raw=True,
                                          event_callbacks=NO_QOS_EVENTS)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.thread = threading.Thread(target=self.executor.spin, daemon=True)
        self.thread.start()

    def _heard(self, namespace: str, data: bytes) -> None:
        self.received[namespace] = data

    def _latest(self, namespace: str) -> Tuple[int, Time]:
        """The step and stamp of the latest plant/state heard in ``namespace`` (never going back)."""
        data = self.received.get(namespace)
        if data is not None:
            msg = deserialize_message(data, TurbineState)
            if msg.step >= self.latest[namespace][0]:
                self.latest[namespace] = (msg.step, msg.header.stamp)
        return self.latest[namespace]

    def __call__(self, namespace: str, level: int, kind: str, detail: str) -> None:
        publisher = self.publishers[namespace]
        start = time.monotonic()
        state = f"{namespace.rstrip('/')}/{TURBINE_STATE}"

        def waiting(waited: float) -> bool:
            if waited < MATCH_WAIT and unmatched_writers(self.node, {publisher.topic_name: publisher}):
                return True
            return namespace not in self.received and (waited < MATCH_WAIT or (
                waited < HEAR_WAIT and self.node.count_publishers(state) > 0))

        while waiting(time.monotonic() - start):
            time.sleep(0.01)
        step, stamp = self._latest(namespace)
        msg = ControlEvent(step=step, source=self.node.get_fully_qualified_name(), level=level, kind=kind,
                           detail=detail)
        msg.header.stamp = stamp
        publisher.publish(msg)
        # The launcher stops the recorder next: it takes what has arrived, so the event must have arrived (acked by
        # every matched reader; a fresh-clone run beside a busy suite once recorded no wall_clock_stop).
        publisher.wait_for_all_acked(Duration(seconds=MATCH_WAIT))

    def close(self) -> None:
        self.executor.shutdown()
        self.thread.join(timeout=5.0)
        self.node.destroy_node()
        rclpy.shutdown(context=self.context)
