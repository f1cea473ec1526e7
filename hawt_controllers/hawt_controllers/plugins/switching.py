"""Controller switching at one plant step (DESIGN.md §6, ros2_control's switch semantics).

The controller manager checks a request against what it knows of the controllers
(:func:`plan_switch`) and publishes a :class:`Switch` for one future step. Every
node applies that switch when it handles that step, so a lockstep run switches at
the same step in any process layout (anchor_ros2.md §3.1: "all in one single
timestep of the controller manager's control loop").

Controllers claim command interfaces (DESIGN §4.1, hawt_core.command_interfaces);
one active claimant per interface. Who publishes the contribution of an interface
at step k, the rule the controllers follow and the loop assembler waits for
(:class:`InterfaceWindows`):

- an activated controller publishes from the switch step S on;
- a deactivated one goes on publishing its ramp to zero for ``ramp_steps`` steps
  (S ≤ k < S + R), then falls silent;
- when one controller replaces another on an interface in one switch, the
  outgoing one is silent from S and the incoming one starts from the outgoing
  one's last output (bumpless transfer, anchor_ros2.md §3.3), so exactly one
  controller publishes each interface at every step.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Callable, Dict, Iterable, List, Mapping, NamedTuple, Optional, Sequence, Tuple

from hawt_core.command_interfaces import COLLECTIVE_PITCH, GENERATOR_TORQUE
from hawt_core.node_role import NodeRole
from hawt_core.parameter_table import ParameterSpec

__all__ = [
    "MANAGER", "PARAMETERS", "ControllerInfo", "Switch", "SwitchRefused", "ScheduledSwitch", "InterfaceWindows",
    "plan_switch", "planned_states", "resolve_controller", "SwitchEffect", "switch_effect", "ramp_steps",
    "parse_schedule", "STATE_NAMES", "TRANSITIONS",
]

PARAMETERS = (
    ParameterSpec("ramp_time", 2.0, "default time over which an outgoing IPC contribution ramps out and an "
                  "incoming one ramps in", "s", minimum=0.0, maximum=600.0),
    ParameterSpec("lead_steps", 50, "an as-soon-as-possible switch takes effect this many steps after the newest "
                  "plant step seen", minimum=1, maximum=100000),
    ParameterSpec("schedule", [""], "switches given in steps, each 'STEP +NAME -NAME ...' (+ activates, - "
                  "deactivates), applied with STRICT checks and ramp_time; [''] = none", read_only=True),
)
"""The controller manager's parameters."""

MANAGER = NodeRole("manager", PARAMETERS)
"""The controller manager's role (the ``controller_manager`` node; entry point ``hawt.nodes: controller_manager``)."""

STATE_NAMES = {1: "unconfigured", 2: "inactive", 3: "active", 4: "finalized"}
"""lifecycle_msgs/State primary state ids -> labels."""

TRANSITIONS = ("configure", "cleanup", "activate", "deactivate", "shutdown")
"""The standard lifecycle transitions a shell may ask a controller for (``ros2 lifecycle set`` labels)."""


@dataclass(frozen=True)
class ControllerInfo:
    """What the controller manager knows of one controller.

    Attributes
    ----------
    name : str
        Fully qualified node name, e.g. ``/wt1/ipc_h1``.
    type : str
        The executable, e.g. ``ipc``.
    interfaces : tuple of str
        Command interfaces it claims, e.g. ``("harmonic/1",)``.
    state : str
        ``unconfigured``, ``inactive``, ``active`` or ``finalized``.
    switchable : bool
        False for a controller the manager must not switch off alone, only swap for another claimant of
        its interfaces (the collective ones).
    publishing_until : float
        Last step + 1 at which it still publishes (its ramp out); inf while active.
    """

    name: str
    type: str
    interfaces: Tuple[str, ...]
    state: str
    switchable: bool = True
    publishing_until: float = 0.0


