"""NREL 5 MW baseline controller: generator torque (regions 1–3) and gain-scheduled PI pitch.

Jonkman, Butterfield, Musial & Scott (2009), NREL/TP-500-38060, chapter 7, step
for step as in J. Jonkman's baseline DISCON (OpenFAST
``reg_tests/5MW_Baseline/ServoData/Source/DISCON_ITIBarge.f90``):

1. Generator speed low-pass: ``ω_f ← (1 − α) ω + α ω_f``, ``α = exp(−ω_c dt)``,
   ω_c = 0.25 Hz (:class:`~hawt_controllers.laws.filters.ExponentialLowPass`).
2. Torque, from ω_f and the previous pitch command θ_prev (:func:`torque_demand`):
   region 3 (ω_f >= ω_rt or θ_prev >= θ_3): T = P_rated/ω_f (constant power);
   region 1 (ω_f <= ω_ci): T = 0; region 1½: linear ramp to k·ω_2²;
   region 2: T = k ω_f²; region 2½: induction-generator line of slip s through
   (ω_rt, P_rated/ω_rt). Then T <= T_max, then |dT/dt| <= 15 kN·m/s.
3. Pitch: GK = 1/(1 + θ_prev/θ_K); e = ω_f − ω_ref;
   θ = GK·(K_P e + K_I ∫e dt), with the integral clamped so that
   GK·K_I∫e stays in [θ_min, θ_max] (anti-windup), the sum clamped to
   [θ_min, θ_max], then rate-limited to ±θ̇_max from the measured pitch and
   clamped again.

The integrator is a :class:`~hawt_controllers.laws.pi.PIController` holding K_I·∫e
(output units before GK) with limits [θ_min/GK, θ_max/GK]: that is exactly
Jonkman's clamp of ∫e to [θ_min/(GK K_I), θ_max/(GK K_I)].

Deviation from the DISCON in normal operation: near rated K_I is reduced (0.4 of Jonkman's at and
below 1° of pitch, rising to his at 4°, :func:`integral_gain_factor`), which removes the rated-wind
limit cycle of this plant (issue 13); the law above 4° (about 12.1 m/s) is Jonkman's. The integrator
holds K_I·∫e in output units, so a change of K_I moves no pitch at once.

Deviations from the DISCON, both outside its normal operation: the torque is
clamped below at 0 (the DISCON has no lower limit; it only matters for a
negative filtered speed), and at ω_f <= 0 in region 3 the torque is T_max
instead of a division by zero. The DISCON's sample-and-hold at PC_DT/VS_DT is
not reproduced: the controller runs at every call.
"""

from __future__ import annotations

import enum
import math
from dataclasses import MISSING, dataclass, fields
from pathlib import Path
from typing import NamedTuple


from hawt_core.validation import finite_array, finite_float, require_finite, require_positive, require_time_step
from hawt_core.exceptions import ConfigurationError
from hawt_core.yaml_text import safe_load
from hawt_controllers.laws.filters import ExponentialLowPass
from hawt_controllers.laws.limits import PitchLimits, limit_angle
from hawt_controllers.laws.pi import PIController
from hawt_controllers.laws.saturation import BoxSaturation
from hawt_controllers.packaged import PACKAGED

__all__ = [
    "BaselineCollectiveConfig",
    "BaselineCollectiveController",
    "CollectiveOutput",
    "DEFAULT_BASELINE_FILE",
    "TorqueRegion",
    "gain_correction_factor",
    "integral_gain_factor",
    "load_baseline_config",
    "torque_demand",
]

DEFAULT_BASELINE_FILE = PACKAGED["nrel_5mw"]["cpc"]


class TorqueRegion(enum.IntEnum):
    """Torque-control region; values equal ``hawt_msgs/CollectivePitch.region`` (15 = 1½, 25 = 2½)."""

    REGION_1 = 1
    REGION_1_5 = 15
    REGION_2 = 2
    REGION_2_5 = 25
    REGION_3 = 3


