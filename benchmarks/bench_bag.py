"""Figures of the bag tools: recording without loss at 1 kHz, replay timing at rate 1, analyze on a 600 s run.

Run from the repository root:  ./hawt bench bag [--record-seconds S] [--skip-record]
(a) a publisher process sends BladeLoads at 1 kHz for S seconds (60 by default) while
    ``hawt record`` records every topic: published and recorded counts, recorder CPU per message,
    and the recorder's own verdict on its bag (what it lost, if anything);
(b) ``replay`` of a 100 Hz bag at rate 1: how late each message left the player (its own clock)
    and how far each arrival at a subscriber strays from the recorded spacing (DDS included);
(c) ``hawt analyze`` on a synthetic 600 s, 100 Hz bag of the full graph's topics (plant, MBC,
    IPC, collective, command, events, /clock): reading, numbers, the whole command, and --report.
Targets: no message lost; replay p99 error < 1 ms; analyze numbers < 2 s.
"""
import argparse
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
for package in ("hawt_bag", "hawt_analysis"):
    sys.path.insert(0, str(ROOT / package))

from hawt_analysis.synthetic_run import synthetic_channels  # noqa: E402
from hawt_bag.column_writing import TopicData, plant_topics, write_topics  # noqa: E402
from hawt_bag.writer import BagWriter  # noqa: E402

PUBLISHER = """
import sys, time, rclpy
from rclpy.qos import QoSProfile, ReliabilityPolicy
from hawt_msgs.msg import BladeLoads
rate, seconds = float(sys.argv[1]), float(sys.argv[2])
with rclpy.init():
    node = rclpy.create_node("bench_publisher")
    publisher = node.create_publisher(BladeLoads, "/bench/loads", QoSProfile(depth=1000,
                                      reliability=ReliabilityPolicy.RELIABLE))
    while publisher.get_subscription_count() < 1:
        time.sleep(0.01)
    time.sleep(0.5)
    message = BladeLoads(root_moment_oop=[1.0, 2.0, 3.0], root_moment_ip=[0.0] * 3, pitch=[0.0] * 3)
    start, n = time.monotonic(), int(rate * seconds)
    for k in range(n):
        message.step = k
        message.header.stamp.sec, message.header.stamp.nanosec = divmod(k * int(1e9 / rate), 10**9)
        publisher.publish(message)
        delay = start + (k + 1) / rate - time.monotonic()
        if delay > 0:
            time.sleep(delay)
    print(n, time.monotonic() - start)
    time.sleep(1.0)
"""


def _hawt(*arguments: str) -> list[str]:
    return [sys.executable, "-m", "hawt_tools.cli", *arguments]


def bench_record(folder: Path, seconds: float) -> None:
    import psutil

    from hawt_bag.reader import BagReader
    bag = folder / "record.mcap"
    recorder = subprocess.Popen(_hawt("record", "-o", str(bag)), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                text=True, start_new_session=True)
    while not bag.exists():
        time.sleep(0.05)
    try:
        cpu_start = sum(psutil.Process(recorder.pid).cpu_times()[:2])
        publisher = subprocess.run([sys.executable, "-c", PUBLISHER, "1000", str(seconds)], capture_output=True,
                                   text=True, timeout=seconds * 3 + 60)
        published, took = publisher.stdout.split()
        cpu_end = sum(psutil.Process(recorder.pid).cpu_times()[:2])
    finally:
        os.killpg(recorder.pid, signal.SIGINT)
        out, err = recorder.communicate(timeout=60)
    with BagReader(bag) as reader:
        recorded = {t.topic: t.count for t in reader.info().topics}["/bench/loads"]
    print(f"(a) record 1 kHz for {seconds:g} s: published {published} in {float(took):.2f} s, recorded {recorded}"
          f" ({int(published) - recorded} lost); recorder CPU {1e6 * (cpu_end - cpu_start) / recorded:.0f} µs per "
          f"message ({100 * (cpu_end - cpu_start) / float(took):.0f} % of one core)")
    for line in (out + err).splitlines():
        if line.startswith(("verify:", "with holes:")):
            print(f"    the recorder said: {line}")


