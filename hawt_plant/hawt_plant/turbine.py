"""Turbine definitions: frozen dataclasses and the loader of the project's YAML format.

A turbine definition is one YAML file (``turbines/<name>/turbine.yaml``) plus one YAML file
per airfoil polar (``airfoils/<name>.yaml`` beside it). SI units throughout (m, kg, s, rad).
An optional ``aerodynamics`` section says which aerodynamic models the plant runs for this turbine
(:class:`AerodynamicOptions`, each with its source); a definition without it keeps hawt's defaults.
The NREL 5 MW reference turbine (Jonkman et al. 2009, NREL/TP-500-38060) ships with the
package; :func:`nrel_5mw` loads it. The loader checks every key and names the file and the
key of the first problem it finds in a :class:`TurbineDefinitionError`.

Sign conventions of the format (they differ from ElastoDyn's): ``cone_angle`` > 0 tilts the
blades upwind, ``shaft_tilt`` > 0 raises the rotor apex, ``overhang`` > 0 puts the apex
upwind of the tower centreline. ``rotor.position: downwind`` (default ``upwind``) puts the
rotor behind the tower: the same three numbers then point away from the tower, i.e. downwind
(apex downwind of the tower, blades coned downwind, the downwind apex raised); the rotor still
turns clockwise seen from upwind.
"""
from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from types import MappingProxyType
from typing import Any, Mapping

import numpy as np
import yaml

from hawt_core.plant_description import PlantDescription
from hawt_core.yaml_text import safe_load
from hawt_plant.disk_cache import cache_root, kept_at
from hawt_plant.kernel_cache import sources_key

__all__ = [
    "AERODYNAMIC_OPTIONS",
    "AerodynamicOptions",
    "AirfoilPolar",
    "BladeAerodynamics",
    "BladeStructure",
    "Drivetrain",
    "Environment",
    "Generator",
    "Nacelle",
    "OperatingSchedule",
    "PitchActuator",
    "ProtectionLimits",
    "Rotor",
    "Tower",
    "Turbine",
    "TurbineDefinitionError",
    "UnsteadyAirfoilParameters",
    "load_turbine",
    "nrel_5mw",
    "nrel_5mw_two_bladed",
    "nrel_5mw_two_bladed_downwind",
    "PACKAGED_TURBINES",
    "turbine_from",
]

_PACKAGED = Path(__file__).resolve().parent / "turbines"


class TurbineDefinitionError(ValueError):
    """A turbine definition file is missing a key or holds an invalid value."""


@dataclass(frozen=True)
class UnsteadyAirfoilParameters:
    """Parameters of an airfoil's unsteady aerodynamics (:mod:`hawt_plant.unsteady_airfoil`), as an AeroDyn polar
    file carries them (AeroDyn 15's names in parentheses; v13 headers have the first three only).

    Attributes
    ----------
    alpha0 : float
        Zero-lift angle of attack [rad] (alpha0, "Zero Cn angle of attack"), in (-pi/4, pi/4]; the model takes
        the polar's zero-lift angle nearest it.
    lift_slope : float
        Slope of the attached-flow lift [1/rad] (C_nalpha, "Cn slope for zero lift"; Cn ~ cl near zero lift), > 0.
    cd0 : float
        Drag coefficient at zero lift [-] (Cd0, "Minimum CD value"), >= 0.
    a1, a2, b1, b2 : float
        The shed wake's indicial response 1 - A1 exp(-b1 s) - A2 exp(-b2 s), s in half-chords travelled (A1, A2,
        b1, b2): A1, A2 >= 0 with A1 + A2 <= 1, b1, b2 > 0. Default AeroDyn's defaults, 0.3, 0.7, 0.14, 0.53.
    pressure_lag : float
        Time constant of the leading-edge pressure (the lagged potential lift) in half-chord times c / (2 V) (T_p),
        > 0; default AeroDyn's 1.7.
    separation_lag : float
        Time constant of the trailing-edge separation point in half-chord times (T_f0), > 0; default AeroDyn's 3.
    """

    alpha0: float
    lift_slope: float
    cd0: float
    a1: float = 0.3
    a2: float = 0.7
    b1: float = 0.14
    b2: float = 0.53
    pressure_lag: float = 1.7
    separation_lag: float = 3.0

    def __post_init__(self) -> None:
        if not (self.a1 >= 0.0 and self.a2 >= 0.0 and self.a1 + self.a2 <= 1.0):
            raise ValueError(f"a1, a2: expected values >= 0 with a1 + a2 <= 1, found {self.a1}, {self.a2}")
        for name in ("b1", "b2", "pressure_lag", "separation_lag"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"{name}: expected a finite value > 0, found {value}")


@dataclass(frozen=True, eq=False)
class AirfoilPolar:
    """Static polar of one airfoil over the full circle of angles of attack.

    Attributes
    ----------
    name : str
        Name the blade's elements refer to.
    alpha : ndarray, shape (K,)
        Angle of attack [rad], strictly increasing from -pi to pi.
    cl, cd, cm : ndarray, shape (K,)
        Lift, drag and pitching-moment coefficients [-].
    unsteady : UnsteadyAirfoilParameters or None
        The unsteady-aerodynamics parameters (the polar file's optional ``unsteady`` section); None: the
        airfoil stays quasi-steady (as AeroDyn's cylinders, whose files give a zero lift slope).
    """

    name: str
    alpha: np.ndarray
    cl: np.ndarray
    cd: np.ndarray
    cm: np.ndarray
    unsteady: UnsteadyAirfoilParameters | None = None