@dataclass(frozen=True)
class BaselineCollectiveConfig:
    """Tuning of the baseline controller; SI units, generator (high-speed) shaft side.

    The values for the NREL 5 MW come from ``data/nrel5mw_baseline.yaml``
    (:func:`load_baseline_config`); DISCON names in brackets.

    Attributes
    ----------
    generator_speed_corner_frequency : float
        Speed filter corner ω_c [rad/s] [CornerFreq].
    rated_generator_speed : float
        Pitch-controller reference ω_ref [rad/s] [PC_RefSpd].
    proportional_gain : float
        K_P at zero pitch [s] [PC_KP].
    integral_gain : float
        K_I at zero pitch [-] [PC_KI]; >= 0.
    gain_doubling_pitch : float
        θ_K [rad] [PC_KK]: the pitch at which the pitch sensitivity has doubled.
    min_pitch, max_pitch : float
        Pitch limits [rad] [PC_MinPit, PC_MaxPit].
    max_pitch_rate : float
        |θ̇| limit [rad/s] [PC_MaxRat].
    cut_in_generator_speed : float
        Region 1 → 1½ [rad/s] [VS_CtInSp].
    region2_start_generator_speed : float
        Region 1½ → 2 [rad/s] [VS_Rgn2Sp].
    region2_torque_constant : float
        k in T = k ω² [N·m/(rad/s)²] [VS_Rgn2K].
    region25_generator_speed : float
        ω_rt, rated speed of the region 2½ line and region-3 threshold [rad/s] [VS_RtGnSp].
    rated_generator_power : float
        P_rated, mechanical at the generator [W] [VS_RtPwr].
    region25_slip : float
        Slip of the region 2½ induction-generator line [-] [VS_SlPc/100].
    region3_min_pitch : float
        θ_3: at or above this previous pitch command the torque is region 3 [rad] [VS_Rgn3MP].
    max_generator_torque : float
        T_max [N·m] [VS_MaxTq].
    max_torque_rate : float
        |dT/dt| limit [N·m/s] [VS_MaxRat].
    near_rated_integral_factor : float
        K_I is multiplied by this at or below ``near_rated_pitch_low``, rising linearly to 1 at
        ``near_rated_pitch_high`` (:func:`integral_gain_factor`; not in the DISCON: 1 keeps Jonkman's law).
    near_rated_pitch_low, near_rated_pitch_high : float
        The pitch [rad] where that ramp starts and ends.
    """

    generator_speed_corner_frequency: float
    rated_generator_speed: float
    proportional_gain: float
    integral_gain: float
    gain_doubling_pitch: float
    min_pitch: float
    max_pitch: float
    max_pitch_rate: float
    cut_in_generator_speed: float
    region2_start_generator_speed: float
    region2_torque_constant: float
    region25_generator_speed: float
    rated_generator_power: float
    region25_slip: float
    region3_min_pitch: float
    max_generator_torque: float
    max_torque_rate: float
    near_rated_integral_factor: float = 1.0
    near_rated_pitch_low: float = 0.0
    near_rated_pitch_high: float = 0.0

    def __post_init__(self) -> None:
        self.validate()

    @property
    def synchronous_generator_speed(self) -> float:
        """Zero-torque speed of the region 2½ line, ω_rt/(1 + s) [rad/s] [VS_SySp]."""
        return self.region25_generator_speed / (1.0 + self.region25_slip)

    @property
    def region15_slope(self) -> float:
        """Torque/speed slope of region 1½ [N·m/(rad/s)] [VS_Slope15]."""
        w2 = self.region2_start_generator_speed
        return self.region2_torque_constant * w2 * w2 / (w2 - self.cut_in_generator_speed)

    @property
    def region25_slope(self) -> float:
        """Torque/speed slope of region 2½ [N·m/(rad/s)] [VS_Slope25]."""
        w_rt = self.region25_generator_speed
        return (self.rated_generator_power / w_rt) / (w_rt - self.synchronous_generator_speed)

    @property
    def region2_end_generator_speed(self) -> float:
        """Region 2 → 2½, where k ω² meets the 2½ line [rad/s] [VS_TrGnSp]."""
        k, slope, w_sync = self.region2_torque_constant, self.region25_slope, self.synchronous_generator_speed
        if k == 0.0:
            return w_sync
        return (slope - math.sqrt(slope * (slope - 4.0 * k * w_sync))) / (2.0 * k)

    @property
    def rated_torque(self) -> float:
        """P_rated/ω_ref [N·m] (43 093.55 N·m for the NREL 5 MW)."""
        return self.rated_generator_power / self.rated_generator_speed

    @property
    def pitch_limits(self) -> PitchLimits:
        """The pitch angle and rate limits as a :class:`~hawt_controllers.laws.limits.PitchLimits`."""
        return PitchLimits(self.min_pitch, self.max_pitch, self.max_pitch_rate)

    def validate(self) -> None:
        """Refuse a tuning the law cannot run, naming the field (the DISCON's own checks).

        Raises
        ------
        ConfigurationError
            NaN/inf anywhere; negative K_P or K_I (K_I = 0 is a P law, the
            repetitive-PD's); non-positive corner frequency, reference speed, θ_K,
            rates, slip; region speeds out of order; region 2 torque above rated;
            T_max below rated torque; min_pitch >= max_pitch.
        """
        for f in fields(self):
            require_finite(f.name, getattr(self, f.name))
        for name in (
            "generator_speed_corner_frequency",
            "rated_generator_speed",
            "gain_doubling_pitch",
            "max_pitch_rate",
            "region25_generator_speed",
            "region25_slip",
            "max_torque_rate",
        ):
            require_positive(name, getattr(self, name))
        for name in ("proportional_gain", "integral_gain"):
            if getattr(self, name) < 0.0:
                raise ConfigurationError(name, f"must be >= 0, found {getattr(self, name)}")
        for name in ("cut_in_generator_speed", "region2_torque_constant", "rated_generator_power"):
            if getattr(self, name) < 0.0:
                raise ConfigurationError(name, f"must be >= 0, found {getattr(self, name)}")
        if self.min_pitch <= -self.gain_doubling_pitch:
            raise ConfigurationError(
                "min_pitch", f"must be > -gain_doubling_pitch ({-self.gain_doubling_pitch}) for GK to exist"
            )
        if self.min_pitch >= self.max_pitch:
            raise ConfigurationError("min_pitch", f"must be < max_pitch ({self.max_pitch}), found {self.min_pitch}")
        if not 0.0 < self.near_rated_integral_factor <= 1.0:
            raise ConfigurationError("near_rated_integral_factor",
                                     f"must be in (0, 1], found {self.near_rated_integral_factor}")
        if self.near_rated_pitch_high < self.near_rated_pitch_low:
            raise ConfigurationError("near_rated_pitch_high", f"must be >= near_rated_pitch_low "
                                     f"({self.near_rated_pitch_low}), found {self.near_rated_pitch_high}")
        if self.region2_start_generator_speed <= self.cut_in_generator_speed:
            raise ConfigurationError(
                "region2_start_generator_speed",
                f"must be > cut_in_generator_speed ({self.cut_in_generator_speed}), "
                f"found {self.region2_start_generator_speed}",
            )
        w_rt = self.region25_generator_speed
        if self.region2_torque_constant * w_rt * w_rt > self.rated_generator_power / w_rt:
            raise ConfigurationError(
                "region2_torque_constant", "k·ω_rt² must not exceed the rated torque P_rated/ω_rt"
            )
        if self.region2_end_generator_speed < self.region2_start_generator_speed:
            raise ConfigurationError(
                "region25_slip",
                f"region 2 would end at {self.region2_end_generator_speed:.6g} rad/s, "
                f"before it starts at {self.region2_start_generator_speed} rad/s",
            )
        if self.max_generator_torque < self.rated_generator_power / w_rt:
            raise ConfigurationError(
                "max_generator_torque", f"must be >= P_rated/ω_rt = {self.rated_generator_power / w_rt:.6g} N·m"
            )


