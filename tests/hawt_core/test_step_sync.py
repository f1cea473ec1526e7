"""Lockstep step matching: a step fires once when complete; repeats are answered again, older steps dropped."""
from types import SimpleNamespace

from hawt_core.step_sync import StepAnswer, StepJoin


def test_a_step_fires_once_when_its_last_required_input_arrives():
    """Inputs of step 3 fire after both arrive, once; a repeat of an input does not fire again."""
    join = StepJoin(("loads", "collective"))
    assert join.add("loads", 3, "L3") is None
    assert join.add("collective", 3, "C3") == {"loads": "L3", "collective": "C3"}
    assert join.add("loads", 3, "L3 again") is None


def test_a_newer_step_discards_the_inputs_of_an_unfinished_one_and_older_inputs_are_ignored():
    """Step 5 starts afresh; an input of step 4 arriving late is ignored."""
    join = StepJoin(("a", "b"))
    join.add("a", 4, "a4")
    assert join.add("b", 5, "b5") is None
    assert join.add("b", 4, "b4") is None
    assert join.add("a", 5, "a5") == {"a": "a5", "b": "b5"}


def test_a_repeated_step_is_answered_again_and_an_older_one_dropped():
    """After answering step 7: step 7 again republishes that answer, step 6 is dropped, step 8 is new."""
    sent = []
    answer = StepAnswer(sent.append)
    assert not answer.handled(7)
    answer.send(SimpleNamespace(step=7))
    assert answer.handled(7) and sent[-1].step == 7 and len(sent) == 2
    assert answer.handled(6) and len(sent) == 2
    assert not answer.handled(8)
