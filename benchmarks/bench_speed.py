"""Where users wait, in one run: the plant step, hawt run with its start, a wind field, a small campaign, OpenFAST.

Measured one after the other on this machine (nothing else of hawt's running):
- the plant core alone: real-time factor of the step (the ipc graph's plant, commands held, 18 m/s turbulence);
- ``hawt run baseline duration:=1``: the wall time of a whole command, most of it start-up;
- case A, ``hawt run baseline`` and ``hawt run ipc`` on 120 s of steady 18 m/s wind with shear 0.2, start-up
  included (wall time of the command): the median of ``--repeat`` runs of each, taken in turns, with their range (a
  2-core VM's speed drifts by tens of percent from one run of a few seconds to the next; OpenFAST's one run of a
  minute averages over that drift);
- a 600 s IEC class B turbulent field for the NREL 5 MW, generated into an empty cache;
- a small campaign: baseline at 13 and 18 m/s, one seed, 60 s + 10 s transient, on two local Dask workers;
- OpenFAST + ROSCO on case A, when ``$HAWT_OPENFAST`` names an OpenFAST executable (``../shared/tools/openfast/``
  has one; its README says how to install it): the inputs ``hawt validate`` writes for ``steady-18`` over 120 s.
Prints each as a real-time factor (simulated time / wall time) and the ratios of case A against OpenFAST.

Usage: ./hawt bench speed [--case-duration S] [--repeat N] [--skip-campaign]
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench_run import plant_core

ROOT = Path(__file__).resolve().parents[1]
HAWT = str(ROOT / "hawt")


def wall_of(command: list, environment: dict = None) -> float:
    """Wall time [s] of ``command``; exits naming it if it fails."""
    start = time.monotonic()
    done = subprocess.run(command, capture_output=True, text=True, env={**os.environ, **(environment or {})})
    wall = time.monotonic() - start
    if done.returncode != 0:
        sys.exit(f"bench speed: {' '.join(command)} failed (exit {done.returncode}):\n{done.stderr[-2000:]}")
    return wall


def case_a(graph: str, duration: float) -> float:
    """Wall time [s] of ``hawt run GRAPH`` on case A (steady 18 m/s, shear 0.2) for ``duration`` s simulated."""
    return wall_of([HAWT, "run", graph, "wind_type:=steady", "wind_speed:=18", "shear_exponent:=0.2",
                    f"duration:={duration:g}"])


def wind_field() -> float:
    """Wall time [s] of a 600 s class B field for the NREL 5 MW's rotor at 18 m/s, into an empty cache."""
    with tempfile.TemporaryDirectory() as cache:
        code = ("from hawt_plant.inflow import InflowSettings, make_wind; "
                "make_wind(InflowSettings(kind='turbulent', wind_speed=18.0, turbulence_class='B', seed=5))")
        return wall_of([sys.executable, "-c", code], {"HAWT_CACHE_DIR": cache})


def small_campaign(folder: Path) -> tuple:
    """Wall time [s] and simulated time [s] of a 2-case campaign on two local workers, its fields generated."""
    campaign = folder / "small.yaml"
    campaign.write_text("wind: {speeds: [13, 18], seeds: 1, turbulence_class: B, shear_exponent: 0.2}\n"
                        "site: {wind_class: I}\nduration: 60\ntransient: 10\n"
                        "controllers:\n  baseline: {graph: baseline}\n")
    wall = wall_of([HAWT, "campaign", str(campaign), "-o", str(folder / "results"), "--workers", "2"],
                   {"HAWT_CACHE_DIR": str(folder / "cache")})
    return wall, 2 * (60 + 10)


def openfast_case_a(executable: Path, duration: float, folder: Path) -> float:
    """Wall time [s] of OpenFAST + ROSCO on case A: the inputs hawt validate writes for steady-18."""
    from hawt_tools.graph_file import find_graph
    from hawt_tools.openfast_case import deck_of, run_openfast
    from hawt_tools.validation import parse_case, prepare_case

    _, written = prepare_case(parse_case("steady-18", duration), "nrel_5mw", find_graph("validation"),
                              deck_of("nrel_5mw"), folder)
    return run_openfast(executable, written.fst)


def main() -> None:
    parser = argparse.ArgumentParser(prog="./hawt bench speed", description=__doc__.splitlines()[0])
    parser.add_argument("--case-duration", type=float, default=120.0, help="simulated time of case A [s]")
    parser.add_argument("--repeat", type=int, default=5, help="runs of each hawt case A, in turns (median) [5]")
    parser.add_argument("--skip-campaign", action="store_true", help="leave out the small campaign")
    args = parser.parse_args()
    duration = args.case_duration
    bad = (f"--repeat: expected at least 1 run, found {args.repeat}" if args.repeat < 1 else
           f"--case-duration: expected a simulated time > 0 s, found {duration:g}" if not duration > 0.0 else None)
    if bad:
        print(f"hawt bench speed: {bad}", file=sys.stderr)
        sys.exit(2)
    core = plant_core(600.0)
    print(f"plant core alone (600 s, 18 m/s turbulence):          {core:7.1f}x real time", flush=True)
    start_up = wall_of([HAWT, "run", "baseline", "duration:=1"])
    print(f"hawt run baseline duration:=1 (start-up):              {start_up:7.2f} s wall", flush=True)
    walls = {"baseline": [], "ipc": []}
    for _ in range(args.repeat):
        for graph, runs in walls.items():
            runs.append(case_a(graph, duration))
    baseline, ipc = (statistics.median(runs) for runs in walls.values())
    for graph, runs in walls.items():
        print(f"case A, hawt run {graph + ' (' + format(duration, 'g') + ' s, start-up included):':38s}"
              f"{duration / statistics.median(runs):7.1f}x real time ({statistics.median(runs):.2f} s wall, median "
              f"of {len(runs)}: {min(runs):.2f}-{max(runs):.2f} s)", flush=True)
    field = wind_field()
    print(f"600 s class B field for the NREL 5 MW, generated:      {field:7.1f} s wall ({600 / field:.0f}x real time)",
          flush=True)
    with tempfile.TemporaryDirectory() as folder:
        if not args.skip_campaign:
            wall, simulated = small_campaign(Path(folder))
            print(f"campaign, 2 cases x 70 s on 2 workers (fields new):    {simulated / wall:7.1f}x real time "
                  f"({wall:.1f} s wall)", flush=True)
        executable = os.environ.get("HAWT_OPENFAST")
        if executable:
            openfast = openfast_case_a(Path(executable), duration, Path(folder) / "openfast")
            print(f"case A, OpenFAST + ROSCO ({duration:g} s):                   {duration / openfast:7.1f}x real "
                  f"time ({openfast:.1f} s wall)")
            print(f"ratio hawt run baseline / OpenFAST on case A: {openfast / baseline:.1f}  (issue 30's target >= 30)")
            print(f"ratio hawt run ipc / OpenFAST on case A:      {openfast / ipc:.1f}")
        else:
            print("OpenFAST: $HAWT_OPENFAST is not set (../shared/tools/openfast/install.sh DIR installs one)")
    print("load average (1, 5, 15 min): {:.2f} {:.2f} {:.2f} on {} CPUs".format(*os.getloadavg(), os.cpu_count()))


if __name__ == "__main__":
    main()
