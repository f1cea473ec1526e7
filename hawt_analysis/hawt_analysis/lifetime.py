"""Lifetime loads of a campaign: wind-speed bins weighted by a site distribution, Miner-consistent.

A campaign runs each wind-speed bin i with several seeds s, each giving a damage-equivalent
load DEL_is for the same equivalent frequency f_eq (``hawt_analysis.fatigue``: N_eq = f_eq·T).
Miner's rule adds damage, which goes with DEL^m, so over the operating time that the bins
cover, with p_i the probability of bin i (normalised over the bins),

    DEL_life = ( Σ_i p_i · mean_s(DEL_is^m) )^(1/m)

for the same f_eq, i.e. N_eq = f_eq · (operating time). pCrunch's "weighted" DEL
(``pCrunch.Crunch.compute_total_fatigue``) is Σ_i p_i·DEL_i, a plain average of DELs, which is
not Miner-consistent: for m = 10 it understates the lifetime DEL whenever the bins differ.

Wind distributions are IEC 61400-1 Ed. 3 §6.3.1.1: Rayleigh with the class's annual mean
V_ave = 0.2·V_ref (10, 8.5 and 7.5 m/s for classes I, II, III), or Weibull with a given mean and
shape. Bin i spans half-way to its neighbours (a bin of the first or last speed as wide on its
outer side as on its inner one).
"""
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["IEC_CLASS_MEAN_SPEED", "HOURS_PER_YEAR", "WindDistribution", "bin_edges", "bin_probabilities",
           "lifetime_del", "annual_energy"]

IEC_CLASS_MEAN_SPEED = {"I": 10.0, "II": 8.5, "III": 7.5}
"""Annual mean wind speed at hub height V_ave [m/s] of the IEC 61400-1 wind turbine classes (0.2 V_ref)."""

HOURS_PER_YEAR = 8766.0
"""Hours in a mean year (365.25 days), as AEP conventionally uses."""


@dataclass(frozen=True)
class WindDistribution:
    """A Weibull distribution of the hub-height 10-min mean wind speed.

    Attributes
    ----------
    mean : float
        Mean wind speed V_ave [m/s], > 0.
    shape : float
        Weibull shape k (2 is Rayleigh, IEC 61400-1's default), > 0.
    """

    mean: float
    shape: float = 2.0

    @property
    def scale(self) -> float:
        """Weibull scale A [m/s] with A·Γ(1 + 1/k) = V_ave."""
        return self.mean / math.gamma(1.0 + 1.0 / self.shape)

    def cdf(self, speed: ArrayLike) -> np.ndarray:
        """P(V < speed) = 1 − exp(−(speed/A)^k) (IEC 61400-1 eq. 9 for k = 2)."""
        speed = np.clip(np.asarray(speed, dtype=float), 0.0, None)
        return 1.0 - np.exp(-(speed / self.scale) ** self.shape)


def bin_edges(speeds: ArrayLike) -> np.ndarray:
    """Edges of bins centred on ``speeds`` (increasing, at least one): half-way between neighbours, the outer
    edges as far out as the first and last inner half-widths (±1 m/s for a single speed)."""
    speeds = np.asarray(speeds, dtype=float)
    if speeds.ndim != 1 or speeds.size == 0 or np.any(np.diff(speeds) <= 0):
        raise ValueError(f"speeds: expected increasing wind speeds, found {speeds.tolist()}")
    if speeds.size == 1:
        return np.array([speeds[0] - 1.0, speeds[0] + 1.0])
    middles = 0.5 * (speeds[1:] + speeds[:-1])
    return np.concatenate(([speeds[0] - (middles[0] - speeds[0])], middles,
                           [speeds[-1] + (speeds[-1] - middles[-1])]))


def bin_probabilities(speeds: ArrayLike, distribution: WindDistribution) -> np.ndarray:
    """Probability of each bin of ``speeds`` under ``distribution`` (not normalised: the time outside the bins
    is left out, as AEP needs)."""
    return np.diff(distribution.cdf(bin_edges(speeds)))


def lifetime_del(dels: ArrayLike, probabilities: ArrayLike, m: float) -> float:
    """Miner-consistent lifetime DEL over the bins (module notes): (Σ_i p_i·mean_s DEL_is^m)^(1/m), p normalised.

    Parameters
    ----------
    dels : array_like, shape (bins, seeds)
        DEL of each seed in each bin, all for the same equivalent frequency; NaN for a seed that did not run
        (left out of its bin's mean; a bin needs at least one).
    probabilities : array_like, shape (bins,)
        Weight of each bin (e.g. `bin_probabilities`); normalised here.
    m : float
        Wöhler exponent of the channel.
    """
    dels = np.atleast_2d(np.asarray(dels, dtype=float))
    weights = np.asarray(probabilities, dtype=float)
    if dels.shape[0] != weights.size:
        raise ValueError(f"dels has {dels.shape[0]} bins, probabilities {weights.size}")
    if np.any(np.all(np.isnan(dels), axis=1)):
        raise ValueError("every bin needs the DEL of at least one seed")
    # scaled by the largest DEL so that DEL^m stays finite for m = 10 and loads of 1e7 N*m
    scale = np.nanmax(dels)
    if scale == 0.0:
        return 0.0
    damage = np.nanmean((dels / scale) ** m, axis=1)
    return float(scale * (np.sum(weights * damage) / np.sum(weights)) ** (1.0 / m))


def annual_energy(mean_power: ArrayLike, probabilities: ArrayLike) -> float:
    """Annual energy production [J]: Σ_i p_i·P_i over a year of HOURS_PER_YEAR, with P_i the mean electrical power
    [W] of bin i (over its seeds) and p_i its probability (not normalised: no energy outside the bins)."""
    return float(np.sum(np.asarray(probabilities) * np.asarray(mean_power)) * HOURS_PER_YEAR * 3600.0)
