"""The recorder node: every topic (or the chosen ones) of the running graph into a bag (``hawt record``).

Like ``ros2 bag record``: topics are found by polling the graph (every 0.1 s), so
topics that appear later are picked up; each is subscribed with ``raw=True`` (the
serialized bytes are written, never deserialized) and a QoS adapted to its publishers
(rosbag2 ``Rosbag2QoS::adapt_request_to_offers``: reliable if all publishers are,
transient-local if all are). ``log_time`` is the middleware's receive time, held from going back
within a topic: a reliable reader delivers in order, but a sample lost on the way and repaired
(NACK, resend) carries its late receive time, and was once written after four later steps, so a
bag read in log-time order had the commands of steps 1936-1949 after 1953 (a busy machine, the
switching graph). ``publish_time`` is the message's ``header.stamp`` when its type starts with a
``std_msgs/Header`` (DESIGN §7), else the log time.

Who sent each message: a topic has one channel per publishing node, its fully qualified name
in the channel's ``publisher`` metadata (`reader.PUBLISHER`), so a bag of a run with an
intruder on ``control/pitch_command`` tells its commands from the loop assembler's. The node
is found from the message's publisher GID through the graph (hawt_node.command_senders
``publisher_names``), asked for each GID not seen before on the topic. A node's announcement
can trail its publisher's discovery (a node that publishes as soon as it is matched: seen in
this project's tests), so the messages of a publisher the graph does not name yet wait in
memory, asked again every ``poll_period``, for ``NAME_WAIT`` at most (and at the end of the
recording); then its channel is named ``gid <hex>``, the GID as an ``intruder`` event gives
an unnamed sender's, with a warning. A topic's channel is opened with its first message: a
topic none of whose messages arrived has no channel in the bag.

A publisher that joins a topic later with a QoS its subscription cannot match (a volatile one,
an intruder, on a topic whose publishers all offered transient local when it was subscribed; a
best-effort one on a reliable subscription) is not lost: the topic gets a second subscription,
adapted to all its publishers, from which only the messages of the publishers the first cannot
match are taken (by GID, through the graph's offers; a GID the graph does not list yet waits for
it, at most ``NAME_WAIT``, then is taken). rosbag2 keeps the first subscription only.

Progress: about every ``poll_period`` the recorder publishes ``/recorder/progress``
(hawt_msgs/RecorderProgress): per recorded topic, the publishers its subscription is matched
with, the stamp of the latest message written and the count. A run waiting for the recorder
starts once it is matched with every publisher of the graph, and a recorded lockstep plant
holds back on it (its ``recorder_window``), so a lockstep recording is complete from its
first step at any machine load. The progress topic is not recorded.

Stopping: SIGINT or SIGTERM, or the death of the process that started the recorder, ends
the recording, and what was queued then is taken (:func:`take_backlog`): each topic until it has
been quiet for 0.1 s or delivers a message received after the stop, however long that takes (a
lockstep plant may be its ``recorder_window`` ahead: a 1 s limit once cut the last 488 steps of a
run stopped by ``--duration`` on a busy machine); a second signal ends it at once. Then the bag
is finished (summary and statistics) and verified: what a
realtime recording could not keep up with is named in one line (``hawt bag verify``'s
verdict), never silently. Chunks are closed at least every ``chunk_interval`` so a SIGKILL
loses at most that much (``hawt bag recover``). A write error (full disk) stops the
recording with exit code 1 and says how to recover. A stop still under way after ``STUCK_REPORT`` prints where
every thread is.
"""
import argparse
import faulthandler
import math
import re
import sys
import time
from contextlib import contextmanager
from typing import Callable, Iterator, List, Optional, Sequence

import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.signals import SignalHandlerOptions
from rclpy.topic_endpoint_info import TopicEndpointInfo

from hawt_core.stop_signals import parent_gone, stop_signals
from hawt_core.topics import RECORDER_PROGRESS
from hawt_msgs.msg import RecorderProgress
from hawt_node.command_senders import publisher_names
from hawt_node.qos import NO_QOS_EVENTS  # it finds a publisher it cannot match itself (watch_offers)
from hawt_node.writer_matching import can_match

