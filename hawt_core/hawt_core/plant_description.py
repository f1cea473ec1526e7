"""Facts of the plant that every node needs, from one source: ``plant/description`` (DESIGN §4.1).

The plant publishes them once, reliable and transient local, so a node that starts later
still gets them; nodes take the step ``dt`` and the number of blades ``blades`` from here at
configure time instead of repeating them as parameters of their own. The in-process runner
hands the same object to the same cores.
"""
import math
from dataclasses import dataclass, fields
from typing import Any, Mapping

__all__ = ["PlantDescription", "DescriptionMismatch"]


class DescriptionMismatch(ValueError):
    """A node configured with a value that contradicts the plant's description (the message names both)."""


@dataclass(frozen=True)
class PlantDescription:
    """The plant a graph runs against.

    Attributes
    ----------
    turbine : str
        Turbine name, e.g. ``NREL 5MW onshore``.
    dt : float
        Plant step [s].
    blades : int
        Number of blades B.
    rated_rotor_speed : float
        [rad/s].
    rated_power : float
        Rated electrical power [W].
    rated_generator_torque : float
        Rated generator torque, high-speed shaft [N·m].
    gearbox_ratio : float
        Generator speed / rotor speed [-].
    min_pitch, max_pitch : float
        Pitch actuator angle limits [rad].
    max_pitch_rate : float
        Pitch actuator rate limit [rad/s].
    """

    turbine: str
    dt: float
    blades: int
    rated_rotor_speed: float
    rated_power: float
    rated_generator_torque: float
    gearbox_ratio: float
    min_pitch: float
    max_pitch: float
    max_pitch_rate: float

    def __post_init__(self) -> None:
        if not (math.isfinite(self.dt) and self.dt > 0):
            raise ValueError(f"plant/description dt: expected a positive step [s], found {self.dt}")
        if self.blades < 2:
            raise ValueError(f"plant/description blades: expected B >= 2, found {self.blades}")

    def as_fields(self) -> dict:
        """The attributes as a plain dict (the fields of ``hawt_msgs/PlantDescription``)."""
        return {f.name: getattr(self, f.name) for f in fields(self)}

    @classmethod
    def from_fields(cls, source: Any) -> "PlantDescription":
        """From any object (a message) or mapping with the attributes' names."""
        get = source.get if isinstance(source, Mapping) else lambda name: getattr(source, name)
        return cls(**{f.name: f.type(get(f.name)) if f.type in (int, float, str) else get(f.name)
                      for f in fields(cls)})

    def check(self, where: str, **given: Any) -> None:
        """Refuse a node's own value that contradicts the plant's (``check('ipc_h1', dt=0.02)``).

        Raises
        ------
        DescriptionMismatch
            ``ipc_h1: dt 0.02 s conflicts with plant/description dt 0.01 s``.
        """
        for name, value in given.items():
            own = getattr(self, name)
            if value is not None and not math.isclose(float(value), float(own), rel_tol=1e-9):
                unit = " s" if name == "dt" else ""
                raise DescriptionMismatch(f"{where}: {name} {value}{unit} conflicts with plant/description "
                                          f"{name} {own}{unit}")
