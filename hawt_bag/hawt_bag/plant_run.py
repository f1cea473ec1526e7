"""A recorded run's plant and control topics as the channel arrays `hawt_analysis` expects.

Topics (DESIGN §5), relative to the turbine's namespace (``/wt1/plant/blade_loads`` …):
``plant/blade_loads`` and ``plant/state`` are required; ``control/pitch_command`` and
``control/events`` are read when present. Rows are matched by ``step`` (one row per
plant step, DESIGN §3); ``time`` is the blade loads' ``header.stamp`` [s]. If the plant
topics miss steps, the longest run of steps both hold is taken, with a warning.

The pitch command is what the plant applied: a publisher the plant refused (named in its
``intruder`` events, hawt_plant.plant_node) has its own channel in a bag recorded by hawt
(`reader.PUBLISHER`), and its messages are counted apart (``refused_commands``), never taken
as a step's command. A bag that does not name the publishers holds them mixed, with a warning.
"""
import re
from dataclasses import dataclass, field
from typing import Callable, Optional

import numpy as np

from hawt_core.topics import BLADE_LOADS, PITCH_COMMAND, TURBINE_STATE, WIND_ESTIMATE
from hawt_core.topics import EVENTS as CONTROL_EVENTS

from .errors import BagError
from .msg_definition import parse_schema, short_type_name
from .reader import BagReader
from .step_coverage import step_coverage, step_ranges
from .topic_columns import TopicColumns, read_topic_columns

__all__ = [
    "PlantRun",
    "find_namespace",
    "load_plant_run",
    "topic_in",
]


_LOAD_FIELDS = ("azimuth", "rotor_speed", "root_moment_oop", "root_moment_ip", "pitch")
_STATE_FIELDS = ("generator_speed", "generator_torque", "electrical_power", "aero_torque", "rotor_thrust",
                 "hub_wind_speed", "tower_top_fa_accel", "tower_top_ss_accel", "tower_top_fa_disp",
                 "tower_top_ss_disp", "hub_tilt_moment", "hub_yaw_moment", "tower_base_fa_moment",
                 "tower_base_ss_moment", "yaw_bearing_tilt_moment", "yaw_bearing_yaw_moment", "effective_wind_mean",
                 "effective_wind_cos", "effective_wind_sin")
"""TurbineState fields that are channels of `hawt_analysis.record` (all but header and step); a bag
recorded before a field was added lacks it, and the run has no such channel."""


def topic_in(namespace: str, relative: str) -> str:
    """``("/wt1", "plant/state")`` → ``/wt1/plant/state``; ``("", …)`` → ``/plant/state``."""
    return f"{namespace.rstrip('/')}/{relative}" if namespace.strip("/") else f"/{relative}"


def _normalise(namespace: str) -> str:
    stripped = namespace.strip("/")
    return f"/{stripped}" if stripped else ""


def find_namespace(topics: list[str], namespace: Optional[str] = None) -> str:
    """The namespace of the turbine whose ``plant/blade_loads`` the bag holds ("" for the root).

    Parameters
    ----------
    topics : list of str
        The bag's topics.
    namespace : str, optional
        Chosen by the user; checked. Needed when the bag holds several turbines.

    Raises
    ------
    BagError
        If no topic ends in ``plant/blade_loads`` (in the given namespace), or several
        do and none was chosen.
    """
    suffix = "/" + BLADE_LOADS
    found = sorted(topic[: -len(suffix)] for topic in topics if topic.endswith(suffix))
    if namespace is not None:
        chosen = _normalise(namespace)
        if chosen not in found:
            raise BagError(f"missing topic {topic_in(chosen, BLADE_LOADS)}"
                           + (f" (turbines in the bag: {', '.join(n or '/' for n in found)})" if found else ""))
        return chosen
    if not found:
        raise BagError(f"missing topic {BLADE_LOADS} (under any namespace)")
    if len(found) > 1:
        raise BagError(f"several turbines in the bag ({', '.join(n or '/' for n in found)}): choose one with "
                       "--namespace")
    return found[0]


