"""The ``offered_qos_profiles`` channel metadata of rosbag2 (metadata version 9).

rosbag2 writes ``YAML::Dump`` of a list of profiles (``rosbag2_storage/src/rosbag2_storage/qos.cpp``,
``serialize_rclcpp_qos_vector``): per profile the keys ``history, depth, reliability,
durability, deadline{sec,nsec}, lifespan{sec,nsec}, liveliness,
liveliness_lease_duration{sec,nsec}, avoid_ros_namespace_conventions`` in that order,
policies as the strings of ``rmw_qos_*_policy_to_str`` (``keep_last``, ``reliable``,
``volatile``, ``automatic``, ``system_default``, ``unknown`` …). An empty list is ``[]``.
Readers of version ≤ 8 bags wrote integers; both forms are read here.
"""
from dataclasses import dataclass

import yaml

from hawt_core.yaml_text import safe_load

from .errors import BagError

__all__ = ["INFINITE_NS", "QosOffer", "parse_offered_qos", "offered_qos_yaml"]

INFINITE_NS = 9_223_372_036_854_775_807
"""RMW_DURATION_INFINITE [ns]: written as ``sec: 9223372036, nsec: 854775807``."""

_HISTORY = ("system_default", "keep_last", "keep_all", "unknown")
_RELIABILITY = ("system_default", "reliable", "best_effort", "unknown", "best_available")
_DURABILITY = ("system_default", "transient_local", "volatile", "unknown", "best_available")
_LIVELINESS = ("system_default", "automatic", "", "manual_by_topic", "unknown", "best_available")
"""Index = the rmw enum value (rmw/types.h); liveliness 2 (MANUAL_BY_NODE) is deprecated and unnamed."""


@dataclass(frozen=True)
class QosOffer:
    """One publisher's offered QoS, with policies named as rmw names them.

    Durations are integer nanoseconds; `INFINITE_NS` is infinite, 0 unspecified.
    """

    history: str = "unknown"
    depth: int = 0
    reliability: str = "reliable"
    durability: str = "volatile"
    deadline_ns: int = INFINITE_NS
    lifespan_ns: int = INFINITE_NS
    liveliness: str = "automatic"
    liveliness_lease_duration_ns: int = INFINITE_NS
    avoid_ros_namespace_conventions: bool = False

    @classmethod
    def from_enums(cls, history: int, depth: int, reliability: int, durability: int, deadline_ns: int,
                   lifespan_ns: int, liveliness: int, liveliness_lease_duration_ns: int,
                   avoid_ros_namespace_conventions: bool) -> "QosOffer":
        """From the rmw enum values (``rclpy.qos`` policies are IntEnums of the same numbers)."""
        return cls(_name(_HISTORY, history, "history"), int(depth), _name(_RELIABILITY, reliability, "reliability"),
                   _name(_DURABILITY, durability, "durability"), int(deadline_ns), int(lifespan_ns),
                   _name(_LIVELINESS, liveliness, "liveliness"), int(liveliness_lease_duration_ns),
                   bool(avoid_ros_namespace_conventions))


def _name(names: tuple, value: int, policy: str) -> str:
    if not 0 <= int(value) < len(names) or not names[int(value)]:
        raise BagError(f"{policy}: unknown QoS policy value {value}")
    return names[int(value)]


def _duration(ns: int) -> str:
    return f"sec: {ns // 1_000_000_000}\n    nsec: {ns % 1_000_000_000}"


def offered_qos_yaml(offers: list[QosOffer]) -> str:
    """The ``offered_qos_profiles`` string of a topic's publishers, as rosbag2 9 writes it."""
    if not offers:
        return "[]"
    entries = []
    for q in offers:
        entries.append(
            f"- history: {q.history}\n  depth: {q.depth}\n  reliability: {q.reliability}\n"
            f"  durability: {q.durability}\n  deadline:\n    {_duration(q.deadline_ns)}\n"
            f"  lifespan:\n    {_duration(q.lifespan_ns)}\n  liveliness: {q.liveliness}\n"
            f"  liveliness_lease_duration:\n    {_duration(q.liveliness_lease_duration_ns)}\n"
            f"  avoid_ros_namespace_conventions: {'true' if q.avoid_ros_namespace_conventions else 'false'}")
    return "\n".join(entries)


def _policy(entry: dict, key: str, names: tuple) -> str:
    value = entry.get(key, "unknown")
    return _name(names, value, key) if isinstance(value, int) else str(value)


def _ns(entry: dict, key: str) -> int:
    value = entry.get(key) or {}
    return int(value.get("sec", 0)) * 1_000_000_000 + int(value.get("nsec", 0))


def parse_offered_qos(text: str) -> list[QosOffer]:
    """Read an ``offered_qos_profiles`` string (version 9 strings or version ≤ 8 integers).

    Raises
    ------
    BagError
        If the text is not a YAML list of profiles.
    """
    if not text.strip():
        return []
    try:
        entries = safe_load(text)
    except yaml.YAMLError as error:
        raise BagError(f"offered_qos_profiles: not YAML ({str(error).splitlines()[0]})") from None
    if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
        raise BagError(f"offered_qos_profiles: expected a list of profiles, found {text[:60]!r}")
    return [QosOffer(_policy(e, "history", _HISTORY), int(e.get("depth", 0)),
                     _policy(e, "reliability", _RELIABILITY), _policy(e, "durability", _DURABILITY),
                     _ns(e, "deadline"), _ns(e, "lifespan"), _policy(e, "liveliness", _LIVELINESS),
                     _ns(e, "liveliness_lease_duration"), bool(e.get("avoid_ros_namespace_conventions", False)))
            for e in entries]
