"""Three small nodes that make the launcher's example graph: source -> relay -> sink.

They exchange real ``hawt_msgs/BladeLoads`` messages. The source publishes a
1P-modulated out-of-plane moment pattern, the relay scales it by its ``gain``,
the sink counts what arrives and can write it to a JSON file, so a graph can be
checked end to end (separate processes or composed).
"""
import json
import math
from typing import Dict

from hawt_msgs.msg import BladeLoads
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.task import Future

from hawt_node.node_main import node_entry_point
from hawt_node.parameters import ParameterSpec, declare_parameters

__all__ = ["PulseSource", "Relay", "CounterSink"]

_QOS = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)


def _blade_loads(step: int, blades: int, rotor_speed: float, dt: float) -> BladeLoads:
    """A rotor turning at constant speed with a 1P out-of-plane moment on each blade."""
    azimuth = (rotor_speed * dt * step) % (2.0 * math.pi)
    psi = [azimuth + 2.0 * math.pi * i / blades for i in range(blades)]
    msg = BladeLoads()
    msg.step = step
    msg.azimuth = azimuth
    msg.rotor_speed = rotor_speed
    msg.root_moment_oop = [1.0e6 * (1.0 + 0.2 * math.cos(p)) for p in psi]
    msg.root_moment_ip = [2.0e5 * math.sin(p) for p in psi]
    msg.pitch = [0.0] * blades
    return msg


class PulseSource(Node):
    """Publishes ``count`` BladeLoads messages on ``out`` at ``rate_hz`` once ``wait_for_subscribers`` are matched."""

    PARAMETERS = (
        ParameterSpec("rate_hz", 50.0, "messages per second", "Hz", minimum=1e-3),
        ParameterSpec("count", 0, "messages to send (0: until stopped)", minimum=0),
        ParameterSpec("blades", 3, "blades of the pretended rotor", minimum=1, maximum=12),
        ParameterSpec("rotor_speed", 1.267, "rotor speed of the pretended rotor", "rad/s"),
        ParameterSpec("wait_for_subscribers", 0, "send the first message once 'out' has this many subscribers",
                      minimum=0),
    )

    def __init__(self, **node_kwargs) -> None:
        super().__init__("pulse_source", **node_kwargs)
        values = declare_parameters(self, self.PARAMETERS)
        self.rate_hz, self.count, self.blades = values["rate_hz"], values["count"], values["blades"]
        self.rotor_speed, self.wait_for_subscribers = values["rotor_speed"], values["wait_for_subscribers"]
        self.get_logger().info(
            f"rate_hz={self.rate_hz} count={self.count} blades={self.blades} rotor_speed={self.rotor_speed}")
        self.publisher = self.create_publisher(BladeLoads, "out", _QOS)
        self.step = 0
        self.done = Future()
        self.timer = self.create_timer(1.0 / self.rate_hz, self._tick)

    def _tick(self) -> None:
        if self.step == 0 and self.publisher.get_subscription_count() < self.wait_for_subscribers:
            return
        if self.count and self.step >= self.count:
            self.get_logger().info(f"sent {self.step} messages")
            self.timer.cancel()
            self.done.set_result(True)
            return
        self.publisher.publish(_blade_loads(self.step, self.blades, self.rotor_speed, 1.0 / self.rate_hz))
        self.step += 1


class Relay(Node):
    """Republishes BladeLoads from ``in`` to ``out`` with the moments multiplied by ``gain``."""

    PARAMETERS = (
        ParameterSpec("gain", 1.0, "factor on the moments"),
        ParameterSpec("label", "", "a name shown in the node's first log line"),
    )

    def __init__(self, **node_kwargs) -> None:
        super().__init__("relay", **node_kwargs)
        values = declare_parameters(self, self.PARAMETERS)
        self.gain, self.label = values["gain"], values["label"]
        self.get_logger().info(f"gain={self.gain} label={self.label!r}")
        self.publisher = self.create_publisher(BladeLoads, "out", _QOS)
        self.create_subscription(BladeLoads, "in", self._relay, _QOS)

    def _relay(self, msg: BladeLoads) -> None:
        msg.root_moment_oop = [self.gain * m for m in msg.root_moment_oop]
        msg.root_moment_ip = [self.gain * m for m in msg.root_moment_ip]
        self.publisher.publish(msg)


class CounterSink(Node):
    """Counts BladeLoads arriving on ``in``; done after ``expect`` messages; writes them to ``record_file``."""

    PARAMETERS = (
        ParameterSpec("expect", 0, "done after this many messages (0: never)", minimum=0),
        ParameterSpec("record_file", "", "JSON file to write what arrived to when the node ends ('': none)"),
    )

    def __init__(self, **node_kwargs) -> None:
        super().__init__("counter_sink", **node_kwargs)
        values = declare_parameters(self, self.PARAMETERS)
        self.expect, self.record_file = values["expect"], values["record_file"]
        self.received: Dict[int, list] = {}
        self.done = Future()
        self.create_subscription(BladeLoads, "in", self._count, _QOS)
        self.create_timer(1.0, self._report)

    def _count(self, msg: BladeLoads) -> None:
        self.received[msg.step] = list(msg.root_moment_oop)
        if self.expect and len(self.received) >= self.expect and not self.done.done():
            self._report()
            self.done.set_result(True)

    def _report(self) -> None:
        if self.received:
            self.get_logger().info(
                f"received {len(self.received)} messages, steps {min(self.received)}..{max(self.received)}")

    def destroy_node(self) -> None:
        self._write()
        super().destroy_node()

    def _write(self) -> None:
        if self.record_file:
            with open(self.record_file, "w") as f:
                json.dump({str(k): v for k, v in sorted(self.received.items())}, f)


main_pulse_source = node_entry_point(PulseSource)
main_relay = node_entry_point(Relay)
main_counter_sink = node_entry_point(CounterSink)
