"""Running and inspecting node graphs: ``hawt launch`` (processes or composed), ``hawt run`` (in process),
``hawt bridge`` (a graph as a simulator's DISCON controller), ``hawt graph list|show`` (the installed graph files)."""
import argparse
import json
import subprocess
import sys
from pathlib import Path
from typing import Any, List, Optional, Sequence

from hawt_core.scheduling import PRIORITY_VARIABLE, check_priority, set_priority
from hawt_tools.commands.options import PORT, POSITIVE, PRIORITY, progress
from hawt_tools.graph_file import (GraphError, find_graph, graph_summary, installed_graphs, launch_arguments,
                                   load_graph, package_prefix)


def _cmd_launch(args: argparse.Namespace) -> int:
    graph = load_graph(find_graph(args.graph), launch_arguments(args.arguments), package_prefix)
    view = _view_command(args.view_port, args.view_allow_parameter_sets) if args.view else None
    return launch_graph(graph, args.param, args.mode, args.duration, args.composed, args.record, args.priority, view,
                        args.record_optional)


def _cmd_graph_show(args: argparse.Namespace) -> int:
    """A graph's launch arguments with their defaults, its nodes with their parameter files, and its programs."""
    from hawt_tools.graph_file import ParameterFile, declared_arguments
    from hawt_tools.node_parameters import node_parameter_sources

    path = find_graph(args.graph)
    graph = load_graph(path, launch_arguments(args.arguments), package_prefix)
    declared = declared_arguments(path)
    print(graph.path)
    described = ", description" if any(argument.description for argument in declared) else ""
    print(f"arguments (NAME:=VALUE, default{described}):" if declared else "arguments: none")
    defaults = {a.name: "(none)" if a.default is None else a.default or '""' for a in declared}
    name_width = max(map(len, defaults), default=0)
    default_width = max(map(len, defaults.values()), default=0)
    for argument in declared:
        print(f"  {argument.name:<{name_width}}  {defaults[argument.name]:<{default_width}}  "
              f"{argument.description}".rstrip())
    print("nodes (namespace/name, package/executable, then parameters in the order they apply; a value a later "
          "source replaces says what applies):")
    label_width = max(len(node.label) for node in graph.nodes)
    for node in graph.nodes:
        print(f"  {node.label:<{label_width}}  {node.package}/{node.executable}")
        applied = node_parameter_sources(node)
        for source in node.parameters:
            lines = [f"from {source.path}"] if isinstance(source, ParameterFile) else (
                f"{name}: {json.dumps(value)}" + _replaced(value, *applied[name]) for name, value in source.values)
            print("".join(f"    {line}\n" for line in lines), end="")
    if graph.programs:
        print("programs (executable actions, run by hawt launch only):")
    for program in graph.programs:
        print(f"  {program.name}: {' '.join(program.command)}")
    return 0


def _replaced(value: Any, applied: Any, origin: Any) -> str:
    """What ``hawt graph show`` adds to a graph's inline value that a later source replaces: the value that applies
    and where it comes from (a parameter file, or a later inline group)."""
    if applied == value:
        return ""
    return f"  (applies: {json.dumps(applied)}, from {origin.path or 'a later value in the graph'})"


