"""Damage-equivalent loads from rainflow counting (ASTM E1049-85, 1 Hz equivalent).

Conventions (pinned because the field's tools differ, see the project notes
``anchor_windcontrol.md`` §3.6):

- cycle counting: ASTM E1049-85 §5.4.4 rainflow counting by the ``rainflow``
  library; residual ranges are half cycles counting 0.5 (pCrunch and fatpack
  count them as full cycles instead);
- ranges are unbinned by default; with ``nbins`` each range is moved to the upper
  edge of its bin (``rainflow.count_cycles``), which can only raise the DEL;
- no mean-stress (Goodman) correction;
- equivalent frequency 1 Hz: N_eq = f_eq·T with T = t_end − t_0 (pCrunch's
  ``elapsed_time``, openfast_toolbox's ``T/Teq``).
"""
from dataclasses import dataclass

import numpy as np
import rainflow
from numpy.typing import ArrayLike

from ._checks import finite_array

__all__ = [
    "CONVENTION",
    "DamageEquivalentLoad",
    "RainflowCycles",
    "WohlerExponents",
    "damage_equivalent_load",
    "rainflow_cycles",
]

CONVENTION = (
    "rainflow counting ASTM E1049-85 (rainflow 3.2.0), residual half cycles count 0.5; "
    "ranges unbinned unless stated; no mean-stress correction; "
    "DEL = (sum n_i S_i^m / N_eq)^(1/m), N_eq = f_eq * (t_end - t_0), f_eq = 1 Hz"
)


@dataclass(frozen=True)
class WohlerExponents:
    """Wöhler (S-N) slopes m by kind of load path.

    Defaults: m = 10 for composite blade-root moments and m = 4 for steel (tower,
    hub, shaft), as in WEIS (``runFAST_pywrapper.py``: RootMc/RootMyb 10,
    TwrBsM/LSShftM 4) and van Engelen (2006) §4 (3–4 steel, 9–10 reinforced plastics).
    """

    blade_root: float = 10.0
    steel: float = 4.0

    def __post_init__(self) -> None:
        for kind in ("blade_root", "steel"):
            if not getattr(self, kind) > 0.0:
                raise ValueError(f"{kind}: Wöhler exponent must be positive, found {getattr(self, kind)}")

    def for_kind(self, kind: str) -> float:
        """Return m for ``kind`` (``"blade_root"`` or ``"steel"``)."""
        if kind not in ("blade_root", "steel"):
            raise ValueError(f"kind: expected 'blade_root' or 'steel', found {kind!r}")
        return getattr(self, kind)


@dataclass(frozen=True)
class RainflowCycles:
    """Rainflow-counted cycles: ranges S_i [signal unit] and counts n_i (0.5 per half cycle)."""

    ranges: np.ndarray
    counts: np.ndarray

    @property
    def n_cycles(self) -> float:
        """Σ n_i, half cycles counting 0.5."""
        return float(self.counts.sum())


@dataclass(frozen=True)
class DamageEquivalentLoad:
    """A damage-equivalent load and how it was obtained.

    Attributes
    ----------
    value : float
        DEL [signal unit, e.g. N·m].
    m : float
        Wöhler exponent used.
    n_eq : float
        Number of equivalent cycles N_eq = f_eq·T.
    n_cycles : float
        Σ n_i of the rainflow count (half cycles counting 0.5).
    convention : str
        The counting and equivalence convention, for reports.
    """

    value: float
    m: float
    n_eq: float
    n_cycles: float
    convention: str


def _reversals(signal: np.ndarray) -> np.ndarray:
    """Values of the turning points of ``signal``, first and last sample included.

    Vectorised equivalent of ``rainflow.reversals``: plateaus (repeated values)
    are collapsed first, so counting the reversals gives the same cycles as
    counting the whole signal, only faster.
    """
    collapsed = signal[np.r_[True, np.diff(signal) != 0.0]]
    if collapsed.size < 3:
        return collapsed
    slope_sign = np.sign(np.diff(collapsed))
    turning = np.flatnonzero(slope_sign[:-1] != slope_sign[1:]) + 1
    return np.concatenate((collapsed[:1], collapsed[turning], collapsed[-1:]))