@dataclass(frozen=True, eq=False)
class BladeAerodynamics:
    """Aerodynamic nodes of one blade (all blades are identical).

    The loads are evaluated at the nodes and each node's load per unit length acts over its width: the widths tile
    the blade from root to tip in the order of the nodes, each node inside its own stretch. AeroDyn 15's layout is
    a node at the root, one at the tip and each reaching halfway to its neighbours (its trapezoidal rule); the
    AeroDyn v14 layout, each node the middle of its element, is another such tiling.

    Attributes
    ----------
    span : ndarray, shape (N,)
        Node position, distance from the blade root along the blade [m].
    width : ndarray, shape (N,)
        Length of blade the node's load acts over [m]; the widths add up to the blade length.
    chord : ndarray, shape (N,)
        Chord [m].
    twist : ndarray, shape (N,)
        Aerodynamic twist [rad], positive towards feather like the pitch.
    airfoil : tuple of str, length N
        Airfoil polar name of each element.
    """

    span: np.ndarray
    width: np.ndarray
    chord: np.ndarray
    twist: np.ndarray
    airfoil: tuple[str, ...]


@dataclass(frozen=True, eq=False)
class BladeStructure:
    """Distributed structural properties and first flap and edgewise modes of one blade (ElastoDyn blade file).

    Attributes
    ----------
    span_fraction : ndarray, shape (S,)
        Station position as a fraction of the blade length, 0 at the root, 1 at the tip.
    structural_twist : ndarray, shape (S,)
        Structural twist [rad].
    mass_density : ndarray, shape (S,)
        Mass per unit length [kg/m], already multiplied by the file's ``mass_density_factor``.
    flap_stiffness, edge_stiffness : ndarray, shape (S,)
        Bending stiffness EI [N m^2].
    flap_mode_shape : ndarray, shape (5,)
        Coefficients of x^2 .. x^6 of the first flap mode (x = span fraction), tip value 1.
    flap_damping_ratio : float
        Structural damping ratio of the first flap mode [-].
    edge_mode_shape : ndarray, shape (5,) or None
        Coefficients of x^2 .. x^6 of the first edgewise mode, tip value 1 (ElastoDyn's BldEdgSh); None: the blade
        is rigid edgewise (a definition written before the plant had the mode, or a deck with EdgeDOF off).
    edge_damping_ratio : float
        Structural damping ratio of the first edgewise mode [-].
    """

    span_fraction: np.ndarray
    structural_twist: np.ndarray
    mass_density: np.ndarray
    flap_stiffness: np.ndarray
    edge_stiffness: np.ndarray
    flap_mode_shape: np.ndarray
    flap_damping_ratio: float
    edge_mode_shape: np.ndarray | None = None
    edge_damping_ratio: float = 0.0


@dataclass(frozen=True)
class Rotor:
    """Rotor geometry and hub mass.

    Attributes
    ----------
    number_of_blades : int
    hub_radius, tip_radius : float
        Distance from the rotor apex to the blade root and tip along the blade [m].
    cone_angle : float
        Precone [rad], positive upwind.
    shaft_tilt : float
        Shaft tilt [rad], positive with the rotor apex raised.
    overhang : float
        Horizontal distance of the rotor apex upwind of the tower centreline [m]
        (measured along the tilted shaft from the yaw axis).
    hub_mass : float
        [kg]
    hub_inertia : float
        Hub inertia about the shaft [kg m^2].
    downwind : bool
        The rotor is behind the tower; cone, tilt and overhang then point away from the tower,
        downwind (module notes).
    """

    number_of_blades: int
    hub_radius: float
    tip_radius: float
    cone_angle: float
    shaft_tilt: float
    overhang: float
    hub_mass: float
    hub_inertia: float
    downwind: bool = False


@dataclass(frozen=True)
class Nacelle:
    """Nacelle mass properties and shaft height.

    Attributes
    ----------
    mass : float
        [kg]
    cm_downwind, cm_above_tower_top : float
        Nacelle centre of mass relative to the tower top [m].
    yaw_inertia : float
        Inertia about the yaw axis [kg m^2]; also used for nodding and rolling.
    shaft_above_tower_top : float
        Height of the shaft above the tower top at the yaw axis [m].
    """

    mass: float
    cm_downwind: float
    cm_above_tower_top: float
    yaw_inertia: float
    shaft_above_tower_top: float


@dataclass(frozen=True, eq=False)
class Tower:
    """Tower distributed properties, first bending modes and aerodynamic outline.

    Heights are above the ground (offshore: mean sea level; below it negative). The tower's beam runs from
    ``clamp_height``, where it is clamped, to its top at ``height``. A tower on the ground is clamped there (both
    base heights 0). A tower on a substructure (ElastoDyn TowerBsHt = ``base_height`` > 0) stands on a rigid base
    when it is clamped at its base (``clamp_height`` = ``base_height``); on a flexible base when the beam reaches
    down to the substructure's own clamp (a monopile's mudline, ``clamp_height`` < ``base_height``), the
    substructure's sections being its stations below ``base_height``.

    Attributes
    ----------
    height : float
        Tower-top height [m].
    height_fraction : ndarray, shape (T,)
        Station heights as fractions of the beam's length (:attr:`length`) from ``clamp_height``.
    mass_density : ndarray, shape (T,)
        [kg/m]
    fa_stiffness, ss_stiffness : ndarray, shape (T,)
        Fore-aft and side-side bending stiffness [N m^2].
    fa_mode_shape, ss_mode_shape : ndarray, shape (5,)
        Coefficients of x^2 .. x^6 of the first mode shapes (x = height fraction), top value 1.
    fa_damping_ratio, ss_damping_ratio : float
        Structural damping ratios [-].
    outline_elevation, outline_diameter : ndarray, shape (A,)
        Outer diameter [m] against height [m], for the tower shadow.
    drag_coefficient : float
        Tower drag coefficient [-] (AeroDyn TwrCd), for the wake behind the tower that a downwind
        rotor's blades cross.
    base_height : float
        Height of the tower's base, the top of its substructure (ElastoDyn TowerBsHt) [m].
    clamp_height : float
        Height where the beam is clamped [m], at most ``base_height``.
    """

    height: float
    height_fraction: np.ndarray
    mass_density: np.ndarray
    fa_stiffness: np.ndarray
    ss_stiffness: np.ndarray
    fa_mode_shape: np.ndarray
    ss_mode_shape: np.ndarray
    fa_damping_ratio: float
    ss_damping_ratio: float
    outline_elevation: np.ndarray
    outline_diameter: np.ndarray
    drag_coefficient: float = 1.0
    base_height: float = 0.0
    clamp_height: float = 0.0

    @property
    def length(self) -> float:
        """The beam's length from its clamp to the tower top [m]."""
        return self.height - self.clamp_height

    @property
    def base_kind(self) -> str:
        """What the tower stands on: ``"ground"``, a ``"rigid"`` base or a ``"flexible"`` one (class notes)."""
        if self.clamp_height < self.base_height:
            return "flexible"
        return "rigid" if self.base_height > 0.0 else "ground"


