"""Realtime endurance and capacity: late steps and memory of full graphs running at 100 Hz.

Run with ``./hawt bench realtime_soak``. Two measurements (issue 6):

- ``soak`` (default): the ipc graph (plant, cpc, mbc, ipc_h1..h3, controller_manager), every
  node its own process, in realtime at 100 Hz for ``--duration`` seconds (default 1800) with
  the recorder; prints the plant's loop latency and late steps, the bag's size, and each
  process's resident memory at the start and the end (growth per hour).
- ``turbines``: N copies of the graph, each in its own namespace (wt1..wtN), all at once in
  realtime for ``--duration`` seconds; N = 1, 2, ... until a turbine has a late step (or
  ``--max-turbines``). Prints each N's late steps and worst p99 latency.

Both run the nodes under SCHED_FIFO ``--priority`` (default 50; 0: normal scheduling).

Usage: ./hawt bench realtime_soak [soak|turbines] [--duration S] [--max-turbines N] [--priority N]
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Dict, List

import psutil
from domain_coordinator import domain_id

from bench_control_loop import FINISHED

CLI = [sys.executable, "-m", "hawt_tools.cli"]


def _memory(launcher: psutil.Process) -> Dict[str, float]:
    """Resident memory [MiB] of each node process of a launcher, keyed by its node name."""
    sizes = {}
    for child in launcher.children(recursive=True):
        try:
            words = child.cmdline()
            name = next((w.split(":=")[1] for w in words if w.startswith("__node:=")),
                        "recorder" if any(w.endswith("/record") for w in words) else Path(words[0]).name)
            sizes[name] = child.memory_info().rss / 2**20
        except (psutil.NoSuchProcess, IndexError):
            continue
    return sizes


def _figures(text: str) -> Dict[str, float]:
    match = FINISHED.search(text)
    if match is None or match.group(4) is None:
        raise RuntimeError("the plant did not report its realtime figures:\n" + text[-2000:])
    steps, _, wall, p50, p99, worst, late = match.groups()
    return {"steps": int(steps), "wall": float(wall), "p50": float(p50), "p99": float(p99), "max": float(worst),
            "late": int(late)}


def soak(duration: float, priority: int) -> None:
    with tempfile.TemporaryDirectory(prefix="hawt_soak_") as folder, domain_id() as domain:
        bag = Path(folder) / "soak.mcap"
        process = subprocess.Popen([*CLI, "launch", "ipc", "--mode", "realtime", "--priority", str(priority),
                                    f"duration:={duration}", "-p", "plant.report_period:=1", "--record", str(bag)],
                                   stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                   env={**os.environ, "ROS_DOMAIN_ID": str(domain)})
        lines: List[str] = []
        reader = threading.Thread(target=lambda: lines.extend(process.stdout), daemon=True)
        reader.start()
        launcher = psutil.Process(process.pid)
        while process.poll() is None and not any(" s (" in line and "t=" in line for line in list(lines)):
            time.sleep(0.5)  # the plant's first progress line: every process is up and stepping
        first = _memory(launcher)
        started = time.monotonic()
        last = first
        while process.poll() is None:
            current = _memory(launcher)
            if len(current) >= len(first):
                last = current
            time.sleep(10.0)
        reader.join(timeout=10)
        hours = max(time.monotonic() - started, 1.0) / 3600
        figures = _figures("".join(lines))
        print(f"soak: ipc graph + recorder, realtime 100 Hz, SCHED_FIFO priority {priority} (0: normal), "
              f"{figures['steps']} steps in {figures['wall']:.0f} s")
        print(f"  loop latency p50 {figures['p50']:.2f} ms, p99 {figures['p99']:.2f} ms, max {figures['max']:.2f} ms;"
              f" late steps {figures['late']}")
        print(f"  bag {bag.stat().st_size / 2**20:.1f} MiB" if bag.exists() else "  bag missing")
        for name in sorted(first):
            if name in last:
                print(f"  {name:<20} RSS {first[name]:7.1f} -> {last[name]:7.1f} MiB "
                      f"({(last[name] - first[name]) / hours:+.1f} MiB/h)")


def turbines(duration: float, most: int, priority: int) -> None:
    for count in range(1, most + 1):
        with domain_id() as domain:
            env = {**os.environ, "ROS_DOMAIN_ID": str(domain)}
            processes = [subprocess.Popen([*CLI, "launch", "ipc", "--mode", "realtime", "--priority", str(priority),
                                           f"namespace:=wt{i + 1}", f"duration:={duration}"], stdout=subprocess.PIPE,
                                          stderr=subprocess.STDOUT, text=True, env=env) for i in range(count)]
            results = [_figures(p.communicate(timeout=duration * 5 + 300)[0]) for p in processes]
        late = [r["late"] for r in results]
        print(f"turbines {count}: late steps {late}, worst p99 {max(r['p99'] for r in results):.2f} ms, "
              f"worst max {max(r['max'] for r in results):.2f} ms  load {os.getloadavg()[0]:.1f}")
        if any(late):
            print(f"most turbines in realtime at 100 Hz with no late step: {count - 1}")
            return
    print(f"no late step up to {most} turbines (raise --max-turbines)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("what", nargs="?", choices=("soak", "turbines"), default="soak")
    parser.add_argument("--duration", type=float, help="seconds per run (soak 1800, turbines 60)")
    parser.add_argument("--max-turbines", type=int, default=8)
    parser.add_argument("--priority", type=int, default=50,
                        help="SCHED_FIFO priority of the nodes (hawt launch --priority); 0: normal scheduling")
    args = parser.parse_args()
    if args.what == "soak":
        soak(args.duration or 1800.0, args.priority)
    else:
        turbines(args.duration or 60.0, args.max_turbines, args.priority)


if __name__ == "__main__":
    main()
