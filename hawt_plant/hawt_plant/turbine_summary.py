"""A turbine definition in a few numbers: rated values, the peak power coefficient and the first modes.

``hawt turbine show`` prints it (:func:`format_summary`). The power coefficient is the plant's steady BEM
(:func:`hawt_plant.bem.rotor_performance`: uniform wind along the shaft, precone included, no tilt, shear or
tower), searched over tip-speed ratio and over pitch from the actuator's lower limit up. The modes are those of
the plant's modal model (:mod:`hawt_plant.modal`), each on its own:

- blade flap: sqrt(k / m) standing still and sqrt((k + Omega^2 k_c) / m) at rated rotor speed (centrifugal
  stiffening), k, m, k_c the generalized stiffness, mass and centrifugal stiffness of the first flap mode;
- tower fore-aft and side-side: sqrt(k / (m + M)), m the tower's generalized mass and M the mass of the rotor
  and nacelle, a point on the top (the plant adds their rotary inertia to the fore-aft mode and couples the
  tower with the blades); over a flexible base, the tower's beam includes its substructure
  (:class:`hawt_plant.turbine.Tower`), and the summary says what the tower stands on;
- drivetrain: the free-free torsion of the rotor and the generator on the shaft spring K,
  sqrt(K (1 / J_rotor + 1 / (N^2 J_generator))), J_rotor the hub's and the coned blades' inertia about the shaft
  (the blades rigid edgewise: in the plant their edgewise modes lower it);
- blade edgewise: sqrt(k / m) of the first edgewise mode standing still; for a blade without one (rigid edgewise in
  the plant) :func:`hawt_plant.modal.blade_edgewise_frequency`'s estimate from the edge stiffness.

It also lists the definition's aerodynamic options (what the plant runs unless its parameters say otherwise), each
with its source, and the levels of its protection system (:class:`hawt_plant.turbine.ProtectionLimits`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, minimize

from hawt_plant.bem import BemBlade, rotor_performance
from hawt_plant.modal import (blade_edge_mode, blade_edgewise_frequency, blade_modal_properties, rotor_inertia,
                              tower_modal_properties)
from hawt_plant.operating_point import schedule_rotor_speed
from hawt_plant.turbine import AERODYNAMIC_OPTIONS, AerodynamicOptions, ProtectionLimits, Turbine

__all__ = ["TurbineSummary", "format_summary", "peak_power_coefficient", "turbine_summary"]

_TIP_SPEED_RATIO_STEP = 1.0  # coarse grid of the Cp search [-]; Nelder-Mead refines from its best point
_TIP_SPEED_RATIOS = np.arange(2.0, 16.01, _TIP_SPEED_RATIO_STEP)
_PITCH_SPAN = math.radians(10.0)  # the Cp search covers pitch from the lower limit to this above it [rad]
_PITCH_STEP = math.radians(2.0)
_SEARCH_WIND_SPEED = 10.0  # [m/s] the BEM's Cp depends on the tip-speed ratio and pitch only


@dataclass(frozen=True)
class TurbineSummary:
    """Rated values, the BEM's peak power coefficient and the first modal frequencies of a turbine.

    Attributes
    ----------
    name : str
    blades : int
    rotor_diameter, hub_height : float
        [m]
    rated_power : float
        Electrical [W].
    rated_rotor_speed : float
        [rad/s]
    rated_generator_torque : float
        [N m], high-speed shaft.
    gearbox_ratio : float
        [-]
    rated_wind_speed : float
        The definition's (its operating schedule) [m/s].
    bem_rated_wind_speed : float
        Where the plant's steady BEM on the schedule (optimal tip-speed ratio, then rated speed, lowest pitch)
        first gives rated power [m/s]; NaN if not below cut-out.
    max_power_coefficient, optimal_tip_speed_ratio, optimal_pitch : float
        The BEM's peak Cp [-], the tip-speed ratio [-] and pitch [rad] where it is.
    schedule_tip_speed_ratio : float
        The definition's optimal tip-speed ratio [-].
    rotor_inertia : float
        J_rotor, the hub's and the coned blades' inertia about the shaft [kg m^2].
    blade_flap_frequency, blade_flap_frequency_rated : float
        First flap mode standing still and at rated rotor speed [Hz].
    tower_base : str
        What the tower stands on (:attr:`hawt_plant.turbine.Tower.base_kind`): "ground", "rigid" or "flexible".
    tower_base_height, tower_clamp_height : float
        The tower's base (the top of its substructure) and where its beam is clamped, above the ground [m].
    tower_fa_frequency, tower_ss_frequency : float
        First fore-aft and side-side tower modes with the rotor and nacelle on top [Hz]; over a flexible base,
        those of the tower and substructure as one beam.
    drivetrain_frequency : float
        Free-free shaft torsion [Hz].
    blade_edge_frequency : float
        First edgewise mode standing still (module notes) [Hz].
    blade_edge_modelled : bool
        Whether the plant has the edgewise mode (else the frequency is an estimate and the blades rigid edgewise).
    aerodynamics : AerodynamicOptions
        The definition's aerodynamic options, with their sources.
    """

    name: str
    blades: int
    rotor_diameter: float
    hub_height: float
    rated_power: float
    rated_rotor_speed: float
    rated_generator_torque: float
    gearbox_ratio: float
    rated_wind_speed: float
    bem_rated_wind_speed: float
    max_power_coefficient: float
    optimal_tip_speed_ratio: float
    optimal_pitch: float
    schedule_tip_speed_ratio: float
    rotor_inertia: float
    blade_flap_frequency: float
    blade_flap_frequency_rated: float
    tower_base: str
    tower_base_height: float
    tower_clamp_height: float
    tower_fa_frequency: float
    tower_ss_frequency: float
    drivetrain_frequency: float
    blade_edge_frequency: float
    blade_edge_modelled: bool
    aerodynamics: AerodynamicOptions
    protection: ProtectionLimits


def peak_power_coefficient(turbine: Turbine, blade: BemBlade | None = None) -> tuple[float, float, float]:
    """The plant's steady BEM peak power coefficient and where it is.

    Searches tip-speed ratios 2..16 and pitch angles from the actuator's lower limit to 10 deg above it on a
    grid (1, 2 deg), then refines from the grid's best point (Nelder-Mead, pitch kept within those bounds).

    Returns
    -------
    cp, tip_speed_ratio, pitch : float
        [-], [-], [rad].
    """
    blade = blade or BemBlade.from_turbine(turbine)
    low = turbine.pitch_actuator.min_angle
    high = min(low + _PITCH_SPAN, turbine.pitch_actuator.max_angle)
    radius = turbine.rotor.tip_radius

    def cp(point: np.ndarray) -> float:
        tsr, pitch = float(point[0]), float(np.clip(point[1], low, high))
        speed = tsr * _SEARCH_WIND_SPEED / radius
        return rotor_performance(turbine, _SEARCH_WIND_SPEED, speed, pitch, blade).power_coefficient

    grid = [(tsr, pitch) for tsr in _TIP_SPEED_RATIOS for pitch in np.arange(low, high + 1e-9, _PITCH_STEP)]
    start = max(grid, key=lambda point: cp(np.array(point)))
    best = minimize(lambda point: -cp(point), np.array(start), method="Nelder-Mead",
                    options={"xatol": 1e-4, "fatol": 1e-7, "initial_simplex": np.array(
                        [start, (start[0] + _TIP_SPEED_RATIO_STEP, start[1]), (start[0], start[1] + _PITCH_STEP)])})
    tsr, pitch = float(best.x[0]), float(np.clip(best.x[1], low, high))
    return cp(np.array([tsr, pitch])), tsr, pitch


def _bem_rated_wind_speed(turbine: Turbine, blade: BemBlade) -> float:
    """The wind speed where the schedule at the lowest pitch first gives rated mechanical power (NaN: not below
    cut-out)."""
    schedule, rated = turbine.schedule, turbine.rated_mechanical_power

    def excess(wind_speed: float) -> float:
        return rotor_performance(turbine, wind_speed, schedule_rotor_speed(turbine, wind_speed),
                                 turbine.pitch_actuator.min_angle, blade).power - rated

    speeds = np.arange(schedule.cut_in_wind_speed, schedule.cut_out_wind_speed + 1e-9, 0.5)
    above = [v for v in speeds if excess(v) > 0.0]
    if not above or above[0] == speeds[0]:
        return math.nan
    return float(brentq(excess, above[0] - 0.5, above[0], xtol=1e-4))


def turbine_summary(turbine: Turbine) -> TurbineSummary:
    """Rated values, the BEM's peak power coefficient and the first modes of ``turbine`` (module notes)."""
    bem = BemBlade.from_turbine(turbine)
    cp, tsr, pitch = peak_power_coefficient(turbine, bem)
    rotor, schedule = turbine.rotor, turbine.schedule
    blade = blade_modal_properties(turbine)
    edge = blade_edge_mode(turbine)
    omega = schedule.rated_rotor_speed
    top = rotor.hub_mass + turbine.nacelle.mass + rotor.number_of_blades * blade.mass
    tower = {direction: tower_modal_properties(turbine, direction, top) for direction in ("fa", "ss")}
    inertia = rotor_inertia(turbine, blade)
    drivetrain = turbine.drivetrain
    generator_inertia = drivetrain.generator_inertia * drivetrain.gearbox_ratio**2
    torsion_inertia = 1.0 / (1.0 / inertia + 1.0 / generator_inertia)

    def hertz(stiffness: float, mass: float) -> float:
        return math.sqrt(stiffness / mass) / (2.0 * math.pi)

    return TurbineSummary(
        name=turbine.name, blades=rotor.number_of_blades, rotor_diameter=2.0 * rotor.tip_radius,
        hub_height=turbine.hub_height, rated_power=turbine.generator.rated_power, rated_rotor_speed=omega,
        rated_generator_torque=turbine.generator.rated_torque, gearbox_ratio=drivetrain.gearbox_ratio,
        rated_wind_speed=schedule.rated_wind_speed, bem_rated_wind_speed=_bem_rated_wind_speed(turbine, bem),
        max_power_coefficient=cp, optimal_tip_speed_ratio=tsr, optimal_pitch=pitch,
        schedule_tip_speed_ratio=schedule.optimal_tip_speed_ratio, rotor_inertia=inertia,
        blade_flap_frequency=hertz(blade.stiffness, blade.modal_mass),
        blade_flap_frequency_rated=hertz(blade.stiffness + omega**2 * blade.centrifugal_stiffness, blade.modal_mass),
        tower_base=turbine.tower.base_kind, tower_base_height=turbine.tower.base_height,
        tower_clamp_height=turbine.tower.clamp_height,
        tower_fa_frequency=hertz(tower["fa"].stiffness, tower["fa"].modal_mass + top),
        tower_ss_frequency=hertz(tower["ss"].stiffness, tower["ss"].modal_mass + top),
        drivetrain_frequency=hertz(drivetrain.torsional_stiffness, torsion_inertia),
        blade_edge_frequency=hertz(edge.stiffness, edge.modal_mass) if edge else blade_edgewise_frequency(turbine),
        blade_edge_modelled=edge is not None,
        aerodynamics=turbine.aerodynamics, protection=turbine.protection,
    )