from .errors import BagError
from .cdr_columns import header_stamp_ns
from .interface_files import has_header
from .message_types import message_class
from .qos_profiles import QosOffer
from .record_options import RecorderOptions, add_record_arguments, options_from
from .verification import verify_bag
from .writer import BagWriter

__all__ = ["NAME_WAIT", "Recorder", "STUCK_REPORT", "TopicDiscovery", "adapted_qos", "main", "record", "take_backlog",
           "visible"]

_QUIET = 0.1
"""[s] A topic that delivers nothing for this long after the stop has delivered what was queued."""
NAME_WAIT = 2.0
"""[s] Wall time a publisher's first messages wait for the graph to name its node; then its channel is named by its
GID."""
STUCK_REPORT = 25.0
"""[s] A recorder still stopping this long after its stop began prints every thread's stack to stderr (from
faulthandler's own thread, so a hang in the middleware's C code shows too), before the launcher escalates at 30 s
(hawt_tools.recording.stop_process): a fresh-clone suite once saw a recorder that did not stop within 35 s, and never
again in 30 runs beside load."""
_PROGRESS_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1, reliability=ReliabilityPolicy.RELIABLE,
                           durability=DurabilityPolicy.VOLATILE)


def _offer(profile) -> QosOffer:
    return QosOffer.from_enums(profile.history, profile.depth, profile.reliability, profile.durability,
                               profile.deadline.nanoseconds, profile.lifespan.nanoseconds, profile.liveliness,
                               profile.liveliness_lease_duration.nanoseconds,
                               profile.avoid_ros_namespace_conventions)


def _gid(info) -> bytes:
    """The publisher GID of a message's info (empty if the middleware gives none)."""
    return bytes(info["publisher_gid"]["data"]) if info.get("publisher_gid") else b""


def visible(topic: str) -> bool:
    """False for a topic with a hidden component (``/_x``), which rosbag2's ``--all`` skips."""
    return not any(part.startswith("_") for part in topic.split("/"))


def adapted_qos(publishers: Sequence[TopicEndpointInfo], depth: int) -> QoSProfile:
    """A subscription QoS that matches every publisher (rosbag2 ``Rosbag2QoS::adapt_request_to_offers``).

    Keep-last ``depth``; reliable if all publishers are, else best effort; transient local if all are.
    """
    reliable = all(p.qos_profile.reliability == ReliabilityPolicy.RELIABLE for p in publishers)
    latched = all(p.qos_profile.durability == DurabilityPolicy.TRANSIENT_LOCAL for p in publishers)
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=depth,
                      reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE)


class TopicDiscovery:
    """Finds the graph's topics as they appear, as ``ros2 bag record`` does, and hands each new one to ``subscribe``.

    ``poll()`` (call it from a timer) passes every topic that ``selected`` accepts, has publishers and one type,
    once, to ``subscribe(topic, type_name, publishers)``; a topic it cannot take (several types, or ``subscribe``
    raised BagError) is named in a warning of ``node``'s logger (``not <doing> TOPIC: why``) and not tried again.
    """

    def __init__(self, node: Node, selected: Callable[[str], bool],
                 subscribe: Callable[[str, str, List[TopicEndpointInfo]], None], doing: str) -> None:
        self._node = node
        self._doing = doing
        self._selected = selected
        self._subscribe = subscribe
        self.taken: set[str] = set()
        self._skipped: set[str] = set()

    def poll(self) -> None:
        """Subscribe to every selected topic that has publishers and is not taken yet."""
        for topic, types in self._node.get_topic_names_and_types():
            if topic in self.taken or topic in self._skipped or not self._selected(topic):
                continue
            publishers = self._node.get_publishers_info_by_topic(topic)
            if not publishers:
                continue
            if len(types) != 1:
                self._skip(topic, f"it has several types ({', '.join(types)})")
                continue
            try:
                self._subscribe(topic, types[0], publishers)
            except BagError as error:
                self._skip(topic, str(error))
                continue
            self.taken.add(topic)

    def _skip(self, topic: str, reason: str) -> None:
        self._skipped.add(topic)
        self._node.get_logger().warning(f"not {self._doing} {topic}: {reason}")


