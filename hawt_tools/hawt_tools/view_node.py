"""The view node: the running graph live in Foxglove over its WebSocket protocol (``hawt view``, ``launch --view``).

Topics are found as the recorder finds them (`hawt_bag.recorder.TopicDiscovery`, every 0.1 s, QoS adapted
to the publishers) and each becomes a channel (``ros2msg`` schema, ``cdr`` encoding: `hawt_tools.view`)
fed with the bytes of a raw subscription, never deserialized. A message's log time is its
``header.stamp`` (the plant's simulated time, DESIGN §3); a message without a header takes the latest
simulated time seen, and ``/clock`` is the server's time, so plots of a live graph and of its bag share
one time axis. The time goes to the clients at most every ``TIME_PERIOD`` of wall time: the protocol's time
messages share a bounded per-client control queue (1024) with the server's other control messages, and a
client that misses more than that is dropped, which ``/clock`` at every plant step (100 Hz, or faster in
lockstep) did to a client that a busy machine kept from reading for a second. A topic whose publishers are all
transient local (latched: ``plant/description``, ``controller_manager/controllers``, the switches, the events, and
the loop's topics, whose writers keep their history for late readers) keeps its last ``LATCHED_REPLAY`` messages,
which are sent again when a client subscribes to it, so a client that joins late sees them as a late ROS reader
would; foxglove-sdk 0.30's Python API cannot send to one client, so the clients already subscribed to that channel
receive them once more. Parameters: the protocol's get
and set go to the nodes' standard ``rcl_interfaces`` parameter services (``/ns/node.param``; an empty get
lists every node's parameters), so a gain can be retuned from the Foxglove app; a node that refuses a value
says why in a status message; what ``/parameter_events`` reports changed, however it was set, goes to the
clients subscribed to it.

Runs as every hawt node does (`hawt_node.node_main.run_nodes`: on the EventsExecutor, stopped by SIGINT
or SIGTERM, or when the process that started it dies).
"""
import argparse
import math
import sys
import threading
import time
from collections import deque
from collections.abc import Iterable, Iterator, Sequence
from typing import List, Optional

import foxglove
from foxglove import Parameter, ParameterType, Schema, StatusLevel
from foxglove.websocket import Capability, ChannelView, Client, ServerListener
from rcl_interfaces.msg import ParameterEvent
from rclpy.node import Node
from rclpy.parameter import Parameter as RosParameter
from rclpy.parameter import parameter_value_to_python
from rclpy.parameter_client import AsyncParameterClient
from rclpy.qos import DurabilityPolicy
from rclpy.task import Future

from hawt_bag.cdr_columns import header_stamp_ns
from hawt_bag.interface_files import has_header, schema_text
from hawt_bag.message_types import message_class
from hawt_bag.recorder import TopicDiscovery, adapted_qos, visible
from hawt_core.topics import CLOCK, VIEW_NODE
from hawt_node.node_main import run_nodes
from hawt_tools.origin_gate import OriginGate
from hawt_tools.view import (CDR, ROS2MSG, ViewOptionError, ViewOptions, add_view_arguments, coerce, is_loopback,
                             options_from, parameter_name, split_parameter_name)

__all__ = ["View", "main", "ros2_schema", "to_parameter", "view", "LATCHED_REPLAY", "TIME_PERIOD"]

TIME_PERIOD = 0.05
"""Wall time [s] between two time messages to the clients (20 per second: smooth for a person watching)."""

LATCHED_REPLAY = 20
"""Messages of a transient-local topic sent again to a client that subscribes to it: every state of a graph's
controllers and its switches; for a loop topic 0.2 s of simulated time. With every channel subscribed at once
(about 20) they stay well inside the server's per-client message queue of 1024."""


def ros2_schema(type_name: str) -> Schema:
    """The ``ros2msg`` schema of ``pkg/msg/Type`` (BagError naming the type if its ``.msg`` is not installed)."""
    return Schema(name=type_name, encoding=ROS2MSG, data=schema_text(type_name).encode())


def to_parameter(full_name: str, value: object) -> Parameter:
    """A protocol parameter from a ROS parameter's Python value (None: not set); floats keep their type."""
    if isinstance(value, float):
        return Parameter(full_name, value=value, type=ParameterType.Float64)
    if isinstance(value, Sequence) and not isinstance(value, (str, bytes)):  # list or array.array
        items = list(value)
        if items and all(isinstance(item, float) for item in items):
            return Parameter(full_name, value=items, type=ParameterType.Float64Array)
        return Parameter(full_name, value=items)
    return Parameter(full_name, value=value)


