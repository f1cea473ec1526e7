"""What the recorder records and how: its options and the ``hawt record`` command line that gives them, without ROS.

``hawt_bag.recorder`` records with them; the command line is read here so that ``hawt``'s parser, built for every
command, does not load rclpy.
"""
import argparse
import math
import re
import time
from dataclasses import dataclass
from typing import Optional

from hawt_core.topics import RECORDER_NODE

from .errors import BagError

__all__ = ["RecorderOptions", "add_record_arguments", "options_from"]


@dataclass(frozen=True)
class RecorderOptions:
    """What to record and how.

    Attributes
    ----------
    output : str
        The new bag file (refused if it exists).
    topics : tuple of str
        Topics to record (absolute names); with ``regex`` both select. All if neither.
    regex : str or None
        Record topics whose name matches (``re.search``).
    include_hidden : bool
        Also topics with a hidden component (``/_x``), which ``--all`` skips in rosbag2.
    poll_period : float
        Graph discovery period [s].
    chunk_size : int
        Chunk size [bytes].
    chunk_interval : float
        Longest time a chunk stays open [s]; bounds what a SIGKILL loses.
    depth : int
        Subscription queue depth (keep-last): how many messages of a topic the recorder may be behind
        before the oldest are lost. A lockstep plant holds back on the recorder's progress (its
        ``recorder_window``, 500 steps by default), so this bounds only a realtime recording's backlog.
        Fast DDS (the default middleware) holds at most 5000 samples per subscription whatever the depth
        (its default resource limit; measured: a reliable publisher's 5001st message waits unacknowledged
        until the recorder takes one), so 50 s of a 100 Hz plant; a reliable publisher keeps the rest in
        its own history (its depth), a best-effort publisher's are lost.
    """

    output: str
    topics: tuple[str, ...] = ()
    regex: Optional[str] = None
    include_hidden: bool = False
    poll_period: float = 0.1
    chunk_size: int = 1024 * 1024
    chunk_interval: float = 1.0
    depth: int = 10000
    node_name: str = RECORDER_NODE


def add_record_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of ``hawt record`` (and of the ``record`` executable)."""
    parser.add_argument("-o", "--output", metavar="FILE.mcap",
                        help="the new bag (default: bags/run_<date>_<time>.mcap); an existing file is refused")
    parser.add_argument("--topics", nargs="+", default=[], metavar="T", help="record only these topics")
    parser.add_argument("-e", "--regex", metavar="R", help="record topics whose name matches this regex")
    parser.add_argument("--include-hidden-topics", action="store_true", help="also topics such as /_x")
    parser.add_argument("--chunk-size", type=int, default=1024 * 1024, metavar="BYTES",
                        help="chunk size before compression (default 1 MiB)")
    parser.add_argument("--chunk-interval", type=float, default=1.0, metavar="S",
                        help="close a chunk at least every S seconds: what a kill can lose (default 1)")
    parser.add_argument("--node-name", default=RECORDER_NODE, help="the recorder node's name")


def options_from(args: argparse.Namespace) -> RecorderOptions:
    """RecorderOptions from parsed `add_record_arguments` options (default output name by date), each checked, the
    output's folders made last (`new_bag_path`).

    Raises
    ------
    BagError
        One line naming the option that is out of range, or the output that cannot be a new bag.
    """
    if args.regex:
        try:
            re.compile(args.regex)
        except re.error as error:
            raise BagError(f"--regex {args.regex!r}: {error}") from None
    if not 0 < args.chunk_interval < math.inf:
        raise BagError(f"--chunk-interval: expected a positive number of seconds, found {args.chunk_interval}")
    if args.chunk_size < 1:
        raise BagError(f"--chunk-size: expected a positive number of bytes, found {args.chunk_size}")
    from .writer import new_bag_path  # here: the mcap writer is not on the path of hawt commands that record nothing

    output = str(new_bag_path(args.output or time.strftime("bags/run_%Y%m%d_%H%M%S.mcap"), "-o"))
    return RecorderOptions(output, tuple(args.topics), args.regex, args.include_hidden_topics,
                           chunk_size=args.chunk_size, chunk_interval=args.chunk_interval, node_name=args.node_name)