class Recorder(Node):
    """Subscribes to the selected topics as they appear and writes what arrives to ``writer``."""

    def __init__(self, options: RecorderOptions, writer: BagWriter, **node_kwargs) -> None:
        super().__init__(options.node_name, start_parameter_services=False, **node_kwargs)
        self.options = options
        self.writer = writer
        self.counts: dict[str, int] = {}  # messages written per topic
        self.taken: dict[str, int] = {}  # messages taken per topic: written, or waiting for their publisher's name
        self.stamps: dict[str, float] = {}
        self.log_times: dict[str, int] = {}  # the latest log time taken per topic [ns, system clock]
        self.failure: Optional[str] = None
        self._types: dict[str, tuple[str, bool]] = {}  # topic: its type, and whether it starts with a header
        self._channels: dict[tuple[str, bytes], int] = {}  # (topic, publisher GID): channel
        self._waiting: dict[tuple[str, bytes], tuple[float, list]] = {}  # (topic, GID): since, messages
        self._second = {}  # topic: its second subscription, for publishers the first cannot match
        self._missed: dict[str, dict[bytes, bool]] = {}  # topic: {GID: the first subscription cannot match it}
        self._unsorted: dict[str, list] = {}  # topic: second-subscription messages of GIDs the graph does not list
        self._pattern = re.compile(options.regex) if options.regex else None
        self._wanted = {"/" + t.strip("/") for t in options.topics}
        self._recorded = {}
        self.discovery = TopicDiscovery(self, self._selected, self._subscribe, "recording")
        self._progress = self.create_publisher(RecorderProgress, RECORDER_PROGRESS, _PROGRESS_QOS)
        self.create_timer(options.poll_period, self.discovery.poll)
        self.create_timer(options.poll_period, self._publish_progress)
        self.create_timer(options.chunk_interval, self._close_chunk)
        self.create_timer(options.poll_period, self.write_waiting)
        self.create_timer(options.poll_period, self.watch_offers)
        self.discovery.poll()

    def _selected(self, topic: str) -> bool:
        if topic == RECORDER_PROGRESS:
            return False
        if not self._wanted and self._pattern is None:
            return self.options.include_hidden or visible(topic)
        return topic in self._wanted or bool(self._pattern and self._pattern.search(topic))

    def _subscribe(self, topic: str, type_name: str, publishers) -> None:
        kind = message_class(type_name)
        qos = adapted_qos(publishers, self.options.depth)
        self.writer.add_schema(type_name)  # a type without its .msg files is refused here, not at its first message
        self._types[topic] = (type_name, has_header(type_name))
        self.counts[topic] = self.taken[topic] = 0
        self.log_times[topic] = 0

        self._recorded[topic] = self.create_subscription(kind, topic, lambda data, info: self._take(topic, data, info),
                                                         qos, raw=True, event_callbacks=NO_QOS_EVENTS)
        self.get_logger().info(f"recording {topic} [{type_name}] "
                               f"({'reliable' if qos.reliability == ReliabilityPolicy.RELIABLE else 'best effort'}, "
                               f"{len(publishers)} publisher(s))")

    def _take(self, topic: str, data: bytes, info) -> None:
        """A message of ``topic``: into its publisher's channel, or waiting for its publisher's name."""
        received = max(info["received_timestamp"], self.log_times.get(topic, 0))  # delivery order kept
        self.log_times[topic] = received
        self.taken[topic] += 1
        key = (topic, _gid(info))
        if key not in self._channels and key not in self._waiting:
            self._open(key)
        if key in self._channels:
            self._write(topic, self._channels[key], received, data)
        elif key in self._waiting:
            self._waiting[key][1].append((received, data))

    def watch_offers(self, final: bool = False) -> None:
        """Give a topic a second subscription once a publisher its subscription cannot match appears (module notes),
        and take what waited there for the graph to list its publisher (``final``: all of it)."""
        for topic, subscription in list(self._recorded.items()):
            if topic in self._second or subscription.get_publisher_count() >= self.count_publishers(topic):
                continue  # matched with every publisher the graph lists: the graph's offers need no look
            publishers = self.get_publishers_info_by_topic(topic)
            if all(can_match(p.qos_profile, subscription.qos_profile) for p in publishers):
                continue
            qos = adapted_qos(publishers, self.options.depth)
            self._second[topic] = self.create_subscription(
                message_class(self._types[topic][0]), topic, lambda data, info, t=topic: self._take_second(t, data, info),
                qos, raw=True, event_callbacks=NO_QOS_EVENTS)
            self.get_logger().info(f"recording {topic} from its publishers of other QoS through a second subscription "
                                   f"({qos.durability.name.lower()}, {qos.reliability.name.lower()})")
        for topic, waiting in list(self._unsorted.items()):
            self._unsorted[topic] = []
            for data, info, since in waiting:
                self._take_second(topic, data, info, -math.inf if final else since)

    def _take_second(self, topic: str, data: bytes, info, since: Optional[float] = None) -> None:
        """A message of the second subscription: taken only from a publisher the first cannot match (the others'
        come through the first); one from a publisher the graph does not list yet waits, at most ``NAME_WAIT``."""
        gid = _gid(info)
        missed = self._missed.setdefault(topic, {})
        if gid not in missed:
            first = self._recorded[topic].qos_profile
            missed.update({bytes(p.endpoint_gid): not can_match(p.qos_profile, first)
                           for p in self.get_publishers_info_by_topic(topic)})
        since = time.monotonic() if since is None else since
        if gid not in missed and time.monotonic() - since < NAME_WAIT:
            self._unsorted.setdefault(topic, []).append((data, info, since))
        elif missed.get(gid, True):
            self._take(topic, data, info)

    def _open(self, key: tuple[str, bytes], final: bool = False) -> None:
        """Open the channel of the publisher ``key`` (topic, GID): its node's (a node's new publisher, after a
        respawn, writes on in its node's channel), and write what waited for it. While the graph does not name the
        node, the publisher's messages wait, at most ``NAME_WAIT`` or until ``final``; then the channel is named by
        the GID."""
        topic, gid = key
        publisher = publisher_names(self, topic).get(gid) if gid else None
        if gid and publisher is None:
            since = self._waiting.setdefault(key, (time.monotonic(), []))[0]
            if not final and time.monotonic() - since < NAME_WAIT:
                return
            publisher = f"gid {gid.hex()}"
            self.get_logger().warning(f"recording {topic} from a publisher the graph does not name: its channel is "
                                      f"named by the publisher's {publisher}")
        channel = self.writer.channels.get((topic, publisher))
        if channel is None:
            offers = [_offer(p.qos_profile) for p in self.get_publishers_info_by_topic(topic)
                      if bytes(p.endpoint_gid) == gid]
            with self._writing():
                channel = self.writer.add_topic(topic, self._types[topic][0], offers, publisher=publisher)
        if channel is None:
            return
        self._channels[key] = channel
        for received, data in self._waiting.pop(key, (0.0, []))[1]:
            self._write(topic, channel, received, data)

    def write_waiting(self, final: bool = False) -> None:
        """Write the messages whose publisher the graph now names (``final``: all, those of an unnamed one in a
        channel named by its GID); called on a timer, and once at the end of the recording."""
        for key in list(self._waiting):
            self._open(key, final)

    def _write(self, topic: str, channel: int, received: int, data: bytes) -> None:
        stamped = self._types[topic][1]
        publish = header_stamp_ns(data) if stamped and len(data) >= 12 else received
        with self._writing():
            self.writer.write(channel, received, data, publish)
            self.counts[topic] += 1
            if stamped:
                self.stamps[topic] = publish * 1e-9

    @contextmanager
    def _writing(self) -> Iterator[None]:
        """A write error (full disk) ends the recording: `failure` says why."""
        try:
            yield
        except OSError as error:
            self._fail(f"writing {self.writer.path} failed ({error.strerror})")

    def _publish_progress(self) -> None:
        topics = sorted(self._recorded)
        self._progress.publish(RecorderProgress(
            topics=topics, publishers=[self._recorded[t].get_publisher_count() for t in topics],
            stamps=[self.stamps.get(t, math.nan) for t in topics], counts=[self.counts[t] for t in topics]))

    def _close_chunk(self) -> None:
        with self._writing():
            self.writer.flush()

    def _fail(self, reason: str) -> None:
        if self.failure is None:
            self.failure = reason
            self.get_logger().error(reason)


