"""Specification of hawt_plant.safety_system: command checks, step order and the latched safety chain."""
import math

import numpy as np
import pytest

from hawt_plant.safety_system import (FEATHERED_TORQUE, CommandOrder, SafetySettings, SafetySystem,
                                      command_rejection)

SETTINGS = SafetySettings(command_timeout=1.0, startup_timeout=30.0, feather_angle=math.pi / 2,
                          feather_rate=math.radians(8.0))
DT = 0.01


def _tripped(pitch=(0.25, 0.25, 0.25)) -> SafetySystem:
    safety = SafetySystem(SETTINGS)
    safety.trip("test", np.array(pitch))
    return safety


@pytest.mark.parametrize("pitch, torque, start_of_reason", [
    ([math.nan, 0.2, 0.2], 4e4, "not finite: pitch [nan"),
    ([0.2, 0.2, 0.2], math.inf, "not finite: pitch [0.2, 0.2, 0.2], generator_torque inf"),
    ([0.2, 0.2], 4e4, "pitch: expected 3 values, found 2"),
    ([0.2, 2.0, 0.2], 4e4, "pitch [0.2, 2.0, 0.2] outside [0.0, 1.5707"),
    ([0.2, 0.2, 0.2], -1.0, "generator_torque -1.0 outside [0, 47402.91] N*m"),
])
def test_a_command_that_cannot_be_applied_is_refused_with_its_reason(pitch, torque, start_of_reason):
    """NaN, infinity, wrong length, pitch or torque out of range: the reason names the field and the value."""
    reason = command_rejection(pitch, torque, 3, 0.0, math.pi / 2, 47402.91)
    assert reason is not None and reason.startswith(start_of_reason)


def test_a_command_within_every_limit_is_accepted():
    """Finite, B values, pitch at both actuator limits, torque at 0 and at its maximum: no reason."""
    assert command_rejection([0.0, math.pi / 2, 0.3], 0.0, 3, 0.0, math.pi / 2, 47402.91) is None
    assert command_rejection([0.1, 0.1, 0.1], 47402.91, 3, 0.0, math.pi / 2, 47402.91) is None


def test_commands_are_applied_in_step_order_once_each():
    """New steps apply, the same step again is a repeat, an older step is stale; the last applied step is kept."""
    order = CommandOrder(burst_gap=1.0)
    assert [order.admit(step, 10, 0.0) for step in (3, 5, 5, 4, 6)] == [
        CommandOrder.APPLY, CommandOrder.APPLY, CommandOrder.REPEAT, CommandOrder.STALE, CommandOrder.APPLY]
    assert order.last_applied == 6


def test_a_command_for_a_step_the_plant_has_not_sent_is_refused_and_changes_nothing():
    """Step 11 while the plant is at step 10: FUTURE, and step 7 still applies afterwards."""
    order = CommandOrder(burst_gap=1.0)
    assert order.admit(11, 10, 0.0) == CommandOrder.FUTURE
    assert order.last_applied is None
    assert order.admit(7, 10, 0.0) == CommandOrder.APPLY


def test_stale_commands_open_a_new_burst_only_after_a_quiet_gap():
    """Stale at t = 0, 0.5, 1.4 s are one burst (gap 1 s); stale at 2.4 s opens the next one."""
    order = CommandOrder(burst_gap=1.0)
    order.admit(100, 100, 0.0)
    firsts = []
    for now in (0.0, 0.5, 1.4, 2.4, 2.5):
        assert order.admit(50, 100, now) == CommandOrder.STALE
        firsts.append(order.new_burst)
    assert firsts == [True, False, False, True, False]


def test_the_watchdog_waits_startup_timeout_for_the_first_command_then_command_timeout():
    """Started at t=0: no trip at 29.9 s, a trip at 30 s naming startup_timeout; after a command, 1 s is the limit."""
    waiting = SafetySystem(SETTINGS)
    waiting.start(0.0)
    assert waiting.watch(29.9, np.zeros(3), "the first command") is None
    assert waiting.watch(30.0, np.zeros(3), "the first command") == "the first command missing for startup_timeout 30 s"
    running = SafetySystem(SETTINGS)
    running.start(0.0)
    running.command_applied(5.0)
    assert running.watch(5.99, np.zeros(3), "step 7") is None
    assert running.watch(6.0, np.zeros(3), "step 7") == "step 7 missing for command_timeout 1 s"
    assert running.tripped


def test_the_watchdog_does_nothing_before_it_is_started():
    """Without start() (no measurement sent yet) no amount of time trips it."""
    safety = SafetySystem(SETTINGS)
    assert safety.watch(1e6, np.zeros(3), "anything") is None
    assert not safety.tripped


def test_a_trip_is_reported_once_and_latches_whatever_commands_follow():
    """The reason comes back once; later commands do not reset it; the first returning command is noted once."""
    safety = SafetySystem(SETTINGS)
    safety.start(0.0)
    safety.command_applied(0.0)
    assert safety.watch(2.0, np.zeros(3), "step 1") is not None
    assert safety.watch(3.0, np.zeros(3), "step 1") is None
    safety.command_applied(3.0)
    assert safety.tripped and safety.reason == "step 1 missing for command_timeout 1 s"
    assert [safety.command_returned() for _ in range(3)] == [True, False, False]


def test_no_command_is_noted_as_returned_before_a_trip():
    """command_returned is False while untripped, and does not use up the report of a later trip."""
    safety = SafetySystem(SETTINGS)
    assert not safety.command_returned()
    safety.trip("test", np.zeros(3))
    assert safety.command_returned()


def test_after_a_trip_every_blade_ramps_from_its_measured_pitch_to_feather_at_the_rate_limit():
    """Each step adds feather_rate*dt to every blade until feather, which it then holds; the torque is 0."""
    safety = _tripped(pitch=(0.25, 0.30, 1.5))
    commands = np.array([safety.feather(DT)[0] for _ in range(1000)])
    expected = np.minimum(np.array([0.25, 0.30, 1.5]) + np.arange(1, 1001)[:, None] * SETTINGS.feather_rate * DT,
                          math.pi / 2)
    np.testing.assert_allclose(commands, expected, rtol=0, atol=1e-12)
    assert np.all(commands[-1] == math.pi / 2)
    assert safety.feather(DT)[1] == FEATHERED_TORQUE == 0.0


def test_feathering_before_a_trip_is_an_error():
    """feather() of an untripped safety system raises, naming why."""
    with pytest.raises(RuntimeError, match="has not tripped"):
        SafetySystem(SETTINGS).feather(DT)


@pytest.mark.parametrize("field", ["command_timeout", "startup_timeout", "feather_rate"])
def test_settings_refuse_a_timeout_or_rate_that_is_not_positive(field):
    """Zero for a timeout or the rate: ValueError naming the field."""
    values = dict(command_timeout=1.0, startup_timeout=30.0, feather_angle=1.5, feather_rate=0.14)
    with pytest.raises(ValueError, match=field):
        SafetySettings(**{**values, field: 0.0})