def bench_replay(folder: Path, n: int = 1000, period_ns: int = 10_000_000) -> None:
    import rclpy
    from hawt_msgs.msg import BladeLoads
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import QoSProfile, ReliabilityPolicy

    from hawt_bag.replayer import ReplayOptions, replay
    bag = folder / "replay.mcap"
    steps = np.arange(n, dtype=np.uint64)
    with BagWriter(bag) as writer:
        write_topics(writer, [TopicData("/bench/replayed", "hawt_msgs/msg/BladeLoads",
                                        {"step": steps, "pitch": np.zeros((n, 3))}, period_ns * steps.astype(int))])
    context = rclpy.Context()
    rclpy.init(context=context)
    node = rclpy.create_node("bench_receiver", context=context)
    arrivals = []
    node.create_subscription(BladeLoads, "/bench/replayed", lambda data: arrivals.append(time.monotonic_ns()),
                             QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE), raw=True)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    result = replay(bag, ReplayOptions(wait_for_subscribers=True), report=lambda _: None)
    time.sleep(0.5)
    executor.shutdown()
    rclpy.shutdown(context=context)
    late = np.abs(result.lateness) * 1e-6
    received = np.array(arrivals, dtype=np.int64)
    offset = (received - received[0]) - period_ns * np.arange(received.size)
    error = np.abs(offset - np.median(offset)) * 1e-6
    print(f"(b) replay of {n} messages at 100 Hz, rate 1: {received.size} received; player lateness p50 "
          f"{np.percentile(late, 50):.3f} ms, p99 {np.percentile(late, 99):.3f} ms, max {late.max():.3f} ms; "
          f"arrival time vs recorded time (median offset removed) p50 {np.percentile(error, 50):.3f} ms, p99 {np.percentile(error, 99):.3f} ms,"
          f" max {error.max():.3f} ms")


def _full_graph_topics(channels: dict) -> list:
    """The plant topics plus what the controllers publish (MBC h1-h3, IPC h1-h3, collective, /clock)."""
    topics = plant_topics(channels, "/wt1", [{"step": 6000 * k, "source": "controller_manager", "level": 20,
                                              "kind": "switch", "detail": f"switch {k}"} for k in range(10)])
    n = channels["time"].size
    log_time = topics[0].log_time
    stamp = {key: values for key, values in topics[0].columns.items() if key.startswith("header") or key == "step"}
    harmonic = {**stamp, "azimuth": channels["azimuth"], "rotor_speed": channels["rotor_speed"],
                "cos": np.ones(n), "sin": np.zeros(n), "mean": np.ones(n)}
    for h in (1, 2, 3):
        topics.append(TopicData(f"/wt1/control/mbc/h{h}", "hawt_msgs/msg/HarmonicLoads",
                                {**harmonic, "harmonic": np.full(n, h, np.uint32)}, log_time))
        topics.append(TopicData(f"/wt1/control/ipc/h{h}", "hawt_msgs/msg/HarmonicPitch",
                                {**stamp, "harmonic": np.full(n, h, np.uint32), "cos": np.zeros(n),
                                 "sin": np.zeros(n)}, log_time))
    topics.append(TopicData("/wt1/control/collective", "hawt_msgs/msg/CollectivePitch",
                            {**stamp, "pitch": channels["pitch"].mean(axis=1), "region": np.full(n, 3, np.uint8),
                             "wind_speed_estimate": np.full(n, np.nan)}, log_time))
    topics.append(TopicData("/clock", "rosgraph_msgs/msg/Clock",
                            {"clock.sec": stamp["header.stamp.sec"], "clock.nanosec": stamp["header.stamp.nanosec"]},
                            log_time))
    return topics


def bench_analyze(folder: Path) -> None:
    from hawt_analysis.summary import summarize

    from hawt_bag.plant_run import load_plant_run
    from hawt_bag.reader import BagReader
    bag = folder / "full_graph.mcap"
    channels = synthetic_channels(duration=600.0, sample_rate=100.0)
    start = time.perf_counter()
    with BagWriter(bag) as writer:
        written = write_topics(writer, _full_graph_topics(channels))
    made = time.perf_counter() - start
    print(f"(c) synthetic full-graph bag: {sum(written.values())} messages on {len(written)} topics, "
          f"{bag.stat().st_size / 2**20:.1f} MiB, written in {made:.1f} s")
    timings = []
    for _ in range(3):
        start = time.perf_counter()
        with BagReader(bag) as reader:
            run = load_plant_run(reader)
        read = time.perf_counter() - start
        summarize(run.channels)
        timings.append((read, time.perf_counter() - start - read))
    read, numbers = min(timings, key=sum)
    print(f"    reading the 4 plant/control topics into arrays {1e3 * read:.0f} ms, summarize {1e3 * numbers:.0f} ms"
          f" (best of 3): {read + numbers:.2f} s for the numbers")
    for label, extra in (("hawt analyze --json (whole command, new process)", ["--json"]),
                         ("hawt analyze --report (whole command, new process)", ["--report", str(folder / "r")])):
        start = time.perf_counter()
        result = subprocess.run(_hawt("analyze", str(bag), *extra), capture_output=True, text=True)
        assert result.returncode == 0, result.stderr
        print(f"    {label}: {time.perf_counter() - start:.2f} s")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--record-seconds", type=float, default=60.0)
    parser.add_argument("--skip-record", action="store_true")
    args = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    with tempfile.TemporaryDirectory(prefix="bench_bag_") as folder:
        bench_analyze(Path(folder))
        bench_replay(Path(folder))
        if not args.skip_record:
            bench_record(Path(folder), args.record_seconds)


if __name__ == "__main__":
    main()
