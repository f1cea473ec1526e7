"""Whether the recorder hears a topic yet: a run that must be complete in its bag starts only once it does."""
from typing import Iterable, List, Mapping, Optional

from rclpy.node import Node

from hawt_core.topics import RECORDER_NODE, RECORDER_PROGRESS

__all__ = ["unmatched_topics", "unrecorded_topics"]


def unrecorded_topics(node: Node, topics: Optional[Iterable[str]] = None, recorder: str = RECORDER_NODE) -> List[str]:
    """The ``topics`` (default: every topic that has a publisher but the recorder's own progress) the node
    ``recorder`` does not subscribe to yet.

    Names are as the graph reports them (fully qualified); the answer is what ``node`` has
    discovered so far.
    """
    if topics is None:
        topics = [name for name, _ in node.get_topic_names_and_types()
                  if name != RECORDER_PROGRESS and node.get_publishers_info_by_topic(name)]
    return [topic for topic in topics
            if not any(info.node_name == recorder for info in node.get_subscriptions_info_by_topic(topic))]


def unmatched_topics(node: Node, matched: Mapping[str, int]) -> List[str]:
    """The topics with more publishers in the graph than ``matched`` (the recorder's /recorder/progress) says its
    subscription is matched with: their first messages could still miss the bag."""
    return [name for name, _ in node.get_topic_names_and_types() if name != RECORDER_PROGRESS
            and matched.get(name, 0) < len(node.get_publishers_info_by_topic(name))]