@dataclass(frozen=True)
class Switch:
    """A switch effective at plant step ``step``: (name, claimed interfaces) pairs in and out, ramp time [s]."""

    step: int
    activate: Tuple[Tuple[str, Tuple[str, ...]], ...] = ()
    deactivate: Tuple[Tuple[str, Tuple[str, ...]], ...] = ()
    ramp_time: float = 0.0

    def replaced(self, interface: str) -> bool:
        """True if a controller claiming ``interface`` comes in while another claiming it goes out."""
        return any(interface in claims for _, claims in self.activate) \
            and any(interface in claims for _, claims in self.deactivate)

    def replaces(self, claims: Sequence[str]) -> bool:
        """True if any of ``claims`` is handed over from one controller to another in this switch."""
        return any(self.replaced(interface) for interface in claims)

    def publish_until(self, claims: Sequence[str], dt: float) -> int:
        """The step from which an outgoing controller that claims ``claims`` falls silent: the switch step if it hands
        any of them over (it then falls silent on all at once), else the end of its ramp out (SwitchRefused for a
        ramp time that is not finite and >= 0)."""
        end = self.step + ramp_steps(self.ramp_time, dt)
        return self.step if self.replaces(claims) else end

    def names(self) -> Tuple[str, ...]:
        """Every controller the switch names."""
        return tuple(name for name, _ in (*self.activate, *self.deactivate))


class SwitchRefused(ValueError):
    """A switch request that cannot be honoured; the message says which name and why."""


def ramp_steps(ramp_time: float, dt: float) -> int:
    """Steps R an output takes to ramp from 1 to 0 at rate 1/ramp_time with step dt: ceil(ramp_time/dt)."""
    if not (math.isfinite(ramp_time) and ramp_time >= 0.0):
        raise SwitchRefused(f"ramp_time: must be finite and >= 0, found {ramp_time}")
    return math.ceil(ramp_time / dt - 1e-9) if ramp_time > 0.0 else 0


class SwitchEffect(NamedTuple):
    """What a switch does to one controller it names, in every engine (bumpless transfer, anchor_ros2.md §3.3)."""

    active: bool
    """Activated (True) or deactivated."""
    ramp_time: float
    """The core's ramp in or out [s]: 0 when it hands over to, or takes over from, another claimant."""
    publish_until: float
    """The step from which it stops publishing: inf when activated; the switch step for one handing over, the end
    of its ramp otherwise."""
    replaced: bool
    """Whether its interfaces are handed over in this switch (an incoming one starts from the outgoing one's last
    output)."""


def switch_effect(switch: Switch, name: str, claims: Sequence[str], dt: float) -> Optional[SwitchEffect]:
    """What ``switch`` does to the controller ``name`` that claims ``claims`` (None if the switch does not name it)."""
    replaced = switch.replaces(claims)
    ramp_time = 0.0 if replaced else switch.ramp_time
    if name in dict(switch.activate):
        return SwitchEffect(True, ramp_time, math.inf, replaced)
    if name in dict(switch.deactivate):
        return SwitchEffect(False, ramp_time, switch.publish_until(claims, dt), replaced)
    return None


def planned_states(switch: Switch, incoming: Sequence[ControllerInfo], outgoing: Sequence[ControllerInfo],
                   dt: float) -> Dict[str, ControllerInfo]:
    """What the controller manager knows of the controllers a planned switch names, by name: the incoming active,
    the outgoing inactive and publishing until :meth:`Switch.publish_until` (the same in every engine)."""
    states = {c.name: replace(c, state="active", publishing_until=math.inf) for c in incoming}
    states.update({c.name: replace(c, state="inactive", publishing_until=switch.publish_until(c.interfaces, dt))
                   for c in outgoing})
    return states