def _tower_base(summary: TurbineSummary) -> str:
    """What the tower stands on, in words."""
    if summary.tower_base == "flexible":
        return (f"a flexible base: its substructure, from its clamp at {summary.tower_clamp_height:g} m to the tower's "
                f"base at {summary.tower_base_height:g} m (heights above the ground, offshore above mean sea level), "
                "bends with it as one beam")
    if summary.tower_base == "rigid":
        return f"a rigid base {summary.tower_base_height:g} m high: the tower is clamped there"
    return "the ground: the tower is clamped there"


def format_summary(summary: TurbineSummary) -> str:
    """The summary as a few lines of text (what ``hawt turbine show`` prints)."""
    s, p = summary, summary.protection
    rpm = 30.0 / math.pi
    bem_rated = "does not reach rated power" if math.isnan(s.bem_rated_wind_speed) else \
        f"reaches rated power at {s.bem_rated_wind_speed:.2f} m/s"
    return "\n".join([
        f"{s.name}: {s.blades} blades, rotor diameter {s.rotor_diameter:.1f} m, hub height {s.hub_height:.1f} m",
        f"rated: {s.rated_power / 1e6:.3g} MW electrical, rotor {s.rated_rotor_speed * rpm:.2f} rpm, generator "
        f"{s.rated_rotor_speed * s.gearbox_ratio * rpm:.1f} rpm and {s.rated_generator_torque / 1e3:.5g} kN m "
        f"(gearbox {s.gearbox_ratio:g}), wind {s.rated_wind_speed:.2f} m/s (the plant's steady BEM {bem_rated})",
        f"Cp-max {s.max_power_coefficient:.4f} at tip-speed ratio {s.optimal_tip_speed_ratio:.2f}, pitch "
        f"{math.degrees(s.optimal_pitch):.2f} deg (the plant's steady BEM; the schedule's tip-speed ratio "
        f"{s.schedule_tip_speed_ratio:g})",
        f"first modes: blade flap {s.blade_flap_frequency:.3f} Hz standing, {s.blade_flap_frequency_rated:.3f} Hz at "
        f"rated speed, blade edgewise {s.blade_edge_frequency:.3f} Hz standing"
        f"{'' if s.blade_edge_modelled else ' (estimated; the plant holds the blades rigid edgewise)'}; tower "
        f"fore-aft {s.tower_fa_frequency:.3f} Hz, side-side {s.tower_ss_frequency:.3f} Hz; drivetrain torsion "
        f"{s.drivetrain_frequency:.3f} Hz (blades rigid edgewise)",
        f"the tower stands on {_tower_base(s)}",
        "aerodynamics (what the plant runs; its parameter of the same name, true or false, overrides one):",
        *(f"  {s.aerodynamics.state(name)}: {s.aerodynamics.sources[name]}" for name in AERODYNAMIC_OPTIONS),
        f"protection (the safety system trips and feathers above these; the definition's protection section sets "
        f"them): rotor {p.rotor_speed_trip * rpm:.2f} rpm ({p.rotor_speed_trip / s.rated_rotor_speed:.3g} x rated; "
        f"warning at {p.rotor_speed_warning * rpm:.2f}), generator {p.generator_speed_trip * rpm:.1f} rpm (warning at "
        f"{p.generator_speed_warning * rpm:.1f}), tower-top acceleration {p.tower_top_acceleration_trip:g} m/s^2, "
        f"pitch asymmetry {math.degrees(p.pitch_asymmetry_trip):.3g} deg, pitch rate "
        f"{math.degrees(p.pitch_rate_trip):.3g} deg/s",
    ])