@dataclass(frozen=True)
class Drivetrain:
    """Gearbox and shaft.

    Attributes
    ----------
    gearbox_ratio : float
        Generator speed / rotor speed [-].
    gearbox_efficiency : float
        [-]
    generator_inertia : float
        Generator inertia about the high-speed shaft [kg m^2].
    torsional_stiffness : float
        Low-speed-shaft torsional spring [N m/rad].
    torsional_damping : float
        Low-speed-shaft torsional damper [N m s/rad].
    """

    gearbox_ratio: float
    gearbox_efficiency: float
    generator_inertia: float
    torsional_stiffness: float
    torsional_damping: float


@dataclass(frozen=True)
class Generator:
    """Generator limits and rated values (high-speed shaft).

    Attributes
    ----------
    efficiency : float
        Electrical power / mechanical generator power [-].
    rated_power : float
        Rated electrical power [W].
    rated_torque : float
        [N m]
    max_torque : float
        [N m]
    max_torque_rate : float
        [N m/s]
    """

    efficiency: float
    rated_power: float
    rated_torque: float
    max_torque: float
    max_torque_rate: float


@dataclass(frozen=True)
class PitchActuator:
    """Second-order pitch actuator of each blade with angle and rate limits.

    Attributes
    ----------
    min_angle, max_angle : float
        [rad]
    max_rate : float
        [rad/s]
    natural_frequency : float
        [rad/s]
    damping_ratio : float
        [-]
    """

    min_angle: float
    max_angle: float
    max_rate: float
    natural_frequency: float
    damping_ratio: float


@dataclass(frozen=True)
class ProtectionLimits:
    """Where the turbine's protection system warns and trips (:class:`hawt_plant.safety_system.Protection`).

    A definition's optional ``protection`` section gives any of them; each one it leaves out takes its
    documented default from the turbine's own ratings (:func:`default_protection`). Speeds are
    compared with the measured rotor and generator speeds, the acceleration with the tower top's
    fore-aft and side-side acceleration combined, the asymmetry with the spread of the measured
    blade pitch angles, the rate with each blade's measured pitch rate.

    Attributes
    ----------
    rotor_speed_warning, rotor_speed_trip : float
        [rad/s]: IEC 61400-1's n_A-style levels on the rotor (low-speed shaft).
    generator_speed_warning, generator_speed_trip : float
        [rad/s]: the same on the generator (high-speed shaft), so a broken shaft or gearbox is seen too.
    tower_top_acceleration_trip : float
        [m/s^2]
    pitch_asymmetry_trip : float
        Largest spread of the blades' pitch angles [rad].
    pitch_rate_trip : float
        Largest measured pitch rate of any blade [rad/s].
    """

    rotor_speed_warning: float
    rotor_speed_trip: float
    generator_speed_warning: float
    generator_speed_trip: float
    tower_top_acceleration_trip: float
    pitch_asymmetry_trip: float
    pitch_rate_trip: float


OVERSPEED_WARNING = 1.12
"""Default overspeed warning level, a fraction of rated speed (rotor and generator)."""
OVERSPEED_TRIP = 1.18
"""Default overspeed trip level, a fraction of rated speed: it acts below 1.2 x rated, above the 1.14 x rated that
the packaged NREL 5 MW reached under IPC in 600 s of class A turbulence at 24 m/s."""
TOWER_TOP_ACCELERATION_TRIP = 2.5
"""Default tower-top acceleration trip level [m/s^2] (about a quarter of g)."""
PITCH_ASYMMETRY_TRIP = math.radians(20.0)
"""Default trip level of the spread of the blades' pitch angles [rad]: IPC spreads them by up to 11.5 deg on the
packaged NREL 5 MW (600 s of class A turbulence at 18 and 24 m/s)."""
PITCH_RATE_MARGIN = 1.1
"""Default pitch-rate trip level, a fraction of the actuator's rate limit."""


def default_protection(schedule: "OperatingSchedule", drivetrain: "Drivetrain",
                       actuator: "PitchActuator") -> ProtectionLimits:
    """The protection levels a definition without its own takes, from its rated rotor speed, gearbox ratio and
    pitch actuator (the module constants above say the factors)."""
    rated, ratio = schedule.rated_rotor_speed, drivetrain.gearbox_ratio
    return ProtectionLimits(
        rotor_speed_warning=OVERSPEED_WARNING * rated, rotor_speed_trip=OVERSPEED_TRIP * rated,
        generator_speed_warning=OVERSPEED_WARNING * rated * ratio, generator_speed_trip=OVERSPEED_TRIP * rated * ratio,
        tower_top_acceleration_trip=TOWER_TOP_ACCELERATION_TRIP, pitch_asymmetry_trip=PITCH_ASYMMETRY_TRIP,
        pitch_rate_trip=PITCH_RATE_MARGIN * actuator.max_rate)


