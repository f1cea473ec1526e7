"""Pitch actuator activity: travel, peak rate and acceleration, duty cycle."""
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy import signal as sps

from ._checks import finite_array, same_length

__all__ = ["DEFAULT_RATE_THRESHOLD", "PitchActivity", "pitch_activity", "pitch_activity_convention"]

DEFAULT_RATE_THRESHOLD = float(np.deg2rad(0.1))
"""Pitch rate above which the actuator counts as moving: 0.1 °/s [rad/s]."""


@dataclass(frozen=True)
class PitchActivity:
    """Pitch activity per blade (arrays of shape (n_blades,)) and its conventions.

    Attributes
    ----------
    travel : numpy.ndarray
        Accumulated pitch travel Σ|Δθ| [rad].
    max_rate : numpy.ndarray
        max |θ̇| [rad/s].
    max_acceleration : numpy.ndarray
        max |θ̈| [rad/s²].
    duty_cycle : numpy.ndarray
        Fraction of samples with |θ̇| > ``rate_threshold`` [-].
    rate_threshold : float
        [rad/s].
    lowpass_cutoff : float or None
        Cut-off of the zero-phase low-pass applied before differencing [Hz]; None if none.
    """

    travel: np.ndarray
    max_rate: np.ndarray
    max_acceleration: np.ndarray
    duty_cycle: np.ndarray
    rate_threshold: float
    lowpass_cutoff: float | None

    @property
    def total_travel(self) -> float:
        """Travel summed over the blades [rad]."""
        return float(self.travel.sum())

    @property
    def overall_max_rate(self) -> float:
        """Largest |θ̇| of any blade [rad/s]."""
        return float(self.max_rate.max())

    @property
    def overall_max_acceleration(self) -> float:
        """Largest |θ̈| of any blade [rad/s²]."""
        return float(self.max_acceleration.max())

    @property
    def mean_duty_cycle(self) -> float:
        """Duty cycle averaged over the blades [-]."""
        return float(self.duty_cycle.mean())


def pitch_activity_convention(rate_threshold: float, lowpass_cutoff: float | None) -> str:
    """How `pitch_activity` obtains rate, acceleration, travel and duty cycle, for reports."""
    filtering = (
        "no filtering"
        if lowpass_cutoff is None
        else f"zero-phase 2nd-order Butterworth low-pass at {lowpass_cutoff:g} Hz first"
    )
    return (
        "rate and acceleration by 2nd-order central differences (numpy.gradient, edge_order=2) "
        f"of the recorded pitch, {filtering}; travel = sum |dtheta| of the same signal; "
        f"duty cycle = fraction of samples with |rate| > {rate_threshold:.6g} rad/s "
        f"({np.rad2deg(rate_threshold):.3g} deg/s)"
    )


def pitch_activity(
    time: ArrayLike,
    pitch: ArrayLike,
    *,
    rate_threshold: float = DEFAULT_RATE_THRESHOLD,
    lowpass_cutoff: float | None = None,
) -> PitchActivity:
    """Pitch travel, peak rate, peak acceleration and duty cycle of each blade.

    Parameters
    ----------
    time : array_like, shape (n_samples,)
        Sample times [s], strictly increasing.
    pitch : array_like, shape (n_samples, n_blades)
        Measured blade pitch θ [rad], positive towards feather.
    rate_threshold : float
        |θ̇| above which the actuator counts as active [rad/s]; default 0.1 °/s.
    lowpass_cutoff : float, optional
        If given, θ is first low-passed by a zero-phase (forward-backward)
        2nd-order Butterworth filter with this cut-off [Hz], e.g. to keep the
        steps of a sampled-and-held signal out of the acceleration. None: no filter.

    Returns
    -------
    PitchActivity

    Notes
    -----
    θ̇ and θ̈ are second-order central differences (one-sided second order at the
    ends) taken twice: θ̈_k ≈ (θ_{k+2} − 2θ_k + θ_{k−2}) / (4Δt²) on uniform steps.
    For a sine of frequency f sampled at f_s the peak rate is under-estimated by
    ≈ (2πf/f_s)²/6: 0.02 % for 3P of 12 rpm at 100 Hz. The figures compare with
    van Engelen (2006) §4: max |θ̇| ≈ 2, 7, 10, 12 °/s and max |θ̈| ≈ 3, 18, 27,
    50 °/s² for CPC, +IPC-1p, +2p, +3p.
    """
    t = finite_array("time", time, ndim=1)
    theta = finite_array("pitch", pitch, ndim=2)
    same_length("pitch", theta, t.size, "time")
    if t.size < 3:
        raise ValueError(f"time: {t.size} samples are too few for pitch activity (need 3)")
    if np.any(np.diff(t) <= 0.0):
        raise ValueError(f"time: not strictly increasing at sample {int(np.argmax(np.diff(t) <= 0.0)) + 1}")
    if not rate_threshold >= 0.0:
        raise ValueError(f"rate_threshold: expected a non-negative rate in rad/s, found {rate_threshold}")
    if lowpass_cutoff is not None:
        sample_rate = (t.size - 1) / (t[-1] - t[0])
        if not 0.0 < lowpass_cutoff < 0.5 * sample_rate:
            raise ValueError(
                f"lowpass_cutoff: expected 0 < cut-off < Nyquist {0.5 * sample_rate:g} Hz, "
                f"found {lowpass_cutoff}"
            )
        sos = sps.butter(2, lowpass_cutoff, fs=sample_rate, output="sos")
        theta = sps.sosfiltfilt(sos, theta, axis=0)
    rate = np.gradient(theta, t, axis=0, edge_order=2)
    acceleration = np.gradient(rate, t, axis=0, edge_order=2)
    return PitchActivity(
        travel=np.abs(np.diff(theta, axis=0)).sum(axis=0),
        max_rate=np.abs(rate).max(axis=0),
        max_acceleration=np.abs(acceleration).max(axis=0),
        duty_cycle=np.mean(np.abs(rate) > rate_threshold, axis=0),
        rate_threshold=float(rate_threshold),
        lowpass_cutoff=None if lowpass_cutoff is None else float(lowpass_cutoff),
    )
