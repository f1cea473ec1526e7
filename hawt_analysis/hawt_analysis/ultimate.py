"""Ultimate loads of a design-load campaign: partial safety factors per DLC, the governing case of each channel,
and the statistical extrapolation of DLC 1.1 extremes to their 50-year value.

Design situations and factors are IEC 61400-1 Ed. 3 Table 2 (the DLCs with ultimate-load analysis, "U") and
Table 3 (partial safety factors for loads, unfavourable): normal (N) γ_f = 1.35, abnormal (A) 1.1, transport and
erection (T) 1.5; for DLC 1.1, whose characteristic load is extrapolated statistically, γ_f = 1.25 (§7.6.2.1). The
design load of a channel is the largest γ_f·F_k over the cases (§7.6.2), and the case that sets it governs.

The extrapolation follows Annex F's approach with a Gumbel distribution of each wind-speed bin's maxima: the
maxima of runs of duration T in bin i (one per seed) are fitted with G_i(F) = exp(-exp(-(F - μ_i)/β_i)) (maximum
likelihood, ``scipy.stats.gumbel_r``), and the long-term probability that a run's maximum exceeds F,

    P(F_max > F; T) = Σ_i p_i · (1 - G_i(F)),

is solved for the exceedance of a 50-year return period, P_e = T / 50 years (3.8·10⁻⁷ for T = 10 min, Ed. 3
eq. (F.1)'s target). p_i is the fraction of time in bin i (:func:`hawt_analysis.lifetime.bin_probabilities`). The
confidence interval is a parametric bootstrap: samples of each bin's size drawn from its fitted distribution,
refitted and solved again.
"""
import math
from dataclasses import dataclass
from typing import Dict, Iterable, List, Mapping, Sequence, Tuple

import numpy as np
from numpy.typing import ArrayLike
from scipy import optimize, stats

__all__ = ["DESIGN_SITUATIONS", "PARTIAL_SAFETY_FACTORS", "EXTRAPOLATED_FACTOR", "FIFTY_YEARS",
           "partial_safety_factor", "UltimateLoad", "ultimate_loads", "governing_loads", "Extrapolation",
           "fifty_year_load"]

DESIGN_SITUATIONS = {
    "1.1": "N", "1.3": "N", "1.4": "N", "1.5": "N",
    "2.1": "N", "2.2": "A", "2.3": "A",
    "3.2": "N", "3.3": "N",
    "4.2": "N",
    "5.1": "N",
    "6.1": "N", "6.2": "A", "6.3": "N",
    "7.1": "A",
    "8.1": "T", "8.2": "A",
}
"""Type of design situation of each ultimate-load DLC (IEC 61400-1 Ed. 3 Table 2): normal, abnormal, transport."""

PARTIAL_SAFETY_FACTORS = {"N": 1.35, "A": 1.1, "T": 1.5}
"""γ_f for unfavourable loads per type of design situation (IEC 61400-1 Ed. 3 Table 3)."""

EXTRAPOLATED_FACTOR = 1.25
"""γ_f of DLC 1.1, whose characteristic load is the statistical extrapolation (IEC 61400-1 Ed. 3 §7.6.2.1)."""

FIFTY_YEARS = 50 * 365.25 * 86400.0
"""The return period of the characteristic load [s]."""


def partial_safety_factor(dlc: str) -> float:
    """γ_f of a design-load case named as IEC numbers it (e.g. "1.3", "6.2"); a ValueError names an unknown one."""
    dlc = str(dlc).strip()
    if dlc == "1.1":
        return EXTRAPOLATED_FACTOR
    if dlc not in DESIGN_SITUATIONS:
        raise ValueError(f"DLC {dlc!r} is not an ultimate-load case of IEC 61400-1 Ed. 3 Table 2 (one of "
                         f"{', '.join(DESIGN_SITUATIONS)})")
    return PARTIAL_SAFETY_FACTORS[DESIGN_SITUATIONS[dlc]]


@dataclass(frozen=True)
class UltimateLoad:
    """The design load of one channel for one controller configuration, and the case that governs it."""

    controller: str
    channel: str
    characteristic: float
    """F_k of the governing case: its extreme of larger magnitude, with its sign."""
    factor: float
    design: float
    """γ_f · F_k, the largest over the cases."""
    dlc: str
    case: str
    wind_speed: float = math.nan
    """The governing case's wind speed [m/s] and seed (its number among a transient DLC's cases), where rows give
    them: what re-runs it (``hawt_tools.campaign.governing_series``)."""
    seed: int = 0


def ultimate_loads(rows: Iterable[Mapping[str, object]], channels: Sequence[str]) -> List[UltimateLoad]:
    """Per controller and channel, the case with the largest γ_f·|F_k|, from campaign rows.

    Each row names its ``controller``, ``case`` and ``dlc`` (and may give its ``wind_speed`` and ``seed``) and holds
    ``max.<channel>`` and ``min.<channel>`` (the campaign's per-case extremes); F_k of a case is whichever of the two
    has the larger magnitude.
    """
    best: Dict[Tuple[str, str], UltimateLoad] = {}
    for row in rows:
        factor = partial_safety_factor(str(row["dlc"]))
        for channel in channels:
            high, low = float(row[f"max.{channel}"]), float(row[f"min.{channel}"])
            characteristic = high if abs(high) >= abs(low) else low
            key = (str(row["controller"]), channel)
            load = UltimateLoad(key[0], channel, characteristic, factor, factor * characteristic, str(row["dlc"]),
                                str(row["case"]), float(row.get("wind_speed", math.nan)), int(row.get("seed", 0)))
            if key not in best or abs(load.design) > abs(best[key].design):
                best[key] = load
    return [best[key] for key in sorted(best)]


