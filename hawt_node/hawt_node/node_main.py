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
waits in slices of ``WAKE_PERIOD``. Nor does a wait with a timeout end while its queue is never empty (rclpy 9's
``EventsQueue::RunUntil`` checks the deadline only when it has nothing to run), as in a composed lockstep graph:
:func:`spin_nodes` has a thread of its own complete a future at the deadline, which stops the wait after the
callback running.

Stopping (SIGINT, SIGTERM, a node done, or the launcher gone) is not a crash: before the nodes are
destroyed, every publisher waits (together at most ``FLUSH_TIMEOUT``) until its
reliable readers have acknowledged what it sent, so the recorder of ``hawt launch
--record`` gets the last steps. rclpy's own signal handler would shut the context
down at once and make that impossible, so :func:`run_nodes` installs its own.
"""
import threading
import time
from contextlib import contextmanager
from typing import Callable, Iterator, List, Optional, Sequence

import rclpy
from rclpy.duration import Duration
from rclpy.executors import Executor
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions
from rclpy.task import Future

from hawt_core.stop_signals import parent_gone, stop_signals
from hawt_core.scheduling import priority_from_environment

__all__ = ["run_node", "run_nodes", "node_entry_point", "spin_nodes", "first_done", "make_executor",
           "wait_for_acknowledgements", "WAKE_PERIOD", "FLUSH_TIMEOUT"]

NodeFactory = Callable[..., Node]

WAKE_PERIOD = 0.1
"""Longest wait [s] of one executor call: how late a done future or a Ctrl-C can be noticed."""
FLUSH_TIMEOUT = 4.0
"""Longest wait [s] at the end for the readers' acknowledgements (a reader that died never acknowledges). Within a
graph node's default sigterm_timeout (5 s), so the launcher does not escalate while a node flushes; 2 s once left a
composed graph's last 300 steps unacknowledged by a recorder that had fallen behind (fresh-clone run beside the
busy suite)."""


def make_executor() -> Executor:
    """The executor every hawt node spins on (on the default context)."""
    return EventsExecutor()


def first_done(nodes: Sequence[Node]) -> Optional[Future]:
    """A future that completes when the first of the nodes' ``done`` futures does (None if no node has one)."""
    return _first_of([node.done for node in nodes if isinstance(getattr(node, "done", None), Future)])


def _first_of(futures: Sequence[Future]) -> Optional[Future]:
    if not futures:
        return None
    any_done = Future()
    for future in futures:
        future.add_done_callback(lambda _f: any_done.done() or any_done.set_result(True))
    return any_done


def spin_nodes(executor, nodes: Sequence[Node], until: Optional[Future] = None,
               timeout: Optional[float] = None, stop_when: Callable[[], bool] = lambda: False) -> None:
    """Spin the nodes on the executor until ``until`` completes, ``timeout`` seconds pass (both None: forever) or
    ``stop_when()`` holds (checked every ``WAKE_PERIOD``)."""
    for node in nodes:
        executor.add_node(node)
    with _due(timeout, stop_when) as due:
        stop = _first_of([f for f in (until, due) if f is not None])
        while not stop.done() and rclpy.ok():
            executor.spin_until_future_complete(stop, timeout_sec=WAKE_PERIOD)


@contextmanager
def _due(timeout: Optional[float], stop_when: Callable[[], bool]) -> Iterator[Future]:
    """A future that a thread completes once ``timeout`` s have passed or ``stop_when()`` holds, checked every
    ``WAKE_PERIOD``; completing it stops the executor's wait even when its queue is never empty."""
    due, ended = Future(), threading.Event()
    deadline = None if timeout is None else time.monotonic() + timeout

    def watch() -> None:
        while not ended.wait(WAKE_PERIOD):
            if (deadline is not None and time.monotonic() >= deadline) or stop_when():
                due.set_result(True)
                return

    watcher = threading.Thread(target=watch, name="spin_nodes deadline", daemon=True)
    watcher.start()
    try:
        yield due
    finally:
        ended.set()
        watcher.join()