@dataclass(frozen=True)
class PlantRun:
    """One turbine's run from a bag.

    Attributes
    ----------
    namespace : str
    channels : dict
        For `hawt_analysis.summary.summarize`: ``time`` [s], the blade loads' fields and
        the TurbineState channels, one row per plant step present in both topics.
    steps : numpy.ndarray of int, shape (n,)
    pitch_command : dict or None
        ``time`` [s], ``step``, ``pitch`` (n, B) [rad], ``collective`` [rad], ``individual``
        (n, B) [rad], ``generator_torque`` [N·m], ``flags`` of the commands not refused; None if
        the topic is absent or holds none.
    flag_names : dict
        Bit value → name of the PitchCommand ``FLAG_*`` constants.
    events : list of dict
        ``time`` [s], ``step``, ``source``, ``level``, ``kind``, ``detail``, in step order.
    wind_estimates : dict
        Controller name → ``rows`` (indices into ``steps``), ``wind_cos``, ``wind_sin`` [m/s]: each
        controller's hawt_msgs/WindEstimate (``control/<name>/wind_estimate``) at the steps it has.
    counts : dict
        Topic → messages read.
    warnings : tuple of str
        One line each, e.g. the plant topics' gaps and the steps analysed instead.
    refused_commands : list of dict
        Per publisher whose pitch commands the plant refused, in the order of its first: ``publisher``,
        ``messages`` (in the bag), ``first_step``, ``last_step``; empty without an intruder.
    """

    namespace: str
    channels: dict
    steps: np.ndarray
    pitch_command: Optional[dict]
    flag_names: dict
    events: list
    counts: dict
    warnings: tuple[str, ...] = ()
    wind_estimates: dict = field(default_factory=dict)
    refused_commands: list = field(default_factory=list)


def _by_step(steps: np.ndarray) -> np.ndarray:
    """Row indices ordered by step, first message of each step (a step recorded twice counts once)."""
    _, first = np.unique(steps, return_index=True)
    return first


def _required(reader: BagReader, topic: str, fields: tuple) -> TopicColumns:
    if topic not in reader.topic_names():
        raise BagError(f"{reader.path}: missing topic {topic}")
    columns = read_topic_columns(reader, topic, ("header.stamp", "step", *fields))
    if len(columns) < 3:
        raise BagError(f"{reader.path}: {topic} holds {len(columns)} messages, too few to analyse (need 3)")
    return columns


def load_plant_run(reader: BagReader, namespace: Optional[str] = None,
                   progress: Callable[[str], None] = lambda _: None) -> PlantRun:
    """Read one turbine's plant and control topics into channel arrays.

    Parameters
    ----------
    reader : BagReader
    namespace : str, optional
        See `find_namespace`.
    progress : callable
        Called with a short line before each topic is read.

    Raises
    ------
    BagError
        Naming the bag and the topic: missing, too short, or header stamps that do not
        increase.
    """
    try:
        namespace = find_namespace(reader.topic_names(), namespace)
    except BagError as error:
        raise BagError(f"{reader.path}: {error}") from None
    loads_topic, state_topic = topic_in(namespace, BLADE_LOADS), topic_in(namespace, TURBINE_STATE)
    progress(f"reading {loads_topic}")
    loads = _required(reader, loads_topic, _LOAD_FIELDS)
    progress(f"reading {state_topic}")
    state = _required(reader, state_topic, _STATE_FIELDS)
    load_rows, state_rows = _by_step(loads.fields["step"]), _by_step(state.fields["step"])
    steps, in_loads, in_state = np.intersect1d(loads.fields["step"][load_rows], state.fields["step"][state_rows],
                                               return_indices=True)
    first, last = max(step_ranges(steps), key=lambda run: run[1] - run[0], default=(0, -1))
    kept = (steps >= first) & (steps <= last)
    steps, load_rows, state_rows = steps[kept], load_rows[in_loads[kept]], state_rows[in_state[kept]]
    gaps = [text for text in (step_coverage(c.topic, c.fields["step"]).gap_text() for c in (loads, state)) if text]
    warnings = ()
    if gaps:
        warnings = (f"steps missing: {'; '.join(gaps)}; analysing steps {first}-{last}, the longest run both "
                    "plant topics hold",)
    time = loads.stamp()[load_rows]
    if np.any(np.diff(time) <= 0.0):
        raise BagError(f"{reader.path}: {loads_topic}: header.stamp does not increase from step to step "
                       f"(first at step {int(steps[np.argmax(np.diff(time) <= 0.0) + 1])})")
    channels = {"time": time}
    channels.update({name: loads.fields[name][load_rows] for name in _LOAD_FIELDS})
    measured = {name: state.fields[name][state_rows] for name in _STATE_FIELDS if name in state.fields}
    unmeasured = [name for name, values in measured.items() if values.size and np.isnan(values).all()]
    channels.update({name: values for name, values in measured.items() if name not in unmeasured})
    if unmeasured:  # a plant that does not have them (a DISCON bridge's simulator) says so with NaN
        warnings += (f"{state_topic}: not measured (NaN at every step), left out: {', '.join(unmeasured)}",)
    counts = {loads_topic: len(loads), state_topic: len(state)}
    events = _events(reader, topic_in(namespace, CONTROL_EVENTS), counts, steps, time)
    command, flag_names, refused, command_warnings = _pitch_command(
        reader, topic_in(namespace, PITCH_COMMAND), counts, progress, channels["pitch"].shape[1], _refused(events))
    warnings += command_warnings
    missed = "" if command is None else step_coverage(topic_in(namespace, PITCH_COMMAND), command["step"]).gap_text()
    if missed:  # a recorder that fell behind, or an assembler that answered late (realtime): say so, as verify does
        warnings += (f"{missed}; the command's pitch activity is over the steps it holds",)
    channels, steps, cut = _before_nan(channels, steps)
    if cut:
        warnings += (cut,)
    estimates = _wind_estimates(reader, namespace, steps, counts, progress)
    return PlantRun(namespace, channels, steps.astype(np.int64), command, flag_names, events, counts, warnings,
                    estimates, refused)


