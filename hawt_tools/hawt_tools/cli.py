"""The ``hawt`` command (DESIGN.md §8): thin argument parsing over library functions.

Exit codes: 0 success, 1 runtime failure, 2 bad usage or bad input, always with a
one-line message naming the file, field or parameter at fault.
"""
import argparse
import json
import sys
import tempfile
import time
from pathlib import Path
from typing import Dict, List, Optional

from hawt_tools.graph_file import GraphError, load_graph

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
    from hawt_tools.launcher import ProcessGraph, package_prefix, parse_overrides, run_composed

    graph = load_graph(find_graph(args.graph), _launch_arguments(args.arguments), package_prefix)
    overrides = parse_overrides(graph, args.param)
    global_parameters = {"mode": args.mode} if args.mode else {}
    if args.composed:
        return run_composed(graph, overrides, args.duration, global_parameters)
    return ProcessGraph(graph, overrides, global_parameters).run(args.duration)


def _cmd_list(args: argparse.Namespace) -> int:
    from hawt_tools.graph_info import snapshot

    print(snapshot(settle=args.settle).text())
    return 0


def _cmd_demo(args: argparse.Namespace) -> int:
    """Run the example graph (source -> relay -> sink, three processes) and say what the sink saw."""
    from hawt_tools.launcher import ProcessGraph, package_prefix, parse_overrides

    with tempfile.TemporaryDirectory(prefix="hawt_demo_") as folder:
        record = Path(folder) / "received.json"
        graph = load_graph(find_graph("example"), {"record_file": str(record)}, package_prefix)
        started = time.monotonic()
        ProcessGraph(graph, parse_overrides(graph, [])).run(args.duration)
        elapsed = time.monotonic() - started
        if not record.is_file():
            print("hawt demo: the sink received no message", file=sys.stderr)
            return 1
        received = {int(k): v for k, v in json.loads(record.read_text()).items()}
    source, relay = graph.node("source"), graph.node("relay")
    gain = dict(p for s in relay.parameters for p in getattr(s, "values", ())).get("gain")
    print(f"\nhawt demo: {len(graph.nodes)} nodes in {len(graph.nodes)} processes ran {elapsed:.1f} s; "
          f"{source.label} -> {relay.label} (gain {gain}) -> sink: {len(received)} BladeLoads messages, "
          f"steps {min(received)}..{max(received)}, blade-1 M_oop of the last {received[max(received)][0]:.4g} N*m")
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
    launch.add_argument("-p", dest="param", action="append", default=[], metavar="NODE.PARAM:=VALUE",
                        help="override a parameter of one node (repeatable)")
    launch.set_defaults(run=_cmd_launch)

    listing = commands.add_parser("list", help="the nodes and topics (with types) of the running graph")
    listing.add_argument("--settle", type=float, default=1.0, metavar="S",
                         help="discovery: wait until the node list is unchanged for S seconds")
    listing.set_defaults(run=_cmd_list)

    demo = commands.add_parser("demo", help="run the example graph and print what it saw")
    demo.add_argument("--duration", type=float, default=4.0, metavar="S", help="wall-clock seconds to run")
    demo.set_defaults(run=_cmd_demo)
    return parser


def main(argv: Optional[List[str]] = None) -> int:
    args = _parser().parse_args(argv)
    try:
        return args.run(args)
    except GraphError as error:
        print(f"hawt {args.command}: {error}", file=sys.stderr)
        return 2
    except RuntimeError as error:
        print(f"hawt {args.command}: {error}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
