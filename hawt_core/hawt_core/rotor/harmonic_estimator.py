"""Harmonic (phasor) estimation over a sliding window of N_R revolutions in azimuth.

Zalkind & Pao, "A Harmonic Model for Loads Analysis and Control Design of a 2-bladed Wind
Turbine", eqs. 2–7 (notes: ``literature/notes/seed001_zalkind.md`` §2.2, Appendix A and C).
A load m(ψ) is written as the Fourier series in the rotor azimuth (eq. 2)::

    m(ψ) = m_0 + Σ_i m_c^{iP} cos(iψ) + m_s^{iP} sin(iψ)

and its components are the integrals over the last N_R revolutions of azimuth (eqs. 3–5)::

    m_0      = 1/(2π N_R) ∫_{ψ−2πN_R}^{ψ} m dψ
    m_c^{iP} = k/(2π N_R) ∫_{ψ−2πN_R}^{ψ} m cos(iψ) dψ
    m_s^{iP} = k/(2π N_R) ∫_{ψ−2πN_R}^{ψ} m sin(iψ) dψ

Conventions (declared; the paper leaves them open):

* **True amplitudes** (k = 2, the default): m = A cos ψ gives m_c^{1P} = A, as the series (2)
  and the hub → main-bearing relations 14–17 need. The printed factor 1/(2πN_R) (k = 1) gives
  half amplitudes (Appendix A erratum); it is kept as ``normalisation="printed"``.
* **Phasor** m^{iP} = m_c^{iP} + j m_s^{iP}: the harmonic is |m^{iP}| cos(iψ − ∠m^{iP}), its peak
  at ψ = ∠m^{iP}/i; |·| and ∠ are eqs. 6–7 with atan2 (``numpy.abs``, ``numpy.angle``). The 0P
  component is real.
* **Azimuth, not time**: the integrals are trapezoid sums over the unwrapped azimuth samples,
  so a varying rotor speed and a varying time step do not bias them; the window is exactly
  2πN_R rad long, its start interpolated linearly between the two samples around it. For
  samples uniform in azimuth the trapezoid sum of a trigonometric polynomial over whole
  periods is exact.
* ψ is the azimuth of blade 1 (DESIGN §3: 0 with blade 1 up, increasing with rotation).
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from hawt_core.validation import finite_array
from hawt_core.exceptions import ConfigurationError, InputError

__all__ = ["HarmonicEstimator", "HarmonicPhasors", "harmonic_basis", "sliding_phasors"]

_NORMALISATIONS = {"amplitude": 2.0, "printed": 1.0}


class HarmonicPhasors(NamedTuple):
    """Harmonic components of one or more channels.

    Attributes
    ----------
    phasors : ndarray, complex, shape (..., n_channels, max_harmonic + 1)
        Column i is m^{iP} = m_c^{iP} + j m_s^{iP}; column 0 is the real mean m_0.
    valid : ndarray of bool, shape (...)
        The window held N_R whole revolutions of samples (False during the first N_R
        revolutions; the phasors then integrate what there is over the full span).
    """

    phasors: np.ndarray
    valid: np.ndarray


def _checked_setup(revolutions: float, max_harmonic: int, normalisation: str) -> tuple[float, float]:
    if not (math.isfinite(revolutions) and revolutions > 0.0):
        raise ConfigurationError("revolutions", f"must be finite and > 0, found {revolutions}")
    if isinstance(max_harmonic, bool) or not isinstance(max_harmonic, (int, np.integer)) or max_harmonic < 0:
        raise ConfigurationError("max_harmonic", f"must be an integer >= 0, found {max_harmonic!r}")
    if normalisation not in _NORMALISATIONS:
        raise ConfigurationError("normalisation", f"must be one of {sorted(_NORMALISATIONS)}, found {normalisation!r}")
    return 2.0 * math.pi * revolutions, _NORMALISATIONS[normalisation]


def harmonic_basis(azimuth: ArrayLike, max_harmonic: int) -> np.ndarray:
    """The complex basis e^{jiψ} = cos iψ + j sin iψ for i = 0..max_harmonic, shape (..., max_harmonic + 1).

    Integrating m·e^{jiψ} gives m_c + j m_s at once (eqs. 4–5).
    """
    psi = np.asarray(azimuth, dtype=float)
    return np.exp(1j * psi[..., np.newaxis] * np.arange(max_harmonic + 1))


def _scale(span: float, factor: float, max_harmonic: int) -> np.ndarray:
    """Per harmonic: 1/(2πN_R) for the mean, factor/(2πN_R) for i >= 1."""
    scale = np.full(max_harmonic + 1, factor / span)
    scale[0] = 1.0 / span
    return scale


def _window_integrals(psi: np.ndarray, products: np.ndarray, cumulative: np.ndarray,
                      end: np.ndarray, start: np.ndarray) -> np.ndarray:
    """∫_{start}^{psi[end]} of the piecewise-linear products, from their cumulative trapezoid sums.

    ``psi`` increasing, shape (n,); ``products`` and ``cumulative`` shape (n, ...); ``end`` sample
    indices and ``start`` azimuths (start <= psi[end]), shape (k,). A start before psi[0] is
    clipped to psi[0].
    """
    start = np.maximum(start, psi[0])
    j = np.clip(np.searchsorted(psi, start, side="right") - 1, 0, max(psi.size - 2, 0))
    k = np.minimum(j + 1, psi.size - 1)
    width = psi[k] - psi[j]
    fraction = np.divide(start - psi[j], width, out=np.zeros_like(start), where=width > 0.0)
    fraction = fraction.reshape(fraction.shape + (1,) * (products.ndim - 1))
    at_start = products[j] + fraction * (products[k] - products[j])
    head = 0.5 * (products[j] + at_start) * (start - psi[j]).reshape(fraction.shape)
    return cumulative[end] - cumulative[j] - head


def _cumulative(psi: np.ndarray, products: np.ndarray) -> np.ndarray:
    steps = np.diff(psi).reshape((-1,) + (1,) * (products.ndim - 1))
    out = np.zeros_like(products)
    np.cumsum(0.5 * (products[1:] + products[:-1]) * steps, axis=0, out=out[1:])
    return out


def sliding_phasors(signals: ArrayLike, azimuth: ArrayLike, revolutions: float = 2.0, max_harmonic: int = 4,
                    normalisation: str = "amplitude") -> HarmonicPhasors:
    """Harmonic phasors at every sample of a record, each over the N_R revolutions before it.

    Parameters
    ----------
    signals : array_like, shape (n_samples,) or (n_samples, n_channels)
        Load signals sampled with ``azimuth``.
    azimuth : array_like, shape (n_samples,)
        Rotor azimuth ψ of blade 1 [rad], wrapped or not; it is unwrapped here and must not
        turn backwards.
    revolutions : float
        Window length N_R [revolutions] (Zalkind & Pao use 2).
    max_harmonic : int
        Highest harmonic i estimated (the paper reconstructs loads from 0P…4P).
    normalisation : {"amplitude", "printed"}
        True Fourier amplitudes (1/(πN_R) for i >= 1), or the printed 1/(2πN_R) of eqs. 4–5.

    Returns
    -------
    HarmonicPhasors
        ``phasors`` shape (n_samples, max_harmonic + 1) or (n_samples, n_channels, max_harmonic + 1).
    """
    span, factor = _checked_setup(float(revolutions), max_harmonic, normalisation)
    single = np.ndim(signals) == 1
    values = finite_array("signals", signals)
    values = values[:, np.newaxis] if single else values
    psi = np.unwrap(finite_array("azimuth", azimuth, shape=(values.shape[0],)))
    if np.any(np.diff(psi) < 0.0):
        raise InputError("azimuth", "must not turn backwards (the rotor's azimuth increases with rotation)")
    products = values[:, :, np.newaxis] * harmonic_basis(psi, max_harmonic)[:, np.newaxis, :]
    cumulative = _cumulative(psi, products)
    start = psi - span
    integrals = _window_integrals(psi, products, cumulative, np.arange(psi.size), start)
    phasors = integrals * _scale(span, factor, max_harmonic)
    phasors[..., 0] = phasors[..., 0].real
    return HarmonicPhasors(phasors[:, 0] if single else phasors, start >= psi[0])


class HarmonicEstimator:
    """Causal, sample-by-sample form of :func:`sliding_phasors` (the "E" blocks of Zalkind & Pao Fig. 7).

    Parameters
    ----------
    n_channels : int
        Number of load signals estimated together (e.g. 2: m_hy, m_hz).
    revolutions, max_harmonic, normalisation
        As in :func:`sliding_phasors`.

    Notes
    -----
    Each :meth:`update` appends one sample and returns the phasors over the last 2πN_R rad of
    azimuth; the samples older than the window are dropped, so the cost per sample is that of
    the window. Same samples give the same phasors as :func:`sliding_phasors` (to rounding).
    """

    def __init__(self, n_channels: int, revolutions: float = 2.0, max_harmonic: int = 4,
                 normalisation: str = "amplitude") -> None:
        if isinstance(n_channels, bool) or not isinstance(n_channels, (int, np.integer)) or n_channels < 1:
            raise ConfigurationError("n_channels", f"must be an integer >= 1, found {n_channels!r}")
        self._span, factor = _checked_setup(float(revolutions), max_harmonic, normalisation)
        self._scale = _scale(self._span, factor, max_harmonic)
        self._shape = (n_channels, max_harmonic + 1)
        self._max_harmonic = max_harmonic
        self.reset()

    def reset(self) -> None:
        """Forget every sample (the next update starts a new window)."""
        self._psi = np.empty(0)
        self._products = np.empty((0,) + self._shape, dtype=complex)
        self._cumulative = np.empty((0,) + self._shape, dtype=complex)
        self._first = math.nan
        self._last_wrapped = math.nan
        self._unwrapped = math.nan

    @property
    def valid(self) -> bool:
        """True once the samples span N_R whole revolutions."""
        return self._psi.size > 0 and self._psi[-1] - self._span >= self._first

    def update(self, azimuth: float, values: ArrayLike) -> np.ndarray:
        """Add one sample at azimuth ψ [rad, wrapped or not] and return the phasors, shape (n_channels, i_max + 1).

        The azimuth is unwrapped against the previous sample (a step of less than π per sample).
        """
        psi = float(azimuth)
        sample = finite_array("values", values, shape=(self._shape[0],))
        if not math.isfinite(psi):
            raise InputError("azimuth", f"must be finite, found {psi}")
        if self._psi.size == 0:
            self._unwrapped = self._first = psi
        else:
            step = (psi - self._last_wrapped + math.pi) % (2.0 * math.pi) - math.pi
            self._unwrapped += step
        self._last_wrapped = psi
        product = sample[:, np.newaxis] * harmonic_basis(self._unwrapped, self._max_harmonic)
        if self._psi.size == 0:
            total = np.zeros(self._shape, dtype=complex)
        else:
            total = self._cumulative[-1] + 0.5 * (self._products[-1] + product) * (self._unwrapped - self._psi[-1])
        start = self._unwrapped - self._span
        keep = max(int(np.searchsorted(self._psi, start, side="right")) - 1, 0)
        self._psi = np.append(self._psi[keep:], self._unwrapped)
        self._products = np.concatenate((self._products[keep:], product[np.newaxis]))
        self._cumulative = np.concatenate((self._cumulative[keep:], total[np.newaxis]))
        integral = _window_integrals(self._psi, self._products, self._cumulative,
                                     np.array([self._psi.size - 1]), np.array([start]))[0]
        phasors = integral * self._scale
        phasors[:, 0] = phasors[:, 0].real
        return phasors
