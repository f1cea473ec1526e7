"""The replayer node: publish a bag's messages again (``hawt replay``).

Timed replay (like ``ros2 bag play``): messages go out in log-time order (equal
times in recorded order) at their recorded spacing divided by ``rate``, serialized
bytes as recorded (``publish`` of raw bytes: no deserialization), each topic with
the QoS its recorded publishers offered. ``--clock HZ`` publishes ``/clock`` with the
player time. Live control, without std_srvs (not installed): the node's parameters
``paused`` (bool) and ``rate`` (double), settable with any parameter client, and the
topic ``~/play_next`` (``std_msgs/msg/Empty``): each message on it publishes the next
bag message while paused.

Step replay (``--step-trigger TOPIC``) feeds a graph one plant step at a time: the
selected topics' messages are grouped by their ``step`` field; group k is published
(after a ``/clock`` of its stamp with ``--clock``), then the player waits for a
message with ``step == k`` on the trigger topic (``control/pitch_command`` for the
controllers, ``relayed`` for the example relay), then goes on with k + 1. Timing is
then the graph's own, so the same inputs give the same outputs on any machine load.

A topic the player publishes that another node publishes too (a replay into a running
graph) mixes the recorded messages with the live ones, in the graph and in any recording
of it: the player says so once per topic, naming the other publisher, as soon as its
graph shows one (it looks every ``FOREIGN_CHECK_PERIOD`` and once at the end).
"""
import itertools
import threading
import time
from dataclasses import dataclass, field
from typing import Callable, Iterable, List, Optional

import numpy as np
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.signals import SignalHandlerOptions
from rcl_interfaces.msg import SetParametersResult
from rosgraph_msgs.msg import Clock
from std_msgs.msg import Empty

from hawt_core.step_sync import RESEND_PERIOD
from hawt_core.stop_signals import stop_signals
from hawt_node.command_senders import publisher_names
from hawt_node.node_main import wait_for_acknowledgements

from .cdr_columns import FieldReader
from .errors import BagError
from .interface_files import schema_text
from .message_types import message_class
from .msg_definition import parse_schema, short_type_name
from .playback_clock import PlaybackClock
from .reader import BagMessage, BagReader, TopicInfo

__all__ = ["FOREIGN_CHECK_PERIOD", "Player", "ReplayOptions", "ReplayResult", "parse_remaps", "replay"]

FOREIGN_CHECK_PERIOD = 0.5
"""Wall time [s] between two looks for another publisher on a replayed topic."""

_SPIN = 300_000
"""The last 0.3 ms before a message is due are waited by polling the clock, not by sleeping [ns]."""


@dataclass(frozen=True)
class ReplayOptions:
    """How to replay a bag.

    Attributes
    ----------
    rate : float
        Speed factor of timed replay (> 0).
    loop : bool
        Start again at the end (timed replay).
    start_offset : float
        Seconds after the bag's first message to start at.
    topics : tuple of str
        Topics to publish (all if empty).
    clock_hz : float
        Publish ``/clock`` at this rate during timed replay (0: not at all); in step
        replay any value > 0 publishes one ``/clock`` per step.
    remaps : tuple of (str, str)
        Recorded topic → topic to publish on.
    start_paused : bool
    wait_for_subscribers : bool
        Before publishing, wait until each topic has a subscriber (always so in step replay).
    wait_timeout : float
        [s] for that wait and for the trigger topic's publisher to appear.
    step_trigger : str or None
        Step replay: the topic whose ``step == k`` message releases step k + 1.
    step_timeout : float
        [s] to wait for each trigger message.
    """

    rate: float = 1.0
    loop: bool = False
    start_offset: float = 0.0
    topics: tuple[str, ...] = ()
    clock_hz: float = 0.0
    remaps: tuple[tuple[str, str], ...] = ()
    start_paused: bool = False
    wait_for_subscribers: bool = False
    wait_timeout: float = 10.0
    step_trigger: Optional[str] = None
    step_timeout: float = 10.0
    node_name: str = "hawt_player"


@dataclass
class ReplayResult:
    """What a replay did: messages published, steps completed, and how late each timed message went out.

    ``lateness`` [ns], shape (n,): wall time of publishing minus the time the player clock
    scheduled it (timed replay only; empty in step replay).
    """

    published: int = 0
    steps: int = 0
    lateness: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))


