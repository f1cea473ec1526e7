"""Faults injected into the plant at a scheduled step: failed sensors, pitch actuators and grid (issue 34).

The plant's ``faults`` parameter lists them, one entry a line, ``KIND key=value ... at=T``:

============================================  ==========================================================
entry                                         the fault, from step k = T/dt on
============================================  ==========================================================
``load_bias blade=2 moment=2e6 at=20``        blade 2's root load sensor reads M_oop + 2e6 N*m
``load_gain blade=2 factor=0.8 at=20``        blade 2's root load sensor reads 0.8 M_oop
``load_frozen blade=2 at=20``                 blade 2's root load sensor repeats its reading of step k-1
``load_dead blade=2 at=20``                   blade 2's root load sensor reads NaN
``azimuth_offset angle=0.1 at=20``            the azimuth sensor reads psi + 0.1 rad (wrapped to [0, 2 pi))
``pitch_stuck blade=1 at=30``                 blade 1's pitch actuator holds the angle of step k
``pitch_runaway blade=1 to=feather at=30``    blade 1's pitch actuator runs to feather (or ``to=fine``)
``grid_loss at=40``                           the generator loses the grid: its torque is 0 at once
============================================  ==========================================================

Where each acts, as in the field:

- **Sensor faults** change what the plant *publishes* on ``plant/blade_loads`` (M_oop of one blade, the
  azimuth), never the physics: the turbine runs on, the controllers read the wrong value. The in-plane
  moment, the speeds and the pitch are published as measured. The plant's protection reads its own
  measurements (speeds, tower-top acceleration, pitch), which these faults leave alone.
- **Actuator and grid faults** act between the command and the physics: the pitch actuator of the blade
  ignores its command from step k on — stuck, it is driven to the angle it had at step k (the second-order
  actuator settles there within its response); run away, it is driven to its angle limit, which it reaches
  at its rate limit. Grid loss takes the generator off the grid over step k
  (:meth:`hawt_plant.model.TurbineModel.disconnect_grid`): its torque is 0 from that step on, at once and
  whatever is commanded, since the converter can no longer load it; the protection's grid monitor sees the
  loss at the end of that step and shuts the turbine down
  (:class:`hawt_plant.safety_system.Protection`, a ``protection_trip``). They
  act after the safety system too: a tripped plant feathers the blades that still answer; a stuck blade
  stays where it is.

One fault per sensor or actuator (the load sensor of each blade, the azimuth sensor, the pitch actuator of
each blade, the grid), for the run; a fault is permanent. :class:`PlantFaults` applies them to a model;
both engines call it at the same points (the plant node and hawt_tools.in_process), so a faulted ``hawt
run`` equals the faulted lockstep graph. Each fault is a ``fault`` event at its step (:func:`fault_event`):
WARN for a sensor, ERROR for an actuator or the grid.

No ROS here.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any, Dict, Mapping, Optional, Sequence, Tuple

import numpy as np

from hawt_core.parameter_table import ParameterError
from hawt_plant.turbine import PitchActuator, Turbine

__all__ = ["FAULT_KINDS", "Fault", "PlantFaults", "fault_event", "make_faults", "parse_faults"]

SENSOR_KINDS = ("load_bias", "load_gain", "load_frozen", "load_dead", "azimuth_offset")
ACTUATOR_KINDS = ("pitch_stuck", "pitch_runaway", "grid_loss")
FAULT_KINDS = SENSOR_KINDS + ACTUATOR_KINDS
"""Every kind of fault an entry may name."""

_KEYS = {"load_bias": ("blade", "moment"), "load_gain": ("blade", "factor"), "load_frozen": ("blade",),
         "load_dead": ("blade",), "azimuth_offset": ("angle",), "pitch_stuck": ("blade",),
         "pitch_runaway": ("blade", "to"), "grid_loss": ()}
_RUNAWAY_TARGETS = ("feather", "fine")
_MAX_MOMENT = 1e9
"""Largest bias a load sensor may get [N*m]: far beyond any blade root's moment."""
_MAX_FACTOR = 100.0
"""Largest gain error a load sensor may get, in magnitude."""


