"""The ``hawt`` command (DESIGN.md §8): thin argument parsing over library functions.

Exit codes: 0 success, 1 runtime failure, 2 bad usage or bad input, always with a
one-line message naming the file, field or parameter at fault.

The commands, their options and handlers are in hawt_tools.commands, one module per group of commands.
"""
import gc
import sys

if __name__ == "__main__":
    gc.disable()  # while the commands' modules are imported (_process)

import argparse
import os
from typing import List, Optional

from hawt_bag.errors import BagError

from hawt_core.scheduling import SchedulingError
from hawt_tools.commands import analysis, bags, campaigns, demo, design, graphs, live, turbines
from hawt_tools.commands.options import Parser
from hawt_tools.graph_file import GraphError
from hawt_tools.view import ViewOptionError

__all__ = ["main"]

COMMANDS = ((graphs, ("launch", "run", "bridge")), (live, ("record", "view")), (bags, ("replay", "bag")),
            (graphs, ("graph",)), (analysis, ("analyze", "compare")), (live, ("list", "switch", "lifecycle")),
            (design, ("coupling", "linearize", "design")), (turbines, ("turbine", "validate")),
            (analysis, ("transfer",)), (campaigns, ("campaign",)), (demo, ("demo",)))
"""Each group's commands in the order ``hawt --help`` lists them."""


def _parser() -> argparse.ArgumentParser:
    parser = Parser(
        prog="hawt", description="ROS 2 toolkit for wind-turbine load alleviation: run node graphs of a "
                                 "simulated turbine and its pitch controllers.",
        epilog="The ./hawt script in the repository also runs: ./hawt test [PYTEST ARGS] (the test suite; --quick "
               "the cores' tests only, --stress beside two busy CPU loops) and ./hawt bench NAME (a benchmark of "
               "benchmarks/bench_NAME.py).")
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for group, names in COMMANDS:
        group.add_parsers(commands, names)
    return parser


def parse_command_line(argv: Optional[List[str]] = None) -> argparse.Namespace:
    """The parsed command; a graph's NAME:=VALUE arguments may come before or after the options."""
    parser = _parser()
    args, extra = parser.parse_known_args(argv)
    if extra and getattr(args, "arguments", None) is not None and all(":=" in word for word in extra):
        args.arguments += extra
    elif extra:
        parser.error(f"unrecognized arguments: {' '.join(extra)}")
    if getattr(args, "record_optional", False) and not args.record:
        parser.error("--record-optional: needs --record")
    return args


def main(argv: Optional[List[str]] = None) -> int:
    args = parse_command_line(argv)
    try:
        return args.run(args)
    except (GraphError, BagError, SchedulingError, ViewOptionError) as error:
        print(f"hawt {args.command}: {error}", file=sys.stderr)
        return 2
    except RuntimeError as error:
        print(f"hawt {args.command}: {error}", file=sys.stderr)
        return 1
    except BrokenPipeError:
        # The reader went away (``hawt bag info … | head``): what it wanted it has; end quietly, and keep
        # Python from failing again when it flushes stdout at exit.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


def _process() -> int:
    """``hawt`` as a process (``python -m hawt_tools.cli``): :func:`main` once the commands' modules are imported
    without the garbage collector, their objects frozen (``gc.freeze``: they live as long as the process, and no
    collection passes over them again). The collector's passes over them while they came were about 45 ms of every
    command's start."""
    gc.freeze()
    gc.enable()
    return main()


if __name__ == "__main__":
    sys.exit(_process())
