"""Spatial repetitive control: a learning memory indexed by azimuth (Fratini 2019 §4.2).

The iterative-learning update of the thesis (eq. 4.4, with the learning filter L a gain
and a forward shift, "first strategy" of §4.2), one iteration per rotor revolution::

    u_{j+1}(ψ) = Q[u_j](ψ) + G · e_j(ψ + δ)

- ψ ∈ [0, 2π) is an azimuth, not a sample index ("spatial" repetitive control, §4.2): the
  memory holds one value per azimuth bin, samples land in the two nearest bins by linear
  interpolation, so any rotor speed and any dt index the same memory;
- e_j is the error seen during revolution j, binned; δ is the shift as an angle (the
  thesis gives it in samples, 70 and 120, and in degrees, 280°: erratum 10 of the notes);
- Q is the robustness filter: identity (the thesis's choice, α0 = 1), the three-tap smoother
  of eq. 4.6 (α1 u(k−1) + α0 u(k) + α1 u(k+1), 2α1 + α0 = 1), or a zero-phase low-pass that
  keeps the harmonics 0..n_Q of the revolution;
- G = g·s: a dimensionless learning gain g (the fraction of an error the next revolution
  removes when the plant is as modelled) times the inverse plant gain s the caller gives
  (e.g. 1/(dM/dθ) for a flap moment), so g carries over between turbines.

The memory learns when a revolution is complete (the azimuth wraps), from the bins the
revolution filled (a bin no sample reached is interpolated from its neighbours; the first,
partial revolution after a reset teaches nothing), and is clipped to [``lower``, ``upper``]:
its size and its values stay bounded however long it runs.

Convergence (:func:`learning_factors`): if a unit change of u at ψ moves the error at
ψ + λ (the plant's lag as an azimuth, λ), the memory's harmonic n evolves per revolution by
the factor ``Q_n − g·exp(i n (δ − λ))``; the learning converges when every factor's
magnitude is below 1 over the harmonics the bins resolve. With δ = λ and Q = identity every
factor is 1 − g (0 < g < 2 converges); a shift that misses the lag needs Q to cut the
harmonics where n(δ − λ) has turned the correction round.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping, Optional, Sequence, Tuple

import numpy as np

from hawt_core.parameter_table import ParameterSpec

from hawt_core.validation import finite_floats, require_finite, require_nonnegative
from hawt_core.exceptions import ConfigurationError

__all__ = ["Q_FILTERS", "RepetitiveConfig", "AzimuthMemory", "learning_factors", "convergence_problem",
           "memory_parameters", "memory_config"]

Q_FILTERS = ("identity", "smoother", "lowpass")
TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class RepetitiveConfig:
    """Tuning of one learning memory (module notes).

    Attributes
    ----------
    bins : int
        Azimuth bins per revolution (the memory's resolution); harmonics up to bins/2 are resolved.
    learning_gain : float
        g, the fraction of the error learnt per revolution (dimensionless; 0 learns nothing).
    shift : float
        δ, the forward shift of the error [rad].
    q_filter : str
        'identity', 'smoother' (eq. 4.6) or 'lowpass' (zero-phase, harmonics 0..``q_harmonics``).
    smoothing : float
        α1 of the smoother (α0 = 1 − 2α1), in [0, 0.5].
    q_harmonics : int
        Highest harmonic of the revolution the low-pass keeps.
    lower, upper : float
        Bounds of the memory's values (units of the output): ±amplitude for a correction, the
        actuator's range for a memory that holds the whole output.
    """

    bins: int = 72
    learning_gain: float = 0.3
    shift: float = 0.0
    q_filter: str = "identity"
    smoothing: float = 0.25
    q_harmonics: int = 6
    lower: float = -math.inf
    upper: float = math.inf

    def validate(self) -> None:
        """Raise :class:`ConfigurationError` naming the first field that cannot be used."""
        if not 4 <= self.bins <= 4096:
            raise ConfigurationError("bins", f"must be in 4..4096, found {self.bins}")
        require_nonnegative("learning_gain", self.learning_gain)
        if not 0.0 <= require_finite("shift", self.shift) < TWO_PI * (1.0 - 2.0 / self.bins):
            raise ConfigurationError("shift", f"must be in [0, 2*pi - 2 bins) so that a bin is learnt before the "
                                              f"rotor is back at it, found {self.shift}")
        if self.q_filter not in Q_FILTERS:
            raise ConfigurationError("q_filter", f"{self.q_filter!r} is not one of {', '.join(Q_FILTERS)}")
        if not 0.0 <= self.smoothing <= 0.5:
            raise ConfigurationError("smoothing", f"alpha1 must be in [0, 0.5], found {self.smoothing}")
        if not 0 <= self.q_harmonics <= self.bins // 2:
            raise ConfigurationError("q_harmonics", f"must be in 0..bins/2 = {self.bins // 2}, found "
                                                    f"{self.q_harmonics}")
        if not self.lower < self.upper:
            raise ConfigurationError("lower", f"must be < upper ({self.upper}), found {self.lower}")

    def q_response(self) -> np.ndarray:
        """Q's gain on harmonics 0..bins/2 of the revolution (real: every Q here is zero-phase)."""
        n = np.arange(self.bins // 2 + 1)
        if self.q_filter == "smoother":
            return (1.0 - 2.0 * self.smoothing) + 2.0 * self.smoothing * np.cos(TWO_PI * n / self.bins)
        if self.q_filter == "lowpass":
            return (n <= self.q_harmonics).astype(float)
        return np.ones(n.size)


def memory_parameters(q_harmonics: int) -> Tuple[ParameterSpec, ...]:
    """The parameter rows every controller with a learning memory shares (bins and Q), its low-pass keeping
    harmonics up to ``q_harmonics`` by default; ``learning_gain`` and ``shift`` each controller states itself."""
    return (
        ParameterSpec("bins", 72, "azimuth bins of each memory", minimum=8, maximum=1024),
        ParameterSpec("q_filter", "lowpass", "robustness filter Q: identity, smoother (Fratini eq. 4.6) or "
                      "lowpass (zero-phase, harmonics 0..q_harmonics)", choices=Q_FILTERS),
        ParameterSpec("smoothing", 0.25, "alpha1 of the smoother", minimum=0.0, maximum=0.5),
        ParameterSpec("q_harmonics", q_harmonics, "highest harmonic of the revolution the lowpass Q keeps",
                      minimum=0, maximum=512),
    )


def memory_config(values: Mapping[str, Any], lower: float, upper: float) -> RepetitiveConfig:
    """The memory's tuning from a controller's parameter values (:func:`memory_parameters`, ``learning_gain``,
    ``shift``) and the bounds of its values."""
    return RepetitiveConfig(bins=values["bins"], learning_gain=values["learning_gain"], shift=values["shift"],
                            q_filter=values["q_filter"], smoothing=values["smoothing"],
                            q_harmonics=values["q_harmonics"], lower=lower, upper=upper)


def learning_factors(config: RepetitiveConfig, plant_lag: float) -> np.ndarray:
    """|Q_n − g·exp(i n (δ − λ))| for n = 0..bins/2: the memory's factor per revolution (module notes).

    Fratini 2019 eq. 4.4 in the frequency domain of the revolution, for a plant that
    moves the error at ψ + λ by the change of u at ψ with unit normalised gain.
    """
    n = np.arange(config.bins // 2 + 1)
    return np.abs(config.q_response() - config.learning_gain * np.exp(1j * n * (config.shift - plant_lag)))


def convergence_problem(config: RepetitiveConfig, plant_lag: float) -> Optional[str]:
    """Why the learning would diverge for a plant lag λ [rad], naming the harmonic; None if it converges."""
    factors = learning_factors(config, plant_lag)
    worst = int(np.argmax(factors))
    if factors[worst] < 1.0:
        return None
    return (f"learning_gain {config.learning_gain:g} with shift {math.degrees(config.shift):.1f} deg and "
            f"q_filter {config.q_filter} diverges at harmonic {worst} of the revolution (factor "
            f"{factors[worst]:.3f} >= 1 per revolution for a plant lag of {math.degrees(plant_lag):.1f} deg): "
            f"lower learning_gain, bring shift nearer the lag, or cut that harmonic with q_filter")


class AzimuthMemory:
    """One azimuth-indexed learning memory (module notes; Fratini 2019 eqs. 4.4, 4.6).

    The update runs bin by bin as the rotor turns: once the error of revolution j is complete
    at ψ_b + δ (its two bins passed), bin b of the memory becomes
    Q[u](b) + g·s·e_j(ψ_b + δ), before the rotor is back at ψ_b for revolution j + 1. Every bin
    is so played with u_j during revolution j, whatever the azimuth of the update, and with
    Q = identity the error of each harmonic falls by exactly the factor of :func:`learning_factors`
    per revolution. (Q acts on the memory as it stands: the bins just behind the rotor already
    hold revolution j + 1.)

    Parameters
    ----------
    config : RepetitiveConfig
        Its tuning (validated here).
    error_scale : float
        s in G = g·s: output units per error unit (e.g. 1/(dM/dθ) [rad/(N·m)]).
    """

    def __init__(self, config: RepetitiveConfig, error_scale: float) -> None:
        self.frozen = False
        self.memory = np.zeros(config.bins)
        self.config = config
        self.reconfigure(config, error_scale)
        self.reset()

    def reset(self, memory: Optional[Sequence[float]] = None) -> None:
        """Forget the learning (or start from ``memory``, one value per bin) and the errors seen so far."""
        bins = self.config.bins
        values = np.zeros(bins) if memory is None else np.asarray(finite_floats("memory", memory))
        if values.shape != (bins,):
            raise ConfigurationError("memory", f"expected {bins} values (one per bin), found {values.size}")
        self.memory = np.clip(values, self.config.lower, self.config.upper)
        self.revolutions = 0
        self._forget_errors()

    def freeze(self, frozen: bool) -> None:
        """Stop (True) or resume learning; the output goes on from the memory. Learning resumes from
        errors seen after the resume."""
        if self.frozen and not frozen:
            self._forget_errors()
        self.frozen = bool(frozen)

    def reconfigure(self, config: RepetitiveConfig, error_scale: float) -> None:
        """New tuning at a step boundary; the learnt memory is kept (resampled if the bin count changes)."""
        config.validate()
        if config.bins != self.config.bins:
            old = np.append(self.memory, self.memory[0])
            self.memory = np.interp(np.linspace(0.0, 1.0, config.bins, endpoint=False),
                                    np.linspace(0.0, 1.0, self.config.bins + 1), old)
            self.config = config
            self._forget_errors()
        self.config = config
        self.error_scale = require_finite("error_scale", error_scale)
        self.memory = np.clip(self.memory, config.lower, config.upper)
        self._q_rows = _q_matrix(config)
        shift = config.shift / TWO_PI * config.bins
        self._shift_bins, self._shift_fraction = int(shift), shift - int(shift)

    def output(self, azimuth: float) -> float:
        """u(ψ): the memory linearly interpolated at ``azimuth`` [rad], periodic."""
        position = (azimuth % TWO_PI) / TWO_PI * self.config.bins
        lower = int(position)
        fraction = position - lower
        bins = self.config.bins
        return (1.0 - fraction) * float(self.memory[lower % bins]) + fraction * float(self.memory[(lower + 1) % bins])

    def step(self, azimuth: float, error: float) -> float:
        """Take the error of this sample at ``azimuth`` [rad], learn the bins it completes, return u(ψ).

        ``error`` is e = reference − measurement (eq. 4.3), finite (the caller checks its inputs).
        """
        bins = self.config.bins
        psi = azimuth % TWO_PI
        if math.isnan(self._position):
            self._position = psi / TWO_PI * bins
            self._completed = math.floor(self._position) - 1
        else:
            turned = (psi - self._last_azimuth + math.pi) % TWO_PI - math.pi
            self._position += turned / TWO_PI * bins
        self._last_azimuth = psi
        if not self.frozen:
            lower = math.floor(self._position)
            fraction = self._position - lower
            self._sums[lower % bins] += (1.0 - fraction) * error
            self._weights[lower % bins] += 1.0 - fraction
            self._sums[(lower + 1) % bins] += fraction * error
            self._weights[(lower + 1) % bins] += fraction
            while self._completed < lower - 1:  # bin c is complete once the rotor is past c + 1
                self._completed += 1
                self._complete_bin(self._completed)
        return self.output(psi)

    def _forget_errors(self) -> None:
        bins = self.config.bins
        self._sums, self._weights = [0.0] * bins, [0.0] * bins
        self._errors = [math.nan] * bins
        self._position = self._last_azimuth = math.nan
        self._completed = 0

    def _complete_bin(self, index: int) -> None:
        """e_j of bin ``index`` (unwrapped) is known: store it and learn the memory bin it completes."""
        bins = self.config.bins
        c = index % bins
        weight = self._weights[c]
        self._errors[c] = self._sums[c] / weight if weight > 0.0 else self._errors[(c - 1) % bins]
        self._sums[c] = self._weights[c] = 0.0
        if c == bins - 1:
            self.revolutions += 1
        b = (index - 1 - self._shift_bins) % bins
        shifted = (1.0 - self._shift_fraction) * self._errors[(c - 1) % bins] + self._shift_fraction * self._errors[c]
        if math.isnan(shifted):  # the errors of this revolution began after a reset: nothing to learn from yet
            return
        learnt = float(self._q_rows[b] @ self.memory) + self.config.learning_gain * self.error_scale * shifted
        self.memory[b] = min(max(learnt, self.config.lower), self.config.upper)


def _q_matrix(config: RepetitiveConfig) -> np.ndarray:
    """Q as a circulant matrix over the bins: row b gives Q[u](b) (eq. 4.6 or the zero-phase low-pass)."""
    bins = config.bins
    offsets = np.arange(bins)
    if config.q_filter == "smoother":
        kernel = np.zeros(bins)
        kernel[[0, 1, -1]] = 1.0 - 2.0 * config.smoothing, config.smoothing, config.smoothing
    elif config.q_filter == "lowpass":
        n = np.arange(1, config.q_harmonics + 1)
        kernel = (1.0 + 2.0 * np.cos(TWO_PI * np.outer(offsets, n) / bins).sum(axis=1)) / bins
        if 2 * config.q_harmonics == bins:  # the Nyquist harmonic has one term, not two
            kernel -= np.cos(np.pi * offsets) / bins
    else:
        kernel = (offsets == 0).astype(float)
    return kernel[(offsets[None, :] - offsets[:, None]) % bins]