class View(Node):
    """Forwards every visible topic of the graph to a Foxglove WebSocket server, and parameters both ways."""

    def __init__(self, options: ViewOptions, **node_kwargs) -> None:
        super().__init__(VIEW_NODE, **node_kwargs)
        self.options = options
        self.now = 0  # the latest simulated time seen [ns]
        self._time_sent = -math.inf  # when the server last sent the time (monotonic wall time [s])
        self.counts: dict[str, int] = {}
        self._channels: dict[str, foxglove.Channel] = {}
        self._latched: dict[str, deque] = {}  # topic -> its last (log time [ns], CDR bytes), for late subscribers
        self._latched_lock = threading.Lock()
        self._advertising = threading.Lock()  # held while a channel is created (hawt_tools.origin_gate)
        self._forwarders = {}
        self._parameter_clients: dict[str, AsyncParameterClient] = {}
        self._lock = threading.Lock()
        self._foxglove = foxglove.Context()
        self.server = foxglove.start_server(
            name="hawt", host="127.0.0.1", port=0, context=self._foxglove,
            capabilities=[Capability.Time, Capability.Parameters], server_listener=_Listener(self))
        self.gate: Optional[OriginGate] = None
        try:
            self.gate = OriginGate(options.host, options.port, f"ws://127.0.0.1:{self.server.port}",
                                   options.allow_origins, self.get_logger().warning, self._advertising)
        except OSError as error:
            raise ViewOptionError(f"--port {options.port} on {options.host}: {error.strerror or error}") from None
        if not is_loopback(options.host):
            self.get_logger().warning(f"serving on {options.host} (--allow-remote): anyone who reaches this address "
                                      "sees the graph")
        self.discovery = TopicDiscovery(self, visible, self._subscribe, "viewing")
        self.create_subscription(ParameterEvent, "/parameter_events", self._parameters_changed, 100)
        self.create_timer(options.poll_period, self.discovery.poll)
        self.discovery.poll()
        self.get_logger().info(f"serving the graph on ws://{options.host}:{self.gate.port} "
                               "(Foxglove: Open connection, Foxglove WebSocket)")

    def _subscribe(self, topic: str, type_name: str, publishers) -> None:
        kind = message_class(type_name)
        qos = adapted_qos(publishers, self.options.depth)
        schema = ros2_schema(type_name)
        kept = deque(maxlen=LATCHED_REPLAY) if qos.durability == DurabilityPolicy.TRANSIENT_LOCAL else None
        with self._advertising:  # the channel is known to replay() before a subscription to it gets through
            channel = foxglove.Channel(topic, schema=schema, message_encoding=CDR, context=self._foxglove)
            self._channels[topic] = channel
            if kept is not None:
                self._latched[topic] = kept
        stamped, clock = has_header(type_name), topic == CLOCK
        self.counts[topic] = 0

        def forward(data: bytes) -> None:  # no message info: the EventsExecutor fails on such callbacks
            stamp = self.now
            if stamped or clock:  # rosgraph_msgs/Clock starts with its time as a Header does
                stamp = header_stamp_ns(data)
                self.now = max(self.now, stamp)
            if clock and time.monotonic() - self._time_sent >= TIME_PERIOD:
                self.server.broadcast_time(stamp)
                self._time_sent = time.monotonic()
            channel.log(data, log_time=stamp)
            self.counts[topic] += 1
            if kept is not None:
                with self._latched_lock:
                    kept.append((stamp, data))

        self._forwarders[topic] = self.create_subscription(kind, topic, forward, qos, raw=True)
        self.get_logger().info(f"viewing {topic} [{type_name}]{' (latched)' if kept is not None else ''}")

    def replay(self, topic: str) -> None:
        """Send the kept messages of a transient-local topic again (called when a client subscribes to it)."""
        with self._latched_lock:
            kept = list(self._latched.get(topic, ()))
        for stamp, data in kept:
            self._channels[topic].log(data, log_time=stamp)

    def destroy_node(self) -> None:
        """Stop the gate and the server (clients are disconnected), close the channels, say what was forwarded,
        destroy."""
        self.server.stop()
        for channel in self._channels.values():
            channel.close()
        if self.gate is not None:  # it served
            self.gate.stop()
            self.get_logger().info(f"forwarded {sum(self.counts.values())} messages of {len(self.counts)} topics")
        super().destroy_node()

    def _parameters_changed(self, event: ParameterEvent) -> None:
        """New and changed values of any node to the clients subscribed to them (however they were set)."""
        changed = [*event.new_parameters, *event.changed_parameters]
        if changed and event.node != self.get_fully_qualified_name():
            self.server.publish_parameter_values([to_parameter(parameter_name(event.node, p.name),
                                                               parameter_value_to_python(p.value)) for p in changed])

    # Parameters: called on the server's thread while the executor spins on the main one.

    def _client(self, node: str) -> AsyncParameterClient:
        with self._lock:
            if node not in self._parameter_clients:
                self._parameter_clients[node] = AsyncParameterClient(self, node)
            client = self._parameter_clients[node]
        if not client.wait_for_services(self.options.timeout):
            raise TimeoutError(f"{node}: no parameter services within {self.options.timeout:g} s")
        return client

    def _result(self, future: Future):
        done = threading.Event()
        future.add_done_callback(lambda _: done.set())
        if not done.wait(self.options.timeout):
            raise TimeoutError(f"no answer within {self.options.timeout:g} s")
        return future.result()

    def _split(self, full_names: Iterable[str]) -> Iterator[tuple[str, str]]:
        """(node, parameter) of each name; a name that is not ``/node.parameter`` is an error status instead."""
        for full_name in full_names:
            try:
                yield split_parameter_name(full_name)
            except ValueError as error:
                self.server.publish_status(str(error), StatusLevel.Error)

    def _nodes(self) -> List[str]:
        own = self.get_fully_qualified_name()
        names = (f"{namespace.rstrip('/')}/{name}" for name, namespace in self.get_node_names_and_namespaces())
        return sorted(name for name in set(names) if name != own)

    def _values(self, node: str, names: Optional[Sequence[str]] = None) -> dict[str, object]:
        """Python values of ``names`` (all if None) of a node."""
        client = self._client(node)
        if names is None:
            names = list(self._result(client.list_parameters()).result.names)
        values = self._result(client.get_parameters(list(names))).values
        return {name: parameter_value_to_python(value) for name, value in zip(names, values)}

    def get_parameters(self, full_names: Sequence[str]) -> List[Parameter]:
        """The protocol's getParameters: the named parameters, or every node's if none are named."""
        wanted: dict[str, Optional[List[str]]] = {node: None for node in self._nodes()} if not full_names else {}
        for node, name in self._split(full_names):
            wanted.setdefault(node, []).append(name)
        found = []
        for node, names in wanted.items():
            try:
                found += [to_parameter(parameter_name(node, name), value)
                          for name, value in self._values(node, names).items()]
            except TimeoutError as error:
                self.get_logger().warning(f"parameters of {node}: {error}")
        return found

    def set_parameters(self, parameters: Sequence[Parameter]) -> List[Parameter]:
        """The protocol's setParameters: each value (as the parameter's type) to its node; the values after."""
        by_node: dict[str, dict[str, object]] = {}
        for parameter in parameters:
            for node, name in self._split([parameter.name]):
                by_node.setdefault(node, {})[name] = parameter.get_value()
        after = []
        for node, values in by_node.items():
            try:
                current = self._values(node, list(values))
                requests = [RosParameter(name, value=coerce(value, current[name])) for name, value in values.items()]
                results = self._result(self._client(node).set_parameters(requests)).results
                for request, result in zip(requests, results):
                    if not result.successful:
                        self.server.publish_status(f"{node}: {request.name} not set: {result.reason}",
                                                   StatusLevel.Warning)
                after += [to_parameter(parameter_name(node, name), value)
                          for name, value in self._values(node, list(values)).items()]
            except (TimeoutError, TypeError, ValueError) as error:
                self.server.publish_status(f"{node}: parameters not set: {error}", StatusLevel.Error)
        return after


