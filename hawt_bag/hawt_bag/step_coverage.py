"""Which plant steps a topic holds: its runs of consecutive steps, the gaps between them, repeated steps.

Every message derived from plant step k carries ``step = k`` (DESIGN §3), so the
``step`` column of a topic tells what a recording lost. Used by ``hawt bag verify``
(`verification`) and by ``hawt analyze`` (`plant_run`), so both name a gap alike.
"""
from dataclasses import dataclass
from typing import Optional

import numpy as np

__all__ = ["StepCoverage", "step_coverage", "step_ranges"]


def step_ranges(steps: np.ndarray) -> tuple[tuple[int, int], ...]:
    """Runs of consecutive steps, first and last step of each (inclusive), in step order.

    Parameters
    ----------
    steps : numpy.ndarray of int, shape (n,)
        Any order; repeats count once.

    Examples
    --------
    >>> step_ranges(np.array([5, 0, 1, 2, 2, 6]))
    ((0, 2), (5, 6))
    """
    unique = np.unique(np.asarray(steps, dtype=np.int64))
    if not unique.size:
        return ()
    breaks = np.flatnonzero(np.diff(unique) != 1)
    firsts = np.concatenate((unique[:1], unique[breaks + 1]))
    lasts = np.concatenate((unique[breaks], unique[-1:]))
    return tuple(zip(firsts.tolist(), lasts.tolist()))


def _plural(count: int, word: str) -> str:
    return f"{count} {word}" if count == 1 else f"{count} {word}s"


@dataclass(frozen=True)
class StepCoverage:
    """The steps of one topic.

    Attributes
    ----------
    topic : str
    count : int
        Messages, repeats included.
    ranges : tuple of (int, int)
        Runs of consecutive steps, ``(first, last)`` inclusive, in step order.
    resent : int
        Messages that repeat an earlier message of their step field for field
        (a lockstep plant resending a step nobody answered yet).
    conflicts : tuple of int
        Steps sent more than once with different content.
    """

    topic: str
    count: int
    ranges: tuple[tuple[int, int], ...]
    resent: int = 0
    conflicts: tuple[int, ...] = ()

    @property
    def first(self) -> int:
        """First step (-1 for an empty topic)."""
        return self.ranges[0][0] if self.ranges else -1

    @property
    def last(self) -> int:
        """Last step (-1 for an empty topic)."""
        return self.ranges[-1][1] if self.ranges else -1

    @property
    def gaps(self) -> tuple[tuple[int, int], ...]:
        """Steps missing between `first` and `last`: ``(first missing, last missing)`` of each gap."""
        return tuple((before[1] + 1, after[0] - 1) for before, after in zip(self.ranges, self.ranges[1:]))

    @property
    def missing(self) -> int:
        """Number of steps missing between `first` and `last`."""
        return sum(last - first + 1 for first, last in self.gaps)

    def missing_text(self) -> str:
        """``"214 steps in 3 gaps"``."""
        return f"{_plural(self.missing, 'step')} in {_plural(len(self.gaps), 'gap')}"

    def gap_text(self) -> str:
        """``"/wt1/plant/state misses 214 steps in 3 gaps, the first after step 1507"`` ("" without gap)."""
        if not self.gaps:
            return ""
        return f"{self.topic} misses {self.missing_text()}, the first after step {self.ranges[0][1]}"


def step_coverage(topic: str, steps: np.ndarray, differs: Optional[np.ndarray] = None) -> StepCoverage:
    """The coverage of one topic from its ``step`` column.

    Parameters
    ----------
    topic : str
    steps : numpy.ndarray of int, shape (n,)
        The ``step`` of each message, in the order recorded.
    differs : numpy.ndarray of bool, shape (n,), optional
        Whether each message differs from the first message of its step (False for the
        first). Repeats of a step count as resent where False, as conflicts where True;
        all as resent if None.

    Returns
    -------
    StepCoverage
    """
    steps = np.asarray(steps, dtype=np.int64)
    unique, first = np.unique(steps, return_index=True)
    repeated = np.ones(steps.size, dtype=bool)
    repeated[first] = False
    conflicting = repeated & differs if differs is not None else np.zeros_like(repeated)
    return StepCoverage(topic, int(steps.size), step_ranges(unique), int(np.count_nonzero(repeated & ~conflicting)),
                        tuple(np.unique(steps[conflicting]).tolist()))
