"""Discrete filters with explicit state: low-pass (1st, 2nd order), notch, cascades.

Continuous prototypes are those of ROSCO (``Filters.f90``; anchor_windcontrol
notes §1.3)::

    first-order low-pass   H(s) = ω / (s + ω)
    second-order low-pass  H(s) = ω² / (s² + 2ζω s + ω²)
    notch                  H(s) = (s² + 2β_num ω s + ω²) / (s² + 2β_den ω s + ω²)

They are discretised with the bilinear (Tustin) transform like ROSCO, but with
frequency prewarping at ω, so the discrete filter has exactly the prototype's
gain at ω (−3 dB at the corner of the first-order filter, depth β_num/β_den at
the notch). ROSCO does not prewarp; the difference is of relative order
(ω·dt)²/12. The filters run as second-order sections in scipy's layout (``sosfilt``), with the state carried
explicitly like ``zi``/``zf``. The Tustin substitution of a first- or second-order prototype, and the steady state of
a constant input, are written out (:func:`_bilinear`, :meth:`DiscreteFilter.reset`) rather than taken from
:mod:`scipy.signal` (``bilinear``, ``tf2sos``, ``sosfilt_zi``; the tests check them against it): importing
scipy.signal, with the scipy.stats and scipy.optimize it loads, took 0.55 s of every controller process that builds
a filter. :mod:`scipy.signal` still filters blocks and computes frequency responses, imported there.

:class:`ExponentialLowPass` is the recursive single-pole filter of the NREL 5 MW
baseline controller (Jonkman et al. 2009, ch. 7), which takes the time step per
call.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from hawt_core.validation import (
    finite_array,
    finite_float,
    require_below_nyquist,
    require_nonnegative,
    require_positive,
    require_time_step,
)
from hawt_core.exceptions import ConfigurationError, InputError

__all__ = [
    "DiscreteFilter",
    "ExponentialLowPass",
    "cascade",
    "first_order_lowpass",
    "notch",
    "second_order_lowpass",
]


class DiscreteFilter:
    """A stable discrete IIR filter in second-order sections, with its own state.

    The filter runs independently on every channel (e.g. the cos and sin axes of
    one harmonic): samples have shape ``channels``, blocks ``(T, *channels)``.

    Parameters
    ----------
    sos : array_like, shape (n_sections, 6)
        Second-order sections ``[b0, b1, b2, 1, a1, a2]`` (scipy's layout).
    dt : float
        Sample time the coefficients were designed for [s].
    channels : tuple of int, optional
        Shape of one sample; ``()`` (default) for a scalar signal.

    Raises
    ------
    ConfigurationError
        ``sos`` with NaN/inf, a wrong shape, a0 != 1, or a pole on or outside the
        unit circle (unstable design); ``dt`` not > 0.

    Notes
    -----
    Each section computes, in transposed direct form II (scipy ``sosfilt``),
    y = (b0 + b1 z⁻¹ + b2 z⁻²)/(1 + a1 z⁻¹ + a2 z⁻²) u. The state starts at
    zero; :meth:`reset` sets it to the steady state of a constant input
    (``scipy.signal.sosfilt_zi``) for a bumpless start.
    """

    def __init__(self, sos: ArrayLike, dt: float, channels: tuple[int, ...] = ()) -> None:
        sos = np.atleast_2d(np.asarray(sos, dtype=float))
        if sos.ndim != 2 or sos.shape[1] != 6 or sos.shape[0] == 0:
            raise ConfigurationError("sos", f"expected shape (n_sections, 6), found {sos.shape}")
        if not np.all(np.isfinite(sos)):
            raise ConfigurationError("sos", "NaN or inf in the filter coefficients")
        if not np.allclose(sos[:, 3], 1.0):
            raise ConfigurationError("sos", "a0 of every section must be 1")
        poles = np.concatenate([np.roots(section[3:]) for section in sos])
        if poles.size and np.max(np.abs(poles)) >= 1.0:
            raise ConfigurationError(
                "sos", f"unstable design: pole magnitude {np.max(np.abs(poles)):.6g} >= 1"
            )
        self.sos = sos
        self.dt = require_positive("dt", dt)
        self.channels = tuple(int(c) for c in channels)
        self._zi_unit = _unit_steady_state(sos)
        self._sections = [tuple(row) for row in sos.tolist()]
        self._size = math.prod(self.channels)
        self.state = np.zeros((sos.shape[0], 2) + self.channels)

    @property
    def state(self) -> np.ndarray:
        """The sections' delay states, shape ``(n_sections, 2, *channels)`` (scipy's ``zi`` layout)."""
        return np.array(self._state).reshape((len(self._sections), 2) + self.channels)

    @state.setter
    def state(self, value: ArrayLike) -> None:
        self._state = np.asarray(value, dtype=float).reshape(len(self._sections), 2, self._size).tolist()

    @property
    def dc_gain(self) -> float:
        """Gain at zero frequency, H(z = 1)."""
        b = self.sos[:, :3].sum(axis=1)
        a = self.sos[:, 3:].sum(axis=1)
        return float(np.prod(b / a))

    def frequency_response(self, omega: ArrayLike) -> np.ndarray:
        """Complex gain H(e^{jω·dt}) at angular frequencies ``omega`` [rad/s]."""
        omega = np.atleast_1d(np.asarray(omega, dtype=float))
        from scipy import signal

        _, h = signal.sosfreqz(self.sos, worN=omega * self.dt)
        return h

    def reset(self, initial: ArrayLike = 0.0) -> None:
        """Set the state to the steady state of a constant input ``initial``.

        Parameters
        ----------
        initial : array_like, shape ``channels`` or broadcastable to it
            Constant input the filter is assumed to have seen forever; the
            output then starts at ``dc_gain * initial`` with no transient.
        """
        value = np.broadcast_to(finite_array("initial", initial), self.channels)
        self.state = self._zi_unit.reshape(self._zi_unit.shape + (1,) * len(self.channels)) * value

    def step(self, sample: ArrayLike) -> np.ndarray:
        """Filter one sample (shape ``channels``) and return the output sample.

        Runs the transposed direct form II recursion of ``sosfilt`` on the
        state directly (same state layout, :meth:`step_values`), which saves
        ``sosfilt``'s per-call checks (~45 µs) on the per-step path;
        :meth:`filter` calls ``sosfilt``.
        """
        x = finite_array("sample", sample)
        if x.shape != self.channels:
            raise InputError("sample", f"expected shape {self.channels}, found {x.shape}")
        return np.array(self.step_values(x.ravel().tolist())).reshape(self.channels)

    def step_values(self, sample: list[float]) -> list[float]:
        """:meth:`step` on plain floats, one per channel (flattened), already checked: the per-step path.

        The recursion of :meth:`step` itself, without arrays (numpy's per-call cost on two
        values is many times the arithmetic).
        """
        output = []
        for channel, x in enumerate(sample):
            for (b0, b1, b2, _, a1, a2), (z0, z1) in zip(self._sections, self._state):
                y = b0 * x + z0[channel]
                z0[channel] = b1 * x - a1 * y + z1[channel]
                z1[channel] = b2 * x - a2 * y
                x = y
            output.append(x)
        return output

    def filter(self, block: ArrayLike) -> np.ndarray:
        """Filter a block of samples, shape ``(T, *channels)``, continuing from the state.

        Filtering a signal in chunks gives the same output as filtering it at once.
        """
        block = finite_array("block", block)
        if block.shape[1:] != self.channels:
            raise InputError("block", f"expected shape (T, *{self.channels}), found {block.shape}")
        from scipy import signal

        output, self.state = signal.sosfilt(self.sos, block, axis=0, zi=self.state)
        return output


def _prewarped(frequency: float, dt: float) -> float:
    """Analog frequency that the bilinear transform maps onto ``frequency`` [rad/s]."""
    return 2.0 / dt * math.tan(frequency * dt / 2.0)


def _check_design(name: str, frequency: float, dt: float) -> tuple[float, float]:
    frequency = require_positive(name, frequency)
    dt = require_positive("dt", dt)
    require_below_nyquist(name, frequency, dt)
    return frequency, dt


def _unit_steady_state(sos: np.ndarray) -> np.ndarray:
    """The sections' delay states once a constant input 1 has run forever (``scipy.signal.sosfilt_zi``).

    Each section's input is the DC gain of those before it, u; its output y = u H_k(1), and the transposed direct
    form II recursion at rest gives z0 = y − b0 u and z1 = b2 u − a2 y.
    """
    states, level = np.zeros((sos.shape[0], 2)), 1.0
    for k, (b0, b1, b2, _, a1, a2) in enumerate(sos):
        output = level * (b0 + b1 + b2) / (1.0 + a1 + a2)
        states[k] = output - b0 * level, b2 * level - a2 * output
        level = output
    return states


def _bilinear(b: list[float], a: list[float], dt: float, channels: tuple[int, ...]) -> DiscreteFilter:
    """The prototype b(s)/a(s) of order 1 or 2 (coefficients from the highest power) as one section, by the Tustin
    substitution s = K (1 − z⁻¹)/(1 + z⁻¹), K = 2/dt (``scipy.signal.bilinear`` then ``tf2sos``)::

        order 1:  p1 s + p0           -> (p1 K + p0) + (p0 − p1 K) z⁻¹
        order 2:  p2 s² + p1 s + p0   -> (p2 K² + p1 K + p0) + 2 (p0 − p2 K²) z⁻¹ + (p2 K² − p1 K + p0) z⁻²

    each multiplied through by (1 + z⁻¹)^order; the section is normalised by the denominator's first coefficient.
    """
    gain = 2.0 / dt
    order = len(a) - 1

    def substituted(p: list[float]) -> list[float]:
        p = [0.0] * (order + 1 - len(p)) + list(p)
        if order == 1:
            return [p[0] * gain + p[1], p[1] - p[0] * gain, 0.0]
        k2 = p[0] * gain * gain
        return [k2 + p[1] * gain + p[2], 2.0 * (p[2] - k2), k2 - p[1] * gain + p[2]]

    numerator, denominator = substituted(b), substituted(a)
    lead = denominator[0]
    return DiscreteFilter([[x / lead for x in numerator] + [x / lead for x in denominator]], dt, channels)


def first_order_lowpass(corner_frequency: float, dt: float, channels: tuple[int, ...] = ()) -> DiscreteFilter:
    """First-order low-pass ω/(s + ω), Tustin with prewarping at ω.

    Parameters
    ----------
    corner_frequency : float
        ω, the −3 dB frequency [rad/s]; 0 < ω < π/dt.
    dt : float
        Sample time [s].
    channels : tuple of int, optional
        Shape of one sample.

    Raises
    ------
    ConfigurationError
        Naming ``corner_frequency`` (NaN, <= 0, at or above Nyquist) or ``dt``.
    """
    w, dt = _check_design("corner_frequency", corner_frequency, dt)
    wa = _prewarped(w, dt)
    return _bilinear([wa], [1.0, wa], dt, channels)


def second_order_lowpass(
    corner_frequency: float, damping: float, dt: float, channels: tuple[int, ...] = ()
) -> DiscreteFilter:
    """Second-order low-pass ω²/(s² + 2ζωs + ω²), Tustin with prewarping at ω.

    Parameters
    ----------
    corner_frequency : float
        Natural frequency ω [rad/s]; 0 < ω < π/dt. The gain at ω is 1/(2ζ)
        (−3 dB for ζ = 1/√2).
    damping : float
        ζ > 0 (ζ <= 0 would be marginally stable or unstable).
    dt : float
        Sample time [s].
    channels : tuple of int, optional
        Shape of one sample.

    Raises
    ------
    ConfigurationError
        Naming ``corner_frequency``, ``damping`` or ``dt``.
    """
    w, dt = _check_design("corner_frequency", corner_frequency, dt)
    zeta = require_positive("damping", damping)
    wa = _prewarped(w, dt)
    return _bilinear([wa * wa], [1.0, 2.0 * zeta * wa, wa * wa], dt, channels)


def notch(
    frequency: float, beta_num: float, beta_den: float, dt: float, channels: tuple[int, ...] = ()
) -> DiscreteFilter:
    """ROSCO's notch (s² + 2β_num ω s + ω²)/(s² + 2β_den ω s + ω²), Tustin prewarped at ω.

    Parameters
    ----------
    frequency : float
        Notch frequency ω [rad/s]; 0 < ω < π/dt.
    beta_num : float
        Numerator damping β_num >= 0; the gain at ω is β_num/β_den (0 = full notch).
    beta_den : float
        Denominator damping β_den > 0; sets the width.
    dt : float
        Sample time [s].
    channels : tuple of int, optional
        Shape of one sample.

    Raises
    ------
    ConfigurationError
        Naming ``frequency``, ``beta_num``, ``beta_den`` (<= 0 is unstable) or ``dt``.
    """
    w, dt = _check_design("frequency", frequency, dt)
    bn = require_nonnegative("beta_num", beta_num)
    bd = require_positive("beta_den", beta_den)
    wa = _prewarped(w, dt)
    return _bilinear([1.0, 2.0 * bn * wa, wa * wa], [1.0, 2.0 * bd * wa, wa * wa], dt, channels)


def cascade(*filters: DiscreteFilter) -> DiscreteFilter:
    """Series connection of filters sharing one ``dt`` and channel shape (fresh zero state)."""
    if not filters:
        raise ConfigurationError("filters", "need at least one filter to cascade")
    dt, channels = filters[0].dt, filters[0].channels
    for f in filters[1:]:
        if not math.isclose(f.dt, dt, rel_tol=1e-12) or f.channels != channels:
            raise ConfigurationError("filters", "all filters of a cascade need the same dt and channels")
    return DiscreteFilter(np.vstack([f.sos for f in filters]), dt, channels)


class ExponentialLowPass:
    """Recursive single-pole low-pass of the NREL 5 MW baseline (Jonkman et al. 2009, ch. 7).

    ``y_k = (1 − α) u_k + α y_{k−1}`` with ``α = exp(−ω·dt)``: exponential
    smoothing: the exact response of ω/(s + ω) to an input equal to u_k over the
    last step.
    The time step is an argument of every call, as in the original DISCON.

    Parameters
    ----------
    corner_frequency : float
        ω [rad/s], > 0 (1.570796 rad/s = 0.25 Hz for the generator speed).

    Attributes
    ----------
    output : float or None
        Last output; ``None`` until :meth:`reset` or the first :meth:`step`, which
        starts the filter at its first input (no transient), like the DISCON.
    """

    def __init__(self, corner_frequency: float) -> None:
        self.corner_frequency = require_positive("corner_frequency", corner_frequency)
        self.output: float | None = None

    def reset(self, initial: float) -> None:
        """Start from the steady state of the constant input ``initial``."""
        self.output = float(finite_array("initial", initial))

    def step(self, sample: float, dt: float) -> float:
        """Filter one sample taken ``dt`` [s] after the previous one; return the output."""
        sample = finite_float("sample", sample)
        dt = require_time_step(dt)
        if self.output is None:
            self.output = sample
            return sample
        alpha = math.exp(-self.corner_frequency * dt)
        self.output = (1.0 - alpha) * sample + alpha * self.output
        return self.output
