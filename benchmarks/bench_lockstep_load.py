"""Lockstep recordings on a busy machine are complete and equal to quiet ones (issue 11).

For the ``ipc`` graph and the ``switching`` graph with a schedule (turbulence, seed 3), one
``hawt launch … --record`` on the quiet machine and one beside two busy CPU loops
(``yes > /dev/null``, twice, started here). Prints, per recording, its wall time and
``hawt bag verify``'s verdict, and per graph whether every field of every stepped topic
(plant, contributions, command) is equal at every step between the two, bit for bit.

Usage: ./hawt bench lockstep_load [--duration S] [--keep FOLDER]
"""
import argparse
import subprocess
import sys
import tempfile
import time
from contextlib import contextmanager, nullcontext
from pathlib import Path

from hawt_bag.step_comparison import step_differences
from hawt_bag.verification import verify_bag

SCHEDULE = "schedule:=['500 +ipc_h1', '1500 +ipc_h4 +blade_sine', '2500 +ipc_h1_retuned -ipc_h1', " \
           "'4000 -blade_sine -ipc_h4']"
GRAPHS = {"ipc": [], "switching": [SCHEDULE]}


@contextmanager
def busy_loops(count: int = 2):
    """``count`` processes that keep a core busy each, for the time of the block."""
    hogs = [subprocess.Popen(["yes"], stdout=subprocess.DEVNULL) for _ in range(count)]
    try:
        yield
    finally:
        for hog in hogs:
            hog.kill()
            hog.wait()


def record(graph: str, duration: float, path: Path) -> float:
    """Wall time of one recorded lockstep run of ``graph``."""
    start = time.monotonic()
    result = subprocess.run([sys.executable, "-m", "hawt_tools.cli", "launch", graph, "wind_type:=turbulent",
                             f"duration:={duration:g}", "seed:=3", *GRAPHS[graph], "--record", str(path)],
                            capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"bench lockstep_load: hawt launch {graph} failed:\n{result.stderr[-2000:]}")
    return time.monotonic() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=120.0, help="simulated time per run [s] (default 120)")
    parser.add_argument("--keep", metavar="FOLDER", help="write the recordings there (default: a temporary folder)")
    args = parser.parse_args()
    if args.keep:
        Path(args.keep).mkdir(parents=True, exist_ok=True)
    with (nullcontext(args.keep) if args.keep else tempfile.TemporaryDirectory()) as folder:
        for graph in GRAPHS:
            paths = {load: Path(folder) / f"{graph}-{load}.mcap" for load in ("quiet", "busy")}
            for path in paths.values():
                path.unlink(missing_ok=True)
            walls = {"quiet": record(graph, args.duration, paths["quiet"])}
            with busy_loops():
                walls["busy"] = record(graph, args.duration, paths["busy"])
            checks = {load: verify_bag(path) for load, path in paths.items()}
            for load in paths:
                print(f"{graph:9s} {load:5s} {args.duration:g} s simulated in {walls[load]:5.1f} s wall; "
                      f"{checks[load].verdict()}")
            topics = [check.coverage.topic for check in checks["quiet"].topics]
            found = step_differences(paths["quiet"], paths["busy"], topics)
            print(f"{graph:9s} quiet = busy, every field of {len(topics)} stepped topics at every step: "
                  + ("yes" if not found else "NO: " + ", ".join(found)))


if __name__ == "__main__":
    main()
