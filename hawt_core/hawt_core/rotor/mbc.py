"""Multi-blade coordinate (Coleman) transform of one harmonic: forward for B >= 3, inverse for B >= 2.

Conventions (DESIGN.md §3): ψ is the azimuth of blade 1 (0 = blade 1 up,
increasing with rotation); blade i sits at ψ_i = ψ + 2π(i−1)/B.

Forward (demodulation) of harmonic n, Fratini (2019) eq. 2.7 / 4.10, van Engelen
(2006) eq. 15/22/26, generalised from B = 3 to B blades::

    mean  = (1/B) Σ_i M_i
    cos_n = (2/B) Σ_i M_i cos(n ψ_i)
    sin_n = (2/B) Σ_i M_i sin(n ψ_i)

Inverse (remodulation) with phase offset φ_n, Fratini (2019) eq. 4.11 with the
offset of ROSCO's ``ColemanTransformInverse`` (φ_n = n·IPC_aziOffset(n))::

    θ_i = c_n cos(n ψ_i + φ_n) + s_n sin(n ψ_i + φ_n)

What is supported, and why
--------------------------
* B >= 3 blades for the forward transform. For B = 2 the pair (cos_n, sin_n) cannot be
  recovered from two blade values at every azimuth (the 2×2 matrix is singular at ψ = 0
  for n = 1); two-bladed rotors need the harmonic-estimator formulation of Zalkind & Pao
  (:mod:`hawt_core.rotor.harmonic_estimator`). The inverse is defined for B = 2: for odd n
  it gives θ_2 = −θ_1, Zalkind & Pao's pitch law eqs. 18–19 (with θ^{1P} = c − j s at φ = 0);
  for even n, θ_2 = θ_1 (a collective-like pattern).
* Every integer harmonic n >= 1. When 2n is not a multiple of B the
  (cos_n, sin_n) rows are orthogonal over the blades, so forward∘inverse is the
  identity at every azimuth (Fratini 2019 AC-7; van Engelen 2006 eq. 23).
* When 2n is a multiple of B the pair has rank 1 (:func:`harmonic_rank`):
  n a multiple of B (n = 3 for B = 3) gives the same pitch on every blade — a
  nP-modulated collective ("3P IPC", van Engelen 2006 eq. 24–27) — and for even
  B, n ≡ B/2 (mod B) gives an alternating pattern. Both are allowed and computed
  by the same formulas; forward∘inverse then is not the identity (it leaves a
  2n·P ripple, van Engelen eq. 27). Callers can warn with :func:`harmonic_rank`.
* Harmonics n and n' with n' ≡ ±n (mod B) drive the same pair of blade patterns
  (B = 3: 1P and 4P, 2P and 5P); loops on such harmonics are separated only by
  their frequency content, i.e. by their filters.
"""

from __future__ import annotations

import math
from typing import List, NamedTuple, Sequence

import numpy as np
from numpy.typing import ArrayLike

from hawt_core.validation import finite_array, finite_floats
from hawt_core.exceptions import ConfigurationError, InputError

__all__ = [
    "HarmonicComponents",
    "blade_azimuths",
    "check_configuration",
    "harmonic_rank",
    "mbc_forward",
    "mbc_forward_sample",
    "mbc_inverse",
    "mbc_inverse_sample",
]


class HarmonicComponents(NamedTuple):
    """Non-rotating components of harmonic n; each has the shape of the azimuth input.

    Attributes
    ----------
    mean : ndarray
        (1/B) Σ M_i, same unit as the blade signals (N·m for moments).
    cos : ndarray
        (2/B) Σ M_i cos(n ψ_i).
    sin : ndarray
        (2/B) Σ M_i sin(n ψ_i).
    """

    mean: np.ndarray
    cos: np.ndarray
    sin: np.ndarray


def check_configuration(harmonic: int, n_blades: int, inverse: bool = False) -> None:
    """Refuse a blade count or harmonic the transform cannot honour.

    Parameters
    ----------
    harmonic : int
        Harmonic number n; must be an integer >= 1.
    n_blades : int
        Number of blades B; must be >= 3, or >= 2 for the inverse alone.
    inverse : bool
        Check for the inverse transform only (remodulating a demand onto the blades).

    Raises
    ------
    ConfigurationError
        ``n_blades`` for B < 3 (B = 2 is singular for the forward transform) or B < 2,
        ``harmonic`` for n < 1 or a non-integer.
    """
    if isinstance(n_blades, bool) or not isinstance(n_blades, (int, np.integer)):
        raise ConfigurationError("n_blades", f"must be an integer, found {n_blades!r}")
    if isinstance(harmonic, bool) or not isinstance(harmonic, (int, np.integer)):
        raise ConfigurationError("harmonic", f"must be an integer, found {harmonic!r}")
    if n_blades == 2 and not inverse:
        raise ConfigurationError(
            "n_blades",
            "the MBC transform is singular for B=2 (two blade values cannot carry mean, cos and sin); "
            "two-bladed rotors need the harmonic-estimator formulation of Zalkind & Pao "
            "(hawt_core.rotor.harmonic_estimator)",
        )
    if n_blades < (2 if inverse else 3):
        fewest = 2 if inverse else 3
        raise ConfigurationError("n_blades", f"must be >= {fewest} for the MBC transform, found {n_blades}")
    if harmonic < 1:
        raise ConfigurationError("harmonic", f"must be >= 1, found {harmonic}")