def governing_loads(tables: Iterable[Sequence[Mapping[str, object]]]) -> List[Dict[str, object]]:
    """The design load of each controller and channel over several DLCs' tables (entries with ``controller``,
    ``channel``, ``design``, ``dlc`` and what governs): the entry of the largest |γ_f·F_k| (IEC 61400-1 Ed. 3
    §7.6.2, the design load is the largest over the load cases); a DLC without a value (NaN) governs only where no
    other has one."""
    best: Dict[Tuple[object, object], Dict[str, object]] = {}
    for table in tables:
        for entry in table:
            key = (entry["controller"], entry["channel"])
            design = abs(float(entry["design"]))
            held = best.get(key)
            if held is None or (design > abs(float(held["design"]))) or (
                    math.isnan(float(held["design"])) and not math.isnan(design)):
                best[key] = dict(entry)
    return list(best.values())


@dataclass(frozen=True)
class Extrapolation:
    """The 50-year value of a run maximum with its bootstrap confidence interval, and each bin's Gumbel fit."""

    value: float
    low: float
    high: float
    confidence: float
    locations: Tuple[float, ...]
    scales: Tuple[float, ...]
    method: str = "Gumbel fit of each bin's run maxima (maximum likelihood), IEC 61400-1 Ed. 3 Annex F"


def _gumbel_fit(sample: np.ndarray) -> Tuple[float, float]:
    """Location and scale of the maximum-likelihood Gumbel fit; a sample without spread (a channel that never
    changed) is its value with a scale too small to matter."""
    spread = float(np.ptp(sample))
    if spread <= 1e-12 * max(1.0, float(np.max(np.abs(sample)))):
        return float(sample[0]), 1e-9 * max(1.0, abs(float(sample[0])))
    return tuple(stats.gumbel_r.fit(sample))


def _solve(locations: np.ndarray, scales: np.ndarray, probabilities: np.ndarray, exceedance: float) -> float:
    """F with Σ_i p_i (1 - G_i(F)) = exceedance."""
    def excess(load: float) -> float:
        with np.errstate(over="ignore"):  # exp(-x) of a bin far below the load, whose exceedance is 0
            return float(np.dot(probabilities, stats.gumbel_r.sf(load, locations, scales))) - exceedance

    low = float(np.min(locations))
    high = float(np.max(locations + 60.0 * scales))
    return optimize.brentq(excess, low, high, xtol=1e-12 * max(1.0, abs(high)), rtol=1e-12)


def fifty_year_load(maxima: Sequence[ArrayLike], probabilities: ArrayLike, duration: float = 600.0,
                    confidence: float = 0.9, resamples: int = 400, seed: int = 0) -> Extrapolation:
    """The load a run maximum exceeds once in 50 years, from each wind-speed bin's run maxima (module docstring).

    Parameters
    ----------
    maxima : sequence of array_like
        Per wind-speed bin, the maxima of its runs (one per seed, at least 3); for a minimum, pass the negated minima.
    probabilities : array_like
        Fraction of time in each bin (not renormalised: time outside the bins contributes no exceedance).
    duration : float
        Duration T of each run [s]; the target exceedance is T / 50 years.
    confidence : float
        Two-sided level of the bootstrap interval.
    """
    samples = [np.asarray(m, dtype=float).ravel() for m in maxima]
    p = np.asarray(probabilities, dtype=float)
    if len(samples) != p.size:
        raise ValueError(f"maxima of {len(samples)} bins but {p.size} bin probabilities")
    for i, sample in enumerate(samples):
        if sample.size < 3 or not np.all(np.isfinite(sample)):
            raise ValueError(f"bin {i}: {sample.size} maxima; a Gumbel fit needs at least 3, all finite")
    if not (np.all(p >= 0.0) and 0.0 < p.sum() <= 1.0 + 1e-9):
        raise ValueError(f"bin probabilities {p.tolist()} must be non-negative and sum to at most 1")
    if not 0.0 < confidence < 1.0 or duration <= 0.0:
        raise ValueError(f"confidence {confidence} must be in (0, 1) and duration {duration} positive")
    exceedance = duration / FIFTY_YEARS
    fits = np.array([_gumbel_fit(sample) for sample in samples])
    value = _solve(fits[:, 0], fits[:, 1], p, exceedance)
    rng = np.random.default_rng(seed)
    values = np.empty(resamples)
    for k in range(resamples):
        refits = np.array([_gumbel_fit(stats.gumbel_r.rvs(loc, scale, size=sample.size, random_state=rng))
                           for (loc, scale), sample in zip(fits, samples)])
        values[k] = _solve(refits[:, 0], refits[:, 1], p, exceedance)
    tail = (1.0 - confidence) / 2.0
    low, high = np.quantile(values, [tail, 1.0 - tail])
    return Extrapolation(value, float(low), float(high), confidence, tuple(fits[:, 0].tolist()),
                         tuple(fits[:, 1].tolist()))
