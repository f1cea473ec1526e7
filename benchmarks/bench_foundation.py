"""Foundation figures: BladeLoads round-trip latency between two node processes, and launcher start-up.

Run with ``./hawt bench foundation``. Prints:
- the round-trip time of a BladeLoads message (B = 3) from this process through a relay node
  process and back, over 2000 samples: p50, p99, max;
- the time from ``hawt launch`` of a 6-node graph (six processes) until every node sees the others
  (all six nodes listed and every topic with its publisher and subscriber matched).
"""
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import rclpy
from domain_coordinator import domain_id
from hawt_msgs.msg import BladeLoads
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy

from hawt_tools.graph_file import package_prefix

SAMPLES = 2000
SIX_NODES = """\
launch:
- node: {pkg: hawt_tools, exec: pulse_source, name: source, namespace: bench, remap: [{from: out, to: a}]}
- node: {pkg: hawt_tools, exec: relay, name: relay1, namespace: bench, remap: [{from: in, to: a}, {from: out, to: b}]}
- node: {pkg: hawt_tools, exec: relay, name: relay2, namespace: bench, remap: [{from: in, to: b}, {from: out, to: c}]}
- node: {pkg: hawt_tools, exec: relay, name: relay3, namespace: bench, remap: [{from: in, to: c}, {from: out, to: d}]}
- node: {pkg: hawt_tools, exec: relay, name: relay4, namespace: bench, remap: [{from: in, to: d}, {from: out, to: e}]}
- node: {pkg: hawt_tools, exec: counter_sink, name: sink, namespace: bench, remap: [{from: in, to: e}]}
"""


def round_trip(node: Node) -> np.ndarray:
    """Round-trip times [s] of SAMPLES BladeLoads messages through a relay in another process."""
    relay = Path(package_prefix("hawt_tools")) / "lib" / "hawt_tools" / "relay"
    process = subprocess.Popen([str(relay), "--ros-args", "-r", "in:=ping", "-r", "out:=pong"],
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    qos = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE)
    replies = []
    publisher = node.create_publisher(BladeLoads, "ping", qos)
    subscription = node.create_subscription(BladeLoads, "pong", replies.append, qos)
    try:
        while publisher.get_subscription_count() == 0 or subscription.get_publisher_count() == 0:
            rclpy.spin_once(node, timeout_sec=0.05)
        msg = BladeLoads(root_moment_oop=[1.0e6] * 3, root_moment_ip=[1.0e5] * 3, pitch=[0.0] * 3)
        times = []
        for step in range(SAMPLES + 50):
            msg.step = step
            replies.clear()
            start = time.perf_counter()
            publisher.publish(msg)
            while not replies:
                rclpy.spin_once(node, timeout_sec=1.0)
            if step >= 50:  # the first exchanges warm the path up
                times.append(time.perf_counter() - start)
        return np.array(times)
    finally:
        process.terminate()
        process.wait()


def launch_to_discovery(node: Node) -> float:
    """Seconds from starting ``hawt launch`` on the 6-node graph until the graph is fully discovered."""
    expected_nodes = {"/bench/source", "/bench/relay1", "/bench/relay2", "/bench/relay3", "/bench/relay4",
                      "/bench/sink"}
    topics = [f"/bench/{t}" for t in "abcde"]
    with tempfile.TemporaryDirectory() as folder:
        graph = Path(folder) / "six.yaml"
        graph.write_text(SIX_NODES)
        start = time.perf_counter()
        launcher = subprocess.Popen([sys.executable, "-m", "hawt_tools.cli", "launch", str(graph)],
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            while True:
                nodes = {f"{ns.rstrip('/')}/{n}" for n, ns in node.get_node_names_and_namespaces()}
                if expected_nodes <= nodes and all(node.count_publishers(t) == 1 and node.count_subscribers(t) == 1
                                                   for t in topics):
                    return time.perf_counter() - start
                if time.perf_counter() - start > 60:
                    raise RuntimeError("the 6-node graph was not discovered within 60 s")
                time.sleep(0.01)
        finally:
            launcher.terminate()
            launcher.wait()


def main() -> None:
    with domain_id() as domain:
        os.environ["ROS_DOMAIN_ID"] = str(domain)
        rclpy.init()
        node = Node("bench_foundation")
        try:
            times = round_trip(node) * 1e6
            print(f"BladeLoads round trip between two processes over {len(times)} samples "
                  f"(ROS_DOMAIN_ID={domain}, {os.environ.get('RMW_IMPLEMENTATION')}): "
                  f"p50 {np.percentile(times, 50):.0f} us, p99 {np.percentile(times, 99):.0f} us, "
                  f"max {times.max():.0f} us")
            runs = [launch_to_discovery(node) for _ in range(3)]
            print(f"hawt launch of a 6-node graph (6 processes) to full discovery: "
                  f"median {statistics.median(runs):.2f} s over {len(runs)} runs "
                  f"({', '.join(f'{r:.2f}' for r in runs)} s)")
        finally:
            node.destroy_node()
            rclpy.shutdown()


if __name__ == "__main__":
    main()
