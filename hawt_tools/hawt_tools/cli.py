"""The ``hawt`` command (DESIGN.md §8): thin argument parsing over library functions.

Exit codes: 0 success, 1 runtime failure, 2 bad usage or bad input, always with a
one-line message naming the file, field or parameter at fault.
"""
import argparse
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Dict, List, Optional

from hawt_bag.errors import BagError

from hawt_tools.graph_file import GraphError, load_graph
from hawt_tools.scheduling import PRIORITY_VARIABLE, SchedulingError, check_priority, set_priority

__all__ = ["main", "find_graph"]

_GRAPH_PACKAGES = ("hawt_tools", "hawt_plant", "hawt_controllers")


def find_graph(name: str) -> Path:
    """A graph file: the path itself if it exists, else ``<name>.yaml`` in a hawt package's ``launch`` folder."""
    path = Path(name)
    if path.exists() or path.suffix in (".yaml", ".yml"):
        return path
    from hawt_tools.launcher import package_prefix

    known = []
    for package in _GRAPH_PACKAGES:
        prefix = package_prefix(package)
        folder = Path(prefix) / "share" / package / "launch" if prefix else None
        if folder and folder.is_dir():
            candidate = folder / f"{name}.yaml"
            if candidate.is_file():
                return candidate
            known += sorted(p.stem for p in folder.glob("*.yaml"))
    raise GraphError(f"{name}: no such graph file, and no installed graph of that name"
                     + (f" (installed graphs: {', '.join(known)})" if known else ""))


def _launch_arguments(words: List[str]) -> Dict[str, str]:
    arguments = {}
    for word in words:
        name, sep, value = word.partition(":=")
        if not sep or not name:
            raise GraphError(f"launch argument {word!r}: expected NAME:=VALUE")
        arguments[name] = value
    return arguments


def _cmd_launch(args: argparse.Namespace) -> int:
    from hawt_tools.launcher import package_prefix

    graph = load_graph(find_graph(args.graph), _launch_arguments(args.arguments), package_prefix)
    return _run_graph(graph, args.param, args.mode, args.duration, args.composed, args.record, args.priority)


def _run_graph(graph, parameters: List[str], mode: Optional[str], duration: Optional[float], composed: bool,
               record: Optional[str], priority: int = 0) -> int:
    """Run a checked graph (separate processes or composed), recording it into ``record`` if given.

    ``priority`` > 0 runs the nodes (not the recorder) under SCHED_FIFO at that priority.
    """
    from hawt_tools.launcher import ProcessGraph, parse_overrides, run_composed

    # --mode beats the graph's own 'mode' values (an override of every node); -p beats --mode
    modes = [f"{spec.label}.mode:={mode}" for spec in graph.nodes] if mode else []
    overrides = parse_overrides(graph, modes + list(parameters))
    global_parameters = {"wait_for_recorder": True} if record else {}  # the plant starts once all is recorded
    if priority:
        check_priority(priority)
    recorder = _start_recorder(Path(record)) if record else None
    try:
        if composed:
            if priority:
                set_priority(priority)
            code = run_composed(graph, overrides, duration, global_parameters)
        else:
            environment = {PRIORITY_VARIABLE: str(priority)} if priority else {}
            code = ProcessGraph(graph, overrides, global_parameters, environment=environment).run(duration)
    finally:
        if recorder is not None:
            recorded = _stop_recorder(recorder)
    if recorder is not None and recorded != 0:
        raise RuntimeError(f"the recorder of {record} failed (exit code {recorded})")
    return code


def _start_recorder(path: Path) -> subprocess.Popen:
    """Start the ``record`` executable of hawt_bag on ``path`` and wait until it has created the bag."""
    from hawt_tools.launcher import package_prefix

    if path.exists():
        raise BagError(f"{path}: exists; refusing to overwrite a bag (choose another --record name)")
    prefix = package_prefix("hawt_bag")
    executable = Path(prefix or "") / "lib" / "hawt_bag" / "record"
    if prefix is None or not executable.is_file():
        raise RuntimeError("hawt_bag's record executable is not installed (run scripts/setup.sh)")
    recorder = subprocess.Popen([str(executable), "-o", str(path)], stdin=subprocess.DEVNULL,
                                start_new_session=True)
    deadline = time.monotonic() + 20.0
    while not path.exists():
        if recorder.poll() is not None:
            raise RuntimeError(f"the recorder of {path} exited before recording (exit code {recorder.returncode})")
        if time.monotonic() > deadline:
            _stop_recorder(recorder)
            raise RuntimeError(f"the recorder of {path} did not start within 20 s")
        time.sleep(0.02)
    return recorder


