"""How a hawt node process starts, spins and stops.

Every node executable's ``main`` calls :func:`run_node` with the node's class. The
same class runs in a process of its own (``hawt launch``) or beside others on one
executor (``hawt launch --composed``): it takes the keyword arguments of
``rclpy.node.Node`` (``context``, ``cli_args``) and never owns the process.

A node that ends by itself (a plant that reached its duration, a source that sent
its count) exposes ``done``, an ``rclpy.task.Future``; the process then exits 0
when it completes, so that ``on_exit: shutdown`` in a graph ends the whole run.

Nodes spin on rclpy's EventsExecutor (C++): the SingleThreadedExecutor rebuilds
its wait set in Python for every callback, which cost about 1 ms per callback in a
composed graph and capped the lockstep loop at 2x real time (``./hawt bench
control_loop`` measures both). The EventsExecutor never returns from a wait without
a timeout, neither for a completed future nor for SIGINT, so :func:`spin_nodes`
waits in slices of ``WAKE_PERIOD``.
"""
import time
from typing import Callable, List, Optional, Sequence

import rclpy
from rclpy.executors import Executor, ExternalShutdownException
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from rclpy.task import Future

__all__ = ["run_node", "node_entry_point", "spin_nodes", "first_done", "make_executor", "WAKE_PERIOD"]

NodeFactory = Callable[..., Node]

WAKE_PERIOD = 0.1
"""Longest wait [s] of one executor call: how late a done future or a Ctrl-C can be noticed."""


def make_executor() -> Executor:
    """The executor every hawt node spins on (on the default context)."""
    return EventsExecutor()


def first_done(nodes: Sequence[Node]) -> Optional[Future]:
    """A future that completes when the first of the nodes' ``done`` futures does (None if no node has one)."""
    futures = [node.done for node in nodes if isinstance(getattr(node, "done", None), Future)]
    if not futures:
        return None
    any_done = Future()
    for future in futures:
        future.add_done_callback(lambda _f: any_done.done() or any_done.set_result(True))
    return any_done


def spin_nodes(executor, nodes: Sequence[Node], until: Optional[Future] = None,
               timeout: Optional[float] = None) -> None:
    """Spin the nodes on the executor until ``until`` completes or ``timeout`` seconds pass (both None: forever)."""
    for node in nodes:
        executor.add_node(node)
    until = until or Future()
    deadline = None if timeout is None else time.monotonic() + timeout
    while not until.done() and rclpy.ok():
        remaining = WAKE_PERIOD if deadline is None else min(WAKE_PERIOD, deadline - time.monotonic())
        if remaining <= 0:
            return
        executor.spin_until_future_complete(until, timeout_sec=remaining)


def run_node(node_class: NodeFactory, args: Optional[List[str]] = None) -> None:
    """Run one node in this process until it is done, interrupted or shut down.

    It uses the default context: rclpy's SIGINT handler wakes only the default
    context's executors (a node on a context of its own would sleep through Ctrl-C).
    """
    try:
        with rclpy.init(args=args):
            node = node_class()
            executor = make_executor()
            try:
                spin_nodes(executor, [node], first_done([node]))
            finally:
                executor.shutdown()
                node.destroy_node()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


def node_entry_point(node_class: NodeFactory) -> Callable[[Optional[List[str]]], None]:
    """The ``main`` of a node executable; it carries ``node_class`` so ``hawt launch --composed`` can compose it."""
    def main(args: Optional[List[str]] = None) -> None:
        run_node(node_class, args)

    main.node_class = node_class
    return main