def _absolute(topic: str) -> str:
    return "/" + topic.strip("/")


def _qos(topic: TopicInfo) -> QoSProfile:
    """rosbag2's ``adapt_offer_to_recorded_offers``: the recorded offer if all publishers agreed, else the default."""
    reliability, durability = ReliabilityPolicy.RELIABLE, DurabilityPolicy.VOLATILE
    if topic.offers and len({(o.reliability, o.durability) for o in topic.offers}) == 1:
        if topic.offers[0].reliability == "best_effort":
            reliability = ReliabilityPolicy.BEST_EFFORT
        if topic.offers[0].durability == "transient_local":
            durability = DurabilityPolicy.TRANSIENT_LOCAL
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=100, reliability=reliability, durability=durability)


class _Control:
    """State shared by the playing thread and the node's callbacks."""

    def __init__(self, clock: PlaybackClock) -> None:
        self.clock = clock
        self.condition = threading.Condition()
        self.stop = False
        self.next_requests = 0
        self.trigger_steps: set[int] = set()

    def notify(self, change: Callable[[], None]) -> None:
        with self.condition:
            change()
            self.condition.notify_all()


class Player(Node):
    """Publishers for the bag's topics, ``/clock``, and the ``paused``/``rate``/``~/play_next`` controls;
    ``warn`` hears of another publisher on a replayed topic."""

    def __init__(self, topics: dict[str, TopicInfo], options: ReplayOptions, control: _Control,
                 warn: Callable[[str], None] = lambda _: None, **node_kwargs) -> None:
        super().__init__(options.node_name, **node_kwargs)
        self.control = control
        self.warn = warn
        self.mixed: set = set()
        remaps = {_absolute(a): _absolute(b) for a, b in options.remaps}
        self.outputs = {topic: self.create_publisher(message_class(info.type), remaps.get(topic, topic), _qos(info))
                        for topic, info in topics.items()}
        self.clock_publisher = None
        if options.clock_hz > 0:
            self.clock_publisher = self.create_publisher(Clock, "/clock", QoSProfile(depth=1))
        self.declare_parameter("rate", options.rate)
        self.declare_parameter("paused", options.start_paused)
        self.add_on_set_parameters_callback(self._check)
        self.add_post_set_parameters_callback(self._apply)
        self.create_subscription(Empty, "~/play_next", self._play_next, 10)
        self.create_timer(FOREIGN_CHECK_PERIOD, self.look_for_other_publishers)

    def look_for_other_publishers(self) -> None:
        """Warn of each replayed topic that another node publishes too (once per topic)."""
        own = self.get_fully_qualified_name()
        for publisher in self.outputs.values():
            topic = publisher.topic_name
            # (a node the graph does not name yet is named at a later look)
            others = sorted(set(publisher_names(self, topic).values()) - {own}) if topic not in self.mixed else []
            if others:
                self.mixed.add(topic)
                self.warn(f"{topic} is also published by {', '.join(others)}: the replayed messages mix with "
                          "that graph's own (in it and in any recording of it)")

    @staticmethod
    def _check(parameters: List[Parameter]) -> SetParametersResult:
        for parameter in parameters:
            if parameter.name == "rate" and not (isinstance(parameter.value, float) and parameter.value > 0.0):
                return SetParametersResult(successful=False, reason=f"rate: expected a positive double, "
                                                                    f"found {parameter.value!r}")
        return SetParametersResult(successful=True)

    def _apply(self, parameters: List[Parameter]) -> None:
        clock = self.control.clock
        for parameter in parameters:
            if parameter.name == "rate":
                self.control.notify(lambda: clock.set_rate(parameter.value))
            elif parameter.name == "paused":
                self.control.notify(clock.pause if parameter.value else clock.resume)

    def _play_next(self, _msg) -> None:
        def more() -> None:
            self.control.next_requests += 1
        self.control.notify(more)

    def publish_clock(self, bag_time: int) -> None:
        if self.clock_publisher is not None:
            message = Clock()
            message.clock.sec, message.clock.nanosec = divmod(max(bag_time, 0), 1_000_000_000)
            self.clock_publisher.publish(message)

    def wait_for_subscribers(self, timeout: float) -> None:
        deadline = time.monotonic() + timeout
        for topic, publisher in self.outputs.items():
            while publisher.get_subscription_count() < 1:
                if time.monotonic() > deadline or self.control.stop:
                    raise RuntimeError(f"no subscriber on {publisher.topic_name} within {timeout:g} s")
                time.sleep(0.01)

    def subscribe_trigger(self, topic: str, timeout: float) -> None:
        """Subscribe to the step trigger once its publisher is in the graph; wait until matched."""
        deadline = time.monotonic() + timeout
        while True:
            types = dict(self.get_topic_names_and_types()).get(topic)
            if types and self.count_publishers(topic) > 0:
                break
            if time.monotonic() > deadline or self.control.stop:
                raise RuntimeError(f"no publisher on the step trigger {topic} within {timeout:g} s")
            time.sleep(0.02)
        type_name = types[0]
        step_of = FieldReader(parse_schema(schema_text(type_name), type_name), short_type_name(type_name), "step")

        def arrived(data: bytes) -> None:
            step = int(step_of(data))
            self.control.notify(lambda: self.control.trigger_steps.add(step))

        subscription = self.create_subscription(message_class(type_name), topic, arrived,
                                                QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE),
                                                raw=True)
        while subscription.get_publisher_count() < 1:
            if time.monotonic() > deadline or self.control.stop:
                raise RuntimeError(f"could not match the step trigger {topic} within {timeout:g} s")
            time.sleep(0.01)