@dataclass(frozen=True)
class Fault:
    """One fault of the schedule (see the module notes).

    Attributes
    ----------
    kind : str
        One of :data:`FAULT_KINDS`.
    step : int
        The first step it acts on.
    entry : str
        The ``faults`` entry it was parsed from.
    blade : int
        The blade 1..B of a load sensor or pitch actuator; 0 for the azimuth sensor and the grid.
    value : float
        The bias [N*m] (load_bias), the factor (load_gain) or the offset [rad] (azimuth_offset); else 0.
    to : str
        pitch_runaway: ``feather`` (the actuator's maximum angle) or ``fine`` (its minimum); else ''.
    """

    kind: str
    step: int
    entry: str
    blade: int = 0
    value: float = 0.0
    to: str = ""

    @property
    def device(self) -> Tuple[str, int]:
        """The sensor or actuator it breaks: one fault each."""
        return ("load" if self.kind.startswith("load_") else self.kind.split("_")[0], self.blade)

    def describe(self, actuator: Optional[PitchActuator] = None) -> str:
        """What fails, in words."""
        b = self.blade
        return {
            "load_bias": f"blade-root load sensor of blade {b} biased: M_oop + {self.value:g} N*m",
            "load_gain": f"blade-root load sensor of blade {b} with a gain error: M_oop x {self.value:g}",
            "load_frozen": f"blade-root load sensor of blade {b} frozen at its last reading",
            "load_dead": f"blade-root load sensor of blade {b} dead: M_oop NaN",
            "azimuth_offset": f"azimuth sensor offset by {self.value:g} rad",
            "pitch_stuck": f"pitch actuator of blade {b} stuck: it ignores its command and holds its angle",
            "pitch_runaway": f"pitch actuator of blade {b} running away to {self.to}"
                             + (f" ({_runaway_angle(self, actuator):g} rad) at its rate limit {actuator.max_rate:g} "
                                "rad/s" if actuator is not None else ""),
            "grid_loss": "grid loss: the generator off the grid, its torque 0",
        }[self.kind]


def _runaway_angle(fault: Fault, actuator: PitchActuator) -> float:
    return actuator.max_angle if fault.to == "feather" else actuator.min_angle


def parse_faults(entries: Sequence[str], dt: float, blades: Optional[int] = None) -> Tuple[Fault, ...]:
    """The faults of the plant's ``faults`` entries (blank ones skipped), in the entries' order.

    Parameters
    ----------
    entries : sequence of str
        ``KIND key=value ... at=T`` (module notes); ``at`` [s] a whole number of steps of ``dt``.
    dt : float
        Plant step [s].
    blades : int, optional
        Number of blades B; blade numbers are checked against it if given (else only >= 1).

    Raises
    ------
    ParameterError
        One line naming the entry: ``faults: entry 'load_dead blade=0 at=3': blade: expected 1..3, found 0``.
    """
    faults = []
    for entry in (e for e in entries if e.strip()):
        fault = _parse(entry, dt, blades)
        clash = next((f for f in faults if f.device == fault.device), None)
        if clash is not None:
            raise ParameterError(f"faults: entry {entry!r}: the same sensor or actuator as entry {clash.entry!r} "
                                 "(one fault each)")
        faults.append(fault)
    return tuple(faults)


def _parse(entry: str, dt: float, blades: Optional[int]) -> Fault:
    def refuse(why: str) -> ParameterError:
        return ParameterError(f"faults: entry {entry!r}: {why}")

    kind, *words = entry.split()
    if kind not in _KEYS:
        raise refuse(f"expected one of {', '.join(FAULT_KINDS)} first, found {kind!r}")
    given: Dict[str, str] = {}
    for word in words:
        key, equals, value = word.partition("=")
        if not equals or not value:
            raise refuse(f"expected key=value, found {word!r}")
        if key in given:
            raise refuse(f"{key} given twice")
        given[key] = value
    wanted = (*_KEYS[kind], "at")
    unknown = [key for key in given if key not in wanted]
    if unknown:
        raise refuse(f"{kind} takes {', '.join(wanted)}, found {unknown[0]!r}")
    missing = [key for key in wanted if key not in given]
    if missing:
        raise refuse(f"{missing[0]} missing ({kind} takes {', '.join(wanted)})")

    def number(key: str, low: float, high: float) -> float:
        try:
            value = float(given[key])
        except ValueError:
            raise refuse(f"{key}: expected a number, found {given[key]!r}") from None
        if not low <= value <= high:  # NaN fails too
            raise refuse(f"{key}: expected {low:g}..{high:g}, found {given[key]}")
        return value

    at = number("at", 0.0, 1e6)
    step = int(round(at / dt))
    if abs(step * dt - at) > 1e-9 * max(1.0, at):
        raise refuse(f"at: {at:g} s is not a whole number of steps of dt {dt:g} s")
    fields: Dict[str, Any] = {}
    if "blade" in given:
        high = blades if blades is not None else 1000
        blade = number("blade", 1, high)
        if blade != int(blade):
            raise refuse(f"blade: expected a whole number 1..{high}, found {given['blade']}")
        fields["blade"] = int(blade)
    for key, low, high in (("moment", -_MAX_MOMENT, _MAX_MOMENT), ("factor", -_MAX_FACTOR, _MAX_FACTOR),
                           ("angle", -2 * math.pi, 2 * math.pi)):
        if key in given:
            fields["value"] = number(key, low, high)
    if "to" in given:
        if given["to"] not in _RUNAWAY_TARGETS:
            raise refuse(f"to: expected feather or fine, found {given['to']!r}")
        fields["to"] = given["to"]
    return Fault(kind, step, entry, **fields)