def load_baseline_config(path: str | Path = DEFAULT_BASELINE_FILE) -> BaselineCollectiveConfig:
    """Read a :class:`BaselineCollectiveConfig` from a YAML file (default: the NREL 5 MW one).

    The file has ``source`` (text naming where the values come from) and
    ``parameters`` (one key per config field, SI units).

    Raises
    ------
    ConfigurationError
        Naming a missing or unknown parameter, or the file if it lacks ``parameters``.
    """
    with open(path, encoding="utf-8") as stream:
        document = safe_load(stream)
    if not isinstance(document, dict) or not isinstance(document.get("parameters"), dict):
        raise ConfigurationError(str(path), "expected a mapping with a 'parameters' mapping")
    values = document["parameters"]
    names = {f.name for f in fields(BaselineCollectiveConfig)}
    for key in values:
        if key not in names:
            raise ConfigurationError(key, f"unknown parameter in {path}")
    for f in fields(BaselineCollectiveConfig):
        if f.name not in values and f.default is MISSING:
            raise ConfigurationError(f.name, f"missing from {path}")
    return BaselineCollectiveConfig(**{name: float(value) for name, value in values.items()})


def gain_correction_factor(pitch: float, gain_doubling_pitch: float) -> float:
    """GK(θ) = 1/(1 + θ/θ_K), Jonkman et al. (2009) ch. 7 pitch gain schedule.

    Examples
    --------
    >>> gain_correction_factor(0.1099965, 0.1099965)
    0.5
    """
    return 1.0 / (1.0 + pitch / gain_doubling_pitch)


