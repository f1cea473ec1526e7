"""A running graph: ``hawt list`` (its nodes, topics and controllers), ``hawt switch`` and ``hawt lifecycle`` (its
controllers), ``hawt view`` (served live to Foxglove), ``hawt record`` (its topics into a bag)."""
import argparse
import os
from typing import Sequence

from hawt_tools.graph_file import GraphError, installed_graphs


def _cmd_view(args: argparse.Namespace) -> int:
    from hawt_tools.view import options_from
    from hawt_tools.view_node import view

    return view(options_from(args))


def _cmd_record(args: argparse.Namespace) -> int:
    from hawt_bag.record_options import options_from
    from hawt_bag.recorder import record

    return record(options_from(args))


def _cmd_list(args: argparse.Namespace) -> int:
    from hawt_tools.controller_client import ControllerManagerError, manager_namespace
    from hawt_tools.graph_info import controllers_in, controllers_text, snapshot

    if args.namespace is not None:
        manager = manager_namespace(args.namespace)
        try:
            print("\n".join(controllers_text(manager + "/", controllers_in(manager))))
        except ControllerManagerError as error:
            raise RuntimeError(str(error)) from None
        return 0
    found = snapshot(settle=args.settle)
    if found.nodes:
        print(found.text())
        return 0
    print(f"no running graph found (ROS_DOMAIN_ID={os.environ.get('ROS_DOMAIN_ID', '0')}); the graphs that can be "
          "started (hawt graph list, hawt graph show GRAPH):\n  " + ", ".join(installed_graphs()))
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


def _cmd_lifecycle(args: argparse.Namespace) -> int:
    from hawt_tools.controller_client import ControllerManagerError, NoSuchController, lifecycle_transition

    try:
        ok, state = lifecycle_transition(args.node, args.transition, args.namespace)
    except NoSuchController as error:
        raise GraphError(str(error)) from None
    except ControllerManagerError as error:
        raise RuntimeError(str(error)) from None
    if not ok:
        raise GraphError(f"{args.node}: transition {args.transition} refused (state {state}; the node's log "
                         "says why)")
    print(f"{args.node}: {state}")
    return 0


def _add_record(commands: argparse._SubParsersAction) -> None:
    from hawt_bag.record_options import add_record_arguments

    record = commands.add_parser("record", help="record topics of the running graph into an MCAP bag",
                                 description="Record all topics (or the chosen ones) into a new MCAP bag until "
                                             "Ctrl-C/SIGTERM; topics that appear later are picked up.")
    add_record_arguments(record)
    record.set_defaults(run=_cmd_record)


def _add_view(commands: argparse._SubParsersAction) -> None:
    from hawt_tools.view import add_view_arguments

    view = commands.add_parser(
        "view", help="serve the running graph live to Foxglove (WebSocket; topics, plant time, parameters)",
        description="Serve every topic of the running graph on a Foxglove WebSocket (ROS 2 channels: ros2msg "
                    "schemas, CDR messages as published), timed by the plant's clock, with the nodes' "
                    "parameters to view and set. In Foxglove: Open connection, Foxglove WebSocket, "
                    "ws://localhost:8765; layout: hawt_tools/foxglove/hawt_layout.json.")
    add_view_arguments(view)
    view.set_defaults(run=_cmd_view)


def _add_list(commands: argparse._SubParsersAction) -> None:
    listing = commands.add_parser("list", help="the nodes, topics (with types) and controllers (with states) of the "
                                               "running graph")
    listing.add_argument("--settle", type=float, default=1.0, metavar="S",
                         help="discovery: wait until the node list is unchanged for S seconds")
    listing.add_argument("--namespace", metavar="NS", help="only the controllers of the turbine NS (e.g. /wt1), "
                                                           "asked of its controller_manager without discovering the "
                                                           "rest of the graph first")
    listing.set_defaults(run=_cmd_list)


def _add_switch(commands: argparse._SubParsersAction) -> None:
    switch = commands.add_parser(
        "switch", help="activate and deactivate controllers of a running graph at one plant step",
        description="Ask the graph's controller_manager to switch controllers atomically at one plant step "
                    "(ros2_control semantics; one active claimant per command interface). An outgoing "
                    "contribution ramps out over the ramp time, an incoming one ramps in; a controller that replaces "
                    "another on its interfaces starts from the other's output. Prints the step the switch takes effect "
                    "at.")
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


def _add_lifecycle(commands: argparse._SubParsersAction) -> None:
    lifecycle = commands.add_parser(
        "lifecycle", help="a controller's lifecycle state, or a standard transition (as ros2 lifecycle set)",
        description="Print a lifecycle node's state, or ask it for a standard transition first. A controller "
                    "hands activate/deactivate to its controller_manager, so they take effect at a plant step "
                    "exactly as 'hawt switch' does.")
    lifecycle.add_argument("node", metavar="NODE", help="node name (e.g. ipc_h1 or /wt1/ipc_h1)")
    from hawt_controllers.plugins.switching import TRANSITIONS

    lifecycle.add_argument("transition", nargs="?", choices=TRANSITIONS, help="the transition to ask for")
    lifecycle.add_argument("--namespace", metavar="NS", help="the turbine (e.g. /wt1) when several are running")
    lifecycle.set_defaults(run=_cmd_lifecycle)


_PARSERS = {"record": _add_record, "view": _add_view, "list": _add_list, "switch": _add_switch,
            "lifecycle": _add_lifecycle}


def add_parsers(commands: argparse._SubParsersAction, names: Sequence[str] = tuple(_PARSERS)) -> None:
    """The subparsers of this group's commands ``names`` (default: all of them), added to hawt's ``commands`` in
    that order."""
    for name in names:
        _PARSERS[name](commands)
