"""One harmonic's individual pitch control law, in the non-rotating (MBC) frame.

Block diagram (ROSCO ``Controllers.f90:IPC``, anchor_windcontrol notes §1.4;
van Engelen 2006 §3.3–3.4; Fratini 2019 §4.5), for harmonic n::

    (cos_n, sin_n) moments ─► low-pass ─► notch ─► PI on both axes ─► |·| ≤ limit ─► × ramp ─► (c_n, s_n), φ_n
                                                   gains × soft start × schedule

* Pre-filter in the non-rotating frame (van Engelen 2006 §3.3: "low pass
  filters around and beyond 3p", applied after demodulation): optional
  first/second-order low-pass and optional notch (ROSCO's form), on both axes.
* PI law per axis, default pure I (van Engelen: the MBC-frame plant is a
  delayed proportional one, "just an I-compensator satisfies")::

      θ_axis = k_p·m_axis + k_i·∫ m_axis dt         (reference 0)

  The pitch-to-moment sensitivity dM/dθ of an out-of-plane moment is negative
  (pitching to feather unloads the blade), so positive gains give negative
  feedback, as ROSCO's positive IPC_KI.
* Integrator clamping and amplitude saturation on the *magnitude* of the
  (cos, sin) vector (:class:`~hawt_controllers.laws.saturation.NormSaturation`), so a
  limited demand keeps its phase. The limit is min(max_amplitude, headroom):
  passing the collective pitch minus the minimum pitch as headroom is ROSCO's
  ``IPC_SatMode = 2`` (the full IPC cycle stays above the minimum pitch).
* Soft start: the gains are multiplied by a cubic ramp σ of the operating point
  between ``soft_start_begin`` and ``soft_start_end`` (ROSCO ``sigma`` over
  ``IPC_Vramp``); like ROSCO, the integrator holds its value where σ = 0.
* Gain schedule: the gains are multiplied by a factor interpolated over the
  same operating point (e.g. collective pitch [rad]).
* Bumpless switching: the output is multiplied by a ramp factor that goes
  linearly 0→1 over ``ramp_time`` after :meth:`HarmonicIpc.activate` and 1→0
  after :meth:`HarmonicIpc.deactivate`; once it reaches 0 the integrator is
  cleared. The pre-filter keeps running while inactive, so an activation sees
  no filter transient.
* φ_n is passed through for the inverse transform (mbc node).
* Without usable moments (a dead blade-root load sensor: NaN) :meth:`HarmonicIpc.hold` stands in
  for :meth:`HarmonicIpc.step`: the filters and the integrator keep their state and a second
  factor, ``measured``, takes the output linearly 1→0 over ``ramp_time``; :meth:`HarmonicIpc.step`
  takes it back to 1 at the same rate once the moments return (issue 34: fade out rather than
  hold a 1P demand computed from loads the controller no longer sees).

Both axes go through the same filter and law; there is no per-axis special
case (ROSCO reads an ``axisYawF_2P`` that is never assigned: its 2P yaw loop
runs on an unset input — not copied here).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property
from typing import NamedTuple

import numpy as np

from hawt_core.validation import (
    finite_array,
    finite_floats,
    require_below_nyquist,
    require_finite,
    require_nonnegative,
    require_positive,
    require_time_step,
)
from hawt_core.exceptions import ConfigurationError, InputError
from hawt_controllers.laws.filters import DiscreteFilter, cascade, first_order_lowpass, notch, second_order_lowpass
from hawt_controllers.laws.interpolation import interpolate
from hawt_controllers.laws.pi import PIController
from hawt_controllers.laws.saturation import NormSaturation

__all__ = ["HarmonicIpc", "HarmonicIpcConfig", "IpcOutput", "design_prefilter", "soft_start_factor"]

_DT_TOLERANCE = 0.01  # relative change of dt that triggers a filter redesign


def soft_start_factor(value: float, begin: float, end: float) -> float:
    """Cubic ramp from 0 at ``begin`` to 1 at ``end`` with zero slope at both ends.

    ROSCO ``Functions.f90:sigma`` with y0 = 0, y1 = 1: for t = (x − begin)/(end − begin)
    clamped to [0, 1], σ = 3t² − 2t³ (the same cubic as ROSCO's a3…a0 form).
    ``begin == end`` gives a step at ``begin``.

    Examples
    --------
    >>> soft_start_factor(10.26, 9.12, 11.4)
    0.5
    """
    if value <= begin:
        return 0.0
    if value >= end:
        return 1.0
    t = (value - begin) / (end - begin)
    return t * t * (3.0 - 2.0 * t)


@dataclass(frozen=True)
class HarmonicIpcConfig:
    """Parameters of one harmonic's IPC law (one ``ipc_h{n}`` node); SI units.

    Attributes
    ----------
    harmonic : int
        n >= 1 (carried into the output; the law itself needs no azimuth).
    integral_gain : float
        k_i [rad/(N·m·s)]. Default 1e-8: DRC_Fortran's NREL 5 MW 1P value
        (anchor_windcontrol notes §1.5; van Engelen's recipe gives ~2π·0.1/|dM/dθ|).
    proportional_gain : float
        k_p [rad/(N·m)]; default 0 (pure I).
    max_amplitude : float
        Limit of |(c_n, s_n)| [rad], > 0. Default 0.0872665 (5°, DRC_Fortran
        NREL 5 MW ``IPC_IntSat``; ROSCO's NREL 5 MW DISCON has 0.3).
    phase_offset : float
        φ_n [rad] for the inverse transform (= n·ROSCO's IPC_aziOffset(n)).
    lowpass_order : int
        0 (no low-pass), 1 or 2.
    lowpass_corner_frequency : float
        Low-pass corner [rad/s]. Default 2.0 (0.32 Hz): below 3P at rated
        (3.80 rad/s), above the ~0.1 Hz loop bandwidth.
    lowpass_damping : float
        ζ of the second-order low-pass, > 0.
    notch_frequency : float
        Notch frequency [rad/s]; 0 = no notch (e.g. 3.80 = 3P at 12.1 rpm).
    notch_beta_num, notch_beta_den : float
        Notch dampings (ROSCO F_NotchBetaNum/Den): depth β_num/β_den, β_den > 0.
    soft_start_begin, soft_start_end : float
        Operating point where the gain ramp starts (0) and ends (1), in the unit
        of the operating point passed to :meth:`HarmonicIpc.step` (m/s for wind
        speed, rad for collective pitch). Both 0 (default) disables the soft
        start; begin == end != 0 makes a step at that point.
    schedule_breakpoints : tuple of float
        Operating points of the gain schedule, strictly increasing; empty = none.
    schedule_factors : tuple of float
        Gain multipliers at the breakpoints [-], same length.
    ramp_time : float
        Default time to ramp the output in or out on (de)activation [s], >= 0.
    """

    harmonic: int
    integral_gain: float = 1e-8
    proportional_gain: float = 0.0
    max_amplitude: float = 0.0872665
    phase_offset: float = 0.0
    lowpass_order: int = 2
    lowpass_corner_frequency: float = 2.0
    lowpass_damping: float = 0.7071
    notch_frequency: float = 0.0
    notch_beta_num: float = 0.0
    notch_beta_den: float = 0.25
    soft_start_begin: float = 0.0
    soft_start_end: float = 0.0
    schedule_breakpoints: tuple[float, ...] = ()
    schedule_factors: tuple[float, ...] = ()
    ramp_time: float = 5.0

    @cached_property
    def soft_start_enabled(self) -> bool:
        """True unless both soft-start bounds are 0."""
        return not (self.soft_start_begin == 0.0 and self.soft_start_end == 0.0)

    @cached_property
    def uses_operating_point(self) -> bool:
        """True if the soft start or the gain schedule needs an operating point."""
        return self.soft_start_enabled or len(self.schedule_breakpoints) > 0

    def validate(self, dt: float | None = None) -> None:
        """Refuse values the law cannot honour, naming the field.

        Parameters
        ----------
        dt : float, optional
            Sample time [s]; if given, the filters are also checked against the
            Nyquist frequency and designed (which checks their stability).

        Raises
        ------
        ConfigurationError
            With ``field`` set to the attribute at fault (NaN gain, negative
            bandwidth, ``notch_beta_den <= 0`` (unstable), corner above Nyquist, ...).
        """
        if isinstance(self.harmonic, bool) or not isinstance(self.harmonic, (int, np.integer)) or self.harmonic < 1:
            raise ConfigurationError("harmonic", f"must be an integer >= 1, found {self.harmonic!r}")
        require_finite("integral_gain", self.integral_gain)
        require_finite("proportional_gain", self.proportional_gain)
        require_positive("max_amplitude", self.max_amplitude)
        require_finite("phase_offset", self.phase_offset)
        if self.lowpass_order not in (0, 1, 2):
            raise ConfigurationError("lowpass_order", f"must be 0, 1 or 2, found {self.lowpass_order!r}")
        if self.lowpass_order > 0:
            require_positive("lowpass_corner_frequency", self.lowpass_corner_frequency)
        if self.lowpass_order == 2:
            require_positive("lowpass_damping", self.lowpass_damping)
        require_nonnegative("notch_frequency", self.notch_frequency)
        if self.notch_frequency > 0.0:
            require_nonnegative("notch_beta_num", self.notch_beta_num)
            if require_finite("notch_beta_den", self.notch_beta_den) <= 0.0:
                raise ConfigurationError(
                    "notch_beta_den", f"must be > 0 (the notch is unstable otherwise), found {self.notch_beta_den}"
                )
        begin = require_finite("soft_start_begin", self.soft_start_begin)
        end = require_finite("soft_start_end", self.soft_start_end)
        if begin > end:
            raise ConfigurationError("soft_start_begin", f"must be <= soft_start_end ({end}), found {begin}")
        self._validate_schedule()
        require_nonnegative("ramp_time", self.ramp_time)
        if dt is not None:
            dt = require_positive("dt", dt)
            if self.lowpass_order > 0:
                require_below_nyquist("lowpass_corner_frequency", self.lowpass_corner_frequency, dt)
            if self.notch_frequency > 0.0:
                require_below_nyquist("notch_frequency", self.notch_frequency, dt)
            design_prefilter(self, dt)

    def _validate_schedule(self) -> None:
        points = np.asarray(self.schedule_breakpoints, dtype=float)
        factors = np.asarray(self.schedule_factors, dtype=float)
        if points.ndim != 1 or factors.ndim != 1:
            raise ConfigurationError("schedule_breakpoints", "schedule tables must be 1-D")
        if factors.size != points.size:
            raise ConfigurationError(
                "schedule_factors", f"expected {points.size} values like schedule_breakpoints, found {factors.size}"
            )
        if not np.all(np.isfinite(points)):
            raise ConfigurationError("schedule_breakpoints", "NaN or inf in the table")
        if not np.all(np.isfinite(factors)):
            raise ConfigurationError("schedule_factors", "NaN or inf in the table")
        if np.any(np.diff(points) <= 0.0):
            raise ConfigurationError("schedule_breakpoints", "must be strictly increasing")

    def gain_factor(self, operating_point: float) -> float:
        """Soft-start factor × schedule factor at ``operating_point`` (1 if neither is configured)."""
        factor = 1.0
        if self.soft_start_enabled:
            factor *= soft_start_factor(operating_point, self.soft_start_begin, self.soft_start_end)
        if self.schedule_breakpoints:
            factor *= interpolate(operating_point, self.schedule_breakpoints, self.schedule_factors)
        return factor


def design_prefilter(config: HarmonicIpcConfig, dt: float) -> DiscreteFilter | None:
    """The low-pass/notch cascade on (cos, sin) that the law applies (None if the config has neither).

    Public because the gain design (:mod:`hawt_controllers.design.ipc_design`) needs the same filter's
    gain and phase at the crossover.
    """
    stages = []
    if config.lowpass_order == 1:
        stages.append(first_order_lowpass(config.lowpass_corner_frequency, dt, channels=(2,)))
    elif config.lowpass_order == 2:
        stages.append(
            second_order_lowpass(config.lowpass_corner_frequency, config.lowpass_damping, dt, channels=(2,))
        )
    if config.notch_frequency > 0.0:
        stages.append(
            notch(config.notch_frequency, config.notch_beta_num, config.notch_beta_den, dt, channels=(2,))
        )
    return cascade(*stages) if stages else None


class IpcOutput(NamedTuple):
    """One step of a harmonic IPC law (fields of ``hawt_msgs/HarmonicPitch`` and diagnostics).

    Attributes
    ----------
    harmonic : int
        n.
    cos, sin : float
        Pitch demand of harmonic n in the non-rotating frame [rad] (after ramp).
    phase_offset : float
        φ_n for the inverse transform [rad].
    filtered_cos, filtered_sin : float
        Pre-filtered moments [N·m].
    gain_factor : float
        Soft start × schedule factor used this step [-].
    ramp : float
        Output ramp factor in [0, 1].
    active : bool
        True while activated (ramping in or fully on); False while ramping out or off.
    saturated : bool
        Amplitude limit active on the integrator or the output.
    """

    harmonic: int
    cos: float
    sin: float
    phase_offset: float
    filtered_cos: float
    filtered_sin: float
    gain_factor: float
    ramp: float
    active: bool
    saturated: bool


class HarmonicIpc:
    """One harmonic's IPC law with explicit state (see the module notes).

    Parameters
    ----------
    config : HarmonicIpcConfig
        Parameters; validated with ``dt``.
    dt : float
        Sample time the pre-filter is designed for [s]. A ``dt`` in :meth:`step`
        more than 1 % away redesigns the filter (its output carried over);
        closer ones (wall-clock jitter) only enter the integration.

    Attributes
    ----------
    prefilter : DiscreteFilter or None
        Low-pass/notch cascade on (cos, sin), state included.
    law : PIController
        Integrator of both axes [rad].
    ramp : float
        Output ramp factor in [0, 1]; starts at 0 (inactive).
    ramp_target : float
        1 after :meth:`activate`, 0 after :meth:`deactivate`.
    ramp_rate : float
        |d ramp/dt| [1/s] of the current transition (inf = immediate).
    """

    def __init__(self, config: HarmonicIpcConfig, dt: float) -> None:
        config.validate(dt)
        self.config = config
        self.dt = float(dt)
        self.prefilter = design_prefilter(config, self.dt)
        self.law = PIController(shape=(2,))
        self.ramp = 0.0
        self.ramp_target = 0.0
        self.ramp_rate = math.inf
        self.measured = 1.0
        self._unramped = [0.0, 0.0]
        self._filtered = [0.0, 0.0]
        self._saturation = NormSaturation(config.max_amplitude)  # rebuilt only when the limit changes

    @property
    def active(self) -> bool:
        """True while activated (ramping in or fully on)."""
        return self.ramp_target == 1.0

    def reconfigure(self, config: HarmonicIpcConfig) -> None:
        """Apply new parameters live, keeping the integrator and the filtered value.

        Raises
        ------
        ConfigurationError
            If ``config`` is invalid; the controller is then unchanged.
        """
        config.validate(self.dt)
        old = self.config
        self.config = config
        if replace(old, **_filter_fields(config)) != old:
            self._redesign(self.dt)

    def reset(self, initial: tuple[float, float] = (0.0, 0.0), moments: tuple[float, float] | None = None) -> None:
        """Bumpless reset: output ``initial`` at zero moment, filter in steady state at ``moments``.

        Parameters
        ----------
        initial : (float, float)
            Integrator (c_n, s_n) [rad]; the output before the ramp equals it at zero error.
        moments : (float, float), optional
            Constant (cos_n, sin_n) moments [N·m] the filter is assumed to have
            seen forever; default zero.
        """
        self.law.reset(finite_array("initial", initial, shape=(2,)))
        values = np.zeros(2) if moments is None else finite_array("moments", moments, shape=(2,))
        if self.prefilter is not None:
            self.prefilter.reset(values)
        self._filtered = values.tolist()

    def activate(self, ramp_time: float | None = None, initial: tuple[float, float] | None = None) -> None:
        """Start ramping the output in over ``ramp_time`` [s] (default ``config.ramp_time``).

        Parameters
        ----------
        ramp_time : float, optional
            Duration of the ramp 0 → 1 [s]; 0 switches on at once.
        initial : (float, float), optional
            Tracked integrator state (c_n, s_n) [rad] to start from; by default
            a controller that is fully off starts from zero, and one still
            ramping out keeps its state.
        """
        if initial is not None:
            self.law.reset(finite_array("initial", initial, shape=(2,)))
        elif self.ramp == 0.0 and self.ramp_target == 0.0:
            self.law.reset(0.0)
        self.ramp_target = 1.0
        self.ramp_rate = self._rate(ramp_time)

    def deactivate(self, ramp_time: float | None = None) -> None:
        """Start ramping the output to zero over ``ramp_time`` [s] (default ``config.ramp_time``)."""
        self.ramp_target = 0.0
        self.ramp_rate = self._rate(ramp_time)

    def step(
        self,
        moment_cos: float,
        moment_sin: float,
        dt: float,
        *,
        operating_point: float = math.nan,
        pitch_headroom: float = math.inf,
    ) -> IpcOutput:
        """Advance one sample.

        Parameters
        ----------
        moment_cos, moment_sin : float
            cos_n and sin_n of the blade-root out-of-plane moments [N·m]
            (:func:`hawt_core.rotor.mbc.mbc_forward`).
        dt : float
            Time since the previous step [s].
        operating_point : float, optional
            Scheduling variable for the soft start and gain schedule (wind
            speed [m/s] or collective pitch [rad]); required (finite) only if
            the config uses one.
        pitch_headroom : float, optional
            Extra amplitude limit [rad], e.g. collective − min pitch (ROSCO
            IPC_SatMode 2); negative values count as 0.

        Returns
        -------
        IpcOutput
        """
        moments = finite_floats("moments", (moment_cos, moment_sin))
        dt = require_time_step(dt)
        if self.config.uses_operating_point and not math.isfinite(operating_point):
            raise InputError(
                "operating_point", f"must be finite for the soft start/gain schedule, found {operating_point}"
            )
        if math.isnan(pitch_headroom):
            raise InputError("pitch_headroom", "must not be NaN")
        if not math.isclose(dt, self.dt, rel_tol=_DT_TOLERANCE):
            self._redesign(dt)
        self._filtered = moments if self.prefilter is None else self.prefilter.step_values(moments)

        self._advance_ramp(dt)
        if self.measured < 1.0:
            self.measured = min(self.measured + self._rate(None) * dt, 1.0)
        factor = self.config.gain_factor(operating_point) if self.config.uses_operating_point else 1.0
        if self.ramp == 0.0 and self.ramp_target == 0.0:
            self.law.reset(0.0)
            demand = self._unramped = [0.0, 0.0]
        else:
            limit = min(self.config.max_amplitude, max(pitch_headroom, 0.0))
            if limit != self._saturation.limit:
                self._saturation = NormSaturation(limit)
            self._unramped = self.law.update_values(
                self._filtered,
                dt,
                kp=factor * self.config.proportional_gain,
                ki=factor * self.config.integral_gain,
                saturation=self._saturation,
            )
            scale = self.ramp * self.measured
            demand = [scale * value for value in self._unramped]
        # positional (a named tuple's keywords cost more than its arithmetic): the fields in IpcOutput's order
        return IpcOutput(int(self.config.harmonic), demand[0], demand[1], float(self.config.phase_offset),
                         self._filtered[0], self._filtered[1], factor, self.ramp, self.active, self.law.saturated)

    def hold(self, dt: float) -> IpcOutput:
        """A step without usable moments: filters and integrator hold, the output fades towards 0.

        The ``measured`` factor falls by dt / ``config.ramp_time`` (at once for 0) and the output is
        ramp × measured × the law's last output; the switch ramp moves on as in :meth:`step`.
        """
        dt = require_time_step(dt)
        self._advance_ramp(dt)
        self.measured = max(self.measured - self._rate(None) * dt, 0.0)
        scale = self.ramp * self.measured
        return IpcOutput(int(self.config.harmonic), scale * self._unramped[0], scale * self._unramped[1],
                         float(self.config.phase_offset), self._filtered[0], self._filtered[1], math.nan, self.ramp,
                         self.active, self.law.saturated)

    def _rate(self, ramp_time: float | None) -> float:
        time = self.config.ramp_time if ramp_time is None else require_nonnegative("ramp_time", ramp_time)
        return math.inf if time == 0.0 else 1.0 / time

    def _advance_ramp(self, dt: float) -> None:
        change = self.ramp_rate * dt
        if self.ramp < self.ramp_target:
            self.ramp = min(self.ramp + change, self.ramp_target)
        elif self.ramp > self.ramp_target:
            self.ramp = max(self.ramp - change, self.ramp_target)

    def _redesign(self, dt: float) -> None:
        self.config.validate(dt)
        self.dt = float(dt)
        self.prefilter = design_prefilter(self.config, self.dt)
        if self.prefilter is not None:
            self.prefilter.reset(self._filtered)


def _filter_fields(config: HarmonicIpcConfig) -> dict:
    names = (
        "lowpass_order",
        "lowpass_corner_frequency",
        "lowpass_damping",
        "notch_frequency",
        "notch_beta_num",
        "notch_beta_den",
    )
    return {name: getattr(config, name) for name in names}
