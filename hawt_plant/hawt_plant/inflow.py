"""Choosing the plant's wind field from a few named settings (the plant node's parameters)."""
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from hawt_plant.bts import read_bts
from hawt_plant.gusts import ExtremeOperatingGust, WindStep
from hawt_plant.iec_extreme import (ExtremeWindShear, extreme_coherent_gust, extreme_direction_change,
                                    steady_extreme_wind)
from hawt_plant.shear_wind import PowerLawWind
from hawt_plant.turbulence import TurbulenceSpec, cached_turbulence, rotor_grid_size
from hawt_plant.wind_field import WindField, YawedWind

__all__ = ["OPERATING_WIND_KINDS", "PARKED_WIND_KINDS", "WIND_KINDS", "InflowSettings", "make_wind"]

OPERATING_WIND_KINDS = ("steady", "turbulent", "bts", "step", "eog", "edc", "ecd", "ews_vertical", "ews_horizontal")
"""The winds an operating rotor runs in: the plant's ``wind_type`` choices."""
PARKED_WIND_KINDS = ("ewm50", "ewm1")
"""The steady extreme wind model's, for an idling or parked rotor only (IEC DLC 6.x; the plant's ``rotor``): no
operating point holds rated power at 56-70 m/s."""
WIND_KINDS = OPERATING_WIND_KINDS + PARKED_WIND_KINDS


@dataclass(frozen=True)
class InflowSettings:
    """What wind the plant sees.

    Attributes
    ----------
    kind : str
        ``steady`` (power-law shear), ``turbulent`` (IEC NTM or ETM Kaimal field, generated with
        pyconturb and cached), ``bts`` (a TurbSim full-field file), ``step`` (hub speed
        stepping from ``wind_speed`` to ``step_speed`` at ``step_time``), or one of IEC 61400-1's
        extreme wind conditions starting at ``step_time``: ``eog`` (extreme operating gust),
        ``edc`` (extreme direction change), ``ecd`` (extreme coherent gust with direction change),
        ``ews_vertical`` and ``ews_horizontal`` (extreme wind shear); or ``ewm50`` and ``ewm1``
        (the steady extreme wind model of ``turbine_class``, 50-year and 1-year).
    wind_speed : float
        Mean hub-height speed [m/s] (ignored for ``bts``: the file's own; and for ``ewm50``, ``ewm1``: the class's).
    shear_exponent : float
        Power-law exponent alpha [-].
    hub_height : float
        Hub height the speed refers to [m].
    rotor_radius : float
        Tip radius R of the rotor [m]: a turbulent field's grid covers it
        (:func:`~hawt_plant.turbulence.rotor_grid_size`); the EOG, EDC and EWS take D = 2 R.
    turbulence_class : str
        IEC turbulence category A, B or C.
    turbulence_model : str
        ``NTM`` or ``ETM``, the sigma_1 of a turbulent field.
    turbine_class : str
        IEC wind turbine class I, II or III (V_ref): the ETM's V_ave, the EOG's V_e1, the EWM's speed.
    seed : int
        Seed of the turbulent field.
    field_duration : float
        Length of the turbulent field [s]; the plant wraps around after it.
    bts_file : str
        Path of the ``.bts`` file.
    step_speed, step_time : float
        Speed after the step [m/s]; time of the step or the gust start [s].
    gust_sign : int
        +1 or -1: the sign of the EDC and ECD direction change and of the EWS shear.
    yaw_misalignment : float
        Angle [rad] in [-pi, pi] of the whole field's mean wind from the shaft's downwind axis, towards +y when
        positive (:class:`~hawt_plant.wind_field.YawedWind`); 0: none.
    """

    kind: str = "steady"
    wind_speed: float = 18.0
    shear_exponent: float = 0.2
    hub_height: float = 90.0
    rotor_radius: float = 63.0
    turbulence_class: str = "B"
    turbulence_model: str = "NTM"
    turbine_class: str = "I"
    seed: int = 0
    field_duration: float = 600.0
    bts_file: str = ""
    step_speed: float = 14.0
    step_time: float = 20.0
    gust_sign: int = 1
    yaw_misalignment: float = 0.0


def make_wind(settings: InflowSettings, progress: Callable[[str], None] = lambda _: None) -> WindField:
    """The wind field the settings describe (ValueError naming the setting at fault); ``progress`` gets the lines
    of :func:`~hawt_plant.turbulence.cached_turbulence` when a turbulent field has to be generated."""
    field = _field(settings, progress)
    return YawedWind(field, settings.yaw_misalignment) if settings.yaw_misalignment else field


def _field(settings: InflowSettings, progress: Callable[[str], None]) -> WindField:
    """The field of :func:`make_wind` before its yaw misalignment."""
    if settings.kind not in WIND_KINDS:
        raise ValueError(f"wind_type: {settings.kind!r} is not one of {', '.join(WIND_KINDS)}")
    common = dict(hub_height=settings.hub_height, shear_exponent=settings.shear_exponent)
    if settings.kind == "steady":
        return PowerLawWind(settings.wind_speed, **common)
    if settings.kind == "turbulent":
        width, height = rotor_grid_size(settings.rotor_radius, settings.hub_height)
        return cached_turbulence(TurbulenceSpec(
            mean_speed=settings.wind_speed, turbulence_class=settings.turbulence_class, seed=settings.seed,
            duration=settings.field_duration, grid_width=width, grid_height=height,
            turbulence_model=settings.turbulence_model, turbine_class=settings.turbine_class, **common),
            progress=progress)
    if settings.kind == "bts":
        if not Path(settings.bts_file).is_file():
            raise ValueError(f"bts_file: {settings.bts_file!r} does not exist")
        return read_bts(settings.bts_file)
    if settings.kind == "step":
        return WindStep(settings.wind_speed, settings.step_speed, settings.step_time, **common)
    if settings.kind in ("ewm50", "ewm1"):
        return steady_extreme_wind(settings.turbine_class, int(settings.kind.removeprefix("ewm")),
                                   hub_height=settings.hub_height)
    if settings.kind == "ecd":
        return extreme_coherent_gust(settings.wind_speed, settings.step_time, sign=settings.gust_sign, **common)
    rotor = dict(turbulence_class=settings.turbulence_class, rotor_diameter=2.0 * settings.rotor_radius, **common)
    if settings.kind == "eog":
        return ExtremeOperatingGust(settings.wind_speed, settings.step_time, turbine_class=settings.turbine_class,
                                    **rotor)
    if settings.kind == "edc":
        return extreme_direction_change(settings.wind_speed, settings.step_time, sign=settings.gust_sign, **rotor)
    return ExtremeWindShear(settings.wind_speed, settings.step_time, orientation=settings.kind.removeprefix("ews_"),
                            sign=settings.gust_sign, **rotor)