def launch_graph(graph, parameters: List[str], mode: Optional[str], duration: Optional[float], composed: bool,
                 record: Optional[str], priority: int = 0, view: Optional[List[str]] = None,
                 record_optional: bool = False) -> int:
    """Run a checked graph (separate processes or composed), recording it into ``record`` if given.

    ``priority`` > 0 runs the nodes (not the recorder) under SCHED_FIFO at that priority. With ``view`` (the
    ``view`` executable's command line, :func:`_view_command`) it serves the graph to Foxglove while it runs. A
    recorder that dies is respawned and the plant waits for it (hawt_tools.recording), unless ``record_optional``.
    """
    from hawt_bag.writer import new_bag_path
    from hawt_tools.launcher import ProcessGraph, class_role, launcher_parameters, run_composed
    from hawt_tools.node_parameters import parse_overrides
    from hawt_tools.parameter_check import check_against_plant, check_graph_parameters, takes_parameter
    from hawt_tools.recording import SupervisedRecorder, stop_process

    # --mode beats the graph's own 'mode' values (an override of every node that has one); -p beats --mode
    modes = [f"{spec.label}.mode:={mode}" for spec in graph.nodes if takes_parameter(graph, spec, "mode", class_role)] \
        if mode else []
    overrides = parse_overrides(graph, modes + list(parameters))
    global_parameters = launcher_parameters(graph, bool(record), record_optional)
    check_against_plant(graph, check_graph_parameters(graph, overrides, global_parameters, class_role))  # before start
    if priority:
        check_priority(priority)
    recorder = SupervisedRecorder(new_bag_path(record, "--record"), record_optional) if record else None
    events = viewer = None
    try:
        if view is not None:
            viewer = subprocess.Popen(view, stdin=subprocess.DEVNULL, start_new_session=True)
        if recorder is not None:  # deaths, respawns and stops from outside into the bag
            from hawt_tools.launch_events import LaunchEvents

            namespaces = [spec.full_namespace for spec in graph.nodes]
            events = LaunchEvents(namespaces)
            recorder.watch(events, namespaces)
        if composed:
            if priority:
                set_priority(priority)
            code = run_composed(graph, overrides, duration, global_parameters, events)
        else:
            environment = {PRIORITY_VARIABLE: str(priority)} if priority else {}
            code = ProcessGraph(graph, overrides, global_parameters, environment=environment,
                                events=events).run(duration)
    finally:
        if recorder is not None:
            recorded = recorder.stop()
        if events is not None:
            events.close()
        if viewer is not None:
            stop_process(viewer)
    if recorder is not None and recorded != 0:
        raise RuntimeError(recorder.lost or f"the recorder of {record} failed (exit code {recorded})")
    return code


def _cmd_run(args: argparse.Namespace) -> int:
    from hawt_tools.in_process import run_graph
    from hawt_tools.node_parameters import parse_overrides
    from hawt_tools.parameter_check import check_against_plant, check_graph_parameters

    graph = load_graph(find_graph(args.graph), launch_arguments(args.arguments), package_prefix)
    overrides = parse_overrides(graph, args.param)
    check_against_plant(graph, check_graph_parameters(graph, overrides))
    record = None
    if args.record:
        from hawt_bag.writer import new_bag_path  # the bag writer (mcap's) only for a run that records

        record = new_bag_path(args.record, "--record")
    run = run_graph(graph, overrides, record, args.duration, progress)
    for event in run.events:
        if event["level"] >= 30:
            print(f"{event['kind']} at t={event['step'] * run.description.dt:.2f} s: {event['detail']}",
                  file=sys.stderr)
    print(run.events[-1]["detail"] + (f"; recorded into {args.record}" if args.record else ""))
    return 0


def _cmd_bridge(args: argparse.Namespace) -> int:
    from hawt_tools.discon_bridge import BridgeClosed, BridgeError, run_bridge

    def say(line: str) -> None:
        print(f"hawt bridge: {line}", file=sys.stderr, flush=True)

    try:
        result = run_bridge(Path(args.file), args.graph, args.arguments, args.param, args.record, say, progress,
                            args.in_process)
    except BridgeError as error:
        raise GraphError(str(error)) from None
    except BridgeClosed as error:
        raise RuntimeError(str(error)) from None
    print(result.summary + (f"; recorded into {result.record}" if result.record else ""))
    return 0