@dataclass(frozen=True)
class OperatingSchedule:
    """Baseline steady operating schedule (wind speeds [m/s], rotor speeds [rad/s])."""

    cut_in_wind_speed: float
    rated_wind_speed: float
    cut_out_wind_speed: float
    min_rotor_speed: float
    rated_rotor_speed: float
    optimal_tip_speed_ratio: float


AERODYNAMIC_OPTIONS = ("tower_shadow", "tower_drag", "skewed_wake", "unsteady_airfoil", "dynamic_inflow")
"""The aerodynamic options of :class:`AerodynamicOptions`, by the names the plant's parameters and
:class:`hawt_plant.model.ModelConfig` give them."""

NO_SECTION = "hawt's default (the definition has no aerodynamics section)"
"""The source of an option a definition does not give."""


def _options_from(values: dict) -> "AerodynamicOptions":
    """:class:`AerodynamicOptions` from its pickled field values."""
    return AerodynamicOptions(**{**values, "sources": MappingProxyType(values["sources"])})


def _default_sources() -> Mapping[str, str]:
    return MappingProxyType(dict.fromkeys(AERODYNAMIC_OPTIONS, NO_SECTION))


@dataclass(frozen=True)
class AerodynamicOptions:
    """Which aerodynamic models the plant runs for a turbine (unless its parameter of the same name says otherwise).

    The defaults are what a definition without an ``aerodynamics`` section gets (hawt's defaults before
    definitions carried them); :func:`hawt_plant.plant_setup.make_plant` resolves the plant's parameters against
    them.

    Attributes
    ----------
    tower_shadow : bool
        The tower's influence on the blade elements: potential flow ahead of an upwind rotor (AeroDyn
        TwrPotent = 1); for a downwind rotor the potential flow and Powles' wake behind the tower (TwrShadow = 1).
    tower_drag : bool
        Aerodynamic drag on the tower (AeroDyn TwrAero).
    skewed_wake : bool
        Pitt & Peters' skewed-wake correction of the axial induction (AeroDyn Skew_Mod = 1 with
        SkewRedistr_Mod = 1).
    unsteady_airfoil : bool
        Hansen-Gaunaa-Madsen dynamic stall on the elements whose polar has unsteady parameters (AeroDyn
        UA_Mod = 4).
    dynamic_inflow : bool
        Øye's dynamic inflow instead of the quasi-steady induction (AeroDyn DBEMT_Mod = 2).
    sources : Mapping[str, str]
        Option name -> where its value comes from (a deck's file and key, or hawt's reason); not compared.
    """

    tower_shadow: bool = True
    tower_drag: bool = True
    skewed_wake: bool = False
    unsteady_airfoil: bool = False
    dynamic_inflow: bool = False
    sources: Mapping[str, str] = field(default_factory=_default_sources, compare=False)

    def __reduce__(self) -> tuple:
        """Pickled with its sources as a plain dict (a mappingproxy does not pickle): :func:`load_turbine` keeps what
        it read on disk."""
        values = {f.name: getattr(self, f.name) for f in fields(self)}
        return _options_from, ({**values, "sources": dict(self.sources)},)

    def overridden(self, values: Mapping[str, bool], source: str) -> "AerodynamicOptions":
        """These options with ``values`` (name -> bool) in place of the definition's, each with the source
        ``source`` and its name, e.g. ``plant parameter skewed_wake``."""
        return replace(self, **values, sources=MappingProxyType(
            {**self.sources, **{name: f"{source} {name}" for name in values}}))

    def state(self, name: str) -> str:
        """One option and whether it is on: ``skewed_wake on``."""
        return f"{name} {'on' if getattr(self, name) else 'off'}"

    def text(self) -> str:
        """The options in one line: ``tower_shadow on, tower_drag on, skewed_wake off, ...``."""
        return ", ".join(self.state(name) for name in AERODYNAMIC_OPTIONS)


@dataclass(frozen=True)
class Environment:
    """Air density [kg/m^3] and gravitational acceleration [m/s^2]."""

    air_density: float
    gravity: float


@dataclass(frozen=True, eq=False)
class Turbine:
    """A complete turbine definition; build one with :func:`load_turbine` or :func:`nrel_5mw`.

    Change a part with :func:`dataclasses.replace`, e.g. a rotor without shaft tilt:
    ``replace(t, rotor=replace(t.rotor, shaft_tilt=0.0))``.
    """

    name: str
    source: str
    environment: Environment
    rotor: Rotor
    nacelle: Nacelle
    blade_aerodynamics: BladeAerodynamics
    blade_structure: BladeStructure
    airfoils: Mapping[str, AirfoilPolar]
    tower: Tower
    drivetrain: Drivetrain
    generator: Generator
    pitch_actuator: PitchActuator
    schedule: OperatingSchedule
    aerodynamics: AerodynamicOptions
    protection: ProtectionLimits

    @property
    def blade_length(self) -> float:
        """Blade length from root to tip [m]."""
        return self.rotor.tip_radius - self.rotor.hub_radius

    @property
    def rated_mechanical_power(self) -> float:
        """Aerodynamic (shaft) power at rated [W]: the rated electrical power over the generator and gearbox
        efficiencies."""
        return self.generator.rated_power / (self.generator.efficiency * self.drivetrain.gearbox_efficiency)

    @property
    def hub_height(self) -> float:
        """Height of the rotor apex above ground [m]."""
        return (
            self.tower.height
            + self.nacelle.shaft_above_tower_top
            + self.rotor.overhang * math.sin(self.rotor.shaft_tilt)
        )

    def description(self, dt: float) -> PlantDescription:
        """What the plant tells every node on ``plant/description`` when it steps at ``dt`` [s]."""
        return PlantDescription(
            turbine=self.name, dt=float(dt), blades=self.rotor.number_of_blades,
            rated_rotor_speed=self.schedule.rated_rotor_speed, rated_power=self.generator.rated_power,
            rated_generator_torque=self.generator.rated_torque, gearbox_ratio=self.drivetrain.gearbox_ratio,
            min_pitch=self.pitch_actuator.min_angle, max_pitch=self.pitch_actuator.max_angle,
            max_pitch_rate=self.pitch_actuator.max_rate)


