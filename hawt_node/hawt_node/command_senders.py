"""Who sent each message on a topic: its publisher's GID and node, so that only the named sources are obeyed.

Every hawt node spins on rclpy's EventsExecutor, which hands a subscription callback the
message alone: a callback that asks for the ``MessageInfo`` (and the publisher GID in it)
fails under it (rclpy 9.1.2). :class:`CommandSenders` gets the GID another way. A second
subscription on the same topic, with the same QoS, belongs to a hidden node that no
executor spins; the owner's own subscription is only the doorbell. When it rings
(:meth:`CommandSenders.rang`), :meth:`CommandSenders.take` takes every sample waiting in the
second subscription with ``take_message``, which does return the message info. While the
announced sample has not reached the second reader yet (:attr:`CommandSenders.missing`) the
owner calls it again a moment later (``LOOK_AGAIN``), and while a sample waits for its
sender's name (:attr:`CommandSenders.waiting`) every ``WAIT_PERIOD``.

A GID is named through the ROS graph (:func:`publisher_names`: node name and namespace of
each publisher, with its GID; ``_NODE_NAME_UNKNOWN_`` until the publisher's node has
announced itself, which can trail the endpoint's discovery). A publisher is allowed when its
node's fully qualified name is one of ``sources`` (names relative to the owner's namespace,
e.g. ``mbc``, or absolute). A sample from a publisher the graph does not name yet waits until
it does, for ``UNKNOWN_GRACE`` seconds at most; then it is handed out as an unnamed
intruder's.

:class:`GuardedSubscription` puts the two together for a node: a callback that sees only the
allowed senders' messages, the first message of every other publisher reported once (the
owner's ``intruder`` event) and every one counted. Its allowed senders may change while it
runs (the loop assembler allows a contribution topic's claimants as they announce
themselves); a sample whose named sender is not allowed yet waits at most ``ANNOUNCE_GRACE``
for it to become so.

What this does not stop (README, Safety and security): a process that names its node like
the source, in the same namespace, is the source as far as the graph can tell; only DDS
security (SROS2) authenticates participants.
"""
import re
import time
from dataclasses import dataclass
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.qos import QoSProfile

__all__ = ["ANNOUNCE_GRACE", "CommandSenders", "GuardedSubscription", "LOOK_AGAIN", "LOOKS", "READER_DEPTH", "Sample",
           "UNKNOWN_GRACE", "UNKNOWN_NODE", "publisher_names", "qualified_names"]

READER_DEPTH = 100
"""Samples the hidden reader keeps until they are taken."""

UNKNOWN_NODE = "_NODE_NAME_UNKNOWN_"
"""The node name the ROS graph (rmw_dds_common) gives an endpoint whose node it has not heard of yet."""
UNKNOWN_GRACE = 10.0
"""Wall time [s] a sample waits for the graph to name its publisher; then it is an unnamed intruder's."""
ANNOUNCE_GRACE = 2.0
"""Wall time [s] a sample whose named sender is not allowed waits for it to become so (``wait_for_allowed``): a
controller's latched announcement comes within milliseconds of its publisher's discovery."""
LOOKS = 50
"""Looks for a sample the doorbell announced before giving up on it (it was taken with an earlier one)."""
LOOK_AGAIN = 0.001
"""Wall time [s] after which a guarded subscription looks again for a sample announced but not taken yet."""
WAIT_PERIOD = 0.05
"""Wall time [s] between a guarded subscription's looks while samples wait for their sender's name."""


@dataclass(frozen=True)
class Sample:
    """One message taken, with what is known of its sender."""

    message: Any
    gid: bytes
    sender: Optional[str]
    """The sending node's fully qualified name (None: the graph did not name this publisher within UNKNOWN_GRACE)."""
    allowed: bool

    @property
    def who(self) -> str:
        """The sender as an event names it: its node, or its publisher GID if the graph does not name it."""
        return self.sender or f"a publisher the graph does not name (publisher gid {self.gid.hex()})"


def publisher_names(node: Node, topic: str) -> Dict[bytes, str]:
    """The fully qualified node name of each publisher of ``topic`` that ``node``'s graph names, by its GID (a
    publisher whose node has not announced itself yet, ``_NODE_NAME_UNKNOWN_``, is left out)."""
    return {bytes(info.endpoint_gid): f"{info.node_namespace.rstrip('/')}/{info.node_name}"
            for info in node.get_publishers_info_by_topic(topic) if info.node_name != UNKNOWN_NODE}


def qualified_names(names: Sequence[str], namespace: str) -> frozenset:
    """Node names made fully qualified against ``namespace`` ('mbc' in '/wt1' -> '/wt1/mbc')."""
    base = namespace.rstrip("/")
    return frozenset(name if name.startswith("/") else f"{base}/{name}" for name in names if name)


