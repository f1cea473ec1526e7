"""The loop assembler: every controller's contribution of one step into the pitch command of that step.

Also the assembler's parameters (the ``mbc`` node's, :data:`ASSEMBLER`) and the command's pitch limits they give
(:func:`pitch_limits`), the same in every engine.

One core for every engine (DESIGN §4.1, §6): the mbc node, the in-process runner, the
IPC design tool and the closed-loop tests call it; there is no second copy. For step k::

    θ_i = limits( θ_coll + Σ_n f_n [c_n cos(n ψ_i + φ_n) + s_n sin(n ψ_i + φ_n)] + f_b Δθ_i )

- θ_coll: the ``collective_pitch`` contribution [rad];
- the sum over the ``harmonic/<n>`` contributions is the inverse Coleman transform with
  phase offset φ_n (DESIGN §3; Fratini 2019 eq. 4.11), at the azimuth ψ of the step
  (realtime: extrapolated by ψ̇ times the latency, :func:`extrapolated_azimuth`);
- Δθ_i: the ``blade_pitch`` contribution, per blade in the rotating frame;
- f: 1, or the fade of a contributor that stopped answering (:func:`fade_factor`);
- limits: per-blade angle and rate limits (:func:`hawt_controllers.laws.limits.limit_pitch`) from
  the previous command.

Contributions are summed in a fixed order (harmonics by n, then blade increments), so
the result does not depend on the order in which they arrived.
"""
from __future__ import annotations

from typing import Any, Iterable, List, Mapping, NamedTuple, Optional, Sequence, Tuple

import numpy as np

from hawt_controllers.laws.limits import NO_NARROWING, LimitFlag, PitchLimits, limit_pitch
from hawt_controllers.plugins.controller import BladeContribution, Contribution, HarmonicContribution
from hawt_core.command_interfaces import InterfaceError, parse_interface
from hawt_core.exceptions import ConfigurationError, InputError
from hawt_core.node_role import AWAIT_SCHEDULE, WAIT_FOR_RECORDER, NodeRole
from hawt_core.parameter_table import ParameterError, ParameterSpec
from hawt_core.plant_description import PlantDescription
from hawt_core.rotor.mbc import check_configuration, mbc_inverse_sample
from hawt_core.validation import finite_floats

__all__ = ["ASSEMBLER", "AssembledCommand", "LIMIT_PARAMETER", "LoopAssembler", "PARAMETERS", "assembly_problem", "check_parameters",
           "extrapolated_azimuth", "fade_factor", "pitch_limits", "requested_limits", "turbine_limits"]


PARAMETERS = (
    ParameterSpec("harmonics", [0], "harmonics n whose forward transform is published on control/mbc/h{n} "
                  "for watching ([0]: none)", read_only=True),
    ParameterSpec("controllers", [""], "controller names that must have announced themselves before the first "
                  "step is answered (lockstep: the graph's controllers, so every run starts alike; ['']: none)",
                  read_only=True),
    AWAIT_SCHEDULE,
    ParameterSpec("mode", "lockstep", "timing mode", choices=("lockstep", "realtime"), read_only=True),
    WAIT_FOR_RECORDER,
    ParameterSpec("min_pitch", NO_NARROWING.min_angle, "lowest pitch command: it may raise the turbine's "
                  "(plant/description), never lower it (the default keeps the turbine's)", "rad", minimum=-0.5,
                  maximum=1.6),
    ParameterSpec("max_pitch", NO_NARROWING.max_angle, "highest pitch command: it may lower the turbine's, never "
                  "raise it (the default keeps the turbine's)", "rad", minimum=-0.5, maximum=1.6),
    ParameterSpec("max_pitch_rate", NO_NARROWING.max_rate, "largest pitch rate: it may lower the turbine's, never "
                  "raise it (the default keeps the turbine's)", "rad/s", minimum=1e-3, maximum=1.0),
    ParameterSpec("stale_steps", 5, "realtime: a contributor whose newest contribution is older than this many "
                  "steps is lost", minimum=1, maximum=1000),
    ParameterSpec("input_timeout", 1.0, "lockstep: a contributor that has not answered the step this long "
                  "(wall clock) after the plant's loads is lost (keep it below the plant's command_timeout; a "
                  "busy machine can delay a live node by a fraction of a second)", "s", minimum=0.01,
                  maximum=60.0),
    ParameterSpec("start_timeout", 60.0, "lockstep: input_timeout of the first step, while the nodes are still "
                  "starting (discovery, the schedule; a machine busy with other graphs can take tens of seconds); "
                  "keep it below the plant's startup_timeout", "s", minimum=0.01,
                  maximum=600.0),
    ParameterSpec("fade_time", 2.0, "time over which a lost contributor's last contribution fades to zero", "s",
                  minimum=0.0, maximum=600.0),
    ParameterSpec("latency", 0.0, "realtime: extra time the command takes to reach the plant, added to the "
                  "azimuth extrapolation", "s", minimum=0.0, maximum=0.1),
)


LIMIT_PARAMETER = {"min_angle": "min_pitch", "max_angle": "max_pitch", "max_rate": "max_pitch_rate"}
"""The assembler's parameter of each PitchLimits field."""


def requested_limits(values) -> PitchLimits:
    """The pitch limits the assembler's parameter values ask for."""
    return PitchLimits(values["min_pitch"], values["max_pitch"], values["max_pitch_rate"])