def nrel_5mw() -> Turbine:
    """The NREL 5 MW onshore reference turbine shipped with the package."""
    return load_turbine(_PACKAGED / "nrel_5mw" / "turbine.yaml")


def nrel_5mw_two_bladed() -> Turbine:
    """A two-bladed variant of the NREL 5 MW shipped with the package (``turbines/nrel_5mw/two_bladed.yaml``)."""
    return load_turbine(_PACKAGED / "nrel_5mw" / "two_bladed.yaml")


def nrel_5mw_two_bladed_downwind() -> Turbine:
    """The two-bladed variant with its rotor downwind of the tower (``turbines/nrel_5mw/two_bladed_downwind.yaml``)."""
    return load_turbine(_PACKAGED / "nrel_5mw" / "two_bladed_downwind.yaml")


PACKAGED_TURBINES = {"nrel_5mw": nrel_5mw, "nrel_5mw_two_bladed": nrel_5mw_two_bladed,
                     "nrel_5mw_two_bladed_downwind": nrel_5mw_two_bladed_downwind}
"""Turbines shipped with the package, by the name a ``turbine_file`` parameter may give instead of a path."""


def turbine_from(name_or_path: str) -> Turbine:
    """The packaged turbine of this name (:data:`PACKAGED_TURBINES`), else the definition file at this path (a
    folder: its ``turbine.yaml``, as ``hawt turbine import`` writes it)."""
    packaged = PACKAGED_TURBINES.get(name_or_path)
    if packaged:
        return packaged()
    path = Path(name_or_path)
    return load_turbine(path / "turbine.yaml" if path.is_dir() else path)


def load_turbine(path: str | Path) -> Turbine:
    """Load and check a turbine definition file.

    Parameters
    ----------
    path : str or Path
        The ``turbine.yaml`` file; airfoil polars are read from ``airfoils/<name>.yaml``
        in the same folder. A file with the key ``derived_from`` (a file name in the same
        folder) holds only what differs from that definition: its mappings are merged into the
        base's key by key, every other value replaces the base's.

    Returns
    -------
    Turbine

    Raises
    ------
    TurbineDefinitionError
        Naming the file and the key at fault, e.g.
        ``turbine.yaml: blade.aerodynamics.chord: expected 17 values, found 16``.

    Notes
    -----
    A definition read once is kept on disk (``$HAWT_CACHE_DIR/turbines``), keyed by the content of the folder's
    definition and polar files and of hawt_plant's sources: an imported turbine's fifty polars parse in 0.3 s, its
    kept definition loads in milliseconds. A changed file or source reads the definition again.
    """
    path = Path(path)
    key = _definition_key(path)
    if key is None:
        return _parsed_turbine(path)  # a file it cannot read: the parse names it
    return kept_at(cache_root() / "turbines" / f"{key}.pickle", lambda: _parsed_turbine(path))


def _definition_key(path: Path) -> str | None:
    """A hash of everything a parse of ``path`` can read (the definition files in its folder, the polars in its
    ``airfoils`` folder) and of the parser (every hawt_plant module): a parsed definition is used only for the same
    files and sources. None when a file cannot be read (the parse then says which)."""
    digest = hashlib.sha256(sources_key().encode())
    try:
        for file in sorted([*path.parent.glob("*.yaml"), *(path.parent / "airfoils").glob("*.yaml")]):
            digest.update(str(file.relative_to(path.parent)).encode())
            digest.update(file.read_bytes())
    except OSError:
        return None
    digest.update(path.name.encode())
    return digest.hexdigest()[:32]


def _parsed_turbine(path: Path) -> Turbine:
    """:func:`load_turbine` without its cache."""
    doc = _Section(path.name, "", _derived(path, _read_yaml(path)))
    rotor = _rotor(doc.section("rotor"))
    aero = _blade_aerodynamics(doc.section("blade").section("aerodynamics"), rotor)
    drivetrain, actuator, schedule = (_drivetrain(doc.section("drivetrain")),
                                      _pitch_actuator(doc.section("pitch_actuator")), _schedule(doc.section("operation")))
    protection = default_protection(schedule, drivetrain, actuator)
    airfoils = {name: _airfoil(path.parent / "airfoils" / f"{name}.yaml") for name in sorted(set(aero.airfoil))}
    return Turbine(
        name=doc.text("name"),
        source=doc.text("source"),
        environment=Environment(
            air_density=doc.section("environment").number("air_density", low=0.0),
            gravity=doc.section("environment").number("gravity", low=0.0, strict=False),
        ),
        rotor=rotor,
        nacelle=_nacelle(doc.section("nacelle")),
        blade_aerodynamics=aero,
        blade_structure=_blade_structure(doc.section("blade").section("structure"), rotor),
        airfoils=airfoils,
        tower=_tower(doc.section("tower")),
        drivetrain=drivetrain,
        generator=_generator(doc.section("generator")),
        pitch_actuator=actuator,
        schedule=schedule,
        aerodynamics=_aerodynamics(doc.section("aerodynamics"), path.name) if doc.has("aerodynamics")
        else AerodynamicOptions(),
        protection=_protection(doc.section("protection"), protection) if doc.has("protection") else protection,
    )