def harmonic_rank(harmonic: int, n_blades: int) -> int:
    """Rank of the (cos_n, sin_n) pair over B blades: 2, or 1 when 2n is a multiple of B.

    Rank 1 means the harmonic's blade pattern is collective (n ≡ 0 mod B) or
    alternating (n ≡ B/2 mod B, even B); see the module notes.

    Examples
    --------
    >>> harmonic_rank(1, 3), harmonic_rank(3, 3), harmonic_rank(2, 4)
    (2, 1, 1)
    """
    check_configuration(harmonic, n_blades)
    return 1 if (2 * harmonic) % n_blades == 0 else 2


def blade_azimuths(azimuth: ArrayLike, n_blades: int) -> np.ndarray:
    """Azimuth of every blade, ψ_i = ψ + 2π(i−1)/B (DESIGN.md §3).

    Parameters
    ----------
    azimuth : array_like, shape (...)
        Azimuth of blade 1 [rad].
    n_blades : int
        Number of blades B.

    Returns
    -------
    ndarray, shape (..., B)
        Blade azimuths [rad], not wrapped.
    """
    psi = np.asarray(azimuth, dtype=float)
    return psi[..., np.newaxis] + (2.0 * math.pi / n_blades) * np.arange(n_blades)


def mbc_forward(blade_values: ArrayLike, azimuth: ArrayLike, harmonic: int) -> HarmonicComponents:
    """Forward Coleman transform of harmonic n (mean, cos_n, sin_n).

    Parameters
    ----------
    blade_values : array_like, shape (..., B)
        One value per blade, blades on the last axis (e.g. root out-of-plane
        moments [N·m]); B >= 3. One sample is shape (B,), a time series (T, B).
    azimuth : array_like, shape (...)
        Azimuth of blade 1 [rad], time-aligned with ``blade_values``.
    harmonic : int
        Harmonic number n >= 1.

    Returns
    -------
    HarmonicComponents
        ``mean``, ``cos``, ``sin``, each of shape (...), in the unit of the input.

    Raises
    ------
    ConfigurationError
        For B < 3 or n < 1 (see :func:`check_configuration`).
    InputError
        For NaN/inf or an azimuth whose shape does not match the samples.

    Notes
    -----
    Fratini (2019) eq. 2.7 and 4.10, van Engelen (2006) eq. 15, 22, 26;
    ``cos_n = (2/B) Σ_i M_i cos(n ψ_i)``, ``sin_n = (2/B) Σ_i M_i sin(n ψ_i)``.
    A rotating mP pattern appears in the non-rotating frame at |m − n|P and
    (m + n)P, only where that number is a multiple of B (Fratini 2019 §3.5);
    for n = 1, B = 3: 1P→0P, 2P→3P, 4P→3P, 5P→6P.

    Examples
    --------
    >>> psi = 0.3
    >>> m = np.cos(blade_azimuths(psi, 3))          # pure 1P "tilt" pattern
    >>> [round(float(v), 12) + 0.0 for v in mbc_forward(m, psi, 1)]
    [0.0, 1.0, 0.0]
    """
    values = finite_array("blade_values", blade_values)
    if values.ndim < 1:
        raise InputError("blade_values", "expected blades on the last axis, found a scalar")
    n_blades = values.shape[-1]
    check_configuration(harmonic, n_blades)
    psi = finite_array("azimuth", azimuth)
    if psi.shape != values.shape[:-1]:
        raise InputError("azimuth", f"expected shape {values.shape[:-1]} to match blade_values, found {psi.shape}")
    angles = harmonic * blade_azimuths(psi, n_blades)
    scale = 2.0 / n_blades
    return HarmonicComponents(
        mean=values.mean(axis=-1),
        cos=scale * np.sum(values * np.cos(angles), axis=-1),
        sin=scale * np.sum(values * np.sin(angles), axis=-1),
    )


