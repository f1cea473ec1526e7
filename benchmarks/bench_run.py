"""Speed of the in-process engine (``hawt run``) against the plant core alone and the lockstep ROS graph.

In one run, on the same turbulent wind (IEC class B, 18 m/s, seed 1):
- the plant core alone (the ipc graph's plant, commands held at the operating point);
- ``hawt run`` of the ``baseline`` and ``ipc`` graphs (the graph's cores in process);
- ``hawt launch ipc`` in lockstep, one process per node (shorter: ``--lockstep-duration``).
Prints each real-time factor and the two ratios issue 10 sets targets for: the in-process
ipc graph against the plant core (target >= 0.8) and against the lockstep graph (target >= 5),
then where a step of the in-process ipc graph goes (a second run with each core timed).

Usage: ./hawt bench run [--duration S] [--lockstep-duration S]
"""
import argparse
import os
import subprocess
import sys
import time
from pathlib import Path
from typing import Callable, Dict

from hawt_tools.graph_file import find_graph
from hawt_tools.graph_file import load_graph
from hawt_tools.in_process import build_run
from hawt_tools.graph_file import package_prefix

ROOT = Path(__file__).resolve().parents[1]


def _arguments(duration: float) -> dict:
    return {"wind_type": "turbulent", "wind_speed": "18.0", "seed": "1", "duration": str(duration)}


def plant_core(duration: float) -> float:
    """Real-time factor of the plant model alone, commands held."""
    run = build_run(load_graph(find_graph("ipc"), _arguments(duration), package_prefix))
    pitch, torque = run.output.pitch.copy(), float(run.output.generator_torque)
    steps = round(duration / run.description.dt)
    start = time.perf_counter()
    for _ in range(steps):
        run.model.step(pitch, torque)
    return duration / (time.perf_counter() - start)


def in_process(graph: str, duration: float) -> float:
    """Real-time factor of ``hawt run GRAPH`` without recording (cores built before the clock starts)."""
    run = build_run(load_graph(find_graph(graph), _arguments(duration), package_prefix))
    steps = round(duration / run.description.dt)
    start = time.perf_counter()
    for _ in range(steps):
        run.step()
    return duration / (time.perf_counter() - start)


def step_breakdown(graph: str, duration: float) -> Dict[str, float]:
    """Mean wall time [us] per step of each core of ``hawt run GRAPH`` (the plant in the loop, every controller,
    the assembly) and of the runner around them; the timing adds about 1 us per timed call."""
    run = build_run(load_graph(find_graph(graph), _arguments(duration), package_prefix))
    spent: Dict[str, float] = {}

    def timed(name: str, function: Callable) -> Callable:
        def call(*args, **kwargs):
            start = time.perf_counter()
            try:
                return function(*args, **kwargs)
            finally:
                spent[name] = spent.get(name, 0.0) + time.perf_counter() - start
        return call

    run.model.step = timed("plant (in the loop)", run.model.step)
    for controller in run.controllers:
        controller.core.update = timed(controller.name.rsplit("/", 1)[-1], controller.core.update)
    run.assembler.assemble = timed("assembly", run.assembler.assemble)
    steps = round(duration / run.description.dt)
    start = time.perf_counter()
    for _ in range(steps):
        run.step()
    total = time.perf_counter() - start
    spent["runner"] = total - sum(spent.values())
    return {name: seconds / steps * 1e6 for name, seconds in spent.items()}


def lockstep(duration: float) -> float:
    """Real-time factor of the lockstep ipc graph, from the plant's own 'finished ... in W s wall' line."""
    words = [f"{k}:={v}" for k, v in _arguments(duration).items()]
    result = subprocess.run([str(ROOT / "hawt"), "launch", "ipc", *words], capture_output=True, text=True,
                            timeout=3600)
    for line in result.stdout.splitlines() + result.stderr.splitlines():
        if "finished" in line and "s wall" in line:
            wall = float(line.split(" in ")[-1].split(" s wall")[0])
            return duration / wall
    sys.exit(f"bench run: the lockstep graph did not finish:\n{result.stderr[-2000:]}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=600.0, help="simulated time of the in-process runs [s]")
    parser.add_argument("--lockstep-duration", type=float, default=60.0, help="simulated time of the ROS graph [s]")
    args = parser.parse_args()
    print(f"turbulent 18 m/s, class B, seed 1, 100 Hz; in process {args.duration:g} s, lockstep graph "
          f"{args.lockstep_duration:g} s")
    core = plant_core(args.duration)
    print(f"plant core alone:            {core:6.1f}x real time")
    baseline = in_process("baseline", args.duration)
    print(f"hawt run baseline:           {baseline:6.1f}x real time")
    ipc = in_process("ipc", args.duration)
    print(f"hawt run ipc:                {ipc:6.1f}x real time")
    graph = lockstep(args.lockstep_duration)
    print(f"hawt launch ipc (lockstep):  {graph:6.1f}x real time")
    print(f"ratio in-process ipc / plant core:     {ipc / core:.2f}  (target >= 0.80)")
    print(f"ratio in-process ipc / lockstep graph: {ipc / graph:.1f}  (target >= 5)")
    print(f"per step of hawt run ipc ({args.duration:g} s, each core timed):")
    for name, micros in step_breakdown("ipc", args.duration).items():
        print(f"  {name:24s} {micros:6.1f} us")
    print("load average (1, 5, 15 min): {:.2f} {:.2f} {:.2f} on {} CPUs".format(*os.getloadavg(), os.cpu_count()))


if __name__ == "__main__":
    main()
