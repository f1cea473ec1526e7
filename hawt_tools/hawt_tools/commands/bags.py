"""Bags: ``hawt replay`` (a bag's messages published again), ``hawt bag info|verify|recover``."""
import argparse
import json
import sys
from typing import Sequence

from hawt_tools.commands.options import NOT_NEGATIVE, POSITIVE


def _cmd_replay(args: argparse.Namespace) -> int:
    from hawt_bag.replayer import ReplayOptions, parse_remaps, replay

    options = ReplayOptions(rate=args.rate, loop=args.loop, start_offset=args.start, topics=tuple(args.topics),
                            clock_hz=args.clock, remaps=parse_remaps(args.remap), start_paused=args.start_paused,
                            wait_for_subscribers=args.wait_for_subscribers, wait_timeout=args.wait_timeout,
                            step_trigger=args.step_trigger, step_timeout=args.step_timeout)
    result = replay(args.bag, options,
                    warn=lambda text: print(f"hawt replay: warning: {text}", file=sys.stderr, flush=True))
    print(f"replayed {result.published} messages" + (f" in {result.steps} steps" if args.step_trigger else ""))
    return 0


def _cmd_bag_info(args: argparse.Namespace) -> int:
    from hawt_bag.reader import BagReader

    with BagReader(args.bag) as reader:
        print(reader.info().text())
    return 0


def _cmd_bag_verify(args: argparse.Namespace) -> int:
    from hawt_bag.verification import verify_bag

    report = verify_bag(args.bag)
    print(json.dumps(report.as_dict()) if args.json else report.text())
    return 0 if report.ok else 1


def _cmd_bag_recover(args: argparse.Namespace) -> int:
    from hawt_bag.errors import BagError
    from hawt_bag.recover import recover_bag
    from hawt_bag.writer import new_bag_path

    recovery = recover_bag(args.bag, new_bag_path(args.output, "-o") if args.output else None)
    if not recovery.message_count:  # an empty bag rescues nothing: say so rather than leave one
        recovery.output.unlink()
        lost = f"; {recovery.orphans} messages whose channel record was lost" if recovery.orphans else ""
        raise BagError(f"{args.bag}: nothing to recover, no readable message (reading stopped at: {recovery.stopped}"
                       f"{lost}); nothing written")
    print(recovery.text())
    return 0


def _add_replay(commands: argparse._SubParsersAction) -> None:
    replay = commands.add_parser("replay", help="publish a bag's messages again, timed or step by step",
                                 description="Replay a bag at its recorded timing (times --rate), or step by step "
                                             "through a graph with --step-trigger. Live control: parameters "
                                             "'paused' and 'rate' of node hawt_player, topic "
                                             "/hawt_player/play_next (std_msgs/Empty) while paused.")
    replay.add_argument("bag", metavar="FILE.mcap")
    replay.add_argument("-r", "--rate", type=POSITIVE, default=1.0, metavar="R", help="speed factor (default 1)")
    replay.add_argument("-l", "--loop", action="store_true", help="start again at the end")
    replay.add_argument("--start", type=NOT_NEGATIVE, default=0.0, metavar="S",
                        help="start S seconds after the bag's first message")
    replay.add_argument("--topics", nargs="+", default=[], metavar="T", help="publish only these topics")
    replay.add_argument("--clock", type=NOT_NEGATIVE, nargs="?", const=40.0, default=0.0, metavar="HZ",
                        help="publish /clock at HZ (default 40 when given without a value); in step replay, "
                             "once per step")
    replay.add_argument("--remap", "-m", nargs="+", default=[], metavar="FROM:=TO", help="publish a topic under "
                                                                                         "another name")
    replay.add_argument("-p", "--start-paused", action="store_true", help="start paused")
    replay.add_argument("--wait-for-subscribers", action="store_true",
                        help="start only once every topic has a subscriber")
    replay.add_argument("--wait-timeout", type=POSITIVE, default=10.0, metavar="S",
                        help="how long to wait for subscribers and the trigger's publisher (default 10)")
    replay.add_argument("--step-trigger", metavar="TOPIC",
                        help="step replay: after publishing the messages of step k, wait for step k on TOPIC "
                             "(e.g. /wt1/control/pitch_command)")
    replay.add_argument("--step-timeout", type=POSITIVE, default=10.0, metavar="S",
                        help="step replay: how long to wait for each step's answer (default 10)")
    replay.set_defaults(run=_cmd_replay)


def _add_bag(commands: argparse._SubParsersAction) -> None:
    bag = commands.add_parser("bag", help="inspect, verify or rescue a bag (info, verify, recover)")
    bag_commands = bag.add_subparsers(dest="bag_command", required=True, metavar="SUBCOMMAND")
    info = bag_commands.add_parser("info", help="duration, size, compression, topics with type, QoS and count")
    info.add_argument("bag", metavar="FILE.mcap")
    info.set_defaults(run=_cmd_bag_info)
    verify = bag_commands.add_parser(
        "verify", help="check every stepped topic for missing and repeated steps, and the file for its summary",
        description="Check a recording lost nothing: plant/blade_loads, plant/state and control/pitch_command must "
                    "hold every step from their first to their last; other stepped topics are listed with their "
                    "runs of steps; a step recorded twice is an error unless resent identical; the file must have "
                    "its summary. Exit 0 if all is well, 1 if not, 2 if the file is missing or not MCAP.")
    verify.add_argument("bag", metavar="FILE.mcap")
    verify.add_argument("--json", action="store_true", help="print the same facts as one JSON object")
    verify.set_defaults(run=_cmd_bag_verify)
    recover = bag_commands.add_parser("recover", help="rewrite what an unfinished bag holds into a complete one")
    recover.add_argument("bag", metavar="FILE.mcap")
    recover.add_argument("-o", "--output", metavar="OUT.mcap", help="default: FILE.recovered.mcap")
    recover.set_defaults(run=_cmd_bag_recover)


_PARSERS = {"replay": _add_replay, "bag": _add_bag}


def add_parsers(commands: argparse._SubParsersAction, names: Sequence[str] = tuple(_PARSERS)) -> None:
    """The subparsers of this group's commands ``names`` (default: all of them), added to hawt's ``commands`` in
    that order."""
    for name in names:
        _PARSERS[name](commands)
