"""``hawt bag verify``: did a recording lose anything? Gaps and repeated steps of every stepped topic, and the summary.

A *stepped* topic is one whose message type has a ``step`` field: a sample of the control
loop, one message per plant step (today BladeLoads, TurbineState, PitchCommand,
CollectivePitch, HarmonicLoads, HarmonicPitch, BladePitch). They are found from the bag's
schemas, under any namespace. The `RECORDS` types also carry a step but record what
happened at it (an event, a controller's state, a switch), any number to a step: they
are not checked.

The plant topics and the pitch command (`CONTIGUOUS`) must hold every step from their
first to their last. Other stepped topics may have windows (an IPC controller publishes
only while active): their runs of steps are reported, their holes are not an error. A
step recorded twice is *resent* if both messages are equal field for field (a lockstep
plant resends a step nobody answered yet), an error otherwise; a bag that records who
published each message (`reader.PUBLISHER`) names the publishers of those steps (a second
publisher on the topic, such as an intruder the plant refused). The file must be finished,
with a summary section holding statistics.
"""
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hawt_core.topics import BLADE_LOADS, PITCH_COMMAND, TURBINE_STATE

from .errors import UnfinishedBagError
from .msg_definition import parse_schema, short_type_name
from .reader import BagReader
from .step_coverage import StepCoverage, step_coverage
from .topic_columns import TopicColumns, read_topics_columns

__all__ = ["CONTIGUOUS", "RECORDS", "TopicCheck", "Verification", "stepped_topics", "verify_bag"]

CONTIGUOUS = (BLADE_LOADS, TURBINE_STATE, PITCH_COMMAND)
"""Topics (relative to any namespace) that must hold every step from their first to their last."""
RECORDS = ("hawt_msgs/ControlEvent", "hawt_msgs/ControllerState", "hawt_msgs/ControllerSwitch")
"""Types (``pkg/Type``) with a ``step`` field that are records of a step, not samples of it."""
_LISTED = 5
"""Steps or ranges named on a line before the rest are only counted."""


def _listed(items: list[str]) -> str:
    shown = ", ".join(items[:_LISTED])
    return shown if len(items) <= _LISTED else f"{shown}, … ({len(items)} in all)"


def _ranges_text(ranges: tuple[tuple[int, int], ...]) -> str:
    return _listed([f"{first}-{last}" if last > first else str(first) for first, last in ranges])


@dataclass(frozen=True)
class TopicCheck:
    """One stepped topic: its steps, whether it must hold every step from its first to its last, and the publishers
    of its messages at the steps held twice with different content (none if the bag does not name them)."""

    coverage: StepCoverage
    contiguous: bool
    conflict_publishers: tuple[str, ...] = ()

    def _sent_by(self) -> str:
        return f" (sent by {', '.join(self.conflict_publishers)})" if self.conflict_publishers else ""

    @property
    def problems(self) -> tuple[str, ...]:
        """``GAP — …`` (a contiguous topic only) and ``DUPLICATE — …``; empty if the topic is fine."""
        found = []
        if self.contiguous and self.coverage.gaps:
            found.append(f"GAP — {self.coverage.gap_text()}")
        conflicts = self.coverage.conflicts
        if conflicts:
            found.append(f"DUPLICATE — {self.coverage.topic} holds {len(conflicts)} step"
                         f"{'s' if len(conflicts) > 1 else ''} twice with different content, the first step "
                         f"{conflicts[0]}{self._sent_by()}")
        return tuple(found)

    def text(self) -> str:
        """One line: count, steps, gaps (their first missing steps) or windows, repeated steps."""
        coverage = self.coverage
        line = f"{coverage.topic}: {coverage.count} messages"
        if coverage.ranges and self.contiguous:
            line += f", steps {coverage.first}-{coverage.last}, "
            line += (f"GAP: misses {coverage.missing_text()}, first missing "
                     f"{_listed([str(first) for first, _ in coverage.gaps])}" if coverage.gaps else "no gap")
        elif coverage.ranges:
            line += f", steps {_ranges_text(coverage.ranges)}" + (" (windows allowed)" if coverage.gaps else "")
        if coverage.resent:
            line += f", {coverage.resent} resent"
        if coverage.conflicts:
            line += (f", DUPLICATE with different content: steps {_listed([str(s) for s in coverage.conflicts])}"
                     + self._sent_by())
        return line

    def as_dict(self) -> dict:
        """The facts of the line for ``--json``."""
        coverage = self.coverage
        return {"topic": coverage.topic, "count": coverage.count, "first_step": coverage.first,
                "last_step": coverage.last, "contiguous": self.contiguous, "ranges": [list(r) for r in coverage.ranges],
                "gaps": [{"first_missing": first, "last_missing": last} for first, last in coverage.gaps],
                "missing": coverage.missing, "resent": coverage.resent, "conflicts": list(coverage.conflicts),
                "conflict_publishers": list(self.conflict_publishers), "problems": list(self.problems)}