def turbine_limits(plant: PlantDescription) -> PitchLimits:
    """The turbine's pitch limits, as plant/description gives them."""
    return PitchLimits(plant.min_pitch, plant.max_pitch, plant.max_pitch_rate)


def pitch_limits(values, plant: PlantDescription) -> PitchLimits:
    """The command's limits: the turbine's, narrowed by the assembler's parameters where they ask for it (the same in
    every engine)."""
    try:
        return requested_limits(values).within(turbine_limits(plant))
    except ConfigurationError as error:
        raise ParameterError(f"min_pitch, max_pitch: nothing left between them within the turbine's limits "
                             f"({error.reason})") from None


def check_parameters(values: Mapping[str, Any]) -> None:
    """The pitch limits must make sense together (min_pitch below max_pitch)."""
    try:
        requested_limits(values).validate()
    except ConfigurationError as error:
        reason = error.reason.replace("max_angle", "max_pitch")
        raise ParameterError(f"{LIMIT_PARAMETER.get(error.field, error.field)}: {reason}") from None


ASSEMBLER = NodeRole("assembler", PARAMETERS, check_parameters)
"""The loop assembler's role (the ``mbc`` node; entry point ``hawt.nodes: mbc``)."""


def assembly_problem(interface: str, blades: int) -> Optional[str]:
    """Why the assembler cannot assemble ``interface`` for ``blades`` blades; None if it can.

    Examples
    --------
    >>> assembly_problem("harmonic/4", 3) is None
    True
    >>> assembly_problem("blade_pitchh", 3)
    'blade_pitchh: no such command interface (did you mean blade_pitch?); the interfaces are collective_pitch, generator_torque, blade_pitch and harmonic/<n>'
    """
    try:
        harmonic = parse_interface(interface).harmonic
        if harmonic:
            check_configuration(harmonic, blades, inverse=True)
    except (InterfaceError, ConfigurationError) as error:
        return f"{interface}: {error}" if isinstance(error, ConfigurationError) else str(error)
    return None


def fade_factor(steps_since_lost: int, dt: float, fade_time: float) -> float:
    """Weight of a lost contributor's last demand, ``steps_since_lost`` steps after it was lost.

    Linear from 1 at the loss to 0 after ``fade_time`` [s]; 0 at once for ``fade_time`` 0.
    """
    return max(0.0, 1.0 - steps_since_lost * dt / fade_time) if fade_time > 0 else 0.0


def extrapolated_azimuth(azimuth: float, rotor_speed: float, delay: float) -> float:
    """The azimuth ``delay`` seconds after a measurement [rad] (realtime: the command's age when applied)."""
    return azimuth + rotor_speed * delay


class AssembledCommand(NamedTuple):
    """The pitch command of one step (fields of ``hawt_msgs/PitchCommand``).

    Attributes
    ----------
    pitch : ndarray, shape (B,)
        Absolute pitch per blade after limits [rad].
    collective : float
        The collective part [rad].
    individual : ndarray, shape (B,)
        ``pitch − collective`` [rad].
    flags : LimitFlag
        Angle and rate saturation.
    """

    pitch: np.ndarray
    collective: float
    individual: np.ndarray
    flags: LimitFlag


def _order(item: Tuple[Contribution, float]) -> tuple:
    contribution = item[0]
    return (0, contribution.harmonic) if isinstance(contribution, HarmonicContribution) else (1, 0)


class LoopAssembler:
    """Assembles the pitch command of each step (module notes).

    Parameters
    ----------
    blades : int
        B.
    limits : PitchLimits
        Angle and rate limits of the command.
    dt : float
        Plant step [s] (the rate limit's time base).
    """

    def __init__(self, blades: int, limits: PitchLimits, dt: float) -> None:
        self.blades = int(blades)
        self.limits = limits
        self.dt = float(dt)

    def individual(self, contributions: Iterable[Tuple[Contribution, float]], azimuth: float) -> np.ndarray:
        """Σ of the weighted harmonic and blade contributions per blade [rad], in the fixed order.

        Raises
        ------
        InputError
            A blade contribution of the wrong length.
        """
        return np.array(self._individual(contributions, azimuth))

    def _individual(self, contributions: Iterable[Tuple[Contribution, float]], azimuth: float) -> List[float]:
        total = [0.0] * self.blades
        for contribution, weight in sorted(contributions, key=_order):
            if isinstance(contribution, HarmonicContribution):
                part = mbc_inverse_sample(contribution.cos, contribution.sin, azimuth, contribution.harmonic,
                                          self.blades, contribution.phase_offset)
            elif isinstance(contribution, BladeContribution):
                part = finite_floats("increment", contribution.increment)
                if len(part) != self.blades:
                    raise InputError("increment", f"expected length B={self.blades}, found {len(part)}")
            else:
                continue
            total = [t + weight * p for t, p in zip(total, part)]
        return total

    def command(self, collective: float, individual: Sequence[float], previous: np.ndarray) -> AssembledCommand:
        """The limited command of ``collective`` + ``individual``, rate-limited from ``previous`` [rad]."""
        limited = limit_pitch([collective + i for i in individual], previous, self.dt, self.limits)
        return AssembledCommand(limited.pitch, collective, limited.pitch - collective, limited.flags)

    def assemble(self, collective: float, contributions: Iterable[Tuple[Contribution, float]], azimuth: float,
                 previous: np.ndarray) -> AssembledCommand:
        """The command of one step: :meth:`individual` at ``azimuth`` added to ``collective``, then limited."""
        return self.command(collective, self._individual(contributions, azimuth), previous)

