"""The plant's own protections: which commands it applies, and the safety chain that feathers without them.

A turbine does not trust its controller blindly. Three guards sit between
``control/pitch_command`` and the actuators, in the order the plant node applies them:

1. :func:`command_rejection` refuses a command that cannot be applied at all (wrong
   number of blades, not finite, outside the actuator's angle or the generator's
   torque range).
2. :class:`CommandOrder` (realtime) applies a command only if its step is newer than
   the last applied one and not ahead of the plant.
3. :class:`SafetySystem` is the safety chain: when no command is applied for too long
   (its watchdog), or when :class:`Protection` finds the turbine beyond a limit of its
   definition (overspeed, tower-top acceleration, pitch asymmetry or rate), it trips,
   latches, and pitches every blade to feather at the actuator's rate limit with the
   generator torque off, whatever arrives afterwards.

The protection looks at the plant's own measurements after every step, in every engine,
and no controller or parameter can switch it off: it is the part IEC 61400-1 (§8.3)
requires to be independent of the control system.

No ROS here: times are plain seconds passed in by the caller.
"""
from __future__ import annotations

import math
import operator
from dataclasses import dataclass
from typing import Any, Optional

import numpy as np

from hawt_core.step_sync import StepVerdict, classify_step
from hawt_plant.turbine import ProtectionLimits

__all__ = ["command_rejection", "CommandOrder", "Protection", "ProtectionFinding", "SafetySettings", "SafetySystem",
           "FEATHERED_TORQUE", "TRIP_EVENTS", "protection_event"]

FEATHERED_TORQUE = 0.0
"""Generator torque [N*m] commanded once the safety system has tripped."""

TRIP_EVENTS = ("protection_trip", "watchdog")
"""The kinds of the plant's events that say its safety system tripped and feathered the turbine: a run's loads are a
feathered turbine's from then on (a campaign case's ``trips``, ``hawt compare``'s warning)."""


def command_rejection(pitch: np.ndarray, generator_torque: float, blades: int, min_angle: float,
                      max_angle: float, max_torque: float) -> Optional[str]:
    """Why a pitch/torque command cannot be applied, or None if it can.

    Parameters
    ----------
    pitch : array_like, shape (B,)
        Commanded pitch per blade [rad].
    generator_torque : float
        Commanded generator torque [N*m].
    blades : int
        Number of blades B of the plant.
    min_angle, max_angle : float
        Pitch actuator limits [rad]; a command outside them by more than 1e-9 rad is refused.
    max_torque : float
        Largest generator torque [N*m]; the range is [0, max_torque].
    """
    values = np.asarray(pitch, dtype=float)
    if values.shape != (blades,):
        return f"pitch: expected {blades} values, found {values.size}"
    floats = values.tolist()  # B plain floats: numpy's per-call cost would be many times the checks
    if not (all(map(math.isfinite, floats)) and math.isfinite(generator_torque)):
        return f"not finite: pitch {floats}, generator_torque {generator_torque}"
    if min(floats) < min_angle - 1e-9 or max(floats) > max_angle + 1e-9:
        return f"pitch {floats} outside [{min_angle}, {max_angle}] rad"
    if not 0.0 <= generator_torque <= max_torque:
        return f"generator_torque {generator_torque} outside [0, {max_torque}] N*m"
    return None


class CommandOrder:
    """Realtime: the command of a step is applied once, in step order, and never ahead of the plant.

    The plant applies the latest command (zero-order hold, DESIGN.md §6), so a command
    whose step is older than the last applied one would move the blades back to an
    earlier decision: it is ignored (STALE). A repeat of the last applied step changes
    nothing (REPEAT). A command for a step the plant has not published yet cannot have
    been computed from its measurements: it is refused (FUTURE). Stale commands come in
    bursts (a delayed link delivering a backlog, a second publisher answering old
    steps); :attr:`new_burst` is True for the first of a burst, so it is reported once.

    Parameters
    ----------
    burst_gap : float
        A stale command after at least this long [s] without one opens a new burst.
    """

    APPLY = "apply"
    REPEAT = "repeat"
    STALE = "stale"
    FUTURE = "future"

    def __init__(self, burst_gap: float) -> None:
        if not burst_gap >= 0.0:
            raise ValueError(f"burst_gap: expected >= 0 s, found {burst_gap}")
        self.burst_gap = burst_gap
        self.last_applied: Optional[int] = None
        self.new_burst = False
        self._last_stale_at: Optional[float] = None

    def admit(self, step: int, plant_step: int, now: float) -> str:
        """The verdict on a command of ``step`` at time ``now`` [s] while the plant is at ``plant_step``.

        An APPLY verdict records ``step`` as the last applied one.
        """
        if step > plant_step:
            return self.FUTURE
        verdict = classify_step(step, self.last_applied)
        if verdict == StepVerdict.NEW:
            self.last_applied = step
            return self.APPLY
        if verdict == StepVerdict.REPEAT:
            return self.REPEAT
        self.new_burst = self._last_stale_at is None or now - self._last_stale_at >= self.burst_gap
        self._last_stale_at = now
        return self.STALE


