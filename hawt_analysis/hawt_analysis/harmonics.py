"""Amplitudes of the rotor harmonics nP of a channel, found in the azimuth domain."""
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ._checks import finite_array, same_length

__all__ = ["HarmonicAmplitudes", "harmonic_amplitudes", "revolutions"]


@dataclass(frozen=True)
class HarmonicAmplitudes:
    """Amplitudes of the harmonics nP of one or more channels.

    Attributes
    ----------
    harmonics : tuple of int
        The harmonic numbers n.
    amplitude : numpy.ndarray, shape (n_channels, n_harmonics) or (n_harmonics,)
        Amplitude of the azimuth-synchronous (periodic) part: |mean over
        revolutions of (a_n − i b_n)| [signal unit].
    amplitude_per_revolution_rms : numpy.ndarray, same shape
        sqrt(mean over revolutions of a_n² + b_n²) [signal unit]; also counts
        content that is not phase-locked to the azimuth (turbulence sampled in the
        band n ± ½ P), so it is ≥ ``amplitude``.
    revolutions : int
        Number of whole revolutions used.
    """

    harmonics: tuple[int, ...]
    amplitude: np.ndarray
    amplitude_per_revolution_rms: np.ndarray
    revolutions: int


def _turns(azimuth: np.ndarray) -> np.ndarray:
    """Revolutions turned since the first sample, counted on the running maximum of the unwrapped azimuth."""
    unwrapped = np.unwrap(azimuth)
    return (np.maximum.accumulate(unwrapped) - unwrapped[0]) / (2.0 * np.pi)


def revolutions(azimuth: ArrayLike) -> float:
    """Revolutions an azimuth record [rad] covers, as :func:`harmonic_amplitudes` counts them: it fits harmonics
    over the whole ones, and refuses a record of less than one (a short record, or a standing or idling rotor's)."""
    psi = finite_array("azimuth", azimuth, ndim=1)
    return float(_turns(psi)[-1]) if psi.size else 0.0


def harmonic_amplitudes(
    signals: ArrayLike,
    azimuth: ArrayLike,
    harmonics: tuple[int, ...] = (1, 2, 3, 4, 5, 6),
    *,
    name: str = "signals",
) -> HarmonicAmplitudes:
    """Fit the harmonics nP of ``signals`` revolution by revolution in the azimuth domain.

    Parameters
    ----------
    signals : array_like, shape (n_samples,) or (n_samples, n_channels)
        Channels sampled with ``azimuth`` [any unit].
    azimuth : array_like, shape (n_samples,)
        Rotor azimuth ψ of blade 1 [rad], wrapped to [0, 2π) or not (DESIGN §3).
        The amplitudes do not depend on which blade's azimuth is used.
    harmonics : tuple of int
        Harmonic numbers n ≥ 1.
    name : str
        Name of ``signals`` in error messages.

    Returns
    -------
    HarmonicAmplitudes

    Raises
    ------
    ValueError
        If the record holds no whole revolution, or a revolution has too few samples.

    Notes
    -----
    The unwrapped azimuth is cut into whole revolutions r counted from the first
    sample, ψ ∈ [ψ_0 + 2πr, ψ_0 + 2π(r+1)); within each, least squares fits

    .. math:: y(\\psi) = c_0 + c_1 \\tau + \\sum_n a_n \\cos n\\psi + b_n \\sin n\\psi,
              \\quad \\tau = \\frac{\\psi - \\psi_0}{2\\pi} - r - \\tfrac12

    The basis is a function of azimuth, not time, so a slowly varying rotor speed
    leaves the estimate exact; the trend term c_1 τ keeps a slowly drifting mean out
    of the harmonics (a ramp over one revolution would otherwise leak as 1/n to
    every harmonic). This is the per-blade form of the demodulation at nψ of
    van Engelen (2006) Eq. 15 / 22 / 26, and equals the Fourier coefficients of
    the revolution when the samples are uniform in azimuth.
    """
    single = np.ndim(signals) == 1
    if single:
        values = finite_array(name, signals, ndim=1)[:, None]
    else:
        values = finite_array(name, signals, ndim=2, columns="channels")
    psi = finite_array("azimuth", azimuth, ndim=1)
    same_length(name, values, psi.size, "azimuth")
    orders = np.asarray(harmonics, dtype=int)
    if orders.size == 0 or orders.min() < 1:
        raise ValueError(f"harmonics: expected harmonic numbers n >= 1, found {tuple(harmonics)}")

    turns = _turns(psi)
    revolution = np.floor(turns).astype(int)
    n_revolutions = int(revolution[-1])
    if n_revolutions < 1:
        raise ValueError(
            f"azimuth: record covers {turns[-1]:.2f} revolutions; harmonics need a whole revolution"
        )
    boundaries = np.searchsorted(revolution, np.arange(n_revolutions + 1))
    n_columns = 2 + 2 * orders.size
    fewest = max(n_columns + 1, 2 * int(orders.max()) + 1)
    per_revolution = np.diff(boundaries)
    if per_revolution.min() < fewest:
        r = int(np.argmin(per_revolution))
        raise ValueError(
            f"azimuth: revolution {r} has only {per_revolution[r]} samples; "
            f"harmonics up to {orders.max()}P need at least {fewest}"
        )

    angle = psi[:, None] * orders[None, :]
    trend = (turns - revolution - 0.5)[:, None]
    basis = np.hstack((np.ones_like(trend), trend, np.cos(angle), np.sin(angle)))
    coefficients = np.empty((n_revolutions, n_columns, values.shape[1]))
    for r in range(n_revolutions):
        rows = slice(boundaries[r], boundaries[r + 1])
        coefficients[r] = np.linalg.lstsq(basis[rows], values[rows], rcond=None)[0]
    cosine = coefficients[:, 2 : 2 + orders.size, :]
    sine = coefficients[:, 2 + orders.size :, :]
    synchronous = np.abs(np.mean(cosine - 1j * sine, axis=0)).T
    per_revolution_rms = np.sqrt(np.mean(cosine**2 + sine**2, axis=0)).T
    if single:
        synchronous, per_revolution_rms = synchronous[0], per_revolution_rms[0]
    return HarmonicAmplitudes(
        harmonics=tuple(int(n) for n in orders),
        amplitude=synchronous,
        amplitude_per_revolution_rms=per_revolution_rms,
        revolutions=n_revolutions,
    )
