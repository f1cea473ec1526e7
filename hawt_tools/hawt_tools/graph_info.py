"""What a running graph holds: its nodes, topics with their types, and controllers with their states (``hawt list``)."""
import time
from collections import Counter
from dataclasses import dataclass
from typing import List, Tuple

import rclpy
from rclpy.node import Node

from hawt_tools.controller_client import ControllerManagerError, ControllerRow, find_managers, list_controllers

__all__ = ["TopicInfo", "GraphSnapshot", "snapshot", "controllers_in", "controllers_text"]


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
    controllers: Tuple[Tuple[str, Tuple[ControllerRow, ...]], ...] = ()

    def text(self) -> str:
        """The human-readable listing; a name that several nodes share (two graphs in one ROS_DOMAIN_ID, whose
        topics then mix) once, with their count."""
        counts = Counter(self.nodes)
        lines = [f"nodes ({len(self.nodes)}):"] + [
            f"  {name}" + (f"  ({count} nodes of this name: several graphs in this ROS_DOMAIN_ID? their topics mix)"
                           if count > 1 else "") for name, count in counts.items()]
        lines.append(f"topics ({len(self.topics)}):")
        width = max((len(t.name) for t in self.topics), default=0)
        for topic in self.topics:
            lines.append(f"  {topic.name:<{width}}  {', '.join(topic.types)}  "
                         f"({topic.publishers} pub, {topic.subscribers} sub)")
        for manager, rows in self.controllers:
            lines += controllers_text(manager, rows)
        return "\n".join(lines)


def controllers_text(manager: str, rows: Tuple[ControllerRow, ...]) -> List[str]:
    """The listing's lines for the controllers of the manager in namespace ``manager`` (ending in '/')."""
    width = max((len(row.name) for row in rows), default=0)
    return [f"controllers of {manager or '/'}controller_manager ({len(rows)}):"] + [
        f"  {row.name:<{width}}  {row.state:<8}  {row.type:<10}  claims {row.interfaces}" for row in rows]


def controllers_in(namespace: str, timeout: float = 5.0) -> Tuple[ControllerRow, ...]:
    """The controllers of the manager in ``namespace``, asked directly: no wait for the rest of the graph's discovery
    (``hawt list --namespace``). Where none answers, the error names the namespaces whose managers the graph has."""
    with rclpy.init():
        node = Node("_hawt_list", start_parameter_services=False, enable_rosout=False)
        try:
            return list_controllers(node, namespace, timeout)
        except ControllerManagerError as error:
            managers = [manager or "/" for manager in find_managers(node, timeout=1.0)]
            raise ControllerManagerError(f"{error}; the graph's controller managers: {', '.join(managers)}" if managers
                                         else str(error)) from None
        finally:
            node.destroy_node()


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
            controllers = []
            for manager in find_managers(node, timeout=1.0 if any(n.endswith('/controller_manager') for n in names) else 0.0):
                try:
                    controllers.append((manager + "/", list_controllers(node, manager)))
                except ControllerManagerError:
                    continue
            return GraphSnapshot(nodes=tuple(names), topics=topics, controllers=tuple(controllers))
        finally:
            node.destroy_node()