def _view_command(port: int, allow_parameter_sets: bool = False) -> List[str]:
    """The command line of hawt_tools' ``view`` executable serving on ``port`` (letting clients set parameters if
    asked)."""

    executable = Path(package_prefix("hawt_tools") or "") / "lib" / "hawt_tools" / "view"
    if not executable.is_file():
        raise RuntimeError("hawt_tools' view executable is not installed (run scripts/setup.sh)")
    return [str(executable), "--port", str(port), *(["--allow-parameter-sets"] if allow_parameter_sets else [])]


def _cmd_graph_list(args: argparse.Namespace) -> int:
    """The installed graph files, each with what its leading comment says it is; starts and discovers nothing."""
    graphs = installed_graphs()
    width = max(map(len, graphs), default=0)
    for name, path in graphs.items():
        print(f"{name:<{width}}  {graph_summary(path)}")
    return 0


def _add_launch(commands: argparse._SubParsersAction) -> None:
    launch = commands.add_parser(
        "launch", help="run a node graph (ROS 2 YAML launch format), each node in its own process",
        description="Run a node graph: each node in its own OS process (or all in one with --composed), "
                    "output prefixed with the node name, all stopped cleanly on Ctrl-C/SIGTERM.")
    launch.add_argument("graph", metavar="GRAPH", help="graph file, or the name of an installed graph")
    launch.add_argument("arguments", nargs="*", metavar="NAME:=VALUE", help="launch arguments of the graph")
    launch.add_argument("--duration", type=POSITIVE, metavar="S",
                        help="stop after S wall-clock seconds (default: run until a node with on_exit: "
                             "shutdown finishes, every node has finished, or Ctrl-C)")
    launch.add_argument("--mode", choices=("lockstep", "realtime"),
                        help="timing mode, given to every node as its 'mode' parameter")
    launch.add_argument("--composed", action="store_true", help="run all nodes in this process on one executor")
    launch.add_argument("--priority", type=PRIORITY, default=0, metavar="N",
                        help="run the nodes under SCHED_FIFO at priority N (1-99), as a realtime loop should: "
                             "fewer late steps in --mode realtime (needs root or CAP_SYS_NICE; the recorder keeps "
                             "normal scheduling)")
    launch.add_argument("-p", dest="param", action="append", default=[], metavar="NODE.PARAM:=VALUE",
                        help="override a parameter of one node (repeatable)")
    launch.add_argument("--record", metavar="FILE.mcap",
                        help="record every topic into this new bag; the recorder starts before the graph "
                             "and stops after it. A recorder that dies is respawned, and a lockstep plant waits "
                             "for it, so the bag has every step")
    launch.add_argument("--record-optional", action="store_true",
                        help="with --record: a recorder that dies is not respawned and the plant goes on without "
                             "it after its recorder_timeout (the bag then misses steps)")
    launch.add_argument("--view", action="store_true",
                        help="serve the graph live to Foxglove while it runs (as 'hawt view', on --view-port)")
    launch.add_argument("--view-port", type=PORT, default=8765, metavar="N",
                        help="port of --view (default 8765; 0: any free one)")
    launch.add_argument("--view-allow-parameter-sets", action="store_true",
                        help="let --view's clients set parameters (as 'hawt view --allow-parameter-sets')")
    launch.set_defaults(run=_cmd_launch)


def _add_run(commands: argparse._SubParsersAction) -> None:
    run = commands.add_parser(
        "run", help="run a graph's cores in this process, without middleware (bit-identical to lockstep)",
        description="The in-process engine: reads the same graph and parameter files as 'launch', builds the "
                    "same plant and controller cores and steps them in lockstep order with no DDS, so the "
                    "result equals 'hawt launch GRAPH' in lockstep bit for bit, only faster. A switch "
                    "schedule in steps works the same way. --record writes the graph's topics to MCAP for "
                    "analyze and compare.")
    run.add_argument("graph", metavar="GRAPH", help="graph file, or the name of an installed graph")
    run.add_argument("arguments", nargs="*", metavar="NAME:=VALUE", help="launch arguments of the graph")
    run.add_argument("--duration", type=POSITIVE, metavar="S",
                     help="simulated seconds to run (default: the plant's duration parameter)")
    run.add_argument("-p", dest="param", action="append", default=[], metavar="NODE.PARAM:=VALUE",
                     help="override a parameter of one node (repeatable)")
    run.add_argument("--record", metavar="FILE.mcap", help="write the run's topics into this new bag")
    run.set_defaults(run=_cmd_run)


