"""How well a controller estimates the wind: its multi-blade wind estimate against the plant's truth (issue 16).

Selvam et al. (2009, §3.2) estimate the cos/sin blade-effective wind û^cm in a Kalman filter with random-walk
wind states and feed it forward. A bag holds the estimate (``control/<controller>/wind_estimate``) and the
truth (``plant/state`` ``effective_wind_cos/sin``: the wind at 3/4 of the tip radius, in multi-blade
coordinates). The estimate is relative to the wind of the design's operating point and also takes up the
constant 1P moment of the shear, so it is compared after removing each signal's mean over the compared span:
per axis the correlation coefficient, the RMS of the error and of the truth, and the Welch spectra of the
error and of the truth (where the error spectrum is below the truth's, the estimate follows the wind).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np
from numpy.typing import ArrayLike

from .spectra import power_spectrum

__all__ = ["AXES", "EstimateQuality", "estimate_quality", "plot_wind_estimate"]

AXES = ("cos", "sin")


@dataclass(frozen=True)
class EstimateQuality:
    """The estimate against the truth on one axis (means removed).

    Attributes
    ----------
    correlation : float
        Pearson correlation of estimate and truth.
    error_rms, truth_rms : float
        RMS of estimate − truth and of the truth [m/s].
    offset : float
        Mean of estimate − truth [m/s] (the operating point's wind and the shear taken up).
    frequencies, error_psd, truth_psd : numpy.ndarray
        Welch spectra [Hz], [(m/s)²/Hz].
    """

    correlation: float
    error_rms: float
    truth_rms: float
    offset: float
    frequencies: np.ndarray
    error_psd: np.ndarray
    truth_psd: np.ndarray

    def summary(self) -> dict:
        """The scalar figures (JSON-ready)."""
        return {"correlation": self.correlation, "error_rms": self.error_rms, "truth_rms": self.truth_rms,
                "offset": self.offset}


def estimate_quality(truth: ArrayLike, estimate: ArrayLike, sample_rate: float,
                     segment_duration: float = 60.0) -> EstimateQuality:
    """Compare one axis of a wind estimate with the truth, sampled alike (see the module notes)."""
    truth, estimate = np.asarray(truth, dtype=float), np.asarray(estimate, dtype=float)
    if truth.shape != estimate.shape or truth.ndim != 1 or truth.size < 3:
        raise ValueError(f"estimate and truth: expected equal 1-D series of 3 or more samples, found shapes "
                         f"{estimate.shape} and {truth.shape}")
    offset = float(np.mean(estimate - truth))
    t, e = truth - truth.mean(), estimate - estimate.mean()
    error = e - t
    truth_spectrum = power_spectrum(t, sample_rate, segment_duration, name="truth")
    error_spectrum = power_spectrum(error, sample_rate, segment_duration, name="error")
    scale = float(np.sqrt(np.sum(t * t) * np.sum(e * e)))
    return EstimateQuality(float(np.sum(t * e) / scale) if scale > 0 else float("nan"),
                           float(np.sqrt(np.mean(error ** 2))), float(np.sqrt(np.mean(t ** 2))), offset,
                           truth_spectrum.frequency, error_spectrum.density, truth_spectrum.density)


def plot_wind_estimate(time: ArrayLike, truth: Mapping[str, ArrayLike], estimate: Mapping[str, ArrayLike],
                       quality: Mapping[str, EstimateQuality], title: str):
    """A figure per axis (cos, sin): estimate and truth over time (means removed), and the spectra of the error
    and of the truth."""
    from matplotlib.figure import Figure

    figure = Figure(figsize=(11, 6.5), layout="constrained")
    axes = figure.subplots(2, 2)
    time = np.asarray(time)
    for row, axis in enumerate(AXES):
        t, e, q = np.asarray(truth[axis]), np.asarray(estimate[axis]), quality[axis]
        ax = axes[row, 0]
        ax.plot(time, t - t.mean(), lw=0.8, label="truth (plant, 3/4 R)")
        ax.plot(time, e - e.mean(), lw=0.8, label="estimate")
        ax.set_ylabel(f"{axis} wind − mean [m/s]")
        ax.set_title(f"{axis}: correlation {q.correlation:.2f}, error RMS {q.error_rms:.2f} of {q.truth_rms:.2f} m/s",
                     fontsize=9)
        ax = axes[row, 1]
        ax.loglog(q.frequencies[1:], q.truth_psd[1:], lw=0.8, label="truth")
        ax.loglog(q.frequencies[1:], q.error_psd[1:], lw=0.8, label="error (estimate − truth)")
        ax.set_ylabel("PSD [(m/s)²/Hz]")
    for ax in axes[1]:
        ax.set_xlabel("time [s]" if ax is axes[1, 0] else "frequency [Hz]")
    axes[0, 0].legend(fontsize=8)
    axes[0, 1].legend(fontsize=8)
    figure.suptitle(title)
    return figure
