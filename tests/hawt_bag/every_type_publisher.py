"""A node process that publishes COUNT messages of every hawt_msgs type, once each topic has SUBSCRIBERS.

Topics are ``/every/<Type>``; message i of a type is ``filled(kind, i)``, the same in the
test that checks the bag. Usage: ``python every_type_publisher.py COUNT SUBSCRIBERS``.
"""
import random
import sys
import time

import hawt_msgs.msg
from builtin_interfaces.msg import Time

MESSAGE_TYPES = ("BladeLoads", "TurbineState", "HarmonicLoads", "HarmonicPitch", "CollectivePitch",
                 "PitchCommand", "ControlEvent")


def filled(kind, index: int):
    """Message ``index`` of ``kind``: every field a distinct value; strings of varying length; B = 3."""
    rng = random.Random(f"{kind.__name__}-{index}")
    msg = kind()
    for field, type_name in kind.get_fields_and_field_types().items():
        if type_name == "std_msgs/Header":
            msg.header.stamp = Time(sec=1000 + index, nanosec=rng.randrange(10**9))
            msg.header.frame_id = "f" * rng.randrange(5)
        elif field == "step":
            msg.step = index
        elif type_name == "sequence<double>":
            setattr(msg, field, [rng.uniform(-1e7, 1e7) for _ in range(3)])
        elif type_name == "double":
            setattr(msg, field, rng.uniform(-1e7, 1e7))
        elif type_name.startswith("uint"):
            setattr(msg, field, rng.randrange(2 ** int(type_name[4:])))
        elif type_name == "string":
            setattr(msg, field, f"{field} {rng.random()} ψ"[: rng.randrange(1, 30)])
        else:
            raise AssertionError(f"{kind.__name__}.{field}: no filler for {type_name}")
    return msg


def main(count: int, subscribers: int) -> None:
    import rclpy
    from rclpy.qos import QoSProfile, ReliabilityPolicy

    with rclpy.init():
        node = rclpy.create_node("every_type_publisher")
        qos = QoSProfile(depth=count, reliability=ReliabilityPolicy.RELIABLE)
        publishers = {name: node.create_publisher(getattr(hawt_msgs.msg, name), f"/every/{name}", qos)
                      for name in MESSAGE_TYPES}
        deadline = time.monotonic() + 30.0
        while any(p.get_subscription_count() < subscribers for p in publishers.values()):
            if time.monotonic() > deadline:
                sys.exit("every_type_publisher: subscribers did not come")
            time.sleep(0.02)
        for index in range(count):
            for name, publisher in publishers.items():
                publisher.publish(filled(getattr(hawt_msgs.msg, name), index))
            time.sleep(0.002)
        time.sleep(0.5)
        node.destroy_node()


if __name__ == "__main__":
    main(int(sys.argv[1]), int(sys.argv[2]))
