"""The controller plug-in interface: a core that claims command interfaces (DESIGN §4.1).

As in ros2_control, a controller is a small class that answers what it claims and
steps on the plant's measurements; the engines do the rest once for every controller:
the ROS graph wraps it in :class:`hawt_controllers.ros.controller_node.ControllerNode`
(lifecycle, step matching, switching, live parameters, holding the last output on
bad input), and the in-process runner (:mod:`hawt_tools.in_process`) calls the
same object without middleware, so both engines compute the same numbers.

A concrete controller fills in:

- ``TYPE`` (the type it is registered under, hawt_controllers.plugins.registry), ``PARAMETERS`` (its
  declarative parameter table, hawt_core.parameter_table) and ``INPUTS`` (``blade_loads``, ``turbine_state``);
- ``__init__(values, plant)``: read and check the parameters (raise
  :class:`~hawt_core.parameter_table.ParameterError` naming the parameter; the law's
  own validation is the one source of ranges beyond the table);
- :meth:`claims`, :meth:`update`, and optionally :meth:`reconfigure`, :meth:`on_activate`
  and :meth:`on_deactivate` for bumpless transfer;
- optionally ``ESTIMATE`` (topic kind and hawt_msgs message type) and :meth:`estimate`: what the
  controller estimates, published by every engine after each update on
  ``control/<controller>/<kind>`` (hawt_core.topics.estimate_topic), active or not.

Inputs are duck-typed so that a ROS message and the plant model's output serve alike:
``loads`` has ``azimuth``, ``rotor_speed``, ``root_moment_oop``, ``root_moment_ip`` and
``pitch`` (``hawt_msgs/BladeLoads``, ``hawt_plant.model.TurbineOutput``); ``state`` has the
fields of ``hawt_msgs/TurbineState``.
"""
from __future__ import annotations

import math
from typing import Any, ClassVar, Mapping, NamedTuple, Optional, Sequence, Tuple, Union

from hawt_core.command_interfaces import (BLADE_PITCH, COLLECTIVE_PITCH, GENERATOR_TORQUE, harmonic_interface,
                                          parse_interface)
from hawt_core.parameter_table import ParameterError, ParameterSpec, resolve_values
from hawt_core.plant_description import PlantDescription

__all__ = [
    "Controller", "CollectiveContribution", "HarmonicContribution", "BladeContribution", "Contribution",
    "OutputRamp", "contribution_topic", "controller_parameters", "update_or_hold", "mean_pitch", "ACTIVE_PARAMETER",
    "ControllerFailure",
]


def mean_pitch(pitch: Any) -> float:
    """The collective of measured blade pitches [rad]: their mean, NaN for none (a float per step, no array)."""
    values = pitch.tolist() if hasattr(pitch, "tolist") else pitch
    return sum(values) / len(values) if len(values) else math.nan


class CollectiveContribution(NamedTuple):
    """``collective_pitch`` and ``generator_torque`` (``hawt_msgs/CollectivePitch``).

    Attributes
    ----------
    pitch : float
        Collective pitch [rad].
    generator_torque : float
        Generator torque demand, HSS [N·m].
    generator_speed_filtered : float
        Filtered generator speed the controller used [rad/s].
    region : int
        Torque-control region (1, 15, 2, 25, 3).
    wind_speed_estimate : float
        Rotor-effective wind speed estimate [m/s]; NaN if none.
    """

    pitch: float
    generator_torque: float
    generator_speed_filtered: float = math.nan
    region: int = 0
    wind_speed_estimate: float = math.nan

    @property
    def interfaces(self) -> Tuple[str, ...]:
        return (COLLECTIVE_PITCH, GENERATOR_TORQUE)

    def finite(self) -> bool:
        return math.isfinite(self.pitch) and math.isfinite(self.generator_torque)


class HarmonicContribution(NamedTuple):
    """``harmonic/<n>``: the cos/sin pitch demand of harmonic n [rad] and its phase offset φ_n [rad]."""

    harmonic: int
    cos: float
    sin: float
    phase_offset: float = 0.0

    @property
    def interfaces(self) -> Tuple[str, ...]:
        return (harmonic_interface(self.harmonic),)

    def scaled(self, factor: float) -> "HarmonicContribution":
        return HarmonicContribution(self.harmonic, factor * self.cos, factor * self.sin, self.phase_offset)

    def finite(self) -> bool:
        return math.isfinite(self.cos) and math.isfinite(self.sin) and math.isfinite(self.phase_offset)


