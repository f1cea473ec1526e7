"""Matching the inputs of one plant step, and answering a repeated step without acting twice.

In lockstep (DESIGN.md §6) the plant sends step k and waits for the command of
step k; each controller waits until every input it needs for step k is there.
The plant re-sends step k if no command comes (discovery races, a restarted
node), so a controller that already answered step k answers again with the same
message and does not advance its state.
"""
from typing import Any, Callable, Dict, Iterable, Optional

__all__ = ["StepAnswer", "StepJoin", "StepVerdict", "classify_step", "RESEND_PERIOD"]

RESEND_PERIOD = 0.5
"""Wall time [s] after which an unanswered step is sent again (the lockstep plant, step replay): a message
that reached a node before its executor watched the subscription is only taken with the next one."""


class StepVerdict:
    NEW = "new"
    REPEAT = "repeat"
    OLD = "old"


def classify_step(step: int, last_answered: Optional[int]) -> str:
    """NEW for a step after the last one answered, REPEAT for that step again, OLD for an earlier one."""
    if last_answered is None or step > last_answered:
        return StepVerdict.NEW
    return StepVerdict.REPEAT if step == last_answered else StepVerdict.OLD


class StepJoin:
    """Collects the latest message of each required input for the newest step.

    ``add`` returns the complete set of inputs once, when the last required input
    of a step arrives; inputs of an older step than the one being collected are
    ignored (returned as None).
    """

    def __init__(self, required: Iterable[str]) -> None:
        self.required = frozenset(required)
        self.step: Optional[int] = None
        self.inputs: Dict[str, Any] = {}
        self._fired = False

    def set_required(self, required: Iterable[str]) -> Optional[Dict[str, Any]]:
        """Change the inputs a step needs; the step's inputs if that completes it (once, as ``add``)."""
        self.required = frozenset(required)
        if self.step is not None and not self._fired and self.required <= self.inputs.keys():
            self._fired = True
            return dict(self.inputs)
        return None

    def add(self, name: str, step: int, message: Any) -> Optional[Dict[str, Any]]:
        """Add one input; the inputs of ``step`` when it is complete for the first time, else None."""
        if self.step is not None and step < self.step:
            return None
        if self.step is None or step > self.step:
            self.step, self.inputs, self._fired = step, {}, False
        self.inputs[name] = message
        if not self._fired and self.required <= self.inputs.keys():
            self._fired = True
            return dict(self.inputs)
        return None


class StepAnswer:
    """A node's last answer, so that a step that is not new is answered again or dropped, never recomputed."""

    def __init__(self, publish: Callable[[Any], None]) -> None:
        self.publish = publish
        self.last: Any = None
        self.published = False

    def handled(self, step: int) -> bool:
        """True if ``step`` is not new: a repeat of the last answered step is answered again, an older one dropped."""
        verdict = classify_step(step, None if self.last is None else self.last.step)
        if verdict == StepVerdict.REPEAT and self.published:
            self.publish(self.last)
        return verdict != StepVerdict.NEW

    def send(self, message: Any, publish: bool = True) -> None:
        """Keep the answer of a new step and publish it (``publish`` False: a step handled in silence)."""
        self.last, self.published = message, publish
        if publish:
            self.publish(message)