def take_backlog(executor: SingleThreadedExecutor, recorder: Recorder, stopped_at: int,
                 interrupted: Callable[[], bool]) -> None:
    """Take and write what was queued for ``recorder`` when the recording stopped at ``stopped_at`` [ns, system
    clock, as the middleware's receive times].

    A topic is done when it delivers a message received after the stop (a publisher still running: its queue is
    empty) or has delivered nothing for ``_QUIET`` s of wall time and for a whole round of the executor (a turn
    per topic and timer, and one more: a process the machine did not run for a while has not seen its topics
    quiet). Ends when every topic is done, on a write error, or when ``interrupted()`` (a second signal).
    """
    last: dict[str, tuple[int, int, float]] = {}  # topic: (count, turn, wall time) when its count last changed
    turn, timers = 0, len(list(recorder.timers))
    while recorder.failure is None and not interrupted():
        executor.spin_once(timeout_sec=0.01)
        turn += 1
        now = time.monotonic()
        turns = len(recorder.taken) + timers + 1
        done = True
        for topic, count in recorder.taken.items():
            if topic not in last or last[topic][0] != count:
                last[topic] = (count, turn, now)
            if recorder.log_times[topic] < stopped_at and (turn - last[topic][1] < turns or
                                                           now - last[topic][2] < _QUIET):
                done = False
        if done:
            return


