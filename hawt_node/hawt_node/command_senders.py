"""Who sent each message on a topic: its publisher's GID and node, so that only the named sources are obeyed.

Every hawt node spins on rclpy's EventsExecutor, which hands a subscription callback the
message alone: a callback that asks for the ``MessageInfo`` (and the publisher GID in it)
fails under it (rclpy 9.1.2). :class:`CommandSenders` gets the GID another way. A second
subscription on the same topic, with the same QoS, belongs to a hidden node that no
executor spins; the owner's own subscription is only the doorbell. When it rings,
:meth:`CommandSenders.take` takes every sample waiting in the second subscription with
``take_message``, which does return the message info. A sample the doorbell announces
that the second reader has not received yet is taken on the next look
(:meth:`CommandSenders.take` says so: the owner looks again a moment later).

A GID is named through the ROS graph (``get_publishers_info_by_topic``: node name and
namespace of each publisher, with its GID; ``_NODE_NAME_UNKNOWN_`` until the publisher's
node has announced itself, which can trail the endpoint's discovery). A publisher is allowed when its node's fully
qualified name is one of ``sources`` (names relative to the owner's namespace, e.g.
``mbc``, or absolute). A sample from a GID the graph does not list yet (its node's
announcement can trail the data by a moment) waits (:attr:`CommandSenders.waiting`) until
the graph names it, for ``UNKNOWN_GRACE`` seconds at most; then it is handed out as from an
unnamed intruder.

What this does not stop (README, Safety and security): a process that names its node like
the source, in the same namespace, is the source as far as the graph can tell; only DDS
security (SROS2) authenticates participants.
"""
import time
from dataclasses import dataclass
from typing import Any, Dict, List, Optional, Sequence, Tuple

from rclpy.node import Node
from rclpy.qos import QoSProfile

__all__ = ["CommandSenders", "READER_DEPTH", "Sample", "UNKNOWN_GRACE", "UNKNOWN_NODE", "qualified_names"]

READER_DEPTH = 100
"""Samples the hidden reader keeps until they are taken."""

UNKNOWN_NODE = "_NODE_NAME_UNKNOWN_"
"""The node name the ROS graph (rmw_dds_common) gives an endpoint whose node it has not heard of yet."""
UNKNOWN_GRACE = 10.0
"""Wall time [s] a sample waits for the graph to name its publisher; then it is an unnamed intruder's."""


@dataclass(frozen=True)
class Sample:
    """One message taken, with what is known of its sender."""

    message: Any
    gid: bytes
    sender: Optional[str]
    """The sending node's fully qualified name (None: the graph did not name this publisher within UNKNOWN_GRACE)."""
    allowed: bool


def qualified_names(names: Sequence[str], namespace: str) -> frozenset:
    """Node names made fully qualified against ``namespace`` ('mbc' in '/wt1' -> '/wt1/mbc')."""
    base = namespace.rstrip("/")
    return frozenset(name if name.startswith("/") else f"{base}/{name}" for name in names if name)


class CommandSenders:
    """The samples of ``topic`` with their senders, for ``node`` that obeys only ``sources`` (module notes)."""

    def __init__(self, node: Node, message_type: type, topic: str, qos: QoSProfile, sources: Sequence[str]) -> None:
        self.node = node
        self.topic = node.resolve_topic_name(topic)
        self.allowed = qualified_names(sources, node.get_namespace())
        self._reader_node = Node(f"_{node.get_name()}_senders", namespace=node.get_namespace(),
                                 context=node.context, enable_rosout=False, start_parameter_services=False)
        # deeper than the doorbell's: an intruder's flood cannot push a source's sample out before it is taken
        reader_qos = QoSProfile(history=qos.history, depth=READER_DEPTH, reliability=qos.reliability,
                                durability=qos.durability)
        self._reader = self._reader_node.create_subscription(message_type, self.topic, lambda _: None, reader_qos)
        self._names: Dict[bytes, str] = {}
        self._unnamed: List[Tuple[Any, bytes, float]] = []
        self.received = 0
        """Samples taken from the reader so far."""

    @property
    def waiting(self) -> bool:
        """Whether samples wait for the graph to name their publisher (look again shortly)."""
        return bool(self._unnamed)

    def take(self) -> List[Sample]:
        """The samples received, oldest first, each with its sender; those of a publisher the graph does not name yet
        wait (at most UNKNOWN_GRACE) and come out of a later call."""
        with self._reader.handle:
            while True:
                taken = self._reader.handle.take_message(self._reader.msg_type, self._reader.raw)
                if taken is None:
                    break
                message, info = taken
                gid = bytes(info["publisher_gid"]["data"]) if info.get("publisher_gid") else b""
                self._unnamed.append((message, gid, time.monotonic()))
                self.received += 1
        samples, unnamed = [], []
        for message, gid, arrived in self._unnamed:
            sender = self._name(gid)
            if sender is None and time.monotonic() - arrived <= UNKNOWN_GRACE:
                unnamed.append((message, gid, arrived))
            else:
                samples.append(Sample(message, gid, sender, sender in self.allowed))
        self._unnamed = unnamed
        return samples

    def _name(self, gid: bytes) -> Optional[str]:
        if gid not in self._names:
            for info in self.node.get_publishers_info_by_topic(self.topic):
                if info.node_name != UNKNOWN_NODE:  # the endpoint is known before its node: ask again later
                    self._names[bytes(info.endpoint_gid)] = f"{info.node_namespace.rstrip('/')}/{info.node_name}"
        return self._names.get(gid)

    def close(self) -> None:
        """Destroy the hidden reader node."""
        self._reader_node.destroy_node()
