"""Steady operating point of the baseline schedule at a given wind speed."""
from __future__ import annotations

import math
from dataclasses import dataclass

from hawt_plant.bem import BemBlade, RotorPerformance, rotor_performance
from hawt_plant.disk_cache import kept
from hawt_plant.turbine import Turbine

__all__ = ["OperatingPoint", "baseline_operating_point", "schedule_rotor_speed"]

_PITCH_SEARCH_LIMIT = 0.8  # [rad] the rated-power pitch is searched below this (46°)


@dataclass(frozen=True)
class OperatingPoint:
    """Rotor speed [rad/s] and collective pitch [rad] of the schedule, with the performance there."""

    wind_speed: float
    rotor_speed: float
    pitch: float
    performance: RotorPerformance


def schedule_rotor_speed(turbine: Turbine, wind_speed: float) -> float:
    """The baseline schedule's rotor speed [rad/s] in ``wind_speed`` [m/s]: the optimal tip-speed ratio's, limited
    to [min_rotor_speed, rated_rotor_speed] (Jonkman et al. 2009 ch. 7)."""
    schedule = turbine.schedule
    speed = schedule.optimal_tip_speed_ratio * wind_speed / turbine.rotor.tip_radius
    return min(max(speed, schedule.min_rotor_speed), schedule.rated_rotor_speed)


def baseline_operating_point(turbine: Turbine, wind_speed: float, blade: BemBlade | None = None) -> OperatingPoint:
    """Rotor speed and pitch of the NREL baseline schedule in steady uniform wind.

    Parameters
    ----------
    turbine : Turbine
    wind_speed : float
        Hub-height wind speed [m/s], > 0.
    blade : BemBlade, optional
        ``BemBlade.from_turbine(turbine)``, precomputed: the result kept on disk is keyed by the turbine, of which the
        blade's constants are a function (a blade of other constants is not this turbine's operating point).

    Returns
    -------
    OperatingPoint

    Notes
    -----
    Jonkman et al. (2009) ch. 7: the rotor runs at the optimal tip-speed ratio, limited to
    [min_rotor_speed, rated_rotor_speed], at the minimum pitch; when that would give more
    than rated power, the rotor runs at rated speed with the pitch that gives rated
    mechanical power, rated_power / (generator efficiency x gearbox efficiency). Power
    comes from :func:`~hawt_plant.bem.rotor_performance`.
    """
    if not (math.isfinite(wind_speed) and wind_speed > 0.0):
        raise ValueError(f"wind_speed: expected a finite value > 0 m/s, found {wind_speed}")
    return kept("baseline_operating_point", (turbine, float(wind_speed)),
                lambda: _solved_operating_point(turbine, wind_speed, blade or BemBlade.from_turbine(turbine)))


def _solved_operating_point(turbine: Turbine, wind_speed: float, blade: BemBlade) -> OperatingPoint:
    """:func:`baseline_operating_point` solved: the pitch for rated power by Brent's method."""
    from scipy.optimize import brentq  # only when not kept (hawt_plant.disk_cache.kept)

    speed = schedule_rotor_speed(turbine, wind_speed)
    pitch = turbine.pitch_actuator.min_angle
    performance = rotor_performance(turbine, wind_speed, speed, pitch, blade)
    rated = turbine.rated_mechanical_power
    if performance.power > rated:
        def excess(angle: float) -> float:
            return rotor_performance(turbine, wind_speed, speed, angle, blade).power - rated

        pitch = brentq(excess, pitch, _PITCH_SEARCH_LIMIT, xtol=1e-7)
        performance = rotor_performance(turbine, wind_speed, speed, pitch, blade)
    return OperatingPoint(wind_speed=wind_speed, rotor_speed=speed, pitch=pitch, performance=performance)