def _before_nan(channels: dict, steps: np.ndarray) -> tuple[dict, np.ndarray, str]:
    """The channels up to the first step at which one of them is NaN (a dead sensor, ``hawt_plant.faults``), and a
    warning naming where and which; the whole run and no warning if none is. NaN from the first step on is left to
    the analysis's own refusal."""
    bad = np.zeros(len(steps), dtype=bool)
    names = []
    for name, values in channels.items():
        nan = np.isnan(values).reshape(len(steps), -1).any(axis=1)
        if nan[1:].any():
            names.append(name)
        bad |= nan
    first = int(np.argmax(bad)) if bad.any() else len(steps)
    if first in (0, len(steps)):
        return channels, steps, ""
    where = f"step {int(steps[first])} (t={channels['time'][first]:.2f} s)"
    return ({name: values[:first] for name, values in channels.items()}, steps[:first],
            f"NaN from {where} in {', '.join(names)} (a dead sensor?): analysing the steps before it")


def _wind_estimates(reader: BagReader, namespace: str, steps: np.ndarray, counts: dict, progress) -> dict:
    """Every controller's wind estimate at the run's steps (PlantRun.wind_estimates)."""
    prefix, suffix = topic_in(namespace, "control/"), "/" + WIND_ESTIMATE
    found = {}
    for topic in sorted(reader.topic_names()):
        if not (topic.startswith(prefix) and topic.endswith(suffix)):
            continue
        progress(f"reading {topic}")
        columns = read_topic_columns(reader, topic, ("step", "wind_cos", "wind_sin"))
        counts[topic] = len(columns)
        rows = _by_step(columns.fields["step"])
        _, at_run, at_topic = np.intersect1d(steps, columns.fields["step"][rows], return_indices=True)
        found[topic[len(prefix):-len(suffix)]] = {"rows": at_run, **{name: columns.fields[name][rows][at_topic]
                                                                      for name in ("wind_cos", "wind_sin")}}
    return found


_INTRUDER = re.compile(rf"^{re.escape(PITCH_COMMAND)} step -?\d+ from (?P<sender>.+?) refused: ")
"""The detail of the plant's ``intruder`` event, naming the sender as hawt_node.command_senders ``Sample.who`` does:
its node's fully qualified name, or ``… (publisher gid <hex>)`` for one the graph does not name."""


def _refused(events: list) -> tuple[str, ...]:
    """The senders whose pitch commands the plant refused, as its ``intruder`` events name them."""
    found = (_INTRUDER.match(event["detail"]) for event in events if event["kind"] == "intruder")
    return tuple(dict.fromkeys(match["sender"] for match in found if match))


def _is_refused(publisher: str, senders: tuple[str, ...]) -> bool:
    """Whether a channel's ``publisher`` (a node name, or ``gid <hex>``) is one of the refused ``senders``."""
    return bool(publisher) and any(publisher == sender or sender.endswith(f"(publisher {publisher})")
                                   for sender in senders)