def _timed(player: Player, reader: BagReader, topics: list[str], start: int, options: ReplayOptions,
           result: ReplayResult) -> None:
    control, clock = player.control, player.control.clock
    period = int(1e9 / options.clock_hz) if options.clock_hz > 0 else None
    lateness = []
    try:
        while not control.stop:
            # The first message is read before the clock starts: reading the bag's first chunk (on a busy machine,
            # tens of milliseconds) would otherwise make it late and the next ones a burst catching up.
            messages = reader.messages(topics, start=start)
            first = next(messages, None)
            control.notify(lambda: clock.jump(start))
            next_tick = time.monotonic_ns()
            for message in itertools.chain(() if first is None else (first,), messages):
                with control.condition:
                    while not control.stop:
                        now = time.monotonic_ns()
                        if period is not None and now >= next_tick:
                            player.publish_clock(clock.bag_now())
                            next_tick = now + period
                        if clock.paused and control.next_requests:
                            control.next_requests -= 1
                            clock.jump(message.log_time)
                            due = now
                            break
                        due = clock.wall_time_of(message.log_time)
                        if due is not None and now >= due:
                            break
                        wait = 100_000_000 if due is None else due - now - _SPIN
                        if period is not None:
                            wait = min(wait, next_tick - now)
                        if wait > 0:
                            control.condition.wait(wait * 1e-9)
                if control.stop:
                    return
                player.outputs[message.topic].publish(message.data)
                lateness.append(time.monotonic_ns() - due)
                result.published += 1
            if not options.loop:
                return
    finally:
        result.lateness = np.asarray(lateness, dtype=np.int64)


def _step_groups(reader: BagReader, topics: list[str], start: int) -> list[list[tuple[int, BagMessage]]]:
    """Messages grouped by their ``step`` field, in step order (recorded order within a step)."""
    readers = {}
    keyed = []
    for message in reader.messages(topics, start=start):
        if message.topic not in readers:
            schema = reader.schema(message.topic)
            try:
                readers[message.topic] = FieldReader(parse_schema(schema.data.decode(), schema.name),
                                                     short_type_name(schema.name), "step")
                readers[message.topic](message.data)
            except BagError:
                raise BagError(f"{reader.path}: {message.topic} ({schema.name}) has no 'step' field; "
                               "step replay needs one in every published topic (choose them with --topics)") from None
        keyed.append((int(readers[message.topic](message.data)), len(keyed), message))
    keyed.sort(key=lambda item: (item[0], item[1]))
    groups: list[list[tuple[int, BagMessage]]] = []
    previous = None
    for step, _, message in keyed:
        if step != previous:
            groups.append([])
            previous = step
        groups[-1].append((step, message))
    return groups