@dataclass(frozen=True)
class ProtectionFinding:
    """What :meth:`Protection.check` found: a warning, or the trip (``trip`` True), with its reason."""

    trip: bool
    reason: str


WARNING_RELEASE = 0.9
"""A speed warning is given again only after the speed has fallen below this fraction of the warning level."""


class Protection:
    """The turbine's protection functions on its measurements of each step (IEC 61400-1 §8.3).

    Parameters
    ----------
    limits : ProtectionLimits
        The turbine's levels (its definition's ``protection`` section or the defaults).
    dt : float
        Plant step [s], for the pitch rate from two consecutive measured angles.

    Notes
    -----
    Per step, with Ω the rotor and Ω_g the generator speed, a_x, a_y the tower-top fore-aft and
    side-side accelerations and θ_i the measured pitch of blade i:

    - overspeed trip: Ω > Ω_trip or Ω_g > Ω_g,trip; warning once per excursion above Ω_warn or
      Ω_g,warn, again after the speed fell below :data:`WARNING_RELEASE` of it;
    - tower-top acceleration: √(a_x² + a_y²) > a_trip;
    - pitch asymmetry: max_i θ_i − min_i θ_i > Δθ_trip;
    - pitch rate: max_i |θ_i(k) − θ_i(k−1)| / Δt > θ̇_trip (the plant's actuator is rate-limited, so
      only a failed actuator reaches it);
    - grid loss: the generator is off the network (the converter's grid monitor, which a
      :mod:`hawt_plant.faults` ``grid_loss`` fails): the turbine cannot be loaded and is shut down at
      the first step that sees it.

    A measurement that is not finite is a trip as well: the protection cannot vouch for a turbine
    it cannot see. The first trip found is the one reported; :class:`SafetySystem` latches it.
    """

    def __init__(self, limits: ProtectionLimits, dt: float) -> None:
        if not dt > 0.0:
            raise ValueError(f"dt: expected > 0 s, found {dt}")
        self.limits = limits
        self.dt = dt
        self._previous_pitch: Optional[list] = None
        self._warned = {"rotor": False, "generator": False}

    def check(self, rotor_speed: float, generator_speed: float, tower_top_fa_accel: float,
              tower_top_ss_accel: float, pitch: np.ndarray, grid_connected: bool = True) -> list[ProtectionFinding]:
        """The warnings and the trip (at most one, last) of one step's measurements (SI units, pitch per blade,
        whether the generator is on the network)."""
        angles = np.asarray(pitch, dtype=float).tolist()  # B plain floats: cheaper than numpy for B = 3
        previous, self._previous_pitch = self._previous_pitch, angles
        limits, found = self.limits, []
        acceleration = math.hypot(tower_top_fa_accel, tower_top_ss_accel)
        values = (rotor_speed, generator_speed, acceleration, *angles)
        if not all(map(math.isfinite, values)):
            return [ProtectionFinding(True, f"measurement not finite: rotor speed {rotor_speed}, generator speed "
                                            f"{generator_speed}, tower-top acceleration {acceleration}, "
                                            f"pitch {angles}")]
        for shaft, speed, warning, trip in (
                ("rotor", rotor_speed, limits.rotor_speed_warning, limits.rotor_speed_trip),
                ("generator", generator_speed, limits.generator_speed_warning, limits.generator_speed_trip)):
            if speed > trip:
                return found + [ProtectionFinding(True, f"{shaft} overspeed: {speed:.5g} rad/s above the trip level "
                                                        f"{trip:.5g} rad/s")]
            if speed > warning and not self._warned[shaft]:
                self._warned[shaft] = True
                found.append(ProtectionFinding(False, f"{shaft} overspeed warning: {speed:.5g} rad/s above "
                                                      f"{warning:.5g} rad/s (trip at {trip:.5g} rad/s)"))
            elif speed < WARNING_RELEASE * warning:
                self._warned[shaft] = False
        if acceleration > limits.tower_top_acceleration_trip:
            return found + [ProtectionFinding(True, f"tower-top acceleration {acceleration:.4g} m/s^2 above the trip "
                                                    f"level {limits.tower_top_acceleration_trip:.4g} m/s^2")]
        spread = max(angles) - min(angles)
        if spread > limits.pitch_asymmetry_trip:
            return found + [ProtectionFinding(True, f"pitch asymmetry {math.degrees(spread):.3g} deg above the trip "
                                                    f"level {math.degrees(limits.pitch_asymmetry_trip):.3g} deg "
                                                    f"(pitch {[round(math.degrees(a), 2) for a in angles]} deg)")]
        if previous is not None:
            rate = max(map(abs, map(operator.sub, angles, previous))) / self.dt
            if rate > limits.pitch_rate_trip:
                return found + [ProtectionFinding(True, f"pitch rate {math.degrees(rate):.3g} deg/s above the trip "
                                                        f"level {math.degrees(limits.pitch_rate_trip):.3g} deg/s")]
        if not grid_connected:
            return found + [ProtectionFinding(True, "grid loss: the generator is off the network")]
        return found