def _add_bridge(commands: argparse._SubParsersAction) -> None:
    bridge = commands.add_parser(
        "bridge", help="a graph as the controller of a simulator that calls libhawt_discon.so (OpenFAST's ServoDyn)",
        description="Serve one simulator run: libhawt_discon.so (ros2_ws/lib/, ServoDyn's DLL_FileName) reads "
                    "the bridge file (DLL_InFile) and sends each DISCON call over its socket. On the first call the "
                    "graph starts as 'hawt launch' starts it (lockstep), with a bridge plant node in place of its "
                    "plant: each call is a plant step and is answered with that step's pitch and torque, so 'hawt "
                    "switch', 'hawt list' and 'hawt view' work during the simulator's run. --in-process steps the "
                    "graph's cores in this process instead (as 'hawt run': faster, no live switching). Ends at the "
                    "simulator's last call. See hawt_tools/discon_bridge.py for the file.")
    bridge.add_argument("graph", nargs="?", metavar="GRAPH", help="graph file or installed graph (default: the "
                        "bridge file's graph)")
    bridge.add_argument("arguments", nargs="*", metavar="NAME:=VALUE", help="launch arguments of the graph")
    bridge.add_argument("--file", required=True, metavar="BRIDGE_FILE",
                        help="the bridge file the simulator is given (its socket, timeouts, graph)")
    bridge.add_argument("-p", dest="param", action="append", default=[], metavar="NODE.PARAM:=VALUE",
                        help="override a parameter of one node (repeatable)")
    bridge.add_argument("--record", metavar="FILE.mcap", help="write the run's topics into this new bag")
    bridge.add_argument("--in-process", action="store_true",
                        help="step the graph in this process (the in-process engine) instead of the ROS graph")
    bridge.set_defaults(run=_cmd_bridge)


def _add_graph(commands: argparse._SubParsersAction) -> None:
    graph = commands.add_parser("graph", help="the installed graph files (list) and what one declares (show)")
    graph_commands = graph.add_subparsers(dest="graph_action", required=True, metavar="ACTION")
    graph_list = graph_commands.add_parser(
        "list", help="the installed graph files, each with what it is (offline: nothing runs)",
        description="List the graphs installed with hawt's packages by name, each with the first sentence of its "
                    "file's comment. Starts and discovers nothing; hawt list shows a running graph.")
    graph_list.set_defaults(run=_cmd_graph_list)
    graph_show = graph_commands.add_parser(
        "show", help="a graph's launch arguments with defaults, its nodes and parameter files, its programs",
        description="List a graph file's launch arguments (NAME:=VALUE) with their defaults and descriptions, "
                    "then its nodes (namespace/name, package/executable) with their parameter files as the "
                    "defaults (or the given arguments) resolve them, then its executable programs. Starts nothing.")
    graph_show.add_argument("graph", metavar="GRAPH", help="graph file, or the name of an installed graph")
    graph_show.add_argument("arguments", nargs="*", metavar="NAME:=VALUE",
                            help="launch arguments to resolve the parameter files with")
    graph_show.set_defaults(run=_cmd_graph_show)


_PARSERS = {"launch": _add_launch, "run": _add_run, "bridge": _add_bridge, "graph": _add_graph}


def add_parsers(commands: argparse._SubParsersAction, names: Sequence[str] = tuple(_PARSERS)) -> None:
    """The subparsers of this group's commands ``names`` (default: all of them), added to hawt's ``commands`` in
    that order."""
    for name in names:
        _PARSERS[name](commands)