def rainflow_cycles(signal: ArrayLike, nbins: int | None = None, *, name: str = "signal") -> RainflowCycles:
    """Count the cycles of ``signal`` by ASTM E1049-85 rainflow counting.

    Parameters
    ----------
    signal : array_like, shape (n_samples,)
        Load history [any unit].
    nbins : int, optional
        If given, ranges are grouped into ``nbins`` bins of width (max − min)/nbins
        and represented by the bin's upper edge; unbinned (exact ranges) by default.
    name : str
        Name used in error messages.

    Returns
    -------
    RainflowCycles
        Ranges S_i and counts n_i; a residual half cycle counts 0.5.

    References
    ----------
    ASTM E1049-85 (2011), §5.4.4, as implemented by ``rainflow`` 3.2.0.
    """
    values = finite_array(name, signal, ndim=1)
    if nbins is not None and nbins < 1:
        raise ValueError(f"nbins: expected a positive bin count, found {nbins}")
    turning_points = _reversals(values)
    if turning_points.size < 2:
        return RainflowCycles(ranges=np.zeros(0), counts=np.zeros(0))
    counted = np.array(rainflow.count_cycles(turning_points, nbins=nbins), dtype=float)
    return RainflowCycles(ranges=counted[:, 0], counts=counted[:, 1])


def damage_equivalent_load(
    signal: ArrayLike,
    m: float,
    duration: float,
    *,
    equivalent_frequency: float = 1.0,
    nbins: int | None = None,
    name: str = "signal",
) -> DamageEquivalentLoad:
    """Short-term damage-equivalent load of a load history.

    Parameters
    ----------
    signal : array_like, shape (n_samples,)
        Load history [N·m or any unit; the DEL has the same unit].
    m : float
        Wöhler exponent (see `WohlerExponents`).
    duration : float
        Record length T = t_end − t_0 [s].
    equivalent_frequency : float
        f_eq [Hz]; N_eq = f_eq·T. 1 Hz by convention.
    nbins : int, optional
        Range binning, see `rainflow_cycles`; unbinned by default.
    name : str
        Name used in error messages.

    Returns
    -------
    DamageEquivalentLoad

    Notes
    -----
    .. math:: \\mathrm{DEL} = \\left(\\frac{\\sum_i n_i S_i^m}{N_{eq}}\\right)^{1/m}

    Hayman (2012), MLife theory manual, Eq. 26 / 30 (project notes
    ``anchor_windcontrol.md`` §3.1). Evaluated as
    S_max·(Σ n_i (S_i/S_max)^m / N_eq)^(1/m) so that S^m cannot overflow.
    """
    if not m > 0.0:
        raise ValueError(f"m: Wöhler exponent must be positive, found {m}")
    if not duration > 0.0:
        raise ValueError(f"duration: expected a positive record length in s, found {duration}")
    if not equivalent_frequency > 0.0:
        raise ValueError(
            f"equivalent_frequency: expected a positive frequency in Hz, found {equivalent_frequency}"
        )
    cycles = rainflow_cycles(signal, nbins, name=name)
    n_eq = equivalent_frequency * duration
    largest = cycles.ranges.max(initial=0.0)
    if largest == 0.0:
        value = 0.0
    else:
        damage_sum = np.sum(cycles.counts * (cycles.ranges / largest) ** m)
        value = float(largest * (damage_sum / n_eq) ** (1.0 / m))
    convention = CONVENTION if nbins is None else f"{CONVENTION}; ranges binned to {nbins} bins (upper edges)"
    return DamageEquivalentLoad(
        value=value, m=float(m), n_eq=float(n_eq), n_cycles=cycles.n_cycles, convention=convention
    )
