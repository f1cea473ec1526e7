"""The loop assembler: every controller's contribution of one step into the pitch command of that step.

One core for every engine (DESIGN §4.1, §6): the mbc node, the in-process runner, the
IPC design tool and the closed-loop tests call it; there is no second copy. For step k::

    θ_i = limits( θ_coll + Σ_n f_n [c_n cos(n ψ_i + φ_n) + s_n sin(n ψ_i + φ_n)] + f_b Δθ_i )

- θ_coll: the ``collective_pitch`` contribution [rad];
- the sum over the ``harmonic/<n>`` contributions is the inverse Coleman transform with
  phase offset φ_n (DESIGN §3; Fratini 2019 eq. 4.11), at the azimuth ψ of the step
  (realtime: extrapolated by ψ̇ times the latency, :func:`extrapolated_azimuth`);
- Δθ_i: the ``blade_pitch`` contribution, per blade in the rotating frame;
- f: 1, or the fade of a contributor that stopped answering (:func:`fade_factor`);
- limits: per-blade angle and rate limits (:func:`hawt_controllers.limits.limit_pitch`) from
  the previous command.

Contributions are summed in a fixed order (harmonics by n, then blade increments), so
the result does not depend on the order in which they arrived.
"""
from __future__ import annotations

from typing import Iterable, List, NamedTuple, Optional, Sequence, Tuple

import numpy as np

from hawt_core.command_interfaces import InterfaceError, parse_interface

from ._validation import finite_floats
from .controller import BladeContribution, Contribution, HarmonicContribution
from .exceptions import ConfigurationError, InputError
from .limits import LimitFlag, PitchLimits, limit_pitch
from .mbc import check_configuration, mbc_inverse_sample

__all__ = ["AssembledCommand", "LoopAssembler", "assembly_problem", "fade_factor", "extrapolated_azimuth"]


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