class BladeContribution(NamedTuple):
    """``blade_pitch``: additive pitch increment per blade in the rotating frame [rad], blade 1 first."""

    increment: Tuple[float, ...]

    @property
    def interfaces(self) -> Tuple[str, ...]:
        return (BLADE_PITCH,)

    def scaled(self, factor: float) -> "BladeContribution":
        return BladeContribution(tuple(factor * value for value in self.increment))

    def finite(self) -> bool:
        return all(math.isfinite(value) for value in self.increment)


class ControllerFailure(RuntimeError):
    """A core that cannot go on (a hosted library that failed): not held like refused input, but stopped.

    The ROS node reports it as a ``controller_failed`` error event and answers no more steps, so the
    plant's safety system takes over; the in-process runner ends the run with the message (exit 1).
    """


# A contribution is built every step by every controller: named tuples, as cheap to build as a tuple.
Contribution = Union[CollectiveContribution, HarmonicContribution, BladeContribution]


def contribution_topic(contribution: Contribution) -> str:
    """The topic a contribution is published on: its (first) interface's (DESIGN §4.1)."""
    return parse_interface(contribution.interfaces[0]).topic


ACTIVE_PARAMETER = ParameterSpec(
    "active", True, "state at start: active (ramps in over the controller's ramp time) or inactive; later "
    "switches come from controller_manager or lifecycle transitions", read_only=True)
"""The one switch that decides whether a controller starts active; every controller has it."""


def controller_parameters(controller_class: type) -> Tuple[ParameterSpec, ...]:
    """The whole parameter table of a controller node: the controller's own rows, then ``active``."""
    return (*controller_class.PARAMETERS, ACTIVE_PARAMETER)


class Controller:
    """Base of every controller core (see the module notes for what a subclass fills in).

    Parameters
    ----------
    values : mapping
        Parameter values by name (the table's defaults fill in what is missing).
    plant : PlantDescription
        The plant the controller runs against (dt, B, rated values).
    """

    TYPE: ClassVar[str] = ""
    PARAMETERS: ClassVar[Tuple[ParameterSpec, ...]] = ()
    INPUTS: ClassVar[Tuple[str, ...]] = ("blade_loads",)
    SWITCHABLE: ClassVar[bool] = True
    ESTIMATE: ClassVar[Optional[Tuple[str, str]]] = None
    WITHOUT_INPUT: ClassVar[str] = "last output held"
    """What the controller does at a step whose input it refused (:meth:`without_input`), for the event."""

    def __init__(self, values: Mapping[str, Any], plant: PlantDescription) -> None:
        self.values = resolve_values(self.PARAMETERS, values)
        self.plant = plant

    @classmethod
    def claimed(cls, values: Mapping[str, Any]) -> Tuple[str, ...]:
        """The command interfaces a controller with these parameter values claims (no plant needed: the
        launcher checks before a graph starts that no two controllers start active on one interface)."""
        raise NotImplementedError

    def claims(self) -> Tuple[str, ...]:
        """The command interfaces this controller claims."""
        return self.claimed(self.values)

    def update(self, step: int, loads: Any, state: Any = None) -> Tuple[Contribution, ...]:
        """Step k: the measurements of step k in, the contributions of step k out.

        Called at every step, active or not (filters keep running while inactive, so an
        activation sees no transient); the engine publishes the result only while the
        controller is active or ramping out.

        Raises ValueError (e.g. :class:`hawt_core.exceptions.InputError`) on input
        it cannot use; the engine then holds the last output and reports it.
        """
        raise NotImplementedError

    def without_input(self, held: Tuple[Contribution, ...]) -> Tuple[Contribution, ...]:
        """The contributions of a step whose input :meth:`update` refused; ``held`` are the last ones answered.

        Default: ``held`` (zero-order hold). A controller whose demand is worthless without its input
        (the IPC without its blade-root moments) fades it out instead (:data:`WITHOUT_INPUT` says so).
        """
        return held

    @classmethod
    def check_values(cls, values: Mapping[str, Any]) -> None:
        """Raise ParameterError if table-checked ``values`` break a rule across parameters that needs no plant.

        Cheap (no filter design, no plant): the launcher calls it before a graph starts
        (hawt_tools.parameter_check). Default: no such rule.
        """

    def check(self, values: Mapping[str, Any]) -> None:
        """Raise ParameterError if ``values`` cannot be applied live (default: the table's checks)."""
        resolve_values(self.PARAMETERS, values)

    def reconfigure(self, values: Mapping[str, Any]) -> None:
        """Apply checked parameter values at a step boundary (default: keep them)."""
        self.values = resolve_values(self.PARAMETERS, values)

    def on_activate(self, ramp_time: Optional[float], initial: Sequence[Contribution], loads: Any) -> None:
        """Start contributing, ramping in over ``ramp_time`` [s] (None: the controller's default).

        ``initial`` holds the outgoing controller's last contributions when this one replaces
        it (start from them, no ramp); ``loads`` are the measurements of the switch step.
        """

    def on_deactivate(self, ramp_time: Optional[float]) -> None:
        """Start ramping the contribution out over ``ramp_time`` [s] (None: the controller's default)."""

    def estimate(self) -> Mapping[str, Any]:
        """The fields (but header and step) of this step's ``ESTIMATE`` message, after :meth:`update`."""
        raise NotImplementedError

    def ramp_time(self) -> float:
        """The default ramp time [s] of a switch (0 if the controller has none)."""
        return float(self.values.get("ramp_time", 0.0))