def record(options: RecorderOptions, ros_args: Optional[List[str]] = None, report=print) -> int:
    """Record until SIGINT/SIGTERM; returns the exit code (0, or 1 after a write error).

    ``report`` is print-like (called with ``file=sys.stderr`` for errors).

    Raises
    ------
    BagError
        If the output exists or cannot be created (its folder is made by `options_from`).
    """
    writer = BagWriter(options.output, chunk_size=options.chunk_size)
    stop = []
    launcher_gone = parent_gone()
    counts, failure = {}, None
    try:
        with stop_signals(lambda *_: stop.append(True)), \
                rclpy.init(args=ros_args, signal_handler_options=SignalHandlerOptions.NO):
            recorder = Recorder(options, writer)
            executor = SingleThreadedExecutor()
            executor.add_node(recorder)
            report(f"recording to {options.output} (Ctrl-C to stop)")
            while not stop and recorder.failure is None and not launcher_gone():
                executor.spin_once(timeout_sec=0.05)
            faulthandler.dump_traceback_later(STUCK_REPORT)
            stopped = len(stop)
            take_backlog(executor, recorder, time.time_ns(), lambda: len(stop) > stopped)
            recorder.watch_offers(final=True)
            recorder.write_waiting(final=True)
            counts, failure = recorder.counts, recorder.failure
            executor.shutdown()
            recorder.destroy_node()
    finally:
        try:
            writer.finish()
        except OSError as error:
            failure = f"could not finish the bag ({error.strerror})"
    report(f"recorded {sum(counts.values())} messages on {len(counts)} topics into {options.output}")
    if failure is None:
        verification = verify_bag(options.output)
        for topic in verification.topics:  # a topic that may have windows (a contribution) but has any is named too
            if topic.coverage.gaps and not topic.problems:
                report(f"with holes: {topic.text()}")
        report(verification.verdict(), **({} if verification.ok else {"file": sys.stderr}))
    faulthandler.cancel_dump_traceback_later()
    if failure is not None:
        report(f"hawt record: {options.output}: {failure}; 'hawt bag recover {options.output}' rescues its "
               "complete chunks", file=sys.stderr)
        return 1
    return 0


def main(argv: Optional[Sequence[str]] = None) -> None:
    """The ``record`` executable (what ``hawt launch --record`` starts): ``record -o FILE [options]``."""
    argv = list(sys.argv[1:] if argv is None else argv)
    ros_args = argv[argv.index("--ros-args"):] if "--ros-args" in argv else []
    own = argv[:len(argv) - len(ros_args)]
    parser = argparse.ArgumentParser(prog="record", description="Record topics of the running graph into a bag.")
    add_record_arguments(parser)
    try:
        sys.exit(record(options_from(parser.parse_args(own)), ["record", *ros_args]))
    except BagError as error:
        print(f"record: {error}", file=sys.stderr)
        sys.exit(2)
