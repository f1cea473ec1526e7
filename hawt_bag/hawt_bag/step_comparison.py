"""Two recordings of one run, step by step: which fields of which topics differ at any step.

A lockstep run is deterministic, so its recording on a busy machine, from the in-process
engine or with a rogue publisher refused must equal a reference in every field of every
step; a resent step is one row. The header is not compared: ``step`` identifies the row.
"""
import os
from typing import Sequence

import numpy as np

from .reader import BagReader
from .step_coverage import step_ranges
from .topic_columns import read_topics_columns

__all__ = ["rows_by_step", "step_differences"]


def rows_by_step(path: os.PathLike, topics: Sequence[str]) -> dict[str, dict[str, np.ndarray]]:
    """Per topic, every decoded field but the header, one row per step in step order (a resent step's first)."""
    with BagReader(path) as reader:
        columns = read_topics_columns(reader, topics)
    rows = {}
    for topic in topics:
        fields = columns[topic].fields
        if "step" not in fields:  # no message
            rows[topic] = {}
            continue
        _, first = np.unique(np.asarray(fields["step"]), return_index=True)
        rows[topic] = {name: np.asarray(values)[first] for name, values in fields.items()
                       if not name.startswith("header.")}
    return rows


def _equal(a: np.ndarray, b: np.ndarray) -> bool:
    if a.shape != b.shape:
        return False
    if a.dtype == object:
        return all(np.array_equal(x, y, equal_nan=True) for x, y in zip(a, b))
    return bool(np.array_equal(a, b, equal_nan=a.dtype.kind == "f"))


def step_differences(first: os.PathLike, second: os.PathLike, topics: Sequence[str],
                     second_topics: Sequence[str] = ()) -> list[str]:
    """What differs between two recordings: ``"TOPIC steps 0-11999 != 0-11998"`` when the steps held differ, and
    ``"TOPIC FIELD"`` for every field that differs at any step both hold.

    ``second_topics`` names the same topics in ``second`` when its namespace differs (default: ``topics``).
    """
    second_topics = list(second_topics) or list(topics)
    rows_a, rows_b = rows_by_step(first, topics), rows_by_step(second, second_topics)
    found = []
    for topic, other in zip(topics, second_topics):
        a, b = rows_a[topic], rows_b[other]
        steps_a, steps_b = a.get("step", np.empty(0, np.uint64)), b.get("step", np.empty(0, np.uint64))
        if not np.array_equal(steps_a, steps_b):
            found.append(f"{topic} steps {_ranges(steps_a)} != {_ranges(steps_b)}")
        _, in_a, in_b = np.intersect1d(steps_a, steps_b, return_indices=True)
        found += [f"{topic} {name}" for name, values in a.items()
                  if not _equal(values[in_a], b[name][in_b] if name in b else np.empty(0))]
    return found


def _ranges(steps: np.ndarray) -> str:
    return ", ".join(f"{first}-{last}" if last > first else f"{first}" for first, last in step_ranges(steps)) or "none"