def resolve_controller(name: str, controllers: Mapping[str, ControllerInfo]) -> str:
    """The known full name for ``name`` (full, or a plain node name that is unique); SwitchRefused if none."""
    if name in controllers:
        return name
    matches = [full for full in controllers if full.rsplit("/", 1)[-1] == name.strip("/")]
    if len(matches) == 1:
        return matches[0]
    if matches:
        raise SwitchRefused(f"{name}: ambiguous, one of {', '.join(sorted(matches))}")
    raise SwitchRefused(f"{name}: no such controller (known: {', '.join(sorted(controllers)) or 'none'})")


def plan_switch(controllers: Mapping[str, ControllerInfo], activate: Sequence[str], deactivate: Sequence[str],
                strict: bool, step: int, assembly_problem: Callable[[str], Optional[str]] = lambda name: None,
                ) -> Tuple[List[ControllerInfo], List[ControllerInfo], List[str]]:
    """Check a switch request at ``step``; the controllers to activate and deactivate, and what was skipped.

    ros2_control semantics (anchor_ros2.md §3.1): STRICT refuses the whole switch if any
    name fails; BEST_EFFORT skips what cannot be done and refuses only if nothing is left.
    In both modes a switch that would leave two controllers publishing one interface
    (two active claimants, or one coming in while another still ramps out) is refused,
    and so is the activation of a controller whose interface the graph's loop assembler
    cannot assemble (``assembly_problem(interface)`` returns the reason).

    Raises
    ------
    SwitchRefused
        With a one-line reason naming the controller.
    """
    skipped: List[str] = []
    chosen: Dict[str, List[ControllerInfo]] = {"activate": [], "deactivate": []}
    for kind, names, target in (("activate", activate, "active"), ("deactivate", deactivate, "inactive")):
        for name in names:
            try:
                info = controllers[resolve_controller(name, controllers)]
                if info.state == target:
                    raise SwitchRefused(f"{info.name}: already {target}")
                if info.state not in ("active", "inactive"):
                    raise SwitchRefused(f"{info.name}: {info.state}, cannot {kind}")
                problems = [p for p in map(assembly_problem, info.interfaces) if p] if kind == "activate" else []
                if problems:
                    raise SwitchRefused(f"{info.name}: cannot be assembled: {problems[0]}")
            except SwitchRefused as reason:
                if strict:
                    raise
                skipped.append(str(reason))
                continue
            chosen[kind].append(info)
    if not chosen["activate"] and not chosen["deactivate"]:
        raise SwitchRefused("nothing to switch: " + ("; ".join(skipped) if skipped else "no controller named"))
    both = {c.name for c in chosen["activate"]} & {c.name for c in chosen["deactivate"]}
    if both:
        raise SwitchRefused(f"{sorted(both)[0]}: both activated and deactivated")
    for outgoing in chosen["deactivate"]:
        # the command cannot go without its collective interfaces; others (blade_pitch of a hosted IPC) may fall silent
        needed = [i for i in outgoing.interfaces if i in (COLLECTIVE_PITCH, GENERATOR_TORQUE)] or outgoing.interfaces
        if not outgoing.switchable and not any(set(needed) <= set(c.interfaces) for c in chosen["activate"]):
            raise SwitchRefused(f"{outgoing.name}: a {outgoing.type} controller can only be swapped for another "
                                f"claimant of {', '.join(needed)} in the same switch, not switched "
                                f"off (without it the plant's safety system would stop the turbine)")
    _check_one_per_interface(controllers, chosen["activate"], chosen["deactivate"], step)
    return chosen["activate"], chosen["deactivate"], skipped


