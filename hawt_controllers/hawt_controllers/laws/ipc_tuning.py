"""Design of one harmonic's IPC loop: integral gain for a bandwidth, phase offset for a delay.

Both functions return values; nothing is stored.

van Engelen (2006) eq. 17: in the MBC frame each axis of harmonic n is a delayed
proportional plant, ``δM_axis(t) = k θ_axis(t − τ) + disturbance``, with
k = dM/dθ [N·m/rad] (negative for out-of-plane moments) and τ the loop delay
(measurement, processing, pitch actuation; 0.2 s in the paper). With the law
θ = k_i ∫ M_f dt on the pre-filtered moment M_f = F M, the loop gain is::

    L(jω) = −k_i k F(jω) e^{−jωτ} / (jω)

The crossover |L(jω_c)| = 1 at the target bandwidth gives
``k_i = −sign(k) ω_c / (|k| |F(jω_c)|)`` (van Engelen: I-control at ca. 0.1 Hz,
"basic scalar control theory ... phase and gain margins"), and the phase margin
is ``π/2 − ω_c τ + ∠F(jω_c)`` (82.8° for 0.1 Hz and 0.2 s without filter,
seed003 notes §3.6 [derived]).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hawt_core.validation import require_finite, require_nonnegative, require_positive
from hawt_core.exceptions import ConfigurationError
from hawt_controllers.laws.filters import DiscreteFilter

__all__ = ["IntegralGainDesign", "design_integral_gain", "phase_offset_for_delay"]


@dataclass(frozen=True)
class IntegralGainDesign:
    """Result of :func:`design_integral_gain`.

    Attributes
    ----------
    integral_gain : float
        k_i [rad/(N·m·s)], signed for negative feedback.
    crossover_frequency : float
        ω_c [rad/s] where |L| = 1 (the requested bandwidth).
    phase_margin : float
        [rad], > 0.
    """

    integral_gain: float
    crossover_frequency: float
    phase_margin: float


def design_integral_gain(
    sensitivity: float,
    bandwidth: float,
    loop_delay: float = 0.0,
    prefilter: DiscreteFilter | None = None,
) -> IntegralGainDesign:
    """Integral gain of a harmonic IPC loop for a target bandwidth (van Engelen 2006 §3.3).

    Parameters
    ----------
    sensitivity : float
        k = dM/dθ of the harmonic's MBC axes [N·m/rad], non-zero (negative for
        out-of-plane root moments pitched to feather).
    bandwidth : float
        Target crossover ω_c [rad/s] (van Engelen: ca. 0.1 Hz = 0.628 rad/s).
    loop_delay : float, optional
        Total loop delay τ [s] (van Engelen: 0.2 s), >= 0.
    prefilter : DiscreteFilter, optional
        The IPC pre-filter; its gain and phase at ω_c enter the design.

    Returns
    -------
    IntegralGainDesign

    Raises
    ------
    ConfigurationError
        ``sensitivity`` zero/NaN, ``bandwidth`` not > 0, ``loop_delay`` < 0, or
        ``bandwidth`` for which the loop has no phase margin left.

    Examples
    --------
    >>> d = design_integral_gain(-1.0e6, 2 * math.pi * 0.1, loop_delay=0.2)
    >>> round(d.integral_gain * 1e7, 4), round(math.degrees(d.phase_margin), 1)
    (6.2832, 82.8)
    """
    k = require_finite("sensitivity", sensitivity)
    if k == 0.0:
        raise ConfigurationError("sensitivity", "must be non-zero")
    wc = require_positive("bandwidth", bandwidth)
    tau = require_nonnegative("loop_delay", loop_delay)
    response = complex(1.0) if prefilter is None else complex(prefilter.frequency_response(wc)[0])
    if abs(response) == 0.0:
        raise ConfigurationError("bandwidth", "the prefilter blocks the crossover frequency")
    margin = math.pi / 2.0 - wc * tau + float(np.angle(response))
    if margin <= 0.0:
        raise ConfigurationError(
            "bandwidth", f"{wc} rad/s leaves no phase margin ({math.degrees(margin):.1f} deg) with this delay/filter"
        )
    return IntegralGainDesign(
        integral_gain=-math.copysign(wc / (abs(k) * abs(response)), k),
        crossover_frequency=wc,
        phase_margin=margin,
    )


def phase_offset_for_delay(harmonic: int, rotor_speed: float, delay: float) -> float:
    """Phase offset φ_n = nΩτ that compensates a pure delay τ between command and blade.

    A delay τ in the rotating frame rotates the (cos_n, sin_n) plane by −nΩτ
    (seed003 notes §2.5 [derived]: 18°/36°/54° for n = 1/2/3 at 15 rpm, 0.2 s);
    remodulating with φ_n = nΩτ (:func:`hawt_core.rotor.mbc.mbc_inverse`) undoes it.

    Parameters
    ----------
    harmonic : int
        n >= 1.
    rotor_speed : float
        Ω [rad/s].
    delay : float
        τ [s], >= 0.

    Returns
    -------
    float
        φ_n [rad].
    """
    if harmonic < 1:
        raise ConfigurationError("harmonic", f"must be >= 1, found {harmonic}")
    return harmonic * require_finite("rotor_speed", rotor_speed) * require_nonnegative("delay", delay)