def mbc_forward_sample(blade_values: Sequence[float], azimuth: float, harmonic: int) -> HarmonicComponents:
    """:func:`mbc_forward` of one sample on plain floats: the per-step path of the controllers.

    Same equations (Fratini 2019 eq. 2.7/4.10) and the same order of operations; on
    three blades, numpy's per-call cost would be many times the arithmetic. The
    caller has checked ``harmonic`` against B (:func:`check_configuration`).

    Returns
    -------
    HarmonicComponents
        ``mean``, ``cos``, ``sin`` as floats.

    Raises
    ------
    InputError
        For NaN/inf.

    Examples
    --------
    >>> psi = 0.3
    >>> m = [math.cos(psi + 2 * math.pi * i / 3) for i in range(3)]
    >>> [round(v, 12) + 0.0 for v in mbc_forward_sample(m, psi, 1)]
    [0.0, 1.0, 0.0]
    """
    values = blade_values.tolist() if isinstance(blade_values, np.ndarray) else list(blade_values)
    n_blades = len(values)
    spacing = 2.0 * math.pi / n_blades
    cos = sin = 0.0
    try:
        for i, value in enumerate(values):
            angle = harmonic * (azimuth + spacing * i)
            cos += value * math.cos(angle)
            sin += value * math.sin(angle)
        mean = sum(values) / n_blades
    except (TypeError, ValueError):  # not numbers; an infinite azimuth
        _check_sample(values, azimuth)
        raise
    if not math.isfinite(mean + cos + sin + azimuth):  # NaN or inf in any input shows in the sums
        _check_sample(values, azimuth)  # (finite input that overflowed: infinite components, as mbc_forward)
    scale = 2.0 / n_blades
    return HarmonicComponents(mean, scale * cos, scale * sin)


def _check_sample(blade_values: List[float], azimuth: float) -> None:
    """Raise :class:`InputError` naming the input of one sample that is NaN, infinite or not a number."""
    finite_floats("blade_values", blade_values)
    finite_floats("azimuth", (azimuth,))


def mbc_inverse_sample(cos: float, sin: float, azimuth: float, harmonic: int, n_blades: int,
                       phase_offset: float = 0.0) -> List[float]:
    """:func:`mbc_inverse` of one sample on plain floats: θ_i = c cos(n ψ_i + φ_n) + s sin(n ψ_i + φ_n).

    The per-step path of the loop assembler (Fratini 2019 eq. 4.11), the same order of
    operations as :func:`mbc_inverse`; the caller has checked ``harmonic`` against B.

    Raises
    ------
    InputError
        For NaN/inf.
    """
    if not (math.isfinite(cos) and math.isfinite(sin) and math.isfinite(azimuth) and math.isfinite(phase_offset)):
        finite_floats("cos, sin, azimuth, phase_offset", (cos, sin, azimuth, phase_offset))
    spacing = 2.0 * math.pi / n_blades
    pitch = []
    for i in range(n_blades):
        angle = harmonic * (azimuth + spacing * i) + phase_offset
        pitch.append(cos * math.cos(angle) + sin * math.sin(angle))
    return pitch


def mbc_inverse(
    cos: ArrayLike,
    sin: ArrayLike,
    azimuth: ArrayLike,
    harmonic: int,
    n_blades: int,
    phase_offset: float = 0.0,
) -> np.ndarray:
    """Inverse Coleman transform of harmonic n with phase offset φ_n: per-blade values.

    Parameters
    ----------
    cos, sin : array_like, shape (...)
        Non-rotating demand of harmonic n (e.g. pitch [rad]).
    azimuth : array_like, shape (...)
        Azimuth of blade 1 at which the demand is applied [rad].
    harmonic : int
        Harmonic number n >= 1.
    n_blades : int
        Number of blades B >= 2 (for B = 2 and odd n, θ_2 = −θ_1: Zalkind & Pao eqs. 18–19).
    phase_offset : float, optional
        φ_n [rad], added inside the cosine and sine. ROSCO's azimuth offset
        ``IPC_aziOffset(n)`` corresponds to φ_n = n·IPC_aziOffset(n).

    Returns
    -------
    ndarray, shape (..., B)
        θ_i = c cos(n ψ_i + φ_n) + s sin(n ψ_i + φ_n). No collective part and
        no 2/B factor (Fratini 2019 eq. 4.11).

    Notes
    -----
    Transforming the result forward again gives the input rotated by −φ_n:
    ``(c cos φ + s sin φ, −c sin φ + s cos φ)`` (for rank-2 harmonics). A pure
    delay τ between command and blade, at rotor speed Ω, rotates by −nΩτ, so
    φ_n = nΩτ compensates it (see :func:`hawt_controllers.laws.ipc_tuning.phase_offset_for_delay`).
    """
    check_configuration(harmonic, n_blades, inverse=True)
    c = finite_array("cos", cos)
    s = finite_array("sin", sin)
    psi = finite_array("azimuth", azimuth)
    phi = float(phase_offset)
    if not math.isfinite(phi):
        raise InputError("phase_offset", f"must be finite, found {phi}")
    angles = harmonic * blade_azimuths(psi, n_blades) + phi
    return c[..., np.newaxis] * np.cos(angles) + s[..., np.newaxis] * np.sin(angles)