def _send(player: Player, group) -> None:
    """Publish one step's recorded messages."""
    for _, message in group:
        player.outputs[message.topic].publish(message.data)


def _stepped(player: Player, groups, options: ReplayOptions, result: ReplayResult) -> None:
    control = player.control
    for group in groups:
        step = group[0][0]
        player.publish_clock(group[0][1].publish_time)
        _send(player, group)
        result.published += len(group)
        deadline = time.monotonic() + options.step_timeout
        resend = time.monotonic() + RESEND_PERIOD
        with control.condition:
            while step not in control.trigger_steps and not control.stop:
                now = time.monotonic()
                if now >= deadline:
                    raise RuntimeError(f"step {step}: no message with that step on {options.step_trigger} "
                                       f"within {options.step_timeout:g} s")
                if now >= resend:
                    _send(player, group)
                    resend = now + RESEND_PERIOD
                control.condition.wait(min(deadline, resend) - now)
            control.trigger_steps.discard(step)
        if control.stop:
            return
        result.steps += 1


def replay(path, options: ReplayOptions = ReplayOptions(), ros_args: Optional[List[str]] = None,
           report: Callable[[str], None] = print, warn: Callable[[str], None] = lambda _: None) -> ReplayResult:
    """Replay a bag until its end (or Ctrl-C/SIGTERM; forever with ``loop``); ``warn`` hears of a replayed topic
    that another node publishes too.

    Raises
    ------
    BagError
        Bad bag, unknown topic in ``topics``, or (step replay) a topic without a ``step`` field.
    RuntimeError
        Step replay: no subscriber or trigger publisher in time, or a step never answered.
    """
    if not options.rate > 0:
        raise BagError(f"--rate: expected a positive speed, found {options.rate}")
    with BagReader(path) as reader:
        info = reader.info()
        known = {t.topic: t for t in info.topics}
        trigger = _absolute(options.step_trigger) if options.step_trigger else None
        wanted = [_absolute(t) for t in options.topics] or [t for t in known if t != trigger]
        unknown = [t for t in wanted if t not in known]
        if unknown:
            raise BagError(f"{path}: no topic {unknown[0]} (topics: {', '.join(known)})")
        start = info.start + round(options.start_offset * 1e9)
        groups = _step_groups(reader, wanted, start) if trigger else None
        control = _Control(PlaybackClock(start, options.rate, paused=options.start_paused))
        result = ReplayResult()
        stop_handler = lambda *_: control.notify(lambda: setattr(control, "stop", True))  # noqa: E731
        with stop_signals(stop_handler), rclpy.init(args=ros_args, signal_handler_options=SignalHandlerOptions.NO):
            player = Player({t: known[t] for t in wanted}, options, control, warn)
            executor = SingleThreadedExecutor()
            executor.add_node(player)
            spinner = threading.Thread(target=executor.spin, daemon=True)
            spinner.start()
            try:
                if trigger:
                    player.subscribe_trigger(trigger, options.wait_timeout)
                if trigger or options.wait_for_subscribers:
                    player.wait_for_subscribers(options.wait_timeout)
                report(f"replaying {path}: {len(wanted)} topic(s)"
                       + (f", {len(groups)} steps through {trigger}" if trigger else f" at rate {options.rate:g}"))
                if trigger:
                    _stepped(player, groups, options, result)
                else:
                    _timed(player, reader, wanted, start, options, result)
                wait_for_acknowledgements([player])  # the last messages reach their readers before the exit
                player.look_for_other_publishers()  # a last look, for a replay shorter than the period
            finally:
                executor.shutdown()
                spinner.join(timeout=2.0)
                player.destroy_node()
    return result


def parse_remaps(words: Iterable[str]) -> tuple[tuple[str, str], ...]:
    """``["a:=b", …]`` → ``(("/a", "/b"), …)`` (BagError naming a malformed one)."""
    remaps = []
    for word in words:
        source, sep, target = word.partition(":=")
        if not sep or not source or not target:
            raise BagError(f"--remap {word!r}: expected FROM:=TO")
        remaps.append((_absolute(source), _absolute(target)))
    return tuple(remaps)
