"""Speed of the closed loop: lockstep real-time factor and realtime loop latency of the node graphs.

Run with ``./hawt bench control_loop``. Each figure comes from a real ``hawt launch`` of an
installed graph (plant, cpc, mbc and, for ``ipc``, ipc_h1..h3) at 100 Hz in IEC class B
turbulence at 18 m/s (the demo's field, cached after its first generation), read from the
plant's ``finished`` line:

- lockstep, every node its own process, and ``--composed`` (one process, one executor):
  simulated time / wall time from step 0 to the last step;
- realtime, every node its own process, for ``--realtime-duration`` simulated (= wall)
  seconds: loop latency (measurement sent -> command of that step received) p50/p99/max and
  the number of late steps (a command that arrived after the next tick).

Targets of issue 4: distributed lockstep >= 10x real time; realtime p99 <= 3 ms, no late step.
The machine's load average is printed: two cores are shared by every process of the graph.

Usage: ./hawt bench control_loop [--duration S] [--realtime-duration S] [--graphs G ...] [--no-realtime]
"""
from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
from typing import Dict, List, Optional

from domain_coordinator import domain_id

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


def realtime(graphs: List[str], duration: float) -> None:
    print(f"realtime, {duration:g} s at 100 Hz, every node its own process")
    for graph in graphs:
        figures = run_graph(graph, duration, ["--mode", "realtime"])
        print(f"  {graph:<9} loop latency p50 {figures['p50']:.2f} ms, p99 {figures['p99']:.2f} ms, "
              f"max {figures['max']:.2f} ms; late steps {figures['late']} of {figures['steps']}  "
              f"load {os.getloadavg()[0]:.1f}")


def main(argv: Optional[List[str]] = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=60.0, help="lockstep: simulated seconds per run")
    parser.add_argument("--realtime-duration", type=float, default=300.0, help="realtime: seconds per run")
    parser.add_argument("--graphs", nargs="+", default=["baseline", "ipc"], help="installed graphs to run")
    parser.add_argument("--no-realtime", action="store_true", help="lockstep figures only")
    args = parser.parse_args(argv)
    lockstep(args.graphs, args.duration)
    if not args.no_realtime:
        realtime(args.graphs, args.realtime_duration)


if __name__ == "__main__":
    main()