DRAIN_TIMEOUT = 30.0
"""Longest wait [s] after a stop for nodes whose output a reader has not taken yet (``unrecorded()``: the plant whose
recorder is behind); the recorder's own stop waits as long (hawt_tools.recording.stop_process)."""


def drain(executor, nodes: Sequence[Node], timeout: float = DRAIN_TIMEOUT) -> None:
    """Spin on, after a stop, while a node says a reader has not yet taken what it sent (its ``unrecorded()``), at
    most ``timeout`` s: a plant stopped by a signal or a wall-clock --duration may be its recorder_window ahead of
    the recorder, whose progress it needs to hear. Such a node first stops sending (its ``stop_sending()``): the
    nodes spun with it, composed in one process, would otherwise keep it stepping."""
    waiting = [node for node in nodes if callable(getattr(node, "unrecorded", None))]
    for node in waiting:
        node.stop_sending()
    deadline = time.monotonic() + timeout
    while any(node.unrecorded() for node in waiting) and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.05)


def wait_for_acknowledgements(nodes: Sequence[Node], timeout: float = FLUSH_TIMEOUT) -> None:
    """Wait until every publisher's reliable readers acknowledged all it sent, at most ``timeout`` s in all."""
    deadline = time.monotonic() + timeout
    for node in nodes:
        for publisher in node.publishers:
            publisher.wait_for_all_acked(Duration(seconds=max(0.0, deadline - time.monotonic())))


@contextmanager
def _stop_on_signals() -> Iterator[Future]:
    """A future completed by SIGINT or SIGTERM while the block runs (the previous handlers come back after)."""
    stop = Future()

    def request_stop(*_) -> None:
        if not stop.done():
            stop.set_result(True)

    with stop_signals(request_stop):
        yield stop


def run_nodes(make_nodes: Callable[[], Sequence[Node]], ending: Callable[[Sequence[Node]], Optional[Future]],
              args: Optional[List[str]] = None, timeout: Optional[float] = None) -> str:
    """Create the nodes and spin them until ``ending(nodes)`` completes, a signal comes, ``timeout`` passes or
    the process that started this one (the launcher) dies; returns which: ``done``, ``signal``, ``timeout`` or
    ``parent_gone``.

    After a signal or the timeout, nodes whose output a reader has not taken yet are spun on (:func:`drain`); then the
    published messages are flushed (:func:`wait_for_acknowledgements`) and the nodes destroyed. The default context
    is used, with this module's signal handling. A realtime priority in the environment (hawt_core.scheduling) is
    set first, so that the middleware's threads run at it too.
    """
    priority_from_environment()
    launcher_gone = parent_gone()
    with _stop_on_signals() as stop, rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO):
        nodes = make_nodes()
        executor = make_executor()
        try:
            ended = ending(nodes)
            spin_nodes(executor, nodes, _first_of([f for f in (stop, ended) if f is not None]), timeout,
                       launcher_gone)
            reason = ("signal" if stop.done() else "done" if ended is not None and ended.done()
                      else "parent_gone" if launcher_gone() else "timeout")
            if reason in ("signal", "timeout"):
                drain(executor, nodes)
            wait_for_acknowledgements(nodes)
        finally:
            executor.shutdown()
            for node in nodes:
                node.destroy_node()
    return reason


def run_node(node_class: NodeFactory, args: Optional[List[str]] = None) -> None:
    """Run one node in this process until it is done or stopped by SIGINT/SIGTERM."""
    run_nodes(lambda: [node_class()], first_done, args)


def node_entry_point(node_class: NodeFactory) -> Callable[[Optional[List[str]]], None]:
    """The ``main`` of a node executable; it carries ``node_class`` so ``hawt launch --composed`` can compose it."""
    def main(args: Optional[List[str]] = None) -> None:
        run_node(node_class, args)

    main.node_class = node_class
    return main
