"""A node process that sends every hawt_msgs message it gets back, and answers both services.

Messages arriving on ``echo_in/<Type>`` are republished unchanged on ``echo_out/<Type>``.
``echo/switch_controllers`` answers with the request's fields folded into the response;
``echo/list_controllers`` answers with a fixed listing. Used by test_interfaces.py.
"""
import json

import hawt_msgs.msg
import rclpy
from hawt_msgs.srv import ListControllers, SwitchControllers
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy

from message_samples import MESSAGE_TYPES

LISTING = {"names": ["ipc_h1", "ipc_h2", "cpc"], "types": ["ipc", "ipc", "cpc"],
           "states": ["active", "inactive", "unconfigured"],
           "interfaces": ["harmonic/1", "harmonic/2", "collective_pitch generator_torque"]}


class Echo(Node):
    def __init__(self):
        super().__init__("echo")
        qos = QoSProfile(depth=50, reliability=ReliabilityPolicy.RELIABLE)
        self.keep = []
        for name in MESSAGE_TYPES:
            kind = getattr(hawt_msgs.msg, name)
            publisher = self.create_publisher(kind, f"echo_out/{name}", qos)
            self.keep.append(self.create_subscription(kind, f"echo_in/{name}", publisher.publish, qos))
        self.create_service(SwitchControllers, "echo/switch_controllers", self.switch)
        self.create_service(ListControllers, "echo/list_controllers", self.listing)

    def switch(self, request, response):
        response.ok = True
        response.message = json.dumps({"activate": list(request.activate), "deactivate": list(request.deactivate),
                                       "strictness": request.strictness, "ramp_time": request.ramp_time})
        response.effective_step = 2**63 + len(request.activate)
        return response

    def listing(self, request, response):
        for field, values in LISTING.items():
            setattr(response, field, values)
        return response


if __name__ == "__main__":
    try:
        with rclpy.init():
            rclpy.spin(Echo())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