def _derived(path: Path, data: Any, seen: tuple[str, ...] = ()) -> Any:
    """``data`` merged onto the definition its ``derived_from`` names, which may derive from another (no cycle)."""
    if not isinstance(data, dict) or "derived_from" not in data:
        return data
    base_name = data["derived_from"]
    if not isinstance(base_name, str) or not base_name or Path(base_name).name != base_name:
        raise TurbineDefinitionError(f"{path.name}: derived_from: expected a file name in the same folder, "
                                     f"found {base_name!r}")
    seen = (*seen, path.name)
    if base_name in seen:
        raise TurbineDefinitionError(f"{path.name}: derived_from: {base_name} derives from it again "
                                     f"({' -> '.join((*seen, base_name))})")
    base = _derived(path.parent / base_name, _read_yaml(path.parent / base_name), seen)
    if not isinstance(base, dict):
        raise TurbineDefinitionError(f"{path.name}: derived_from: {base_name} must be a definition (a mapping)")

    def merged(below: Any, above: Any) -> Any:
        if isinstance(below, dict) and isinstance(above, dict):
            return {**below, **{key: merged(below.get(key), value) for key, value in above.items()}}
        return above

    return merged(base, {key: value for key, value in data.items() if key != "derived_from"})


def _read_yaml(path: Path) -> Any:
    try:
        text = path.read_text()
    except OSError as err:
        raise TurbineDefinitionError(f"{path}: cannot read the file ({err.strerror})") from err
    try:
        return safe_load(text)
    except yaml.YAMLError as err:
        raise TurbineDefinitionError(f"{path.name}: not valid YAML ({err})") from err


class _Section:
    """A mapping of the YAML document that reports errors as ``file: key.path: problem``."""

    def __init__(self, file: str, prefix: str, data: Any) -> None:
        if not isinstance(data, dict):
            raise TurbineDefinitionError(f"{file}: {prefix or 'document'}: expected a mapping")
        self._file = file
        self._prefix = prefix
        self._data = data

    def error(self, key: str, problem: str) -> TurbineDefinitionError:
        return TurbineDefinitionError(f"{self._file}: {self._prefix}{key}: {problem}")

    def has(self, key: str) -> bool:
        return key in self._data

    def keys(self) -> tuple[str, ...]:
        return tuple(self._data)

    def raw(self, key: str) -> Any:
        if key not in self._data:
            raise self.error(key, "missing")
        return self._data[key]

    def section(self, key: str) -> "_Section":
        value = self.raw(key)
        if not isinstance(value, dict):
            raise self.error(key, "expected a mapping")
        return _Section(self._file, f"{self._prefix}{key}.", value)

    def text(self, key: str) -> str:
        value = self.raw(key)
        if not isinstance(value, str) or not value:
            raise self.error(key, "expected a non-empty string")
        return value

    def number(self, key: str, low: float | None = None, high: float | None = None, strict: bool = True,
               default: float | None = None) -> float:
        """The number at ``key`` within the bounds; ``default`` if given and the key is absent."""
        if default is not None and key not in self._data:
            return default
        value = self.raw(key)
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise self.error(key, f"expected a finite number, found {value!r}")
        if low is not None and (value <= low if strict else value < low):
            raise self.error(key, f"expected a value {'>' if strict else '>='} {low}, found {value}")
        if high is not None and value > high:
            raise self.error(key, f"expected a value <= {high}, found {value}")
        return float(value)

    def choice(self, key: str, choices: tuple[str, ...], default: str) -> str:
        """One of ``choices`` at ``key`` (``default`` if the key is absent)."""
        value = self._data.get(key, default)
        if value not in choices:
            raise self.error(key, f"expected one of {', '.join(choices)}, found {value!r}")
        return value

    def integer(self, key: str, low: int) -> int:
        value = self.raw(key)
        if isinstance(value, bool) or not isinstance(value, int) or value < low:
            raise self.error(key, f"expected an integer >= {low}, found {value!r}")
        return value

    def array(self, key: str, length: int | None = None, positive: bool = False,
              increasing: bool = False) -> np.ndarray:
        value = self.raw(key)
        if not isinstance(value, list) or not all(
            isinstance(v, (int, float)) and not isinstance(v, bool) for v in value
        ):
            raise self.error(key, "expected a list of numbers")
        out = np.array(value, dtype=float)
        if length is not None and out.size != length:
            raise self.error(key, f"expected {length} values, found {out.size}")
        if out.size == 0 or not np.all(np.isfinite(out)):
            raise self.error(key, "expected finite values")
        if positive and np.any(out <= 0.0):
            raise self.error(key, "expected positive values")
        if increasing and np.any(np.diff(out) <= 0.0):
            raise self.error(key, "expected strictly increasing values")
        out.flags.writeable = False
        return out

    def names(self, key: str, length: int) -> tuple[str, ...]:
        value = self.raw(key)
        if not isinstance(value, list) or not all(isinstance(v, str) and v for v in value):
            raise self.error(key, "expected a list of names")
        if len(value) != length:
            raise self.error(key, f"expected {length} values, found {len(value)}")
        return tuple(value)


def _rotor(s: _Section) -> Rotor:
    hub_radius = s.number("hub_radius", low=0.0, strict=False)
    tip_radius = s.number("tip_radius", low=hub_radius)
    return Rotor(
        number_of_blades=s.integer("number_of_blades", low=2),
        hub_radius=hub_radius,
        tip_radius=tip_radius,
        cone_angle=s.number("cone_angle", low=-0.5, high=0.5),
        shaft_tilt=s.number("shaft_tilt", low=-0.5, high=0.5),
        overhang=s.number("overhang"),
        hub_mass=s.number("hub_mass", low=0.0, strict=False),
        hub_inertia=s.number("hub_inertia", low=0.0, strict=False),
        downwind=s.choice("position", ("upwind", "downwind"), default="upwind") == "downwind",
    )


def _nacelle(s: _Section) -> Nacelle:
    return Nacelle(
        mass=s.number("mass", low=0.0, strict=False),
        cm_downwind=s.number("cm_downwind"),
        cm_above_tower_top=s.number("cm_above_tower_top"),
        yaw_inertia=s.number("yaw_inertia", low=0.0, strict=False),
        shaft_above_tower_top=s.number("shaft_above_tower_top"),
    )