def update_or_hold(core: "Controller", step: int, loads: Any, state: Any,
                   held: Tuple[Contribution, ...]) -> Tuple[Tuple[Contribution, ...], Optional[str]]:
    """Step ``core`` at ``step``: its contributions and None, or ``held`` (the last valid ones) and why not.

    Every engine steps a controller through this, so a core that refuses its input (ValueError) or
    gives a value that is not finite holds its last output the same way everywhere; a core that
    refuses its input answers what :meth:`Controller.without_input` says (by default ``held``).
    """
    try:
        contributions = core.update(step, loads, state)
    except ValueError as error:
        return core.without_input(held), str(error)
    for contribution in contributions:
        if not contribution.finite():
            return held, f"output not finite: {contributions}"
    return contributions, None


class MeasuredFactor:
    """The factor on a demand that is worthless without its input (a dead blade-root load sensor, issue 34): each
    step without its input takes it linearly towards 0 over the controller's ramp time, each step with it back
    towards 1 (at once for a ramp time of 0). A controller multiplies its output by it and answers its last
    unscaled output, faded, in :meth:`Controller.without_input`."""

    def __init__(self) -> None:
        self.value = 1.0

    def step(self, measured: bool, dt: float, ramp_time: float) -> float:
        """The factor of this step, moved one step of ``dt`` [s] towards 1 if ``measured``, else towards 0."""
        rate = math.inf if ramp_time == 0.0 else 1.0 / ramp_time
        self.value = min(self.value + rate * dt, 1.0) if measured else max(self.value - rate * dt, 0.0)
        return self.value


class OutputRamp:
    """A factor that goes linearly 0 → 1 after :meth:`start` and 1 → 0 after :meth:`stop` (bumpless switching).

    Parameters
    ----------
    dt : float
        Step [s].
    """

    def __init__(self, dt: float) -> None:
        self.dt = float(dt)
        self.value = 0.0
        self.target = 0.0
        self.rate = math.inf

    def start(self, ramp_time: float, at_once: bool = False) -> None:
        """Ramp to 1 over ``ramp_time`` [s]; ``at_once`` sets 1 now."""
        self.target, self.rate = 1.0, self._rate(ramp_time)
        if at_once:
            self.value = 1.0

    def stop(self, ramp_time: float) -> None:
        """Ramp to 0 over ``ramp_time`` [s]."""
        self.target, self.rate = 0.0, self._rate(ramp_time)

    def advance(self) -> float:
        """The factor of this step (moved one step towards the target)."""
        change = self.rate * self.dt
        self.value = min(self.value + change, self.target) if self.value < self.target \
            else max(self.value - change, self.target)
        return self.value

    @staticmethod
    def _rate(ramp_time: float) -> float:
        if not (math.isfinite(ramp_time) and ramp_time >= 0):
            raise ParameterError(f"ramp_time: expected a finite time >= 0 [s], found {ramp_time}")
        return math.inf if ramp_time == 0.0 else 1.0 / ramp_time