def _stop_recorder(recorder: subprocess.Popen) -> int:
    """Stop the recorder after the graph (SIGINT: it takes what is still arriving, then finishes the bag)."""
    for sig, timeout in ((signal.SIGINT, 30.0), (signal.SIGTERM, 5.0), (signal.SIGKILL, 5.0)):
        if recorder.poll() is not None:
            break
        os.killpg(recorder.pid, sig)
        try:
            recorder.wait(timeout)
        except subprocess.TimeoutExpired:
            continue
    return recorder.wait()


def _cmd_record(args: argparse.Namespace) -> int:
    from hawt_bag.recorder import options_from, record

    return record(options_from(args))


def _cmd_replay(args: argparse.Namespace) -> int:
    from hawt_bag.replayer import ReplayOptions, parse_remaps, replay

    options = ReplayOptions(rate=args.rate, loop=args.loop, start_offset=args.start, topics=tuple(args.topics),
                            clock_hz=args.clock, remaps=parse_remaps(args.remap), start_paused=args.start_paused,
                            wait_for_subscribers=args.wait_for_subscribers, wait_timeout=args.wait_timeout,
                            step_trigger=args.step_trigger, step_timeout=args.step_timeout)
    result = replay(args.bag, options)
    print(f"replayed {result.published} messages" + (f" in {result.steps} steps" if args.step_trigger else ""))
    return 0


def _cmd_bag_info(args: argparse.Namespace) -> int:
    from hawt_bag.reader import BagReader

    with BagReader(args.bag) as reader:
        print(reader.info().text())
    return 0


def _cmd_bag_recover(args: argparse.Namespace) -> int:
    from hawt_bag.recover import recover_bag

    print(recover_bag(args.bag, args.output).text())
    return 0


def _progress(line: str) -> None:
    """Stage lines of long work, on an interactive terminal only (stderr stays one error line otherwise)."""
    if sys.stderr.isatty():
        print(f"hawt: {line}", file=sys.stderr, flush=True)


def _cmd_analyze(args: argparse.Namespace) -> int:
    from hawt_bag.analysis_report import analysis_text, write_analysis_report
    from hawt_bag.run_analysis import analyze_bag

    analysis = analyze_bag(args.bag, args.namespace, progress=_progress)
    print(json.dumps(analysis.summary) if args.json else analysis_text(analysis.summary))
    if args.report:
        _progress(f"writing the report into {args.report}")
        _progress(f"report: {write_analysis_report(analysis, args.report)}")
    return 0


def _cmd_compare(args: argparse.Namespace) -> int:
    from hawt_bag.analysis_report import comparison_text, write_comparison_report
    from hawt_bag.run_analysis import compare_bags

    _, comparison = compare_bags(args.bags, args.namespace, progress=_progress)
    print(json.dumps(comparison) if args.json else comparison_text(comparison))
    if args.report:
        _progress(f"report: {write_comparison_report(comparison, args.report)}")
    return 0


def _cmd_list(args: argparse.Namespace) -> int:
    from hawt_tools.graph_info import snapshot

    print(snapshot(settle=args.settle).text())
    return 0


def _cmd_switch(args: argparse.Namespace) -> int:
    from hawt_tools.controller_client import ControllerManagerError, switch_controllers

    if not args.activate and not args.deactivate:
        raise GraphError("nothing to switch: give --activate NAME and/or --deactivate NAME")
    try:
        result = switch_controllers(args.activate, args.deactivate, strict=not args.best_effort,
                                    ramp_time=-1.0 if args.ramp is None else args.ramp, at_step=args.at_step,
                                    namespace=args.namespace)
    except ControllerManagerError as error:
        raise RuntimeError(str(error)) from None
    if not result.ok:
        raise GraphError(f"refused: {result.message}")
    print(f"switched {result.message}")
    return 0


