"""``hawt demo``: the baseline and IPC graphs on the same turbulent wind, each recorded, and their loads compared."""
import argparse
import logging
import os
import time
from pathlib import Path
from typing import Dict, List, Mapping, Sequence

from hawt_tools.commands.graphs import launch_graph
from hawt_tools.commands.options import POSITIVE, progress
from hawt_tools.graph_file import find_graph, load_graph, package_prefix


CAUTION = "hawt demo: caution:"
"""How a line about a run that did not go as meant begins (scripts/readme_demo.py refuses output with one)."""
DEFAULT_DURATION = 60.0
"""[s] Simulated time of each of the demo's runs unless ``--duration`` says otherwise."""


def cautions(events: Mapping[str, Sequence[Dict]]) -> List[str]:
    """One line for each run (label -> its ``control/events`` timeline) that has a warning or an error: a
    controller's contribution lost (a process that did not answer a lockstep step within the loop assembler's
    input_timeout), a recorder given up, a safety trip. Such a run is not the comparison the demo means, whatever
    its numbers; a clean run has only informational events."""
    lines = []
    for label, timeline in events.items():
        bad = [e for e in timeline if e["level"] >= logging.WARNING]
        if bad:
            first = bad[0]
            lines.append(f"{CAUTION} {label} has {len(bad)} warning or error event(s), the first at t="
                         f"{first['time']:.2f} s, {first['source']}: {first['kind']} ({first['detail']}); its "
                         "numbers are not the comparison the demo means: run it again on a quieter machine")
    return lines


def _cmd_demo(args: argparse.Namespace) -> int:
    """Baseline and IPC (1P+2P) graphs on the same turbulent wind, each recorded; their loads compared. Without a
    ROS_DOMAIN_ID of the user's, on a domain reserved for the demo (domain_coordinator, as the test suite does), so
    another graph on the machine's default domain with the same namespace cannot feed its controllers."""
    from hawt_analysis.analysis_report import headline_text, write_comparison_report
    from hawt_analysis.run_analysis import compare_bags

    if "ROS_DOMAIN_ID" not in os.environ:  # the default domain is every ROS user's on this machine: take one alone
        from domain_coordinator import domain_id

        with domain_id() as domain:
            os.environ.update(ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST")
            progress(f"hawt demo: on ROS domain {domain}, reserved for it (another graph on this machine cannot "
                     "reach its topics; set ROS_DOMAIN_ID to choose the domain)")
            try:
                return _cmd_demo(args)
            finally:
                for name in ("ROS_DOMAIN_ID", "ROS_AUTOMATIC_DISCOVERY_RANGE"):
                    os.environ.pop(name, None)
    run = time.strftime("demo-%Y%m%d-%H%M%S")
    bags = Path(args.output) / run
    bags.mkdir(parents=True, exist_ok=False)
    wind = {"wind_type": "turbulent", "wind_speed": str(args.wind_speed), "seed": str(args.seed),
            "duration": str(args.duration)}
    paths = []
    # IPC 1P+2P: the project's study shows 3P adds little to the blades and raises the tower loads
    for name, arguments in (("baseline", {}), ("ipc", {"ipc_h3": "false"})):
        path = bags / f"{name}.mcap"
        progress(f"hawt demo: {name} graph, {args.duration:g} s of IEC class B turbulence at {args.wind_speed:g} m/s "
                 f"(seed {args.seed}), recording {path}")
        graph = load_graph(find_graph(name), {**wind, **arguments}, package_prefix)
        # plant/blade_loads has three subscribers (cpc, mbc, recorder): step 0 waits for all of them
        launch_graph(graph, ["plant.wait_for_subscribers:=3"], None, None, False, str(path))
        paths.append(path)
    analyses, comparison = compare_bags([str(p) for p in paths], None, progress=progress)
    print(f"hawt demo: IPC 1P+2P against the baseline, {args.duration:g} s of IEC class B turbulence at "
          f"{args.wind_speed:g} m/s (seed {args.seed})")
    print(headline_text(comparison))
    for line in cautions({p.name: a.run.events for p, a in zip(paths, analyses)}):
        print(line)
    report = write_comparison_report(comparison, bags / "report", analyses)
    print(f"every number (DELs, harmonics, spectra, pitch activity): {report}\n"
          f"(or: ./hawt compare {' '.join(str(p) for p in paths)})")
    return 0


def _add_demo(commands: argparse._SubParsersAction) -> None:
    demo = commands.add_parser(
        "demo", help="run the baseline and IPC graphs on the same turbulent wind and compare their loads",
        description="Runs the baseline graph (plant, cpc, mbc) and the IPC graph with 1P+2P (+ ipc_h1, ipc_h2), "
                    "one process per node, in lockstep on the same IEC turbulent wind, records both to MCAP and "
                    "prints the headline of the load comparison (blade, hub and tower DEL changes, pitch activity, "
                    "speed and power held) and the report with every number.")
    demo.add_argument("--duration", type=POSITIVE, default=DEFAULT_DURATION, metavar="S", help="simulated seconds per run")
    demo.add_argument("--wind-speed", type=float, default=18.0, metavar="M_PER_S", help="mean hub wind speed")
    demo.add_argument("--seed", type=int, default=1, help="turbulence seed")
    demo.add_argument("--output", default="bags", metavar="DIR", help="folder for the run's bags and report")
    demo.set_defaults(run=_cmd_demo)


_PARSERS = {"demo": _add_demo}


def add_parsers(commands: argparse._SubParsersAction, names: Sequence[str] = tuple(_PARSERS)) -> None:
    """The subparsers of this group's commands ``names`` (default: all of them), added to hawt's ``commands`` in
    that order."""
    for name in names:
        _PARSERS[name](commands)
