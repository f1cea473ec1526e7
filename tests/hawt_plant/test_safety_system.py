"""Specification of hawt_plant.safety_system: command checks, step order and the latched safety chain."""
import math
from types import SimpleNamespace

import numpy as np
import pytest

from hawt_plant.safety_system import (FEATHERED_TORQUE, WARNING_RELEASE, CommandOrder, Protection,
                                      SafetySettings, SafetySystem, command_rejection, protection_event)
from hawt_plant.turbine import ProtectionLimits, nrel_5mw

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


def test_no_command_is_noted_as_returned_before_the_watchdog_expires():
    """command_returned is False while the watchdog has not expired, a protection trip included (the plant still
    steps on its controllers' answers then), and does not use up the report of a later expiry."""
    safety = SafetySystem(SETTINGS)
    safety.start(0.0)
    assert not safety.command_returned()
    safety.trip("test", np.zeros(3))
    assert not safety.command_returned()
    assert safety.watch(31.0, np.zeros(3), "step 1") == "step 1 missing for startup_timeout 30 s"
    assert safety.reason == "test" and safety.expired
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


LIMITS = ProtectionLimits(rotor_speed_warning=1.4, rotor_speed_trip=1.5, generator_speed_warning=140.0,
                          generator_speed_trip=150.0, tower_top_acceleration_trip=2.5,
                          pitch_asymmetry_trip=math.radians(20.0), pitch_rate_trip=math.radians(8.8))
NORMAL = dict(rotor_speed=1.2, generator_speed=120.0, tower_top_fa_accel=0.3, tower_top_ss_accel=0.1,
              pitch=np.array([0.2, 0.21, 0.19]))
"""One step's measurements well inside every level of LIMITS."""


def _findings(**changed):
    """What a fresh protection finds on NORMAL's measurements with ``changed`` replacing some."""
    found = Protection(LIMITS, DT).check(**{**NORMAL, **changed})
    return [(f.trip, f.reason) for f in found]


def test_measurements_inside_every_level_find_nothing():
    """Speeds below their warnings, a small acceleration, spread and rate: no finding."""
    protection = Protection(LIMITS, DT)
    assert protection.check(**NORMAL) == []
    assert protection.check(**{**NORMAL, "pitch": NORMAL["pitch"] + math.radians(8.0) * DT}) == []


@pytest.mark.parametrize("changed, reason", [
    (dict(rotor_speed=1.51), "rotor overspeed: 1.51 rad/s above the trip level 1.5 rad/s"),
    (dict(generator_speed=150.5), "generator overspeed: 150.5 rad/s above the trip level 150 rad/s"),
    (dict(tower_top_fa_accel=2.0, tower_top_ss_accel=1.6), "tower-top acceleration 2.561 m/s^2 above the trip level"),
    (dict(pitch=np.array([0.0, 0.0, math.radians(20.5)])), "pitch asymmetry 20.5 deg above the trip level 20 deg"),
    (dict(rotor_speed=math.nan), "measurement not finite: rotor speed nan"),
])
def test_each_level_exceeded_is_a_trip_naming_the_cause_and_the_value(changed, reason):
    """Overspeed of either shaft, the combined tower-top acceleration, the spread of the pitch angles, and a
    measurement that is not finite: one trip finding, its reason naming what and how much."""
    ((trip, text),) = _findings(**changed)
    assert trip and text.startswith(reason), text


def test_a_blade_moving_faster_than_its_rate_level_trips():
    """9 deg/s between two steps against a level of 8.8 deg/s: a trip; the first step has no rate to judge."""
    protection = Protection(LIMITS, DT)
    assert protection.check(**NORMAL) == []
    moved = NORMAL["pitch"] + np.array([0.0, math.radians(9.0) * DT, 0.0])
    ((finding,),) = [protection.check(**{**NORMAL, "pitch": moved})]
    assert finding.trip and finding.reason.startswith("pitch rate 9 deg/s above the trip level 8.8 deg/s")


def test_an_overspeed_warning_comes_once_per_excursion():
    """Above the warning level for three steps: one warning; below WARNING_RELEASE of it, then above again: a second
    one; just below the warning level in between does not re-arm it."""
    protection = Protection(LIMITS, DT)
    speeds = [1.41, 1.42, 1.41, 1.39, 1.41, WARNING_RELEASE * 1.4 - 0.01, 1.45]
    warnings = [[f.reason for f in protection.check(**{**NORMAL, "rotor_speed": w})] for w in speeds]
    assert [len(w) for w in warnings] == [1, 0, 0, 0, 0, 0, 1]
    assert warnings[0][0] == "rotor overspeed warning: 1.41 rad/s above 1.4 rad/s (trip at 1.5 rad/s)"


def test_the_grid_monitor_trips_when_the_generator_is_off_the_network():
    """A lost grid (the converter's monitor) is a trip however normal the other measurements are."""
    assert _findings(grid_connected=False) == [(True, "grid loss: the generator is off the network")]
    assert _findings(grid_connected=True) == []


def test_the_safety_system_trips_on_the_protections_trip_and_then_finds_nothing_more():
    """protect() trips the system with the finding's reason; later steps, whatever they measure, find nothing; the
    trip's event is an ERROR protection_trip saying what the trip does."""
    safety = SafetySystem(SETTINGS, Protection(LIMITS, DT))
    assert safety.protect(SimpleNamespace(**NORMAL)) == []
    (finding,) = safety.protect(SimpleNamespace(**{**NORMAL, "rotor_speed": 1.6}))
    assert safety.tripped and safety.reason == finding.reason and not safety.expired
    assert safety.protect(SimpleNamespace(**{**NORMAL, "rotor_speed": 3.0})) == []
    level, kind, detail = protection_event(finding, safety)
    assert (level, kind) == (40, "protection_trip")
    assert detail.endswith("feathering to 1.5708 rad at 0.139626 rad/s with generator torque 0; latched until the "
                           "plant restarts")


def test_the_packaged_turbine_trips_below_1_2_times_rated_speed():
    """The NREL 5 MW has no protection section: its levels are the defaults from its ratings, warning at 1.12 and trip
    at 1.18 x rated (12.1 rpm, HSS x 97), 2.5 m/s^2, 20 deg of spread, 1.1 x the 8 deg/s actuator."""
    turbine = nrel_5mw()
    rated = turbine.schedule.rated_rotor_speed
    limits = turbine.protection
    assert limits.rotor_speed_trip / rated == pytest.approx(1.18) and limits.rotor_speed_warning / rated == \
        pytest.approx(1.12)
    assert limits.generator_speed_trip == pytest.approx(1.18 * rated * 97.0)
    assert (limits.tower_top_acceleration_trip, math.degrees(limits.pitch_asymmetry_trip),
            math.degrees(limits.pitch_rate_trip)) == pytest.approx((2.5, 20.0, 8.8))
