"""What a running graph holds: its nodes and its topics with their types (``hawt list``)."""
import time
from dataclasses import dataclass
from typing import List, Tuple

import rclpy
from rclpy.node import Node

__all__ = ["TopicInfo", "GraphSnapshot", "snapshot"]


@dataclass(frozen=True)
class TopicInfo:
    name: str
    types: Tuple[str, ...]
    publishers: int
    subscribers: int


@dataclass(frozen=True)
class GraphSnapshot:
    nodes: Tuple[str, ...]
    topics: Tuple[TopicInfo, ...]

    def text(self) -> str:
        """The human-readable listing."""
        lines = [f"nodes ({len(self.nodes)}):"] + [f"  {name}" for name in self.nodes]
        lines.append(f"topics ({len(self.topics)}):")
        width = max((len(t.name) for t in self.topics), default=0)
        for topic in self.topics:
            lines.append(f"  {topic.name:<{width}}  {', '.join(topic.types)}  "
                         f"({topic.publishers} pub, {topic.subscribers} sub)")
        return "\n".join(lines)


def _fully_qualified(namespace: str, name: str) -> str:
    return f"{namespace.rstrip('/')}/{name}"


def snapshot(settle: float = 1.0, timeout: float = 5.0) -> GraphSnapshot:
    """Discover the graph: wait until the node list stays the same for ``settle`` s (at most ``timeout`` s).

    Hidden nodes (names starting with ``_``), this node included, and the
    parameter-event and rosout topics every node has are left out.
    """
    with rclpy.init():
        node = Node("_hawt_list", start_parameter_services=False, enable_rosout=False)
        try:
            start = stable_since = time.monotonic()
            names: List[str] = []
            while time.monotonic() - start < timeout:
                current = sorted(_fully_qualified(ns, n) for n, ns in node.get_node_names_and_namespaces()
                                 if not n.startswith("_"))
                now = time.monotonic()
                if current != names:
                    names, stable_since = current, now
                elif names and now - stable_since >= settle:
                    break
                time.sleep(0.1)
            topics = tuple(
                TopicInfo(name, tuple(types), node.count_publishers(name), node.count_subscribers(name))
                for name, types in sorted(node.get_topic_names_and_types())
                if name not in ("/parameter_events", "/rosout"))
            return GraphSnapshot(nodes=tuple(names), topics=topics)
        finally:
            node.destroy_node()