@dataclass(frozen=True)
class SafetySettings:
    """When the safety chain trips and where it takes the blades.

    Attributes
    ----------
    command_timeout : float
        Longest wait [s] for the next applied command once one has been applied.
    startup_timeout : float
        Longest wait [s] for the first command after the watchdog started (controllers starting up).
    feather_angle : float
        Pitch the blades are driven to [rad] (the actuator's maximum angle).
    feather_rate : float
        Rate of the feather ramp [rad/s] (the actuator's rate limit).
    """

    command_timeout: float
    startup_timeout: float
    feather_angle: float
    feather_rate: float

    def __post_init__(self) -> None:
        for name in ("command_timeout", "startup_timeout", "feather_rate"):
            if not getattr(self, name) > 0.0:
                raise ValueError(f"{name}: expected > 0, found {getattr(self, name)}")
        if not math.isfinite(self.feather_angle):
            raise ValueError(f"feather_angle: expected a finite angle, found {self.feather_angle}")


class SafetySystem:
    """The plant's safety chain: a watchdog on the commands and the turbine's protection; once tripped, it feathers
    and stays tripped.

    Parameters
    ----------
    settings : SafetySettings
    protection : Protection, optional
        The protection functions :meth:`protect` runs on every step's measurements.

    Notes
    -----
    Watchdog: started at ``start(t0)``; the deadline is ``t0 + startup_timeout`` until
    the first ``command_applied(t)``, then ``t + command_timeout`` after every applied
    command. :meth:`watch` trips once the deadline has passed. :meth:`protect` trips on the
    first trip the protection finds.

    After the trip every blade's command ramps from its measured pitch θ_i at the trip
    to the feather angle at the actuator's rate limit, θ_c,i(k+1) = min(θ_c,i(k) +
    θ̇_max Δt, θ_feather), and the generator torque command is 0: an emergency stop
    (IEC 61400-1 DLC 5.1) opens the generator breaker and feathers on the pitch
    system's own supply, because the component that would ramp the torque down (the
    turbine controller and converter control, as in ROSCO's normal shutdown with
    ``SD_MaxTorqueRate``) is the one that was lost. The plant's generator model then
    takes the torque down at its own rate limit.

    The trip latches: commands that come back later are not applied, as a real safety
    chain stays open until it is reset on site; restarting the plant resets it here.
    """

    def __init__(self, settings: SafetySettings, protection: Optional[Protection] = None) -> None:
        self.settings = settings
        self.protection = protection
        self.reason: Optional[str] = None
        self.expired = False
        self._deadline: Optional[float] = None
        self._armed = False
        self._feather_command: Optional[np.ndarray] = None
        self._return_reported = False

    @property
    def tripped(self) -> bool:
        """True once the safety system has tripped (it stays tripped)."""
        return self.reason is not None

    def start(self, now: float) -> None:
        """Start the watchdog at ``now`` [s]: the first command is due within ``startup_timeout``."""
        if self._deadline is None:
            self._deadline = now + self.settings.startup_timeout

    def command_applied(self, now: float) -> None:
        """A command was applied at ``now`` [s]: the next one is due within ``command_timeout``."""
        self._armed = True
        self._deadline = now + self.settings.command_timeout

    def watch(self, now: float, pitch: np.ndarray, awaiting: str) -> Optional[str]:
        """Trip if the deadline has passed at ``now`` [s]; the reason the one time it expires, else None.

        The watchdog expires once, also after a protection trip: the commands a tripped plant still
        awaits in lockstep (it steps on them, feathering) have stopped coming too, and the caller then
        steps on its own (:attr:`expired`).

        Parameters
        ----------
        now : float
            [s], on the clock of ``start`` and ``command_applied``.
        pitch : array_like, shape (B,)
            Measured pitch [rad], where the feather ramp starts.
        awaiting : str
            What is missing, for the reason (e.g. "control/pitch_command of step 412").
        """
        if self.expired or self._deadline is None or now < self._deadline:
            return None
        self.expired = True
        timeout, name = ((self.settings.command_timeout, "command_timeout") if self._armed
                         else (self.settings.startup_timeout, "startup_timeout"))
        reason = f"{awaiting} missing for {name} {timeout:g} s"
        self.trip(reason, pitch)
        return reason

    def protect(self, output: Any, grid_connected: bool = True) -> list[ProtectionFinding]:
        """Run the protection on one step's measurements (:meth:`Protection.check`), tripping on a trip it finds;
        what it found, to be reported (nothing once tripped, or without a protection).

        ``output`` is the model's output of the step (:class:`hawt_plant.model.TurbineOutput`, or anything with its
        ``rotor_speed``, ``generator_speed``, ``tower_top_fa_accel``, ``tower_top_ss_accel`` and ``pitch``);
        ``grid_connected`` whether the generator was on the network over it
        (:meth:`hawt_plant.faults.PlantFaults.grid_connected`).
        """
        if self.tripped or self.protection is None:
            return []
        found = self.protection.check(output.rotor_speed, output.generator_speed, output.tower_top_fa_accel,
                                      output.tower_top_ss_accel, output.pitch, grid_connected)
        if found and found[-1].trip:
            self.trip(found[-1].reason, output.pitch)
        return found

    @property
    def consequence(self) -> str:
        """What a trip does, for its event."""
        return (f"safety system tripped, feathering to {self.settings.feather_angle:g} rad at "
                f"{self.settings.feather_rate:g} rad/s with generator torque 0; latched until the plant restarts")

    def trip(self, reason: str, pitch: np.ndarray) -> None:
        """Trip now for ``reason``, the feather ramp starting at the measured ``pitch`` [rad] (no-op if tripped)."""
        if self.tripped:
            return
        self.reason = reason
        self._feather_command = np.minimum(np.array(pitch, dtype=float), self.settings.feather_angle)

    def feather(self, dt: float) -> tuple[np.ndarray, float]:
        """The command over the next step of ``dt`` [s] after the trip: pitch [rad] per blade, generator torque [N*m]."""
        if not self.tripped:
            raise RuntimeError("feather: the safety system has not tripped")
        self._feather_command = np.minimum(self._feather_command + self.settings.feather_rate * dt,
                                           self.settings.feather_angle)
        return self._feather_command.copy(), FEATHERED_TORQUE

    def command_returned(self) -> bool:
        """Note a command arriving after the watchdog expired; True for the first one only (to report it once)."""
        first = self.expired and not self._return_reported
        self._return_reported = self._return_reported or self.expired
        return first


def protection_event(finding: ProtectionFinding, safety: SafetySystem) -> tuple[int, str, str]:
    """The ``control/events`` level, kind and detail of a protection finding (the same in every engine).

    Levels are ``hawt_msgs/ControlEvent``'s: WARN 30 for a warning, ERROR 40 for a trip.
    """
    if finding.trip:
        return 40, "protection_trip", f"{finding.reason}: {safety.consequence}"
    return 30, "protection_warning", finding.reason