def _check_one_per_interface(controllers: Mapping[str, ControllerInfo], activate: List[ControllerInfo],
                             deactivate: List[ControllerInfo], step: int) -> None:
    outgoing = {c.name for c in deactivate}
    for incoming in activate:
        for interface in incoming.interfaces:
            same = [c for c in activate if interface in c.interfaces and c.name != incoming.name]
            if same:
                raise SwitchRefused(f"{incoming.name}, {same[0].name}: both claim {interface}; only one "
                                    f"controller per interface may be active")
            for other in controllers.values():
                if other.name == incoming.name or interface not in other.interfaces or other.name in outgoing:
                    continue
                if other.state == "active":
                    raise SwitchRefused(f"{incoming.name}: {other.name} is the active claimant of {interface}; "
                                        f"deactivate it in the same switch to swap them")
                if other.publishing_until > step:
                    raise SwitchRefused(f"{incoming.name}: {other.name} still ramps out {interface} until step "
                                        f"{int(other.publishing_until)}")


class InterfaceWindows:
    """Steps at which each command interface has a controller publishing its contribution (module notes).

    Parameters
    ----------
    initial : iterable of str
        Interfaces with an active claimant from step 0.
    dt : float
        Plant step [s], to turn ramp times into steps.
    """

    def __init__(self, initial: Iterable[str], dt: float) -> None:
        self.dt = float(dt)
        self._windows: Dict[str, List[List[float]]] = {name: [[0, math.inf]] for name in initial}

    def apply(self, switch: Switch) -> None:
        """Update the windows with a switch (switches must be applied in step order)."""
        for _, claims in switch.deactivate:
            silent_from = switch.publish_until(claims, self.dt)
            for interface in claims:
                window = self._window_at(interface, switch.step)
                if window is not None:
                    window[1] = silent_from
        for _, claims in switch.activate:
            for interface in claims:
                window = self._window_at(interface, switch.step)
                if window is None:
                    self._windows.setdefault(interface, []).append([switch.step, math.inf])
                else:
                    window[1] = math.inf

    def start(self, interfaces: Iterable[str], step: int = 0) -> None:
        """Interfaces whose claimant is active from ``step`` on (a controller that starts active)."""
        for interface in interfaces:
            if self._window_at(interface, step) is None:
                self._windows.setdefault(interface, []).append([step, math.inf])

    def publishing(self, step: int) -> frozenset:
        """The interfaces whose contribution of ``step`` comes from a controller."""
        return frozenset(name for name, windows in self._windows.items()
                         if any(start <= step < end for start, end in windows))

    def interfaces(self) -> frozenset:
        """Every interface that has had or will have a publishing controller."""
        return frozenset(self._windows)

    def _window_at(self, interface: str, step: int):
        for window in self._windows.get(interface, ()):
            if window[0] <= step < window[1]:
                return window
        return None


@dataclass(frozen=True)
class ScheduledSwitch:
    """One entry of a switch schedule: at ``step``, activate and deactivate these names."""

    step: int
    activate: Tuple[str, ...] = ()
    deactivate: Tuple[str, ...] = ()


def parse_schedule(entries: Sequence[str]) -> List[ScheduledSwitch]:
    """Parse schedule entries ``"STEP +name -name ..."`` (``+`` activates, ``-`` deactivates), in step order.

    Raises
    ------
    SwitchRefused
        Naming the entry: "schedule entry '10 ipc_h1': expected +NAME or -NAME, found 'ipc_h1'".
    """
    parsed = []
    for entry in entries:
        words = entry.split()
        if not words or not words[0].isdigit() or len(words) < 2:
            raise SwitchRefused(f"schedule entry {entry!r}: expected 'STEP +NAME -NAME ...' (e.g. '3000 +ipc_h1')")
        bad = [w for w in words[1:] if w[:1] not in "+-" or len(w) < 2]
        if bad:
            raise SwitchRefused(f"schedule entry {entry!r}: expected +NAME or -NAME, found {bad[0]!r}")
        parsed.append(ScheduledSwitch(int(words[0]), tuple(w[1:] for w in words[1:] if w[0] == "+"),
                                      tuple(w[1:] for w in words[1:] if w[0] == "-")))
    steps = [s.step for s in parsed]
    if steps != sorted(steps) or len(set(steps)) != len(steps):
        raise SwitchRefused(f"schedule: steps must increase, found {steps}")
    return parsed