def _blade_aerodynamics(s: _Section, rotor: Rotor) -> BladeAerodynamics:
    span = s.array("span", increasing=True)
    n = span.size
    width = s.array("width", length=n, positive=True)
    length = rotor.tip_radius - rotor.hub_radius
    if abs(width.sum() - length) > 1e-3 * length:
        raise s.error("width", f"widths add up to {width.sum():.4f} m, the blade is {length:.4f} m long")
    upper = np.cumsum(width)
    lower = upper - width
    if np.any(span < lower - 1e-3) or np.any(span > upper + 1e-3):
        raise s.error("span", "expected each node inside the stretch of blade its width gives it, the widths tiling "
                              "the blade from the root in the order of the nodes")
    return BladeAerodynamics(
        span=span,
        width=width,
        chord=s.array("chord", length=n, positive=True),
        twist=s.array("twist", length=n),
        airfoil=s.names("airfoil", n),
    )


def _blade_structure(s: _Section, rotor: Rotor) -> BladeStructure:
    fraction = s.array("span_fraction", increasing=True)
    if fraction[0] != 0.0 or fraction[-1] != 1.0:
        raise s.error("span_fraction", "expected the first value 0 and the last 1")
    n = fraction.size
    factor = s.number("mass_density_factor", low=0.0)
    mass_density = s.array("mass_density", length=n, positive=True) * factor
    mass_density.flags.writeable = False
    mode = _mode_shape(s, "flap_mode_shape")
    edge_mode = _mode_shape(s, "edge_mode_shape") if s.has("edge_mode_shape") else None
    if edge_mode is not None and not s.has("edge_damping_ratio"):
        raise s.error("edge_damping_ratio", "missing: an edgewise mode needs its damping ratio")
    length = rotor.tip_radius - rotor.hub_radius
    mass = float(np.trapezoid(mass_density, fraction * length))
    cg = float(np.trapezoid(mass_density * fraction * length, fraction * length)) / mass
    for key, found in (("reference_mass", mass), ("reference_cg_from_root", cg)):
        stated = s.number(key, low=0.0)
        if abs(found - stated) > 0.02 * stated:
            raise s.error(key, f"the distributed properties give {found:.4g}, more than 2 % from {stated:.4g}")
    return BladeStructure(
        span_fraction=fraction,
        structural_twist=s.array("structural_twist", length=n),
        mass_density=mass_density,
        flap_stiffness=s.array("flap_stiffness", length=n, positive=True),
        edge_stiffness=s.array("edge_stiffness", length=n, positive=True),
        flap_mode_shape=mode,
        flap_damping_ratio=s.number("flap_damping_ratio", low=0.0, high=1.0, strict=False),
        edge_mode_shape=edge_mode,
        edge_damping_ratio=s.number("edge_damping_ratio", low=0.0, high=1.0, strict=False) if edge_mode is not None
        else 0.0,
    )


def _mode_shape(s: _Section, key: str, end: str = "tip") -> np.ndarray:
    """An ElastoDyn mode shape's five coefficients of x^2 .. x^6, which add up to the unit value at its ``end``."""
    mode = s.array(key, length=5)
    if abs(mode.sum() - 1.0) > 1e-3:
        raise s.error(key, f"coefficients add up to {mode.sum():.4f}, expected 1 (unit {end} value)")
    return mode


def _tower(s: _Section) -> Tower:
    fraction = s.array("height_fraction", increasing=True)
    if fraction[0] != 0.0 or fraction[-1] != 1.0:
        raise s.error("height_fraction", "expected the first value 0 and the last 1")
    n = fraction.size
    modes = {}
    for key in ("fa_mode_shape", "ss_mode_shape"):
        modes[key] = _mode_shape(s, key, end="top")
    elevation = s.array("outline_elevation", increasing=True)
    height = s.number("height", low=0.0)
    base = s.number("base_height", low=0.0, strict=False, default=0.0)
    if base >= height:
        raise s.error("base_height", f"expected a value below the tower top (height {height:g}), found {base:g}")
    return Tower(
        height=height,
        height_fraction=fraction,
        mass_density=s.array("mass_density", length=n, positive=True),
        fa_stiffness=s.array("fa_stiffness", length=n, positive=True),
        ss_stiffness=s.array("ss_stiffness", length=n, positive=True),
        fa_mode_shape=modes["fa_mode_shape"],
        ss_mode_shape=modes["ss_mode_shape"],
        fa_damping_ratio=s.number("fa_damping_ratio", low=0.0, high=1.0, strict=False),
        ss_damping_ratio=s.number("ss_damping_ratio", low=0.0, high=1.0, strict=False),
        outline_elevation=elevation,
        outline_diameter=s.array("outline_diameter", length=elevation.size, positive=True),
        drag_coefficient=s.number("drag_coefficient", low=0.0, strict=False, default=1.0),
        base_height=base,
        clamp_height=s.number("clamp_height", high=base, default=base),
    )


def _drivetrain(s: _Section) -> Drivetrain:
    return Drivetrain(
        gearbox_ratio=s.number("gearbox_ratio", low=0.0),
        gearbox_efficiency=s.number("gearbox_efficiency", low=0.0, high=1.0),
        generator_inertia=s.number("generator_inertia", low=0.0),
        torsional_stiffness=s.number("torsional_stiffness", low=0.0),
        torsional_damping=s.number("torsional_damping", low=0.0, strict=False),
    )


def _generator(s: _Section) -> Generator:
    rated_torque = s.number("rated_torque", low=0.0)
    return Generator(
        efficiency=s.number("efficiency", low=0.0, high=1.0),
        rated_power=s.number("rated_power", low=0.0),
        rated_torque=rated_torque,
        max_torque=s.number("max_torque", low=rated_torque, strict=False),
        max_torque_rate=s.number("max_torque_rate", low=0.0),
    )


