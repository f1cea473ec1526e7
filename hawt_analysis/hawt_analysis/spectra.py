"""Power spectral densities of load channels, their peaks and the rotor harmonics nP."""
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy import ndimage
from scipy import signal as sps

from ._checks import finite_array

__all__ = [
    "PowerSpectrum",
    "SpectralPeak",
    "power_spectrum",
    "rotor_harmonic_frequencies",
    "spectral_peaks",
]

_PEAK_WINDOW = 21
"""Bins over which a peak's prominence and the running median of the log-PSD are taken."""
_PEAK_SCATTERS = 7.0
"""Prominence a peak needs, in robust standard deviations of the log-PSD scatter."""
_PEAK_MIN_DECADES = 0.3
"""Prominence a peak needs at least, in decades."""


@dataclass(frozen=True)
class PowerSpectrum:
    """One-sided power spectral density.

    Attributes
    ----------
    frequency : numpy.ndarray, shape (n_frequencies,)
        Frequencies [Hz], from 0 to the Nyquist frequency.
    density : numpy.ndarray, shape (n_frequencies,)
        PSD [unit²/Hz] (e.g. (N·m)²/Hz); ∫ density df = variance.
    segment_duration : float
        Length of the Welch segments actually used [s].
    """

    frequency: np.ndarray
    density: np.ndarray
    segment_duration: float

    @property
    def resolution(self) -> float:
        """Frequency resolution Δf = 1 / segment_duration [Hz]."""
        return 1.0 / self.segment_duration


@dataclass(frozen=True)
class SpectralPeak:
    """A peak of a PSD: frequency [Hz], density [unit²/Hz], harmonic n if it sits at nP, else None."""

    frequency: float
    density: float
    harmonic: int | None


def power_spectrum(
    signal: ArrayLike, sample_rate: float, segment_duration: float = 60.0, *, name: str = "signal"
) -> PowerSpectrum:
    """Welch estimate of the one-sided PSD.

    Parameters
    ----------
    signal : array_like, shape (n_samples,)
        Uniformly sampled channel [any unit].
    sample_rate : float
        Sampling frequency [Hz].
    segment_duration : float
        Welch segment length [s]; shortened to the record if the record is shorter.
        The default 60 s gives Δf ≈ 0.017 Hz, about a tenth of 1P of a multi-MW
        rotor (0.2 Hz at 12 rpm), and 19 averages over a 600 s record.
    name : str
        Name used in error messages.

    Returns
    -------
    PowerSpectrum

    Notes
    -----
    Hann window, 50 % overlap, segment means removed, density scaling
    (``scipy.signal.welch``; Welch 1967).
    """
    values = finite_array(name, signal, ndim=1)
    if not sample_rate > 0.0:
        raise ValueError(f"sample_rate: expected a positive frequency in Hz, found {sample_rate}")
    if not segment_duration > 0.0:
        raise ValueError(f"segment_duration: expected a positive length in s, found {segment_duration}")
    segment_samples = min(values.size, int(round(segment_duration * sample_rate)))
    if segment_samples < 8:
        raise ValueError(f"{name}: {values.size} samples are too few for a spectrum (need 8)")
    frequency, density = sps.welch(
        values, fs=sample_rate, window="hann", nperseg=segment_samples, detrend="constant", scaling="density"
    )
    return PowerSpectrum(frequency=frequency, density=density, segment_duration=segment_samples / sample_rate)


def rotor_harmonic_frequencies(rotor_speed: float, harmonics: ArrayLike = (1, 2, 3, 4, 5, 6)) -> np.ndarray:
    """Frequencies f_nP = n·Ω / (2π) [Hz] of the rotor harmonics for mean rotor speed Ω [rad/s]."""
    return np.asarray(harmonics, dtype=float) * rotor_speed / (2.0 * np.pi)


def spectral_peaks(
    spectrum: PowerSpectrum, n_peaks: int = 8, rotor_frequency: float | None = None
) -> list[SpectralPeak]:
    """The most prominent peaks of a PSD, in increasing frequency.

    Parameters
    ----------
    spectrum : PowerSpectrum
    n_peaks : int
        Largest number of peaks returned.
    rotor_frequency : float, optional
        1P frequency [Hz]; a peak within 1.5 Δf of n·1P (n ≥ 1) is labelled harmonic n.

    Returns
    -------
    list of SpectralPeak

    Notes
    -----
    Peaks are local maxima of L = log10(density) (0 Hz excluded) ranked by their
    prominence within ±10 bins (``scipy.signal.find_peaks``, ``wlen=21``). A peak
    must stand out of the estimate's own scatter: its prominence must reach 7 σ_L
    and 0.3 decade, where σ_L = 1.4826·MAD of L about its 21-bin running median
    (the scatter grows as the number of Welch averages falls; white noise of 600 s
    in 60 s segments reaches about 5 σ_L at most over 3000 bins).
    """
    if n_peaks < 1:
        raise ValueError(f"n_peaks: expected at least 1, found {n_peaks}")
    level = np.log10(np.maximum(spectrum.density[1:], np.finfo(float).tiny))
    residual = level - ndimage.median_filter(level, _PEAK_WINDOW, mode="nearest")
    scatter = 1.4826 * np.median(np.abs(residual - np.median(residual)))
    threshold = max(_PEAK_MIN_DECADES, _PEAK_SCATTERS * scatter)
    index, properties = sps.find_peaks(level, prominence=threshold, wlen=_PEAK_WINDOW)
    strongest = index[np.argsort(properties["prominences"])[::-1][:n_peaks]] + 1
    peaks = []
    for k in np.sort(strongest):
        frequency = float(spectrum.frequency[k])
        harmonic = None
        if rotor_frequency is not None and rotor_frequency > 0.0:
            n = int(round(frequency / rotor_frequency))
            if n >= 1 and abs(frequency - n * rotor_frequency) <= 1.5 * spectrum.resolution:
                harmonic = n
        peaks.append(SpectralPeak(frequency=frequency, density=float(spectrum.density[k]), harmonic=harmonic))
    return peaks