class _Listener(ServerListener):
    """The server's subscriptions (latched topics are replayed) and parameter requests, handed to the view node."""

    def __init__(self, node: View) -> None:
        self._node = node

    def on_subscribe(self, client: Client, channel: ChannelView) -> None:
        self._node.replay(channel.topic)

    def on_get_parameters(self, client: Client, param_names: list[str],
                          request_id: Optional[str] = None) -> list[Parameter]:
        return self._node.get_parameters(param_names)

    def on_set_parameters(self, client: Client, parameters: list[Parameter],
                          request_id: Optional[str] = None) -> list[Parameter]:
        if not self._node.options.allow_parameter_sets:
            self._node.server.publish_status("parameters not set: this view is read-only (hawt view "
                                             "--allow-parameter-sets lets clients set them)", StatusLevel.Error)
            return self._node.get_parameters([parameter.name for parameter in parameters])
        return self._node.set_parameters(parameters)


def view(options: ViewOptions, ros_args: Optional[List[str]] = None) -> int:
    """Serve the graph until SIGINT/SIGTERM or the death of the starting process; returns the exit code."""
    run_nodes(lambda: [View(options)], lambda _nodes: None, ros_args)
    return 0


def main(argv: Optional[Sequence[str]] = None) -> None:
    """The ``view`` executable (what ``hawt launch --view`` starts): ``view [--host H] [--port N]``."""
    argv = list(sys.argv[1:] if argv is None else argv)
    ros_args = argv[argv.index("--ros-args"):] if "--ros-args" in argv else []
    parser = argparse.ArgumentParser(prog="view", description="Serve the running graph to Foxglove.")
    add_view_arguments(parser)
    try:
        sys.exit(view(options_from(parser.parse_args(argv[:len(argv) - len(ros_args)])), ["view", *ros_args]))
    except ViewOptionError as error:
        print(f"view: {error}", file=sys.stderr)
        sys.exit(2)
