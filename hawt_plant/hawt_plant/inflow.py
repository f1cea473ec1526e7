"""Choosing the plant's wind field from a few named settings (the plant node's parameters)."""
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from hawt_plant.bts import read_bts
from hawt_plant.gusts import ExtremeOperatingGust, WindStep
from hawt_plant.shear_wind import PowerLawWind
from hawt_plant.turbulence import TurbulenceSpec, cached_turbulence, rotor_grid_size
from hawt_plant.wind_field import WindField

__all__ = ["WIND_KINDS", "InflowSettings", "make_wind"]

WIND_KINDS = ("steady", "turbulent", "bts", "step", "eog")


@dataclass(frozen=True)
class InflowSettings:
    """What wind the plant sees.

    Attributes
    ----------
    kind : str
        ``steady`` (power-law shear), ``turbulent`` (IEC NTM Kaimal field, generated with
        pyconturb and cached), ``bts`` (a TurbSim full-field file), ``step`` (hub speed
        stepping from ``wind_speed`` to ``step_speed`` at ``step_time``) or ``eog`` (IEC extreme
        operating gust starting at ``step_time``).
    wind_speed : float
        Mean hub-height speed [m/s] (ignored for ``bts``: the file's own).
    shear_exponent : float
        Power-law exponent alpha [-].
    hub_height : float
        Hub height the speed refers to [m].
    rotor_radius : float
        Tip radius of the rotor [m]: a turbulent field's grid covers it (:func:`~hawt_plant.turbulence.rotor_grid_size`).
    turbulence_class : str
        IEC turbulence category A, B or C.
    seed : int
        Seed of the turbulent field.
    field_duration : float
        Length of the turbulent field [s]; the plant wraps around after it.
    bts_file : str
        Path of the ``.bts`` file.
    step_speed, step_time : float
        Speed after the step [m/s]; time of the step or the gust start [s].
    """

    kind: str = "steady"
    wind_speed: float = 18.0
    shear_exponent: float = 0.2
    hub_height: float = 90.0
    rotor_radius: float = 63.0
    turbulence_class: str = "B"
    seed: int = 0
    field_duration: float = 600.0
    bts_file: str = ""
    step_speed: float = 14.0
    step_time: float = 20.0


def make_wind(settings: InflowSettings, progress: Callable[[str], None] = lambda _: None) -> WindField:
    """The wind field the settings describe (ValueError naming the setting at fault); ``progress`` gets the lines
    of :func:`~hawt_plant.turbulence.cached_turbulence` when a turbulent field has to be generated."""
    if settings.kind not in WIND_KINDS:
        raise ValueError(f"wind_type: {settings.kind!r} is not one of {', '.join(WIND_KINDS)}")
    common = dict(hub_height=settings.hub_height, shear_exponent=settings.shear_exponent)
    if settings.kind == "steady":
        return PowerLawWind(settings.wind_speed, **common)
    if settings.kind == "turbulent":
        width, height = rotor_grid_size(settings.rotor_radius, settings.hub_height)
        return cached_turbulence(TurbulenceSpec(
            mean_speed=settings.wind_speed, turbulence_class=settings.turbulence_class, seed=settings.seed,
            duration=settings.field_duration, grid_width=width, grid_height=height, **common), progress=progress)
    if settings.kind == "bts":
        if not Path(settings.bts_file).is_file():
            raise ValueError(f"bts_file: {settings.bts_file!r} does not exist")
        return read_bts(settings.bts_file)
    if settings.kind == "step":
        return WindStep(settings.wind_speed, settings.step_speed, settings.step_time, **common)
    return ExtremeOperatingGust(settings.wind_speed, settings.step_time, turbulence_class=settings.turbulence_class,
                                **common)