def _cmd_demo(args: argparse.Namespace) -> int:
    """Baseline and IPC graphs on the same turbulent wind, each recorded; their loads compared."""
    from hawt_bag.analysis_report import comparison_text, write_comparison_report
    from hawt_bag.run_analysis import compare_bags
    from hawt_tools.launcher import package_prefix

    run = time.strftime("demo-%Y%m%d-%H%M%S")
    bags = Path(args.output) / run
    bags.mkdir(parents=True, exist_ok=False)
    wind = {"wind_type": "turbulent", "wind_speed": str(args.wind_speed), "seed": str(args.seed),
            "duration": str(args.duration)}
    paths = []
    for name in ("baseline", "ipc"):
        path = bags / f"{name}.mcap"
        _progress(f"hawt demo: {name} graph, {args.duration:g} s of IEC class B turbulence at {args.wind_speed:g} m/s "
                  f"(seed {args.seed}), recording {path}")
        graph = load_graph(find_graph(name), wind, package_prefix)
        # plant/blade_loads has three subscribers (cpc, mbc, recorder): step 0 waits for all of them
        _run_graph(graph, ["plant.wait_for_subscribers:=3"], None, None, False, str(path))
        paths.append(path)
    _, comparison = compare_bags([str(p) for p in paths], None, progress=_progress)
    print(comparison_text(comparison))
    print(f"\nreport: {write_comparison_report(comparison, bags / 'report')}")
    return 0


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="hawt", description="ROS 2 toolkit for wind-turbine load alleviation: run node graphs of a "
                                 "simulated turbine and its pitch controllers.")
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    launch = commands.add_parser(
        "launch", help="run a node graph (ROS 2 YAML launch format), each node in its own process",
        description="Run a node graph: each node in its own OS process (or all in one with --composed), "
                    "output prefixed with the node name, all stopped cleanly on Ctrl-C/SIGTERM.")
    launch.add_argument("graph", metavar="GRAPH", help="graph file, or the name of an installed graph")
    launch.add_argument("arguments", nargs="*", metavar="NAME:=VALUE", help="launch arguments of the graph")
    launch.add_argument("--duration", type=float, metavar="S",
                        help="stop after S wall-clock seconds (default: run until a node with on_exit: "
                             "shutdown finishes, every node has finished, or Ctrl-C)")
    launch.add_argument("--mode", choices=("lockstep", "realtime"),
                        help="timing mode, given to every node as its 'mode' parameter")
    launch.add_argument("--composed", action="store_true", help="run all nodes in this process on one executor")
    launch.add_argument("--priority", type=int, default=0, metavar="N",
                        help="run the nodes under SCHED_FIFO at priority N (1-99), as a realtime loop should: "
                             "fewer late steps in --mode realtime (needs root or CAP_SYS_NICE; the recorder keeps "
                             "normal scheduling)")
    launch.add_argument("-p", dest="param", action="append", default=[], metavar="NODE.PARAM:=VALUE",
                        help="override a parameter of one node (repeatable)")
    launch.add_argument("--record", metavar="FILE.mcap",
                        help="record every topic into this new bag; the recorder starts before the graph "
                             "and stops after it")
    launch.set_defaults(run=_cmd_launch)

    from hawt_bag.recorder import add_record_arguments

    record = commands.add_parser("record", help="record topics of the running graph into an MCAP bag",
                                 description="Record all topics (or the chosen ones) into a new MCAP bag until "
                                             "Ctrl-C/SIGTERM; topics that appear later are picked up.")
    add_record_arguments(record)
    record.set_defaults(run=_cmd_record)

    replay = commands.add_parser("replay", help="publish a bag's messages again, timed or step by step",
                                 description="Replay a bag at its recorded timing (times --rate), or step by step "
                                             "through a graph with --step-trigger. Live control: parameters "
                                             "'paused' and 'rate' of node hawt_player, topic "
                                             "/hawt_player/play_next (std_msgs/Empty) while paused.")
    replay.add_argument("bag", metavar="FILE.mcap")
    replay.add_argument("-r", "--rate", type=float, default=1.0, metavar="R", help="speed factor (default 1)")
    replay.add_argument("-l", "--loop", action="store_true", help="start again at the end")
    replay.add_argument("--start", type=float, default=0.0, metavar="S",
                        help="start S seconds after the bag's first message")
    replay.add_argument("--topics", nargs="+", default=[], metavar="T", help="publish only these topics")
    replay.add_argument("--clock", type=float, nargs="?", const=40.0, default=0.0, metavar="HZ",
                        help="publish /clock at HZ (default 40 when given without a value); in step replay, "
                             "once per step")
    replay.add_argument("--remap", "-m", nargs="+", default=[], metavar="FROM:=TO", help="publish a topic under "
                                                                                         "another name")
    replay.add_argument("-p", "--start-paused", action="store_true", help="start paused")
    replay.add_argument("--wait-for-subscribers", action="store_true",
                        help="start only once every topic has a subscriber")
    replay.add_argument("--wait-timeout", type=float, default=10.0, metavar="S",
                        help="how long to wait for subscribers and the trigger's publisher (default 10)")
    replay.add_argument("--step-trigger", metavar="TOPIC",
                        help="step replay: after publishing the messages of step k, wait for step k on TOPIC "
                             "(e.g. /wt1/control/pitch_command)")
    replay.add_argument("--step-timeout", type=float, default=10.0, metavar="S",
                        help="step replay: how long to wait for each step's answer (default 10)")
    replay.set_defaults(run=_cmd_replay)

    bag = commands.add_parser("bag", help="inspect or rescue a bag (info, recover)")
    bag_commands = bag.add_subparsers(dest="bag_command", required=True, metavar="SUBCOMMAND")
    info = bag_commands.add_parser("info", help="duration, size, compression, topics with type, QoS and count")
    info.add_argument("bag", metavar="FILE.mcap")
    info.set_defaults(run=_cmd_bag_info)
    recover = bag_commands.add_parser("recover", help="rewrite what an unfinished bag holds into a complete one")
    recover.add_argument("bag", metavar="FILE.mcap")
    recover.add_argument("-o", "--output", metavar="OUT.mcap", help="default: FILE.recovered.mcap")
    recover.set_defaults(run=_cmd_bag_recover)

    analyze = commands.add_parser("analyze", help="DELs, harmonics, spectra, pitch activity and events of a run",
                                  description="Analyse one turbine's run in a bag: plant/blade_loads and "
                                              "plant/state (required), control/pitch_command and control/events.")
    analyze.add_argument("bag", metavar="FILE.mcap")
    analyze.add_argument("--json", action="store_true", help="print the JSON object of DESIGN §8")
    analyze.add_argument("--report", metavar="DIR", help="write index.html, plots and summary.json into DIR")
    analyze.add_argument("--namespace", metavar="NS", help="the turbine (e.g. /wt1) when the bag holds several")
    analyze.set_defaults(run=_cmd_analyze)

    compare = commands.add_parser("compare", help="several runs side by side, changes against the first")
    compare.add_argument("bags", nargs="+", metavar="FILE.mcap")
    compare.add_argument("--json", action="store_true", help="print the comparison as JSON")
    compare.add_argument("--report", metavar="DIR", help="write index.html, comparison.png and comparison.json")
    compare.add_argument("--namespace", metavar="NS", help="the turbine (e.g. /wt1) when a bag holds several")
    compare.set_defaults(run=_cmd_compare)

    listing = commands.add_parser("list", help="the nodes, topics (with types) and controllers (with states) of the "
                                               "running graph")
    listing.add_argument("--settle", type=float, default=1.0, metavar="S",
                         help="discovery: wait until the node list is unchanged for S seconds")
    listing.set_defaults(run=_cmd_list)

    switch = commands.add_parser(
        "switch", help="activate and deactivate controllers of a running graph at one plant step",
        description="Ask the graph's controller_manager to switch controllers atomically at one plant step "
                    "(ros2_control semantics). An outgoing IPC contribution ramps out over the ramp time, an "
                    "incoming one ramps in; a controller that replaces another of its harmonic starts from the "
                    "other's output. Prints the step the switch takes effect at.")
    switch.add_argument("--activate", nargs="+", default=[], metavar="NAME", help="controllers to activate")
    switch.add_argument("--deactivate", nargs="+", default=[], metavar="NAME", help="controllers to deactivate")
    switch.add_argument("--ramp", type=float, metavar="S", help="ramp time (default: the manager's ramp_time)")
    switch.add_argument("--best-effort", action="store_true",
                        help="apply what can be applied (default STRICT: refuse the whole switch if any name fails)")
    switch.add_argument("--at-step", type=int, default=0, metavar="K",
                        help="plant step to switch at (default: as soon as possible)")
    switch.add_argument("--namespace", metavar="NS", help="turbine namespace of the controller manager (needed only "
                                                          "if the graph has several)")
    switch.set_defaults(run=_cmd_switch)

    demo = commands.add_parser(
        "demo", help="run the baseline and IPC graphs on the same turbulent wind and compare their loads",
        description="Runs the baseline graph (plant, cpc, mbc) and the IPC graph (+ ipc_h1..h3), one process per "
                    "node, in lockstep on the same IEC turbulent wind, records both to MCAP and prints the "
                    "load comparison (DELs, harmonics, pitch activity) with the report it wrote.")
    demo.add_argument("--duration", type=float, default=60.0, metavar="S", help="simulated seconds per run")
    demo.add_argument("--wind-speed", type=float, default=18.0, metavar="M_PER_S", help="mean hub wind speed")
    demo.add_argument("--seed", type=int, default=1, help="turbulence seed")
    demo.add_argument("--output", default="bags", metavar="DIR", help="folder for the run's bags and report")
    demo.set_defaults(run=_cmd_demo)
    return parser


def parse_command_line(argv: Optional[List[str]] = None) -> argparse.Namespace:
    """The parsed command; a graph's NAME:=VALUE arguments may come before or after the options."""
    parser = _parser()
    args, extra = parser.parse_known_args(argv)
    if extra and getattr(args, "arguments", None) is not None and all(":=" in word for word in extra):
        args.arguments += extra
    elif extra:
        parser.error(f"unrecognized arguments: {' '.join(extra)}")
    return args


def main(argv: Optional[List[str]] = None) -> int:
    args = parse_command_line(argv)
    try:
        return args.run(args)
    except (GraphError, BagError, SchedulingError) as error:
        print(f"hawt {args.command}: {error}", file=sys.stderr)
        return 2
    except RuntimeError as error:
        print(f"hawt {args.command}: {error}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
