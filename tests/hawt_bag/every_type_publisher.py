"""A node process that publishes COUNT messages of every hawt_msgs type, once each topic has SUBSCRIBERS.

Topics are ``/every/<Type>``; message i of a type is ``filled(kind, i)``, the same in the
test that checks the bag. Usage: ``python every_type_publisher.py COUNT SUBSCRIBERS``.
"""
import sys
import time
from pathlib import Path

import hawt_msgs.msg

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from message_samples import MESSAGE_TYPES, filled  # noqa: E402

def main(count: int, subscribers: int) -> None:
    import rclpy
    import rclpy.duration
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
        for publisher in publishers.values():
            publisher.wait_for_all_acked(rclpy.duration.Duration(seconds=30))
        node.destroy_node()


if __name__ == "__main__":
    main(int(sys.argv[1]), int(sys.argv[2]))