@dataclass(frozen=True)
class Verification:
    """What ``hawt bag verify`` found in one bag.

    Attributes
    ----------
    path : pathlib.Path
    topics : tuple of TopicCheck
        Every stepped topic, by name (none if the file is unfinished).
    file_problems : tuple of str
        ``UNFINISHED — …`` or ``NO SUMMARY — …``, pointing to ``hawt bag recover``.
    """

    path: Path
    topics: tuple[TopicCheck, ...]
    file_problems: tuple[str, ...] = ()

    @property
    def problems(self) -> tuple[str, ...]:
        """Everything that fails the bag, file first, one line each."""
        return self.file_problems + tuple(problem for topic in self.topics for problem in topic.problems)

    @property
    def ok(self) -> bool:
        """No problem: ``hawt bag verify`` exits 0."""
        return not self.problems

    def verdict(self) -> str:
        """``verify: OK — 10 topics, no gap`` or ``verify: GAP — /wt1/plant/state misses …`` (problems: ``; ``)."""
        if not self.ok:
            return f"verify: {'; '.join(self.problems)}"
        resent = sum(topic.coverage.resent for topic in self.topics)
        return f"verify: OK — {len(self.topics)} topics, no gap" + (
            f", {resent} resent (a step the lockstep plant sent again, identical; analysed once)" if resent else "")

    def text(self) -> str:
        """One line per stepped topic, then the verdict."""
        return "\n".join([topic.text() for topic in self.topics] + [self.verdict()])

    def as_dict(self) -> dict:
        """The same facts for ``--json``."""
        return {"file": str(self.path), "ok": self.ok, "verdict": self.verdict(), "problems": list(self.problems),
                "topics": [topic.as_dict() for topic in self.topics]}


def stepped_topics(reader: BagReader) -> list[str]:
    """The bag's topics whose ``ros2msg`` type has a ``step`` field and is not one of `RECORDS`, sorted."""
    found = set()
    for channel in reader.summary.channels.values():
        schema = reader.summary.schemas.get(channel.schema_id)
        if schema is None or schema.encoding != "ros2msg" or short_type_name(schema.name) in RECORDS:
            continue
        fields = parse_schema(schema.data.decode(), schema.name)[short_type_name(schema.name)].fields
        if any(f.name == "step" for f in fields):
            found.add(channel.topic)
    return sorted(found)


def _equal_rows(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row i of ``a`` equals row i of ``b`` (NaN equal to NaN); rows of object arrays are 1-D arrays."""
    if a.dtype == object:
        return np.array([x.shape == y.shape and bool(np.all((x == y) | ((x != x) & (y != y)))) for x, y in zip(a, b)],
                        dtype=bool)
    same = (a == b) | ((a != a) & (b != b))
    return same.all(axis=tuple(range(1, same.ndim)))


def _differs(columns: TopicColumns) -> np.ndarray:
    """Whether each message differs in any decoded field from the first message of its step."""
    _, first, inverse = np.unique(columns.fields["step"], return_index=True, return_inverse=True)
    reference = first[inverse]
    differs = np.zeros(len(columns), dtype=bool)
    for values in columns.fields.values():
        differs |= ~_equal_rows(values, values[reference])
    return differs


def verify_bag(path: os.PathLike) -> Verification:
    """Check a bag for lost and repeated steps in every stepped topic, and for a finished file.

    Parameters
    ----------
    path : path-like

    Returns
    -------
    Verification
        Not `ok` if a contiguous topic has a gap, a step was recorded twice with
        different content, or the file is unfinished or has no summary statistics.

    Raises
    ------
    BagError
        If the file is missing, not MCAP, or a chunk cannot be read (naming the file).
    """
    path = Path(path)
    try:
        reader = BagReader(path)
    except UnfinishedBagError as error:
        return Verification(path, (), (f"UNFINISHED — {error}",))
    with reader:
        names = stepped_topics(reader)
        coverages = {topic: step_coverage(topic, columns.fields.get("step", np.zeros(0, np.int64)))
                     for topic, columns in read_topics_columns(reader, names, ("step",)).items()}
        repeated = [topic for topic, coverage in coverages.items() if coverage.resent]
        senders = {}
        for topic, columns in read_topics_columns(reader, repeated).items():
            coverages[topic] = step_coverage(topic, columns.fields["step"], _differs(columns))
            conflicting = np.isin(columns.fields["step"], coverages[topic].conflicts)
            senders[topic] = tuple(name for name in np.unique(columns.publisher[conflicting]).tolist() if name)
        topics = tuple(TopicCheck(coverages[topic], any(topic.endswith(f"/{relative}") for relative in CONTIGUOUS),
                                  senders.get(topic, ())) for topic in names)
        summary = () if reader.has_summary else (
            f"NO SUMMARY — {path} has no summary section with statistics; 'hawt bag recover {path}' writes a "
            "complete copy",)
        return Verification(path, topics, summary)