class CommandSenders:
    """The samples of ``topic`` with their senders, for ``node`` that obeys only ``sources`` (module notes).

    With ``wait_for_allowed``, a sample whose named sender is not in :attr:`allowed` waits for it
    (at most ``ANNOUNCE_GRACE``), as one whose sender is not named yet does (``UNKNOWN_GRACE``).
    """

    def __init__(self, node: Node, message_type: type, topic: str, qos: QoSProfile, sources: Sequence[str],
                 wait_for_allowed: bool = False) -> None:
        self.node = node
        self.topic = node.resolve_topic_name(topic)
        self.allowed = qualified_names(sources, node.get_namespace())
        self.wait_for_allowed = wait_for_allowed
        hidden = f"_{node.get_name()}_senders_{re.sub(r'[^A-Za-z0-9_]', '_', topic.strip('/'))}"
        self._reader_node = Node(hidden, namespace=node.get_namespace(), context=node.context, enable_rosout=False,
                                 start_parameter_services=False)
        # deeper than the doorbell's: an intruder's flood cannot push a source's sample out before it is taken
        reader_qos = QoSProfile(history=qos.history, depth=READER_DEPTH, reliability=qos.reliability,
                                durability=qos.durability)
        self._reader = self._reader_node.create_subscription(message_type, self.topic, lambda _: None, reader_qos)
        self._names: Dict[bytes, str] = {}
        self._unnamed: List[Tuple[Any, bytes, float]] = []
        self._received = self._received_at_ring = 0
        self._looks = LOOKS

    def rang(self) -> None:
        """The doorbell rang: a sample is on its way to the reader."""
        self._received_at_ring, self._looks = self._received, 0

    @property
    def missing(self) -> bool:
        """Whether :meth:`take` should be called again at once: the announced sample has not reached the reader
        yet (at most LOOKS looks)."""
        return self._received == self._received_at_ring and self._looks < LOOKS

    @property
    def waiting(self) -> bool:
        """Whether samples wait for their sender to be named or allowed."""
        return bool(self._unnamed)

    def take(self) -> List[Sample]:
        """The samples received, oldest first, each with its sender; those of a publisher the graph does not name yet
        wait (at most UNKNOWN_GRACE) and come out of a later call."""
        self._looks += 1
        with self._reader.handle:
            while True:
                taken = self._reader.handle.take_message(self._reader.msg_type, self._reader.raw)
                if taken is None:
                    break
                message, info = taken
                gid = bytes(info["publisher_gid"]["data"]) if info.get("publisher_gid") else b""
                self._unnamed.append((message, gid, time.monotonic()))
                self._received += 1
        samples, unnamed = [], []
        for message, gid, arrived in self._unnamed:
            sender = self._name(gid)
            allowed = sender in self.allowed
            grace = UNKNOWN_GRACE if sender is None else ANNOUNCE_GRACE if self.wait_for_allowed and not allowed \
                else -1.0
            if time.monotonic() - arrived <= grace:
                unnamed.append((message, gid, arrived))
            else:
                samples.append(Sample(message, gid, sender, allowed))
        self._unnamed = unnamed
        return samples

    def _name(self, gid: bytes) -> Optional[str]:
        if gid not in self._names:
            self._names.update(publisher_names(self.node, self.topic))
        return self._names.get(gid)

    def close(self) -> None:
        """Destroy the hidden reader node."""
        self._reader_node.destroy_node()


class GuardedSubscription:
    """A subscription of ``node`` to ``topic`` whose ``callback`` gets only the messages of ``sources``.

    The first sample of every other publisher goes to ``report`` (the owner's ``intruder``
    event), and :attr:`refused` counts them all by publisher GID. ``sources`` may be changed
    later (:meth:`allow`) with ``wait_for_allowed`` (module notes).
    """

    def __init__(self, node: Node, message_type: type, topic: str, qos: QoSProfile, sources: Sequence[str],
                 callback: Callable[[Any], None], report: Callable[[Sample], None],
                 wait_for_allowed: bool = False) -> None:
        self.senders = CommandSenders(node, message_type, topic, qos, sources, wait_for_allowed)
        self.callback, self.report = callback, report
        self.refused: Dict[bytes, int] = {}
        node.create_subscription(message_type, topic, self._ring, qos)
        # wall-time waits: steady-clock timers, which register no time-jump callback on the node's ROS clock (rcl
        # warns once a clock has many, and a loop assembler guards one topic per interface)
        steady = Clock(clock_type=ClockType.STEADY_TIME)
        self._look_again = node.create_timer(LOOK_AGAIN, self._take, clock=steady)
        self._look_again.cancel()
        self._wait = node.create_timer(WAIT_PERIOD, self._take, clock=steady)
        self._wait.cancel()

    @property
    def allowed(self) -> frozenset:
        """The fully qualified names of the nodes whose messages are handed over."""
        return self.senders.allowed

    def allow(self, sources: Sequence[str]) -> None:
        """Hand over the messages of ``sources`` from now on, those waiting for it included."""
        self.senders.allowed = qualified_names(sources, self.senders.node.get_namespace())
        if self.senders.waiting:
            self._take()

    def _ring(self, _: Any) -> None:
        self.senders.rang()
        self._take()

    def _take(self) -> None:
        samples = self.senders.take()
        for timer, needed in ((self._look_again, self.senders.missing), (self._wait, self.senders.waiting)):
            if not needed:
                timer.cancel()
            elif timer.is_canceled():
                timer.reset()
        for sample in samples:
            if sample.allowed:
                self.callback(sample.message)
                continue
            count = self.refused[sample.gid] = self.refused.get(sample.gid, 0) + 1
            if count == 1:
                self.report(sample)

    def close(self) -> None:
        """Destroy the hidden reader node."""
        self.senders.close()