def integral_gain_factor(pitch: float, config: BaselineCollectiveConfig) -> float:
    """The factor on K_I at ``pitch`` [rad]: ``near_rated_integral_factor`` at or below ``near_rated_pitch_low``, 1 at
    or above ``near_rated_pitch_high``, linear between (not in Jonkman's DISCON).

    Why: near rated the plant's pitch sensitivity is a third of what Jonkman's schedule GK assumes (the Cp peak
    is at -0.25 deg) and the collective flap puts a right-half-plane zero in pitch -> speed (0.91 rad/s at 11.4
    m/s); with the constant-power torque the loop's phase margin on the linear model is -7.6 deg at 11.4 m/s
    and a 0.05 Hz limit cycle grows to 0-2.3 deg of pitch (measured on the plant before it took AeroDyn 15's
    nodes). Halving K_I there gives +13.3 deg (the PI's zero moves below the crossover); the shipped 0.4 settles the
    plant on AeroDyn 15's nodes too (0.5 leaves a 0.10 deg pitch std at 11.4 m/s); the law is unchanged from 4 deg
    of pitch (about 12.1 m/s) up.

    Examples
    --------
    >>> config = load_baseline_config()
    >>> integral_gain_factor(0.0, config), integral_gain_factor(math.radians(10.0), config)
    (0.4, 1.0)
    """
    low, high, factor = config.near_rated_pitch_low, config.near_rated_pitch_high, config.near_rated_integral_factor
    if pitch <= low:
        return factor
    if pitch >= high:
        return 1.0
    return factor + (1.0 - factor) * (pitch - low) / (high - low)


def torque_demand(
    config: BaselineCollectiveConfig, generator_speed_filtered: float, previous_pitch_command: float
) -> tuple[float, TorqueRegion]:
    """Generator torque of the baseline law before the rate limit, and its region.

    Parameters
    ----------
    config : BaselineCollectiveConfig
        Tuning.
    generator_speed_filtered : float
        ω_f [rad/s].
    previous_pitch_command : float
        θ_prev [rad]; at or above ``region3_min_pitch`` the law is region 3.

    Returns
    -------
    torque : float
        T [N·m], in [0, max_generator_torque].
    region : TorqueRegion
    """
    w = float(generator_speed_filtered)
    c = config
    if w >= c.region25_generator_speed or previous_pitch_command >= c.region3_min_pitch:
        region = TorqueRegion.REGION_3
        torque = c.rated_generator_power / w if w > 0.0 else c.max_generator_torque
    elif w <= c.cut_in_generator_speed:
        region, torque = TorqueRegion.REGION_1, 0.0
    elif w < c.region2_start_generator_speed:
        region, torque = TorqueRegion.REGION_1_5, c.region15_slope * (w - c.cut_in_generator_speed)
    elif w < c.region2_end_generator_speed:
        region, torque = TorqueRegion.REGION_2, c.region2_torque_constant * w * w
    else:
        region, torque = TorqueRegion.REGION_2_5, c.region25_slope * (w - c.synchronous_generator_speed)
    return min(max(torque, 0.0), c.max_generator_torque), region


class CollectiveOutput(NamedTuple):
    """One step of the baseline controller (fields of ``hawt_msgs/CollectivePitch`` and flags).

    Attributes
    ----------
    pitch : float
        Collective pitch demand [rad].
    generator_torque : float
        Generator torque demand, HSS [N·m].
    generator_speed_filtered : float
        ω_f [rad/s].
    region : TorqueRegion
        Torque region of this step.
    wind_speed_estimate : float
        NaN: the baseline has no estimator [m/s].
    gain_factor : float
        GK used this step [-].
    pitch_saturated : bool
        Pitch angle clamp, integrator clamp or rate limit active (true below
        rated, where the integrator rests on min_pitch).
    torque_saturated : bool
        Maximum torque or torque rate limit active.
    """

    pitch: float
    generator_torque: float
    generator_speed_filtered: float
    region: TorqueRegion
    wind_speed_estimate: float
    gain_factor: float
    pitch_saturated: bool
    torque_saturated: bool