def _pitch_actuator(s: _Section) -> PitchActuator:
    min_angle = s.number("min_angle", low=-math.pi / 2, high=math.pi / 2, strict=False)
    return PitchActuator(
        min_angle=min_angle,
        max_angle=s.number("max_angle", low=min_angle, high=math.pi),
        max_rate=s.number("max_rate", low=0.0),
        natural_frequency=s.number("natural_frequency", low=0.0),
        damping_ratio=s.number("damping_ratio", low=0.0),
    )


def _protection(s: _Section, defaults: ProtectionLimits) -> ProtectionLimits:
    """The section's levels, each one left out its default; a warning level above its trip level is refused."""
    unknown = sorted(set(s.keys()) - {f.name for f in fields(ProtectionLimits)})
    if unknown:
        raise s.error(unknown[0], f"unknown protection level (expected one of: "
                                  f"{', '.join(f.name for f in fields(ProtectionLimits))})")
    limits = ProtectionLimits(**{f.name: s.number(f.name, low=0.0, default=getattr(defaults, f.name))
                                 for f in fields(ProtectionLimits)})
    for shaft in ("rotor", "generator"):
        warning, trip = getattr(limits, f"{shaft}_speed_warning"), getattr(limits, f"{shaft}_speed_trip")
        if warning > trip:
            raise s.error(f"{shaft}_speed_warning", f"expected a value <= {shaft}_speed_trip ({trip}), found {warning}")
    return limits


def _schedule(s: _Section) -> OperatingSchedule:
    cut_in = s.number("cut_in_wind_speed", low=0.0)
    rated = s.number("rated_wind_speed", low=cut_in)
    min_speed = s.number("min_rotor_speed", low=0.0)
    return OperatingSchedule(
        cut_in_wind_speed=cut_in,
        rated_wind_speed=rated,
        cut_out_wind_speed=s.number("cut_out_wind_speed", low=rated),
        min_rotor_speed=min_speed,
        rated_rotor_speed=s.number("rated_rotor_speed", low=min_speed),
        optimal_tip_speed_ratio=s.number("optimal_tip_speed_ratio", low=0.0),
    )


def _aerodynamics(s: _Section, file: str) -> AerodynamicOptions:
    """Each option ``true``/``false`` (its source: this file and key) or ``{value: true, source: text}``; an
    option left out keeps hawt's default."""
    unknown = sorted(set(s.keys()) - set(AERODYNAMIC_OPTIONS))
    if unknown:
        raise s.error(unknown[0], f"no such option (expected {', '.join(AERODYNAMIC_OPTIONS)})")
    values, sources = {}, dict(AerodynamicOptions().sources)
    for name in AERODYNAMIC_OPTIONS:
        if not s.has(name):
            continue
        raw = s.raw(name)
        if isinstance(raw, bool):
            values[name], sources[name] = raw, f"{file} aerodynamics.{name}"
        elif isinstance(raw, dict) and set(raw) == {"value", "source"} and isinstance(raw["value"], bool) \
                and isinstance(raw["source"], str) and raw["source"]:
            values[name], sources[name] = raw["value"], raw["source"]
        else:
            raise s.error(name, f"expected true or false, or {{value: true or false, source: text}}, found {raw!r}")
    return AerodynamicOptions(**values, sources=MappingProxyType(sources))


def _airfoil(path: Path) -> AirfoilPolar:
    doc = _Section(path.name, "", _read_yaml(path))
    name = doc.text("name")
    if name != path.stem:
        raise doc.error("name", f"expected {path.stem!r} like the file name, found {name!r}")
    if doc.raw("columns") != ["alpha", "cl", "cd", "cm"]:
        raise doc.error("columns", "expected [alpha, cl, cd, cm]")
    rows = doc.raw("table")
    try:
        table = np.array(rows, dtype=float)
    except (TypeError, ValueError) as err:
        raise doc.error("table", "expected rows of four numbers") from err
    if table.ndim != 2 or table.shape[1] != 4 or table.shape[0] < 2 or not np.all(np.isfinite(table)):
        raise doc.error("table", "expected at least two rows of four finite numbers")
    alpha = table[:, 0]
    if np.any(np.diff(alpha) <= 0.0):
        raise doc.error("table", "angles of attack must increase strictly")
    if abs(alpha[0] + math.pi) > 1e-6 or abs(alpha[-1] - math.pi) > 1e-6:
        raise doc.error("table", "angles of attack must run from -pi to pi")
    columns = [np.ascontiguousarray(table[:, k]) for k in range(4)]
    for column in columns:
        column.flags.writeable = False
    unsteady = None
    if doc.has("unsteady"):
        s = doc.section("unsteady")
        unknown = sorted(set(s.keys()) - {f.name for f in fields(UnsteadyAirfoilParameters)})
        if unknown:
            raise s.error(unknown[0], "no such parameter (expected "
                          f"{', '.join(f.name for f in fields(UnsteadyAirfoilParameters))})")
        defaults = {f.name: f.default for f in fields(UnsteadyAirfoilParameters)}
        lags = {name: s.number(name, low=0.0, default=defaults[name])
                for name in ("b1", "b2", "pressure_lag", "separation_lag")}
        weights = {name: s.number(name, low=0.0, high=1.0, strict=False, default=defaults[name])
                   for name in ("a1", "a2")}
        if weights["a1"] + weights["a2"] > 1.0:
            raise s.error("a2", f"expected a1 + a2 <= 1, found {weights['a1']} + {weights['a2']}")
        unsteady = UnsteadyAirfoilParameters(alpha0=s.number("alpha0", low=-math.pi / 4, high=math.pi / 4),
                                             lift_slope=s.number("lift_slope", low=0.0),
                                             cd0=s.number("cd0", low=0.0, strict=False), **weights, **lags)
    return AirfoilPolar(name=name, alpha=columns[0], cl=columns[1], cd=columns[2], cm=columns[3], unsteady=unsteady)