def _applied(columns: TopicColumns, senders: tuple[str, ...]) -> tuple[dict, list, tuple[str, ...]]:
    """The pitch commands' fields (``time`` added) without the messages of the refused ``senders``; per refused
    publisher, in the order of its first message, its name, messages, first and last step; and a warning if a refused
    sender has no channel in the bag."""
    publishers = set(columns.publisher.tolist())
    refused = np.isin(columns.publisher, [name for name in publishers if _is_refused(name, senders)])
    unmatched = [sender for sender in senders if not any(_is_refused(name, (sender,)) for name in publishers)]
    warnings = ()
    if unmatched and "" in publishers:
        warnings = (f"{columns.topic}: the plant refused the commands of {', '.join(unmatched)}, but the bag does not "
                    "tell them from the applied ones (it does not name the publisher of each message): the commanded "
                    "pitch is analysed from all of them",)
    elif unmatched:
        applied = sorted(publishers - set(columns.publisher[refused].tolist()))
        warnings = (f"{columns.topic}: the plant refused the commands of {', '.join(unmatched)}, but the bag holds "
                    "none by that name (the recorder did not receive them, or knew their publisher by its GID only): "
                    f"the commanded pitch is that of {', '.join(applied)}",)
    steps, names = columns.fields["step"][refused], columns.publisher[refused]
    refused_commands = [{"publisher": name, "messages": int(np.count_nonzero(names == name)),
                         "first_step": int(steps[names == name].min()), "last_step": int(steps[names == name].max())}
                        for name in dict.fromkeys(names.tolist())]
    fields = {name: values[~refused] for name, values in {**columns.fields, "time": columns.stamp()}.items()}
    return fields, refused_commands, warnings


def _pitch_command(reader: BagReader, topic: str, counts: dict, progress, blades: int,
                   senders: tuple[str, ...]) -> tuple[Optional[dict], dict, list, tuple[str, ...]]:
    """The applied commands by step, the flag names of the message type, the refused commands (`_applied`: those of
    the refused ``senders``) and warnings: one naming the malformed messages (a pitch or individual of another length
    than ``blades``), which are counted and skipped, and `_applied`'s."""
    if topic not in reader.topic_names():
        return None, {}, [], ()
    progress(f"reading {topic}")
    columns = read_topic_columns(reader, topic, ("header.stamp", "step", "pitch", "collective", "individual",
                                                 "generator_torque", "flags"))
    counts[topic] = len(columns)
    schema = reader.schema(topic)
    definition = parse_schema(schema.data.decode(), schema.name)[short_type_name(schema.name)]
    flag_names = {int(value): name for name, value in definition.constants.items() if name.startswith("FLAG_")}
    if not len(columns):
        return None, flag_names, [], ()
    fields, refused_commands, warnings = _applied(columns, senders)
    if not len(fields["step"]):
        return None, flag_names, refused_commands, warnings
    sizes = [np.array([len(row) for row in fields[name]]) for name in ("pitch", "individual")]
    wellformed = (sizes[0] == blades) & (sizes[1] == blades)
    if not wellformed.all():
        bad = np.flatnonzero(~wellformed)
        warnings += (f"{topic}: {bad.size} malformed message(s) skipped (pitch and individual must hold {blades} "
                     f"values; the first at step {int(fields['step'][bad[0]])} holds {int(sizes[0][bad[0]])} and "
                     f"{int(sizes[1][bad[0]])})",)
        fields = {name: values[wellformed] for name, values in fields.items()}
        if not len(fields["step"]):
            return None, flag_names, refused_commands, warnings
    # rows of one length once the malformed or refused ones are out
    fields.update({name: np.stack(fields[name]).astype(np.float64) for name in ("pitch", "individual")
                   if fields[name].dtype == object})
    rows = _by_step(fields["step"])
    command = {name: fields[name][rows] for name in ("step", "pitch", "collective", "individual",
                                                     "generator_torque", "flags", "time")}
    return command, flag_names, refused_commands, warnings


def _events(reader: BagReader, topic: str, counts: dict, steps: np.ndarray, times: np.ndarray) -> list:
    """The events in step order; one without a header stamp (a node that does not know the plant's time) gets the
    plant's time of its step, from the plant's steps and times."""
    if topic not in reader.topic_names():
        return []
    columns = read_topic_columns(reader, topic)
    counts[topic] = len(columns)
    if not len(columns):
        return []
    time = columns.stamp()
    unstamped = time == 0.0
    if np.any(unstamped) and steps.size > 1:
        dt = (times[-1] - times[0]) / float(steps[-1] - steps[0])
        time[unstamped] = times[0] + dt * (columns.fields["step"][unstamped].astype(np.float64) - float(steps[0]))
    order = np.lexsort((np.arange(len(columns)), columns.fields["step"]))
    return [{"time": float(time[i]), "step": int(columns.fields["step"][i]),
             "source": str(columns.fields["source"][i]), "level": int(columns.fields["level"][i]),
             "kind": str(columns.fields["kind"][i]), "detail": str(columns.fields["detail"][i])}
            for i in order.tolist()]
