"""A node in the test process that watches a running graph: own context and executor, waits on conditions."""
import subprocess
import threading
import time
from typing import Callable, Optional

import rclpy
from rclpy.executors import SingleThreadedExecutor

from hawt_node.recording import unrecorded_topics


class ProbeNode:
    """``node`` in a context of its own; spun in a background thread (``background``) or while waiting.

    Every wait is on a condition, with a timeout only as the limit of a failing test.
    """

    def __init__(self, name: str, background: bool = False) -> None:
        self.context = rclpy.Context()
        rclpy.init(context=self.context)
        self.node = rclpy.create_node(name, context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.thread = threading.Thread(target=self.executor.spin, daemon=True) if background else None
        if self.thread is not None:
            self.thread.start()

    def spin(self, seconds: float) -> None:
        """Take everything that arrives during ``seconds`` of wall time (in the background: just wait)."""
        deadline = time.monotonic() + seconds
        while (remaining := deadline - time.monotonic()) > 0:
            if self.thread is None:
                self.executor.spin_once(timeout_sec=remaining)
            else:
                time.sleep(min(remaining, 0.01))

    def wait_until(self, condition: Callable[[], bool], what: str, alive: Optional[subprocess.Popen] = None,
                   timeout: float = 60.0) -> None:
        """Spin until ``condition()`` holds; fails if ``alive`` (a process the condition needs) ends or ``timeout``
        passes first. A process that ends has flushed what it sent to this node's reliable subscriptions
        (hawt_node.node_main.wait_for_acknowledgements), so what arrived is taken before the condition is given up."""
        deadline = time.monotonic() + timeout
        while not condition():
            if alive is not None and alive.poll() is not None:
                self.take_what_arrived()
                assert condition(), f"the process ended (exit code {alive.returncode}) before {what}"
                return
            assert time.monotonic() < deadline, f"no {what} within {timeout:g} s"
            self.spin(0.01)

    def take_what_arrived(self) -> None:
        """Hand every message waiting in this node's subscriptions to its callback, without waiting for more. Once a
        graph has ended, that is everything its nodes sent: a node flushes what it sent to its reliable readers, this
        node among them, before it exits (hawt_node.node_main.wait_for_acknowledgements)."""
        for subscription in self.node.subscriptions:
            with subscription.handle:
                while (taken := subscription.handle.take_message(subscription.msg_type, subscription.raw)) is not None:
                    subscription.callback(taken[0])

    def wait_subscribed(self, topic: str, node_name: str, timeout: float = 30.0) -> None:
        """Until node ``node_name`` subscribes to ``topic``; then 0.3 s for a publisher there to match it (what
        this probe cannot see)."""
        self.wait_until(lambda: not unrecorded_topics(self.node, [topic], node_name),
                        f"a subscription of {node_name} to {topic}", timeout=timeout)
        self.spin(0.3)

    def close(self) -> None:
        self.executor.shutdown()
        if self.thread is not None:
            self.thread.join(timeout=5)
        self.node.destroy_node()
        rclpy.shutdown(context=self.context)
