"""The baseline collective controller (:mod:`hawt_controllers.laws.collective`) tuned from a turbine definition.

Jonkman, Butterfield, Musial & Scott (2009), NREL/TP-500-38060, chapter 7, tuned the NREL 5 MW's controller from
its model; :func:`design_collective` does the same for any turbine the plant runs (``hawt design cpc``), from the
plant's own steady BEM (:mod:`hawt_plant.bem`), modal model (:mod:`hawt_plant.modal`) and summary
(:func:`hawt_plant.turbine_summary.turbine_summary`):

1. Region-2 torque gain (Jonkman §7.2), on the high-speed shaft:
   ``k = 1/2 rho pi R^5 Cp_max / (lambda_opt^3 N^3)``, Cp_max and lambda_opt the plant's steady-BEM peak and R the
   tip radius (the swept area the plant's Cp refers to). ROSCO's ``vs_rgn2K`` (``rosco/toolbox/controller.py``)
   also multiplies by the gearbox efficiency: the plant's drivetrain dynamics have no gearbox loss, so it is left out.
2. Rated-speed pitch PI (Jonkman §7.4). The rotor and the generator are one inertia on the low-speed shaft,
   ``I = J_rotor + N^2 J_generator``; linearised at rated speed Omega_0 with the aerodynamic damping left out,
   ``I dOmega/dt = (1/Omega_0) (dP/dtheta) dtheta``, and the law ``dtheta = N (K_P dOmega + K_I int dOmega dt)``
   (the gains act on the generator-speed error) closes the loop ``phi'' + 2 zeta omega_n phi' + omega_n^2 phi = 0``
   with (:func:`pitch_gains`)

       K_P = 2 I Omega_0 zeta omega_n / (N (-dP/dtheta)),   K_I = I Omega_0 omega_n^2 / (N (-dP/dtheta)).

   Jonkman chose omega_n = 0.6 rad/s and zeta = 0.7 (the defaults here); ROSCO tunes the IEA 15 MW with 0.2 rad/s
   and 1.0. dP/dtheta is the plant's frozen-wake sensitivity (:func:`hawt_plant.bem.pitch_sensitivity`: the
   induction held, as Jonkman's FAST linearisation with AeroDyn v13 computed it) at the steady region-3 points
   (:func:`region3_points`). Jonkman's observation that it is nearly linear in the pitch,
   ``dP/dtheta = dP/dtheta(0) (1 + theta/theta_K)``, makes the gains ``K(theta) = K(0) GK(theta)`` with
   ``GK = 1/(1 + theta/theta_K)``, the law's schedule: a least-squares line through the points gives dP/dtheta(0)
   and theta_K (:func:`fit_sensitivity`; Jonkman: -25.52 MW/rad and 6.302336 deg).

   ROSCO (``ControllerTypes.second_order_PI``) writes the same loop as ``d(omega_g)/dt = A omega_g + B theta`` with
   ``B = N dQ/dtheta / I`` (< 0) and the error ``omega_ref - omega_g``: ``K_P = (2 zeta omega_n + A)/B``,
   ``K_I = omega_n^2/B`` (both negative in its DISCON.IN; here the error is ``omega_g - omega_ref`` and the gains
   are positive). With A = 0 these are Jonkman's. ROSCO's ``A = (dQ/dOmega + P/Omega_0^2)/I`` keeps the
   aerodynamic damping and, with constant-power torque as this law's region 3, the generator's negative damping;
   its K_P changes sign over region 3, which the law's one-gain-times-GK schedule cannot follow. The design keeps
   Jonkman's A = 0 and reports A at each point (the equilibrium dQ/dOmega, as ROSCO's from its Cp surface) and the
   damping ratio the loop then has, ``zeta - A/(2 omega_n)``.

   The plant's induction is quasi-steady by default (its ``dynamic_inflow`` parameter off): there the pitch acts
   with the equilibrium sensitivity, smaller than the frozen-wake one by about half just above rated and by 12-17 %
   at cut-out (NREL 5 MW, IEA 15 MW), and the loop is that much slower than designed; the design reports both.
3. Generator-speed filter (Jonkman §7.1): the corner at a quarter of the blade's first edgewise frequency (his
   0.25 Hz for about 1 Hz; ROSCO's IEA 15 MW F_LPFCornerFreq is its bld_edgewise_freq / 4 too). The plant has no
   edgewise mode: :func:`hawt_plant.modal.blade_edgewise_frequency` estimates it from the edge stiffness.
4. Set points and limits: the turbine definition's rated rotor speed x N (the pitch reference), rated power /
   generator efficiency (the mechanical rated power at the generator, as Jonkman's VS_RtPwr), maximum torque and
   torque rate, pitch limits and rate; the cut-in speed is the definition's minimum rotor speed x N (Jonkman's
   670 rpm for 6.9 rpm). The rest keeps the NREL 5 MW file's conventions (``data/nrel5mw_baseline.yaml``, read
   from it: :data:`~hawt_controllers.laws.collective.DEFAULT_BASELINE_FILE`): region 2 starts 30 % above cut-in,
   region 2 1/2 ends at 99 % of rated speed with a 10 % slip, region 3 from 1 deg above the lowest pitch, and the
   near-rated K_I factor (0.4 below 1 deg above the lowest pitch, 1 from 4 deg).

References
----------
.. [1] J. Jonkman, S. Butterfield, W. Musial, G. Scott, "Definition of a 5-MW Reference Wind Turbine for Offshore
   System Development", NREL/TP-500-38060, 2009, §7.1-7.4.
.. [2] N. Abbas, D. Zalkind, L. Pao, A. Wright, "A reference open-source controller for fixed and floating offshore
   wind turbines", Wind Energy Science 7:53-73, 2022 (ROSCO; its toolbox ``rosco/toolbox/controller.py``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np

from hawt_plant.bem import BemBlade, pitch_sensitivity, rotor_performance
from hawt_plant.operating_point import baseline_operating_point
from hawt_plant.turbine import Turbine
from hawt_plant.turbine_summary import turbine_summary

from hawt_controllers.laws.collective import BaselineCollectiveConfig, gain_correction_factor, load_baseline_config
from hawt_core.exceptions import ConfigurationError

__all__ = ["CollectiveDesign", "JONKMAN_DAMPING_RATIO", "JONKMAN_NATURAL_FREQUENCY", "Region3Points",
           "design_collective", "discon_comparison", "fit_sensitivity", "format_comparison", "format_design",
           "jonkman_comparison", "pitch_gains", "region3_points", "write_design"]

JONKMAN_NATURAL_FREQUENCY = 0.6
"""omega_n of the pitch loop [rad/s], Jonkman et al. (2009) §7.4."""
JONKMAN_DAMPING_RATIO = 0.7
"""zeta of the pitch loop [-], Jonkman et al. (2009) §7.4."""
NATURAL_FREQUENCY_RANGE = (0.02, 3.0)
"""The omega_n [rad/s] a design may ask for: ROSCO's tunings lie within 0.1-1 rad/s (IEA 15 MW 0.2, Jonkman 0.6);
beyond 3 rad/s the loop would reach the drivetrain and tower modes, below 0.02 it no longer regulates."""
DAMPING_RATIO_RANGE = (0.1, 5.0)
"""The zeta [-] a design may ask for (ROSCO's tunings: 0.7-1.0)."""
_CORNER_SHARE = 0.25  # the speed filter's corner as a share of the blade's first edgewise frequency (Jonkman §7.1)
_SPEED_STEP = 1e-3  # [rad/s] central difference of the aerodynamic torque over the rotor speed


@dataclass(frozen=True, eq=False)
class Region3Points:
    """The steady region-3 operating points of a turbine and the plant's sensitivities there.

    Attributes
    ----------
    wind_speed, pitch, rotor_speed : ndarray, shape (M,)
        [m/s], [rad], [rad/s] (:func:`hawt_plant.operating_point.baseline_operating_point`).
    sensitivity : ndarray, shape (M,)
        Frozen-wake dP/dtheta of the aerodynamic power [W/rad].
    equilibrium_sensitivity : ndarray, shape (M,)
        dP/dtheta with the induction re-solved [W/rad].
    torque_speed_slope : ndarray, shape (M,)
        dQ/dOmega of the aerodynamic torque with the induction re-solved [N m s/rad] (< 0: aerodynamic damping).
    """

    wind_speed: np.ndarray
    pitch: np.ndarray
    rotor_speed: np.ndarray
    sensitivity: np.ndarray
    equilibrium_sensitivity: np.ndarray
    torque_speed_slope: np.ndarray


def region3_points(turbine: Turbine, blade: BemBlade | None = None) -> Region3Points:
    """The plant's steady points where the schedule pitches, and dP/dtheta and dQ/dOmega there.

    The wind speeds are the definition's rated wind speed and the whole m/s above it up to cut-out; a point whose
    schedule pitch stays at the lower limit (the plant's BEM reaches rated power above that speed) is left out.

    Raises
    ------
    ConfigurationError
        Fewer than two such points.
    """
    blade = blade or BemBlade.from_turbine(turbine)
    schedule = turbine.schedule
    speeds = [schedule.rated_wind_speed, *np.arange(math.floor(schedule.rated_wind_speed) + 1.0,
                                                    schedule.cut_out_wind_speed + 1e-9)]
    rows = []
    for wind_speed in speeds:
        point = baseline_operating_point(turbine, float(wind_speed), blade)
        if point.pitch <= turbine.pitch_actuator.min_angle:
            continue
        omega, pitch = point.rotor_speed, point.pitch
        slope = (rotor_performance(turbine, point.wind_speed, omega + _SPEED_STEP, pitch, blade).torque
                 - rotor_performance(turbine, point.wind_speed, omega - _SPEED_STEP, pitch, blade).torque) / (
                     2.0 * _SPEED_STEP)
        rows.append((point.wind_speed, pitch, omega,
                     pitch_sensitivity(turbine, point.wind_speed, omega, pitch, frozen_wake=True, blade=blade),
                     pitch_sensitivity(turbine, point.wind_speed, omega, pitch, frozen_wake=False, blade=blade),
                     slope))
    if len(rows) < 2:
        raise ConfigurationError("turbine", f"{turbine.name}: the schedule pitches at {len(rows)} of the wind speeds "
                                            f"{speeds[0]:g}..{speeds[-1]:g} m/s; the design needs two or more")
    return Region3Points(*(np.array(column) for column in zip(*rows)))


def fit_sensitivity(pitch: np.ndarray, sensitivity: np.ndarray) -> tuple[float, float]:
    """Jonkman's linear model of the pitch sensitivity: dP/dtheta = dP/dtheta(0) (1 + theta/theta_K).

    Parameters
    ----------
    pitch : ndarray, shape (M,)
        [rad]
    sensitivity : ndarray, shape (M,)
        dP/dtheta [W/rad] at those pitch angles.

    Returns
    -------
    at_zero, gain_doubling_pitch : float
        dP/dtheta(0) [W/rad] (< 0) and theta_K [rad], from the least-squares line through the points.

    Raises
    ------
    ConfigurationError
        A line whose value at zero pitch is not negative or that does not grow in magnitude with the pitch.

    Examples
    --------
    >>> at_zero, theta_k = fit_sensitivity(np.array([0.1, 0.2]), np.array([-2.0, -3.0]))
    >>> round(at_zero, 9), round(theta_k, 9)
    (-1.0, 0.1)
    """
    pitch = np.asarray(pitch, float)
    slope, at_zero = np.polyfit(pitch, np.asarray(sensitivity, float), 1)
    # A flat line's fitted slope is round-off of either sign (it depends on the BLAS): growth is judged over the range.
    if not (at_zero < 0.0 and slope * np.ptp(pitch) < -1e-9 * abs(at_zero)):
        raise ConfigurationError("sensitivity", f"the line dP/dtheta = {at_zero:.6g} + {slope:.6g} theta W/rad is "
                                                "not of the form dP/dtheta(0) (1 + theta/theta_K), theta_K > 0")
    return float(at_zero), float(at_zero / slope)


def pitch_gains(sensitivity: float, drivetrain_inertia: float, rated_rotor_speed: float, gearbox_ratio: float,
                natural_frequency: float, damping_ratio: float) -> tuple[float, float]:
    """Jonkman's PI gains on the generator-speed error for a pitch sensitivity (Jonkman et al. 2009 §7.4).

    Parameters
    ----------
    sensitivity : float
        dP/dtheta [W/rad], < 0.
    drivetrain_inertia : float
        I = J_rotor + N^2 J_generator [kg m^2] on the low-speed shaft.
    rated_rotor_speed : float
        Omega_0 [rad/s].
    gearbox_ratio : float
        N [-].
    natural_frequency, damping_ratio : float
        omega_n [rad/s] and zeta [-] of the closed speed loop.

    Returns
    -------
    proportional, integral : float
        K_P = 2 I Omega_0 zeta omega_n / (N (-dP/dtheta)) [s] and K_I = I Omega_0 omega_n^2 / (N (-dP/dtheta)) [-].

    Examples
    --------
    Jonkman's NREL 5 MW at zero pitch (I = 43 784 725 kg m^2, dP/dtheta(0) = -25.52 MW/rad): his PC_KP and
    PC_KI are 0.01882681 s and 0.008068634.

    >>> kp, ki = pitch_gains(-25.52e6, 43784725.0, 1.26711, 97.0, 0.6, 0.7)
    >>> print(f"{kp:.6f} {ki:.6f}")
    0.018826 0.008068
    """
    if not sensitivity < 0.0:
        raise ConfigurationError("sensitivity", f"must be < 0 (feathering sheds power), found {sensitivity}")
    scale = drivetrain_inertia * rated_rotor_speed / (gearbox_ratio * -sensitivity)
    return 2.0 * scale * damping_ratio * natural_frequency, scale * natural_frequency**2


@dataclass(frozen=True, eq=False)
class CollectiveDesign:
    """A tuning of the baseline controller and the numbers it came from (module notes).

    Attributes
    ----------
    config : BaselineCollectiveConfig
        The tuning.
    turbine : str
        The turbine definition's name.
    natural_frequency, damping_ratio : float
        omega_n [rad/s] and zeta [-] the pitch loop was designed for.
    drivetrain_inertia : float
        I = J_rotor + N^2 J_generator [kg m^2].
    rotor_inertia : float
        J_rotor [kg m^2] (the turbine summary's).
    gearbox_ratio : float
        N [-].
    max_power_coefficient, optimal_tip_speed_ratio : float
        The plant's steady-BEM peak Cp [-] and its tip-speed ratio [-].
    blade_edge_frequency : float
        The estimated first edgewise frequency [Hz].
    points : Region3Points
        The region-3 points the pitch gains were fitted over.
    sensitivity_at_zero_pitch : float
        dP/dtheta(0) of the fitted line [W/rad].
    """

    config: BaselineCollectiveConfig
    turbine: str
    natural_frequency: float
    damping_ratio: float
    drivetrain_inertia: float
    rotor_inertia: float
    gearbox_ratio: float
    max_power_coefficient: float
    optimal_tip_speed_ratio: float
    blade_edge_frequency: float
    points: Region3Points
    sensitivity_at_zero_pitch: float

    def scheduled_gains(self, pitch: float) -> tuple[float, float]:
        """K_P(theta) = K_P(0) GK(theta) [s] and K_I(theta) = K_I(0) GK(theta) [-], the law's schedule (before its
        near-rated K_I factor)."""
        gain = gain_correction_factor(pitch, self.config.gain_doubling_pitch)
        return gain * self.config.proportional_gain, gain * self.config.integral_gain

    @property
    def speed_damping(self) -> np.ndarray:
        """ROSCO's A = (dQ/dOmega + P/Omega_0^2) / I at each point [1/s] (P the law's constant region-3 power)."""
        omega = self.config.rated_generator_speed / self.gearbox_ratio
        return (self.points.torque_speed_slope + self.config.rated_generator_power / omega**2) / self.drivetrain_inertia

    @property
    def damping_with_speed_terms(self) -> np.ndarray:
        """The loop's damping ratio at each point with A counted, zeta - A / (2 omega_n) [-] (the gains there the
        schedule's, the pitch sensitivity the frozen-wake line's)."""
        return self.damping_ratio - self.speed_damping / (2.0 * self.natural_frequency)


def design_collective(turbine: Turbine, natural_frequency: float = JONKMAN_NATURAL_FREQUENCY,
                      damping_ratio: float = JONKMAN_DAMPING_RATIO) -> CollectiveDesign:
    """The baseline controller tuned for ``turbine`` by Jonkman's method (module notes).

    Parameters
    ----------
    turbine : Turbine
    natural_frequency : float
        omega_n of the pitch loop [rad/s], within :data:`NATURAL_FREQUENCY_RANGE`.
    damping_ratio : float
        zeta [-], within :data:`DAMPING_RATIO_RANGE`.

    Returns
    -------
    CollectiveDesign

    Raises
    ------
    ConfigurationError
        Naming the argument or the field at fault (a turbine whose numbers give a tuning the law refuses, e.g.
        region 2 ending before it starts).
    """
    for name, value, (low, high), unit in (("natural_frequency", natural_frequency, NATURAL_FREQUENCY_RANGE, " rad/s"),
                                           ("damping_ratio", damping_ratio, DAMPING_RATIO_RANGE, "")):
        if not low <= value <= high:
            raise ConfigurationError(name, f"{value:g}{unit} outside the design range [{low:g}, {high:g}]{unit}")
    summary = turbine_summary(turbine)
    points = region3_points(turbine)
    at_zero, theta_k = fit_sensitivity(points.pitch, points.sensitivity)
    drivetrain = turbine.drivetrain
    ratio = drivetrain.gearbox_ratio
    inertia = summary.rotor_inertia + ratio**2 * drivetrain.generator_inertia
    omega = turbine.schedule.rated_rotor_speed
    kp, ki = pitch_gains(at_zero, inertia, omega, ratio, natural_frequency, damping_ratio)
    radius = turbine.rotor.tip_radius
    k = (0.5 * turbine.environment.air_density * math.pi * radius**5 * summary.max_power_coefficient
         / (summary.optimal_tip_speed_ratio**3 * ratio**3))
    nrel = load_baseline_config()
    actuator = turbine.pitch_actuator
    lowest = actuator.min_angle
    cut_in = turbine.schedule.min_rotor_speed * ratio
    config = BaselineCollectiveConfig(
        generator_speed_corner_frequency=2.0 * math.pi * _CORNER_SHARE * summary.blade_edge_frequency,
        rated_generator_speed=omega * ratio,
        proportional_gain=kp,
        integral_gain=ki,
        gain_doubling_pitch=theta_k,
        min_pitch=lowest,
        max_pitch=actuator.max_angle,
        max_pitch_rate=actuator.max_rate,
        cut_in_generator_speed=cut_in,
        region2_start_generator_speed=cut_in * nrel.region2_start_generator_speed / nrel.cut_in_generator_speed,
        region2_torque_constant=k,
        region25_generator_speed=omega * ratio * nrel.region25_generator_speed / nrel.rated_generator_speed,
        rated_generator_power=turbine.generator.rated_power / turbine.generator.efficiency,
        region25_slip=nrel.region25_slip,
        region3_min_pitch=lowest + nrel.region3_min_pitch - nrel.min_pitch,
        max_generator_torque=turbine.generator.max_torque,
        max_torque_rate=turbine.generator.max_torque_rate,
        near_rated_integral_factor=nrel.near_rated_integral_factor,
        near_rated_pitch_low=lowest + nrel.near_rated_pitch_low - nrel.min_pitch,
        near_rated_pitch_high=lowest + nrel.near_rated_pitch_high - nrel.min_pitch,
    )
    return CollectiveDesign(
        config=config, turbine=turbine.name, natural_frequency=float(natural_frequency),
        damping_ratio=float(damping_ratio), drivetrain_inertia=inertia, rotor_inertia=summary.rotor_inertia,
        gearbox_ratio=ratio,
        max_power_coefficient=summary.max_power_coefficient, optimal_tip_speed_ratio=summary.optimal_tip_speed_ratio,
        blade_edge_frequency=summary.blade_edge_frequency, points=points, sensitivity_at_zero_pitch=at_zero)


_WHERE = {
    "generator_speed_corner_frequency": "1/4 of the blade's first edgewise mode, {edge:.4g} Hz (estimated from the "
                                        "edge stiffness)",
    "rated_generator_speed": "the definition's rated rotor speed x gearbox ratio",
    "proportional_gain": "K_P(0) = 2 I Omega_0 zeta omega_n / (N (-dP/dtheta(0)))",
    "integral_gain": "K_I(0) = I Omega_0 omega_n^2 / (N (-dP/dtheta(0)))",
    "gain_doubling_pitch": "theta_K of the least-squares line dP/dtheta(0) (1 + theta/theta_K), {theta_k:.4f} deg",
    "min_pitch": "the definition's pitch actuator",
    "max_pitch": "the definition's pitch actuator",
    "max_pitch_rate": "the definition's pitch actuator",
    "cut_in_generator_speed": "the definition's minimum rotor speed x gearbox ratio",
    "region2_start_generator_speed": "30 % above cut-in (the NREL 5 MW file's 871/670 rpm)",
    "region2_torque_constant": "1/2 rho pi R^5 Cp_max / (lambda_opt^3 N^3), Cp_max {cp:.4f} at lambda_opt {tsr:.3f}",
    "region25_generator_speed": "99 % of rated_generator_speed (the NREL 5 MW file's)",
    "rated_generator_power": "the definition's rated power / generator efficiency",
    "region25_slip": "the NREL 5 MW file's",
    "region3_min_pitch": "1 deg above min_pitch (the NREL 5 MW file's)",
    "max_generator_torque": "the definition's generator",
    "max_torque_rate": "the definition's generator",
    "near_rated_integral_factor": "the NREL 5 MW file's",
    "near_rated_pitch_low": "1 deg above min_pitch (the NREL 5 MW file's)",
    "near_rated_pitch_high": "4 deg above min_pitch (the NREL 5 MW file's)",
}


def write_design(design: CollectiveDesign, path: str | Path) -> Path:
    """Write the tuning as a file :func:`~hawt_controllers.laws.collective.load_baseline_config` reads (the format of
    ``data/nrel5mw_baseline.yaml``), each value with where it comes from; returns the path."""
    path = Path(path)
    d = design
    where = {name: text.format(edge=d.blade_edge_frequency, theta_k=math.degrees(d.config.gain_doubling_pitch),
                               cp=d.max_power_coefficient, tsr=d.optimal_tip_speed_ratio)
             for name, text in _WHERE.items()}
    lines = [
        f"# {d.turbine}: baseline collective pitch and generator-torque controller, SI units.",
        "#",
        "# Designed by hawt design cpc (hawt_controllers.design.cpc_design) from the turbine definition with the method of",
        "# Jonkman et al. (2009), NREL/TP-500-38060, ch. 7: pitch loop natural frequency "
        f"{d.natural_frequency:g} rad/s, damping {d.damping_ratio:g};",
        f"# drivetrain inertia I = {d.drivetrain_inertia:.6g} kg m^2 on the low-speed shaft; the plant's frozen-wake",
        f"# dP/dtheta(0) = {d.sensitivity_at_zero_pitch / 1e6:.4f} MW/rad fitted over {len(d.points.wind_speed)} "
        f"steady region-3 points, {d.points.wind_speed[0]:g}..{d.points.wind_speed[-1]:g} m/s.",
        "# Keys are the fields of hawt_controllers.laws.collective.BaselineCollectiveConfig.",
        f'source: "hawt design cpc: {d.turbine}, Jonkman et al. (2009) ch. 7 method, omega_n '
        f'{d.natural_frequency:g} rad/s, zeta {d.damping_ratio:g}"',
        "parameters:",
        *(f"  {f.name}: {getattr(d.config, f.name):.10g}  # {where[f.name]}" for f in fields(d.config)),
    ]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def format_design(design: CollectiveDesign) -> str:
    """The design as text: its inputs, the region-3 schedule point by point and the tuning's other values."""
    d, c = design, design.config
    p = d.points
    line = d.sensitivity_at_zero_pitch * (1.0 + p.pitch / c.gain_doubling_pitch)
    rows = [f"{v:6.2f} {math.degrees(theta):7.2f} {frozen / 1e6:9.2f} {fit / 1e6:9.2f} {slow / 1e6:9.2f} "
            f"{d.scheduled_gains(theta)[0]:10.5g} {d.scheduled_gains(theta)[1]:10.5g} {a:8.4f} {zeta:6.3f}"
            for v, theta, frozen, fit, slow, a, zeta in zip(p.wind_speed, p.pitch, p.sensitivity, line,
                                                          p.equilibrium_sensitivity, d.speed_damping,
                                                          d.damping_with_speed_terms)]
    return "\n".join([
        f"{d.turbine}: baseline collective controller, Jonkman et al. (2009) ch. 7 method, omega_n "
        f"{d.natural_frequency:g} rad/s, zeta {d.damping_ratio:g}",
        f"drivetrain inertia I = {d.rotor_inertia:.6g} (rotor) + N^2 J_gen = {d.drivetrain_inertia:.6g} kg m^2, "
        f"N = {d.gearbox_ratio:g}, rated {c.rated_generator_speed:.6g} rad/s at the generator",
        f"pitch sensitivity (frozen wake): dP/dtheta = {d.sensitivity_at_zero_pitch / 1e6:.4f} MW/rad x (1 + theta / "
        f"{math.degrees(c.gain_doubling_pitch):.4f} deg); K_P(0) = {c.proportional_gain:.6g} s, "
        f"K_I(0) = {c.integral_gain:.6g}",
        f"{'wind':>6s} {'pitch':>7s} {'dP/dth':>9s} {'line':>9s} {'equil.':>9s} {'K_P':>10s} {'K_I':>10s} "
        f"{'A':>8s} {'zeta_A':>6s}",
        f"{'[m/s]':>6s} {'[deg]':>7s} {'[MW/rad]':>9s} {'[MW/rad]':>9s} {'[MW/rad]':>9s} {'[s]':>10s} {'[-]':>10s} "
        f"{'[1/s]':>8s} {'[-]':>6s}",
        *rows,
        "(dP/dth frozen wake, line the fit, equil. with the induction re-solved as the plant's quasi-steady induction "
        "sees it; K_P, K_I the law's schedule K(0) GK(theta); A = (dQ/dOmega + P/Omega_0^2)/I, ROSCO's term the "
        "design leaves out, and zeta_A the damping with it)",
        f"region 2: k = {c.region2_torque_constant:.6g} N m/(rad/s)^2 from Cp-max {d.max_power_coefficient:.4f} at "
        f"tip-speed ratio {d.optimal_tip_speed_ratio:.3f}; speed filter corner "
        f"{c.generator_speed_corner_frequency:.4f} rad/s ({c.generator_speed_corner_frequency / (2.0 * math.pi):.4f} "
        f"Hz, 1/4 of the estimated blade edgewise {d.blade_edge_frequency:.4f} Hz)",
    ])


def jonkman_comparison(design: CollectiveDesign,
                       reference: BaselineCollectiveConfig | None = None) -> list[tuple[str, float, float]]:
    """The design beside Jonkman's NREL 5 MW tuning (default ``data/nrel5mw_baseline.yaml``): the gains at zero pitch,
    theta_K, the schedule's K_P across region 3, k and the speed filter's corner."""
    jonkman = reference or load_baseline_config()
    c = design.config
    rows = [("K_P(0) [s]", c.proportional_gain, jonkman.proportional_gain),
            ("K_I(0) [-]", c.integral_gain, jonkman.integral_gain),
            ("theta_K [deg]", math.degrees(c.gain_doubling_pitch), math.degrees(jonkman.gain_doubling_pitch))]
    for degrees in (5.0, 10.0, 15.0, 20.0, 23.47):
        theta = math.radians(degrees)
        rows.append((f"K_P({degrees:g} deg) [s]", design.scheduled_gains(theta)[0],
                     gain_correction_factor(theta, jonkman.gain_doubling_pitch) * jonkman.proportional_gain))
    return rows + [
        ("k [N m/(rad/s)^2]", c.region2_torque_constant, jonkman.region2_torque_constant),
        ("speed filter corner [Hz]", c.generator_speed_corner_frequency / (2.0 * math.pi),
         jonkman.generator_speed_corner_frequency / (2.0 * math.pi)),
        ("cut-in generator speed [rad/s]", c.cut_in_generator_speed, jonkman.cut_in_generator_speed),
        ("rated generator power [W]", c.rated_generator_power, jonkman.rated_generator_power),
    ]


def _discon_numbers(settings: Mapping[str, str], name: str) -> np.ndarray:
    if name not in settings:
        raise ConfigurationError(name, "missing from the DISCON.IN")
    try:
        return np.array([float(word) for word in settings[name].split()])
    except ValueError:
        raise ConfigurationError(name, f"expected numbers, found {settings[name]!r}") from None


def discon_comparison(design: CollectiveDesign, settings: Mapping[str, str],
                      every: int = 5) -> list[tuple[str, float, float]]:
    """The design beside a ROSCO DISCON.IN's tuning (its settings, :func:`hawt_controllers.discon.rosco_input.read_settings`):
    K_P and K_I at every ``every``-th pitch of PC_GS_angles and the last (ROSCO's signs turned: its error is
    reference - speed), VS_Rgn2K, F_LPFCornerFreq and PC_RefSpd.

    Raises
    ------
    ConfigurationError
        A setting missing or not numbers, naming it.
    """
    angles, kp, ki = (_discon_numbers(settings, name) for name in ("PC_GS_angles", "PC_GS_KP", "PC_GS_KI"))
    c = design.config
    rows = []
    for k in sorted({*range(0, len(angles), every), len(angles) - 1}):
        proportional, integral = design.scheduled_gains(float(angles[k]))
        degrees = math.degrees(angles[k])
        rows += [(f"K_P({degrees:.2f} deg) [s]", proportional, -kp[k]),
                 (f"K_I({degrees:.2f} deg) [-]", integral, -ki[k])]
    return rows + [
        ("k [N m/(rad/s)^2] (VS_Rgn2K)", c.region2_torque_constant, float(_discon_numbers(settings, "VS_Rgn2K")[0])),
        ("speed filter corner [rad/s] (F_LPFCornerFreq)", c.generator_speed_corner_frequency,
         float(_discon_numbers(settings, "F_LPFCornerFreq")[0])),
        ("rated generator speed [rad/s] (PC_RefSpd)", c.rated_generator_speed,
         float(_discon_numbers(settings, "PC_RefSpd")[0])),
    ]


def format_comparison(title: str, rows: Sequence[tuple[str, float, float]]) -> str:
    """Rows (quantity with its unit, designed value, reference value) of :func:`jonkman_comparison` or
    :func:`discon_comparison` as a table under ``title``, with the difference in per cent."""
    width = max(len(name) for name, _, _ in rows)
    lines = [title, f"{'':{width}s} {'designed':>12s} {'reference':>12s} {'difference':>10s}"]
    for name, designed, reference in rows:
        same_sign = designed * reference > 0.0  # a ratio of opposite signs or to zero means nothing
        difference = f"{100.0 * (designed / reference - 1.0):+9.1f}%" if same_sign else f"{'':>10s}"
        lines.append(f"{name:{width}s} {designed:12.6g} {reference:12.6g} {difference}")
    return "\n".join(lines)