class PlantFaults:
    """The faults of a run applied to a plant's model, step by step (module notes).

    Parameters
    ----------
    faults : sequence of Fault
        From :func:`parse_faults`.
    blades : int
        Number of blades B (every fault's blade is checked against it).
    actuator : PitchActuator
        The turbine's pitch actuator (the limits a runaway goes to).

    Notes
    -----
    With M_i the true out-of-plane moment of blade i at step j ≥ k (the fault's step) and ψ the azimuth,
    the published values are M_i + b (bias), g M_i (gain), M_i(k−1) (frozen; M_i(0) if k = 0), NaN (dead)
    and (ψ + δ) mod 2π (azimuth offset). The command of blade i over step j ≥ k is θ_i(k) (stuck) or
    θ_max / θ_min (runaway); grid loss disconnects the model's generator. Without a fault acting, the model's
    output and the command pass through unchanged (the same objects), so a run without faults is the run
    it was.

    :meth:`measure` must see every step's output once, in order (step 0, then each output of :meth:`step`).
    """

    def __init__(self, faults: Sequence[Fault], blades: int, actuator: PitchActuator) -> None:
        for fault in faults:
            if fault.blade > blades:
                raise ParameterError(f"faults: entry {fault.entry!r}: blade: expected 1..{blades}, found "
                                     f"{fault.blade} (the rotor has {blades} blades)")
        self.faults = tuple(faults)
        self.actuator = actuator
        self._sensors = tuple(f for f in faults if f.kind in SENSOR_KINDS)
        self._actuators = tuple(f for f in faults if f.kind in ACTUATOR_KINDS)
        self._held: Dict[Fault, float] = {}
        self._moments: Optional[np.ndarray] = None
        self._pitch: Optional[np.ndarray] = None

    def grid_connected(self, step: int) -> bool:
        """Whether the generator was on the network over ``step`` (False from a ``grid_loss`` fault's step on): what
        the protection's grid monitor reads (:class:`hawt_plant.safety_system.Protection`)."""
        return not any(f.kind == "grid_loss" and f.step <= step for f in self._actuators)

    def starting(self, step: int) -> Tuple[Fault, ...]:
        """The faults that start acting at ``step`` (to be reported)."""
        return tuple(f for f in self.faults if f.step == step)

    def measure(self, step: int, output: Any) -> Any:
        """The model's output of ``step`` as the faulty sensors publish it (``output`` itself if none acts).

        ``output`` is a :class:`hawt_plant.model.TurbineOutput` (a frozen dataclass; a changed one is a copy).
        """
        moments, self._moments, self._pitch = self._moments, output.root_moment_oop, output.pitch
        acting = [f for f in self._sensors if f.step <= step]
        if not acting:
            return output
        published, azimuth = np.array(output.root_moment_oop, dtype=float), output.azimuth
        for fault in acting:
            i = fault.blade - 1
            if fault.kind == "load_bias":
                published[i] += fault.value
            elif fault.kind == "load_gain":
                published[i] *= fault.value
            elif fault.kind == "load_frozen":
                if fault not in self._held:
                    self._held[fault] = float((output.root_moment_oop if moments is None else moments)[i])
                published[i] = self._held[fault]
            elif fault.kind == "load_dead":
                published[i] = math.nan
            else:
                azimuth = (azimuth + fault.value) % (2.0 * math.pi)
        return dataclasses.replace(output, root_moment_oop=published, azimuth=azimuth)

    def step(self, model: Any, step: int, pitch: np.ndarray, generator_torque: float) -> Any:
        """Advance ``model`` over ``step`` with the command (pitch [rad] per blade, torque [N*m]) as the faulty
        actuators and grid apply it; the output of step + 1 as the sensors publish it (:meth:`measure`)."""
        acting = [f for f in self._actuators if f.step <= step]
        if acting:
            pitch = np.array(pitch, dtype=float)
            for fault in acting:
                if fault.kind == "grid_loss":
                    model.disconnect_grid()
                elif fault.kind == "pitch_stuck":
                    if fault not in self._held:
                        self._held[fault] = float(self._pitch[fault.blade - 1])
                    pitch[fault.blade - 1] = self._held[fault]
                else:
                    pitch[fault.blade - 1] = _runaway_angle(fault, self.actuator)
        return self.measure(step + 1, model.step(pitch, generator_torque))


def make_faults(values: Mapping[str, Any], turbine: Turbine) -> PlantFaults:
    """The faults of the plant's parameter ``values`` (``faults``, ``dt``) on ``turbine`` (ParameterError if bad)."""
    return PlantFaults(parse_faults(values["faults"], values["dt"]), turbine.rotor.number_of_blades,
                       turbine.pitch_actuator)


def fault_event(fault: Fault, dt: float, actuator: Optional[PitchActuator] = None) -> Tuple[int, str, str]:
    """The ``control/events`` level, kind and detail of a fault starting (the same in every engine).

    Levels are ``hawt_msgs/ControlEvent``'s: WARN 30 for a sensor, ERROR 40 for an actuator or the grid.
    """
    level = 30 if fault.kind in SENSOR_KINDS else 40
    return level, "fault", (f"{fault.describe(actuator)} from step {fault.step} (t={fault.step * dt:g} s; "
                            f"faults entry {fault.entry!r})")
