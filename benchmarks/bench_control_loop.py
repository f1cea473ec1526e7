"""Speed of the closed loop: lockstep real-time factor and realtime loop latency of the node graphs.

Run with ``./hawt bench control_loop``. Each figure comes from a real ``hawt launch`` of an
installed graph (plant, cpc, mbc and, for ``ipc``, ipc_h1..h3) at 100 Hz in IEC class B
turbulence at 18 m/s (the demo's field, cached after its first generation), read from the
plant's ``finished`` line:

- lockstep, every node its own process, and ``--composed`` (one process, one executor):
  simulated time / wall time from step 0 to the last step;
- realtime, separate processes and composed, for ``--realtime-duration`` simulated (= wall)
  seconds, the nodes under SCHED_FIFO ``--priority`` (0: normal scheduling): loop latency
  (measurement sent -> command of that step received) p50/p99/max and the number of late
  steps (a command that arrived after the next tick).

Targets of issue 4: distributed lockstep >= 10x real time; realtime p99 <= 3 ms, no late step.
The machine's load average is printed: two cores are shared by every process of the graph.

The floor under the lockstep figures is measured too (``--hops``): a ring of relay
processes (hawt_tools' example ``relay`` node, rclpy on the EventsExecutor) passing one
BladeLoads message around, each lap closed by this process. A lockstep step needs at
least its critical path of hops (baseline: plant -> cpc -> mbc -> plant, 3; ipc: the same 3,
plant -> ipc_hn -> mbc -> plant, since the IPC nodes take plant/blade_loads themselves), so
10 ms / (hops x time per hop) bounds its real-time factor with no computation at all.

Usage: ./hawt bench control_loop [--duration S] [--realtime-duration S] [--graphs G ...] [--no-realtime]
                                 [--hops N ...] [--laps N] [--priority N]
"""
from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import time
from pathlib import Path
from typing import Dict, List, Optional

import numpy as np
import rclpy
from ament_index_python.packages import get_package_prefix
from domain_coordinator import domain_id
from hawt_msgs.msg import BladeLoads
from rclpy.qos import QoSProfile, ReliabilityPolicy

from hawt_node.node_main import make_executor

FINISHED = re.compile(r"finished (\d+) steps \(([\d.]+) s simulated\) in ([\d.]+) s wall"
                      r"(?:; loop latency p50 ([\d.]+) ms, p99 ([\d.]+) ms, max ([\d.]+) ms; late steps (\d+))?")
WIND = ["wind_type:=turbulent", "wind_speed:=18.0", "seed:=1"]


def run_graph(graph: str, duration: float, options: List[str]) -> Dict[str, float]:
    """Launch ``graph`` for ``duration`` simulated seconds; the figures of the plant's finished line."""
    command = [sys.executable, "-m", "hawt_tools.cli", "launch", graph, f"duration:={duration}", *WIND, *options]
    with domain_id() as domain:
        result = subprocess.run(command, capture_output=True, text=True, timeout=duration * 20 + 300,
                                env={**os.environ, "ROS_DOMAIN_ID": str(domain)})
    match = FINISHED.search(result.stdout + result.stderr)
    if result.returncode != 0 or match is None:
        tail = "\n".join((result.stdout + result.stderr).splitlines()[-15:])
        raise RuntimeError(f"{' '.join(command[3:])} failed (exit {result.returncode}):\n{tail}")
    steps, simulated, wall, p50, p99, worst, late = match.groups()
    figures = {"steps": int(steps), "simulated": float(simulated), "wall": float(wall)}
    if p50 is not None:
        figures.update(p50=float(p50), p99=float(p99), max=float(worst), late=int(late))
    return figures


def lockstep(graphs: List[str], duration: float) -> None:
    print(f"lockstep, {duration:g} s simulated at 100 Hz (real-time factor = simulated / wall from step 0)")
    for graph in graphs:
        for layout, options in (("processes", []), ("composed", ["--composed"])):
            figures = run_graph(graph, duration, options)
            print(f"  {graph:<9} {layout:<9} {figures['simulated'] / figures['wall']:6.1f}x real time "
                  f"({figures['steps']} steps in {figures['wall']:.1f} s, "
                  f"{figures['wall'] / figures['steps'] * 1e3:.2f} ms per step)  load {os.getloadavg()[0]:.1f}")


def realtime(graphs: List[str], duration: float, priority: int) -> None:
    scheduling = f"SCHED_FIFO priority {priority} (--priority)" if priority else "normal scheduling"
    print(f"realtime, {duration:g} s at 100 Hz, nodes under {scheduling}")
    for graph in graphs:
        for layout, options in (("processes", []), ("composed", ["--composed"])):
            figures = run_graph(graph, duration, ["--mode", "realtime", "--priority", str(priority), *options])
            print(f"  {graph:<9} {layout:<9} loop latency p50 {figures['p50']:.2f} ms, p99 {figures['p99']:.2f} ms, "
                  f"max {figures['max']:.2f} ms; late steps {figures['late']} of {figures['steps']}  "
                  f"load {os.getloadavg()[0]:.1f}")


