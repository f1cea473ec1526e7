"""Write bags from numpy columns, without ROS: a run computed offline becomes a bag like a recorded one.

`write_topics` serializes each topic at once with `cdr_columns.encode_messages` and
writes all messages in log-time order, interleaved as a recorder would have written
them; `plant_topics` turns the channel arrays of `hawt_analysis.record` (e.g. from
`hawt_analysis.synthetic_run`) into the plant and control topics of DESIGN §5, as the
plant and controllers would publish them.
"""
from dataclasses import dataclass
from typing import Mapping, Optional, Sequence

import numpy as np

from hawt_core.topics import BLADE_LOADS, PITCH_COMMAND, TURBINE_STATE
from hawt_core.topics import EVENTS as CONTROL_EVENTS

from .cdr_columns import encode_messages
from .errors import BagError
from .interface_files import schema_text
from .msg_definition import parse_schema, short_type_name
from .plant_run import topic_in
from .qos_profiles import QosOffer
from .writer import BagWriter

__all__ = ["TopicData", "plant_topics", "write_topics"]

_RELIABLE = QosOffer(history="unknown", depth=0, reliability="reliable", durability="volatile")
"""What a live graph reports for the control loop's publishers (DESIGN §4)."""


@dataclass(frozen=True)
class TopicData:
    """A topic to write: one message per row of ``columns``.

    Attributes
    ----------
    topic : str
    type_name : str
        ``pkg/msg/Type``; its schema comes from the installed ``.msg`` files.
    columns : mapping
        Field path → one row per message (see `cdr_columns.encode_messages`).
    log_time : numpy.ndarray of int, shape (n,)
        [ns].
    publish_time : numpy.ndarray of int, shape (n,), optional
        [ns]; log_time if None.
    """

    topic: str
    type_name: str
    columns: Mapping[str, np.ndarray]
    log_time: np.ndarray
    publish_time: Optional[np.ndarray] = None


def write_topics(writer: BagWriter, topics: Sequence[TopicData]) -> dict[str, int]:
    """Add the topics and write their messages in log-time order (ties in the order of ``topics``).

    Returns
    -------
    dict
        Topic → messages written.
    """
    channels, payloads, logs, publishes = [], [], [], []
    for data in topics:
        log = np.asarray(data.log_time, dtype=np.int64)
        text = schema_text(data.type_name)
        payloads += encode_messages(parse_schema(text, data.type_name), short_type_name(data.type_name),
                                    data.columns, log.size)
        channel = writer.add_topic(data.topic, data.type_name, [_RELIABLE], definition=text)
        channels.append(np.full(log.size, channel))
        logs.append(log)
        publishes.append(log if data.publish_time is None else np.asarray(data.publish_time, dtype=np.int64))
    channel_of, log_time, publish_time = (np.concatenate(a) for a in (channels, logs, publishes))
    for i in np.argsort(log_time, kind="stable").tolist():
        writer.write(int(channel_of[i]), int(log_time[i]), payloads[i], int(publish_time[i]))
    return {data.topic: int(np.asarray(data.log_time).size) for data in topics}


def _stamp(time: np.ndarray) -> dict[str, np.ndarray]:
    ns = np.round(np.asarray(time) * 1e9).astype(np.int64)
    return {"header.stamp.sec": ns // 1_000_000_000, "header.stamp.nanosec": ns % 1_000_000_000}


def plant_topics(channels: Mapping[str, np.ndarray], namespace: str = "", events: Sequence[Mapping] = (),
                 start_time: int = 0) -> list[TopicData]:
    """A run's channels as ``plant/blade_loads``, ``plant/state``, ``control/pitch_command``
    (and ``control/events``) under ``namespace``.

    Parameters
    ----------
    channels : mapping
        ``time`` [s] and the channels of `hawt_analysis.record` (``azimuth``,
        ``rotor_speed``, ``root_moment_oop`` (n, B), …, ``pitch`` (n, B)). The pitch
        command of step k is the pitch of step k: its collective part is the blade
        mean, its individual part the rest.
    namespace : str
        E.g. ``/wt1``; "" for none.
    events : sequence of mapping
        ``control/events`` messages: ``step``, ``source``, ``level``, ``kind``, ``detail``
        (stamped with the time of their step).
    start_time : int
        Log time of step 0 [ns]; later log times follow the header stamps.
    """
    if "time" not in channels or "pitch" not in channels:
        raise BagError("channels: 'time' and 'pitch' are required for the plant topics")
    time = np.asarray(channels["time"], dtype=np.float64)
    n = time.size
    stamp = _stamp(time)
    log_time = start_time + np.round((time - time[0]) * 1e9).astype(np.int64)
    publish_time = stamp["header.stamp.sec"] * 1_000_000_000 + stamp["header.stamp.nanosec"]
    common = {**stamp, "step": np.arange(n, dtype=np.uint64)}
    pitch = np.asarray(channels["pitch"], dtype=np.float64)
    collective = pitch.mean(axis=1)
    loads = {name: channels[name] for name in ("azimuth", "rotor_speed", "root_moment_oop", "root_moment_ip", "pitch")
             if name in channels}
    state_type = parse_schema(schema_text("hawt_msgs/msg/TurbineState"), "hawt_msgs/msg/TurbineState")
    state = {f.name: channels[f.name] for f in state_type["hawt_msgs/TurbineState"].fields if f.name in channels}
    command = {"pitch": pitch, "collective": collective, "individual": pitch - collective[:, None],
               "generator_torque": channels.get("generator_torque", np.zeros(n))}
    topics = [TopicData(topic_in(namespace, relative), type_name, {**common, **columns}, log_time, publish_time)
              for relative, type_name, columns in ((BLADE_LOADS, "hawt_msgs/msg/BladeLoads", loads),
                                                   (TURBINE_STATE, "hawt_msgs/msg/TurbineState", state),
                                                   (PITCH_COMMAND, "hawt_msgs/msg/PitchCommand", command))]
    if events:
        at = np.array([int(e["step"]) for e in events])
        columns = {"step": at.astype(np.uint64), "level": np.array([int(e["level"]) for e in events], dtype=np.uint8),
                   **{k: np.array([str(e[k]) for e in events]) for k in ("source", "kind", "detail")},
                   **_stamp(time[at])}
        topics.append(TopicData(topic_in(namespace, CONTROL_EVENTS), "hawt_msgs/msg/ControlEvent", columns,
                                log_time[at], publish_time[at]))
    return topics