class BaselineCollectiveController:
    """The NREL 5 MW baseline controller with explicit state (see the module notes).

    Parameters
    ----------
    config : BaselineCollectiveConfig
        Tuning, e.g. ``load_baseline_config()``.

    Attributes
    ----------
    speed_filter : ExponentialLowPass
        Generator-speed filter state.
    pitch_integrator : PIController
        K_I·∫e state (rad, before the gain factor GK).
    pitch_command : float or None
        Previous pitch command θ_prev [rad] (sets GK and region 3).
    torque_command : float or None
        Previous torque command [N·m] (for the rate limit).
    """

    def __init__(self, config: BaselineCollectiveConfig) -> None:
        config.validate()
        self.config = config
        self.pitch_limits = config.pitch_limits
        self.speed_filter = ExponentialLowPass(config.generator_speed_corner_frequency)
        self.pitch_integrator = PIController()
        self.pitch_command: float | None = None
        self.torque_command: float | None = None

    def reset(self, generator_speed: float, pitch: float, generator_torque: float | None = None) -> None:
        """Bumpless start at a measured operating point, as the DISCON's first call.

        Parameters
        ----------
        generator_speed : float
            Measured generator speed [rad/s]; the filter starts there.
        pitch : float
            Measured collective pitch [rad]; the integrator is set so that the
            pitch command stays there at zero speed error.
        generator_torque : float, optional
            Torque currently applied [N·m]; if None, the first step's torque
            law value is taken without rate limit.
        """
        pitch = float(finite_array("pitch", pitch))
        self.speed_filter.reset(generator_speed)
        self.pitch_command = pitch
        self.pitch_integrator.reset(pitch / gain_correction_factor(pitch, self.config.gain_doubling_pitch))
        self.torque_command = None
        if generator_torque is not None:
            self.torque_command = float(finite_array("generator_torque", generator_torque))

    def step(self, generator_speed: float, measured_pitch: float, dt: float,
             extra: float = 0.0) -> CollectiveOutput:
        """Advance the controller by one sample.

        Parameters
        ----------
        generator_speed : float
            Measured generator speed, HSS [rad/s].
        measured_pitch : float
            Measured collective pitch [rad] (mean over the blades); it starts
            the controller on its first call. The rate limit counts from the
            previous command (see the note in the code).
        dt : float
            Time since the previous step [s].
        extra : float, optional
            Pitch [rad] added to the gain-scheduled PI's demand before the limits (a companion
            law's term, e.g. the repetitive-PD's derivative and learnt terms; finite, the caller checks).

        Returns
        -------
        CollectiveOutput
        """
        c = self.config
        generator_speed = finite_float("generator_speed", generator_speed)
        measured_pitch = finite_float("measured_pitch", measured_pitch)
        dt = require_time_step(dt)
        if self.pitch_command is None:
            self.reset(generator_speed, measured_pitch)
        speed = self.speed_filter.step(generator_speed, dt)

        torque, region = torque_demand(c, speed, self.pitch_command)
        torque_saturated = torque >= c.max_generator_torque
        if self.torque_command is not None:
            step = c.max_torque_rate * dt
            limited = min(max(torque, self.torque_command - step), self.torque_command + step)
            torque_saturated = torque_saturated or limited != torque
            torque = limited
        self.torque_command = torque

        gain = gain_correction_factor(self.pitch_command, c.gain_doubling_pitch)
        demand = gain * self.pitch_integrator.update_values(
            [speed - c.rated_generator_speed],
            dt,
            kp=c.proportional_gain,
            ki=c.integral_gain * integral_gain_factor(self.pitch_command, c),
            saturation=BoxSaturation(c.min_pitch / gain, c.max_pitch / gain),
        )[0] + extra
        # The rate limit counts from the previous collective command, not from the measured mean
        # pitch as Jonkman's DISCON does: with B blades, IPC of harmonics n = B, 2B, … moves every
        # blade alike, so the measured mean carries it and the collective would follow it (that
        # feedback made 3P IPC unstable on the NREL 5 MW, measured in this project).
        limits = self.pitch_limits
        self.pitch_command, angle_saturated, rate_saturated = limit_angle(
            finite_float("demand", demand), self.pitch_command, limits.min_angle, limits.max_angle,
            limits.max_rate * dt)
        # positional (a named tuple's keywords cost more than its arithmetic): the fields in CollectiveOutput's order
        return CollectiveOutput(self.pitch_command, torque, speed, region, math.nan, gain,
                                self.pitch_integrator.saturated or angle_saturated or rate_saturated, torque_saturated)