def ring_lap_times(hops: int, laps: int, period: float = 0.0) -> np.ndarray:
    """Wall time [s] of each lap of one message around a ring of ``hops`` hops (``hops - 1`` relay processes).

    ``period`` 0: each lap starts when the last one ends (every process stays busy, like
    lockstep); else one lap every ``period`` seconds (the processes idle between laps, like
    realtime at 1/period Hz).
    """
    relay = Path(get_package_prefix("hawt_tools")) / "lib" / "hawt_tools" / "relay"
    qos = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
    sent: List[float] = []
    times: List[float] = []
    with domain_id() as domain:
        environment = {**os.environ, "ROS_DOMAIN_ID": str(domain)}
        relays = [subprocess.Popen([str(relay), "--ros-args", "-r", f"__node:=relay{k}", "-r", f"in:=/ring/h{k - 1}",
                                    "-r", f"out:=/ring/h{k}"], env=environment, stdout=subprocess.DEVNULL,
                                   stderr=subprocess.DEVNULL) for k in range(1, hops)]
        os.environ["ROS_DOMAIN_ID"] = str(domain)
        try:
            with rclpy.init():
                node = rclpy.create_node("ring_bench")
                publisher = node.create_publisher(BladeLoads, "/ring/h0", qos)
                message = BladeLoads(root_moment_oop=[1e6] * 3, root_moment_ip=[1e5] * 3, pitch=[0.1] * 3)

                def send() -> None:
                    message.step = len(sent)
                    sent.append(time.perf_counter())
                    publisher.publish(message)

                def lap(msg: BladeLoads) -> None:
                    if msg.step != len(sent) - 1:
                        return  # a connection probe
                    times.append(time.perf_counter() - sent[-1])
                    if period == 0.0 and len(times) < laps:
                        send()

                def tick() -> None:
                    if len(times) == len(sent) < laps:
                        send()
                node.create_subscription(BladeLoads, f"/ring/h{hops - 1}", lap, qos)
                executor = make_executor()
                executor.add_node(node)
                deadline = time.monotonic() + 60.0
                while not times and time.monotonic() < deadline:
                    sent.clear()
                    send()  # until the ring is connected; that lap is not counted
                    executor.spin_once(timeout_sec=0.2)
                times.clear()
                sent.clear()
                if period > 0.0:
                    node.create_timer(period, tick)
                else:
                    send()
                while len(times) < laps and time.monotonic() < deadline + 600.0:
                    executor.spin_once(timeout_sec=0.1)
                executor.shutdown()
                node.destroy_node()
        finally:
            for process in relays:
                process.terminate()
                process.wait()
    if len(times) < laps:
        raise RuntimeError(f"the {hops}-hop ring completed {len(times)} of {laps} laps")
    return np.array(times)


def message_floor(hop_counts: List[int], laps: int) -> None:
    print(f"message-passing floor: one BladeLoads around a ring of processes, {laps} laps")
    for hops in hop_counts:
        per_lap = ring_lap_times(hops, laps) * 1e3
        mean = per_lap.mean()
        paced = ring_lap_times(hops, laps, period=0.01) * 1e3
        print(f"  {hops} hops back to back: lap p50 {np.percentile(per_lap, 50):.2f} ms, p99 "
              f"{np.percentile(per_lap, 99):.2f} ms, mean {mean:.2f} ms = {mean / hops:.3f} ms per hop -> a {hops}-hop "
              f"lockstep loop at 100 Hz runs at most {10.0 / mean:.1f}x real time  load {os.getloadavg()[0]:.1f}")
        print(f"  {hops} hops one lap per 10 ms: lap p50 {np.percentile(paced, 50):.2f} ms, p99 "
              f"{np.percentile(paced, 99):.2f} ms, max {paced.max():.2f} ms (a realtime loop's latency floor)")


def main(argv: Optional[List[str]] = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=60.0, help="lockstep: simulated seconds per run")
    parser.add_argument("--realtime-duration", type=float, default=300.0, help="realtime: seconds per run")
    parser.add_argument("--graphs", nargs="*", default=["baseline", "ipc"], help="installed graphs to run (none: skip)")
    parser.add_argument("--no-realtime", action="store_true", help="lockstep figures only")
    parser.add_argument("--hops", nargs="*", type=int, default=[2, 3, 4],
                        help="ring sizes of the message-passing floor (none: skip it)")
    parser.add_argument("--laps", type=int, default=3000, help="laps per ring")
    parser.add_argument("--priority", type=int, default=50,
                        help="realtime: SCHED_FIFO priority of the nodes (hawt launch --priority); 0: normal")
    args = parser.parse_args(argv)
    if args.hops:
        message_floor(args.hops, args.laps)
    lockstep(args.graphs, args.duration)
    if not args.no_realtime:
        realtime(args.graphs, args.realtime_duration, args.priority)


if __name__ == "__main__":
    main()
