"""An OpenFAST input deck converted into the hawt turbine definition (``hawt turbine import``, issue 20).

The deck is read with NREL's openfast-io (``InputReader_OpenFAST``), one module at a time: the main ``.fst``
file, ElastoDyn with its blade and tower files, AeroDyn with its blade file and airfoil polars, and ServoDyn;
then the ROSCO ``DISCON.IN`` that ServoDyn's controller reads (with
:func:`hawt_controllers.discon.rosco_input.read_settings`: openfast-io reads it only through ROSCO's toolbox, which needs
WISDEM). The other modules (InflowWind, HydroDyn, SubDyn, MoorDyn, ...) are not read; the plant does not model
them. :func:`import_deck` returns the definition with the source file and key of every value;
:func:`write_turbine` writes it as ``turbine.yaml`` and ``airfoils/<name>.yaml``, which
:func:`hawt_plant.turbine.load_turbine` loads, and a plant's ``turbine_file`` parameter may name.

What comes from where (ED ElastoDyn, AD AeroDyn, SD ServoDyn, DISCON the ROSCO input):

- rotor: ED NumBl, HubRad, TipRad, HubMass, HubIner; PreCone(1), ShftTilt, OverHang with the format's signs
  (:mod:`hawt_plant.turbine`): negated for an upwind rotor (OverHang <= 0), kept for a downwind one, which the
  definition marks ``position: downwind``;
- nacelle: ED NacMass + YawBrMass (the yaw bearing, at the tower top, lumped into the nacelle keeping the mass
  moments), NacCMxn, NacCMzn, NacYIner, Twr2Shft;
- blade aerodynamics: AD blade file BlSpn, BlChord, BlTwist, BlAFID at its nodes (their widths:
  :func:`node_widths`) and the first table of each airfoil file AFNames(i) (AD AFTabMod = 1 reads only
  that one), with its UA coefficients alpha0, C_nalpha, Cd0, A1, A2, b1, b2, T_p, T_f0 ("Default": AeroDyn's) for
  the plant's unsteady airfoil option when it has them;
- blade structure: ED blade file BlFract, StrcTwst, BMassDen with AdjBlMs, FlpStff x AdjFlSt x FlStTunr(1),
  EdgStff x AdjEdSt, BldFl1Sh, BldFlDmp(1), and BldEdgSh, BldEdDmp(1) if ED EdgeDOF (else the blade is rigid
  edgewise);
- tower: ED TowerHt, tower file HtFract, TMassDen x AdjTwMa, TwFAStif x AdjFASt x FAStTunr(1), TwSSStif x AdjSSSt
  x SSStTunr(1), TwFAM1Sh, TwSSM1Sh, TwrFADmp(1), TwrSSDmp(1); AD TwrElev, TwrDiam, TwrCd (their mean, if the
  nodes differ) for the tower shadow and drag. A tower on a substructure (ED TowerBsHt > 0) keeps its heights
  (the hub is the deck's) and stands on a flexible base if the deck's SubDyn input (CompSub = 1) is a monopile
  (:func:`_monopile`): the tower's beam then reaches down to SubDyn's clamp with the monopile's circular sections
  (YoungE, MatDens, XsecD, XsecT) below TowerBsHt, and its first mode shapes are that beam's
  (:func:`hawt_plant.modal.beam_first_mode`, with the rotor and nacelle on top), not the tower file's of the tower
  clamped at TowerBsHt. Otherwise (no SubDyn, or another structure) it stands on a rigid base: clamped at
  TowerBsHt, with the tower file's modes. The approximations say which, and why;
- drivetrain: ED GBRatio, GBoxEff, GenIner, DTTorSpr (for a rigid drivetrain, DrTrDOF = False, at most the
  stiffness of a :data:`RIGID_TORSION_FREQUENCY` torsion), DTTorDmp;
- generator: SD GenEff; DISCON VS_RtPwr, VS_RtTq, VS_MaxTq, VS_MaxRat;
- pitch actuator: DISCON PC_MinPit (or PC_FinePit, if higher: the plant's lower limit is also its below-rated
  pitch), PC_MaxPit, PC_MaxRat; PA_CornerFreq and PA_Damping (PA_Mode = 2; PA_Mode = 1: the second-order
  actuator with the same -3 dB bandwidth, damping 1/sqrt(2)); without actuator dynamics (PA_Mode = 0)
  :data:`DEFAULT_ACTUATOR`, as the shipped NREL 5 MW;
- operation: ROSCO's tuning writes its wind speeds into WE_FOPoles_v, v_min to v_rated then v_rated to v_max
  (``rosco/toolbox/controller.py``: WE_FOPoles_N - PC_GS_n values below rated, PC_GS_n + 1 from rated): cut-in
  WE_FOPoles_v(1), rated WE_FOPoles_v(WE_FOPoles_N - PC_GS_n), cut-out WE_FOPoles_v(WE_FOPoles_N); rotor speeds
  VS_MinOMSpd / GBRatio and PC_RefSpd / GBRatio; VS_TSRopt;
- environment: AD AirDens (the ``.fst`` AirDens when AD says "default"), ``.fst`` Gravity;
- aerodynamics (the plant's aerodynamic options, :class:`hawt_plant.turbine.AerodynamicOptions`, each written with
  its source so that ``hawt turbine show`` and a run can say where it came from; :func:`aerodynamic_options`):
  tower_shadow from AD TwrPotent (and TwrShadow for a downwind rotor), tower_drag from TwrAero, skewed_wake from
  Skew_Mod and SkewRedistr_Mod, unsteady_airfoil from UA_Mod, dynamic_inflow from Wake_Mod and DBEMT_Mod (OpenFAST
  4: dynamic BEMT is Wake_Mod = 1 with DBEMT_Mod > 0; Wake_Mod = 2 is the older inputs' DBEMT). What the plant
  does differently (another UA or DBEMT model, the Bak correction, drag in the induction, no tip loss, ...) is an
  approximation or not modelled, listed with the others.

Decks the import refuses, with the file and key named (:class:`DeckError`): a missing file, including those the
DISCON.IN names (PerfFileName, and OL_Filename unless "unused": ``hawt turbine import`` copies them beside the
turbine's DISCON.IN); CompElast other than 1 (BeamDyn blades or SimpleElastoDyn: the plant's blade is ElastoDyn's),
CompAero other than 2 (no AeroDyn blade), CompServo other than 1 or a ServoDyn controller that is not ROSCO (PCMode
and VSContrl 5 with a ROSCO DLL_InFile: the limits and rated values come from it, so an imported turbine always has
its DISCON.IN), MHK turbines; blades that differ (ED PreCone, BldFile or AD ADBlFile per blade), AD AFTabMod other
than 1 (polars over Reynolds number or a control setting), a polar without lift or drag columns or not over
-180..180 deg. A value out of range is refused before anything is written: the values
the import computes with where they are read (:data:`_FLOORS`, TipRad > HubRad), every other one by the
definition's own checks, run on it before :func:`write_turbine` writes it (one line naming the deck's file and
key, the value and the range allowed; e.g. ``..._ElastoDyn.dat: GBRatio: expected a value > 0, found 0``).
"""
from __future__ import annotations

import importlib.metadata
import json
import math
import os
import re
import shutil
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Sequence, Tuple

import numpy as np
from openfast_io.FAST_reader import InputReader_OpenFAST

from hawt_controllers.discon.rosco_input import RELATIVE_PATH_SETTINGS, read_settings
from hawt_plant.modal import beam_first_mode
from hawt_plant.turbine import TurbineDefinitionError, UnsteadyAirfoilParameters, load_turbine

__all__ = ["DEFAULT_ACTUATOR", "RIGID_TORSION_FREQUENCY", "AerodynamicMapping", "DeckError", "ImportedAirfoil",
           "ImportedTurbine", "Sourced", "node_widths", "aerodynamic_options", "import_deck", "turbine_text",
           "write_turbine"]

DEFAULT_ACTUATOR = (11.11, 0.6)
"""Natural frequency [rad/s] and damping ratio [-] of the pitch actuator of a deck without actuator dynamics
(DISCON.IN PA_Mode = 0), as the shipped NREL 5 MW: the benchmark of Odgaard, Stoustrup & Kinnaert (2013)."""

RIGID_TORSION_FREQUENCY = 10.0
"""[Hz] The shaft torsion of a deck whose drivetrain is rigid (ElastoDyn DrTrDOF = False) is kept at or below
this: the plant always has the torsion, and its semi-implicit Euler step (0.01 s by default) integrates it
stably only well below 1 / (pi dt) = 32 Hz (the IEA 15 MW's DTTorSpr gives 31 Hz). 10 Hz is far above the
controllers' bandwidth and integrated to 2 % in frequency at 0.01 s."""

_LENGTH_TOLERANCE = 1e-3  # [m] lengths that agree to within this are the same (as the loader takes them)
_ALPHA_TOLERANCE = 1e-4  # [deg] a polar's first and last angle of attack are -180 and 180 to within this


class DeckError(ValueError):
    """A deck the import cannot convert; the message names the file (relative to the deck) and the key."""


@dataclass(frozen=True)
class Sourced:
    """A value of the turbine definition and where it comes from: the deck's file and key, and any conversion.

    ``in_file``: the definition file holds the source with the value (``{value: ..., source: ...}``, read by the
    loader, as for the aerodynamic options); otherwise it is the comment after the value.
    """

    value: Any
    source: str
    in_file: bool = False


@dataclass(frozen=True)
class AerodynamicMapping:
    """The plant's aerodynamic options for a deck's AeroDyn input (:func:`aerodynamic_options`): the definition's
    ``aerodynamics`` section (option -> :class:`Sourced`), and where the plant does differently."""

    section: Dict[str, Sourced]
    approximations: Tuple[str, ...]
    not_modelled: Tuple[str, ...]


@dataclass(frozen=True, eq=False)
class ImportedAirfoil:
    """One airfoil polar: angle of attack [rad], lift, drag and moment coefficients as rows of ``table`` (K, 4),
    and its unsteady-aerodynamics parameters if the table has them with a lift slope (None: it stays
    quasi-steady, as the cylinders), with the names of those the file left to AeroDyn's default (``defaulted``)."""

    name: str
    table: np.ndarray
    source: str
    description: str
    unsteady: UnsteadyAirfoilParameters | None
    defaulted: Tuple[str, ...] = ()


@dataclass(frozen=True, eq=False)
class ImportedTurbine:
    """A deck converted: the definition's sections (key -> :class:`Sourced` or a nested section), the airfoils
    its elements use, how values were approximated, and what of the deck the plant does not model."""

    deck: Path
    definition: Dict[str, Any]
    airfoils: Tuple[ImportedAirfoil, ...]
    approximations: Tuple[str, ...]
    not_modelled: Tuple[str, ...]


def _key(name: str) -> str:
    """openfast-io's key as the deck's files write it: ``BldFile1`` -> ``BldFile(1)``."""
    return re.sub(r"(?<=[A-Za-z])(\d)$", r"(\1)", name)


_FLOORS = {"GBRatio": (0.0, True), "GenIner": (0.0, True), "DTTorSpr": (0.0, True), "HubIner": (0.0, False),
           "HubRad": (0.0, False), "AdjBlMs": (0.0, True), "BMassDen": (0.0, True)}
"""Lower bounds (value, strict) of the deck values the import computes with before the definition is checked
(rotor speeds over GBRatio, the shaft's torsion frequency from the inertias and DTTorSpr, the blade's mass): a
value out of range is refused where it is read, naming it, instead of failing in that arithmetic. Every other
range is the turbine definition's (:func:`hawt_plant.turbine.load_turbine`, run by :func:`write_turbine`)."""


def _below_floor(key: str, values: np.ndarray, file: str) -> None:
    """Refuse the first of ``values`` under the floor of ``key`` (:data:`_FLOORS`), if it has one."""
    if key not in _FLOORS:
        return
    low, strict = _FLOORS[key]
    bad = np.flatnonzero(values <= low if strict else values < low)
    if bad.size:
        where = f" (value {bad[0] + 1} of {values.size})" if values.size > 1 else ""
        raise DeckError(f"{file}: {_key(key)}: expected {'values' if values.size > 1 else 'a value'} "
                        f"{'>' if strict else '>='} {low:g}, found {values[bad[0]]:g}{where}")


def _number(values: Mapping[str, Any], key: str, file: str) -> float:
    value = values.get(key)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise DeckError(f"{file}: {_key(key)}: expected a number, found {value!r}")
    _below_floor(key, np.array([value], dtype=float), file)
    return float(value)


def _array(values: Mapping[str, Any], key: str, file: str) -> np.ndarray:
    try:
        out = np.array(values.get(key), dtype=float)
    except (TypeError, ValueError):
        out = np.array([np.nan])
    if out.ndim != 1 or out.size == 0 or not np.all(np.isfinite(out)):
        raise DeckError(f"{file}: {_key(key)}: expected a list of numbers, found {values.get(key)!r}")
    _below_floor(key, out, file)
    return out


def _blade_length(ed: Mapping[str, Any], file: str) -> float:
    """ElastoDyn TipRad - HubRad [m], which must be positive."""
    hub, tip = _number(ed, "HubRad", file), _number(ed, "TipRad", file)
    if tip <= hub:
        raise DeckError(f"{file}: TipRad: expected a value > HubRad ({hub:g}), found {tip:g}")
    return tip - hub


class _Discon:
    """The settings of a ROSCO DISCON.IN, numbers read with the file and key in their errors."""

    def __init__(self, path: Path, name: str) -> None:
        self.name = name
        self.settings = read_settings(path)
        if "PerfFileName" not in self.settings:
            raise DeckError(f"{name}: PerfFileName: missing; the import reads a ROSCO controller input (DISCON.IN)")

    def array(self, key: str) -> np.ndarray:
        if key not in self.settings:
            raise DeckError(f"{self.name}: {key}: missing")
        try:
            out = np.array([float(word) for word in self.settings[key].split()])
        except ValueError:
            out = np.array([np.nan])
        if out.size == 0 or not np.all(np.isfinite(out)):
            raise DeckError(f"{self.name}: {key}: expected numbers, found {self.settings[key]!r}")
        return out

    def number(self, key: str) -> float:
        return float(self.array(key)[0])


class _Deck:
    """openfast-io's reader on one deck; files are named relative to the deck's folder."""

    def __init__(self, fst: Path) -> None:
        self.folder = fst.resolve().parent
        self.reader = InputReader_OpenFAST()
        self.reader.FAST_InputFile = fst.name
        self.reader.FAST_directory = str(self.folder)
        self.vt = self.reader.fst_vt

    def name(self, path: str | os.PathLike) -> str:
        return os.path.relpath(os.path.normpath(os.path.join(self.folder, path)), self.folder)

    def existing(self, referrer: str, key: str, base: str | os.PathLike, value: str) -> Path:
        """The file ``value`` names (relative to ``base``), which must exist."""
        path = Path(os.path.normpath(os.path.join(self.folder, base, value)))
        if not path.is_file():
            raise DeckError(f"{referrer}: {_key(key)}: {self.name(path)}: no such file")
        return path

    def read(self, file: str, read: Callable[[], None]) -> None:
        """Run an openfast-io reader of ``file``; a file it cannot find or parse becomes a :class:`DeckError`."""
        try:
            read()
        except FileNotFoundError as error:
            referrer, key = self._naming(file, os.path.basename(error.filename or ""))
            raise DeckError(f"{referrer}: {key}: {self.name(error.filename)}: no such file") from None
        except (ValueError, IndexError, KeyError, TypeError, UnicodeDecodeError) as error:
            raise DeckError(f"{file}: openfast-io {importlib.metadata.version('openfast-io')} cannot read it "
                            f"({type(error).__name__}: {error})") from None

    def _naming(self, file: str, missing: str) -> Tuple[str, str]:
        """The file and key that name the file ``missing``. The other files are checked before they are read;
        AeroDyn's reader opens the files its input names itself: the blade files (``ADBlFile(1)``), the polars
        (``AFNames(3)``) and their coordinates (an airfoil file's ``NumCoords``)."""
        def names(value: Any) -> bool:
            return isinstance(value, str) and os.path.basename(value.strip('@"')) == missing

        aerodyn = self.vt["AeroDyn"]
        for key, value in aerodyn.items():
            if names(value):
                return file, _key(key)
            if isinstance(value, list):
                for index, item in enumerate(value):
                    if names(item):
                        return file, f"{key}({index + 1})"
        for index, tables in enumerate(aerodyn.get("af_data") or []):
            if tables and names(tables[0].get("NumCoords")):
                return self.name(aerodyn["AFNames"][index]), "NumCoords"
        return file, "a file it names"


def import_deck(fst: str | os.PathLike) -> ImportedTurbine:
    """Read an OpenFAST deck and convert it into the hawt turbine definition (module notes).

    Parameters
    ----------
    fst : path
        The deck's main input file (``.fst``).

    Returns
    -------
    ImportedTurbine

    Raises
    ------
    DeckError
        A file is missing or unreadable, or an option is one the plant cannot honour; the message names the file
        and the key, e.g. ``NREL-5MW.fst: CompAero: 1 (AeroDisk) is not supported: ...``.
    """
    fst = Path(fst)
    if not fst.is_file():
        raise DeckError(f"{fst}: no such file")
    deck = _Deck(fst)
    deck.read(fst.name, deck.reader.read_MainInput)
    main = deck.vt["Fst"]
    _check_main(main, fst.name)
    files = {"fst": fst.name}
    ed, blade, tower = _read_elastodyn(deck, main, files)
    ad, ad_blade = _read_aerodyn(deck, main, ed, files)
    sd, discon = _read_servodyn(deck, main, files)
    length = _blade_length(ed, files["ed"])
    aerodynamics, airfoils = _blade_aerodynamics(deck, ad, ad_blade, length, files)
    torsion = _torsion_frequency(ed, blade, files)
    base = _number(ed, "TowerBsHt", files["ed"])
    substructure = _monopile(deck, main, base, files) if base else "on the ground"
    structure = _blade_structure(blade, length, files["blade"], ed["EdgeDOF"])
    nacelle = _nacelle(ed, files["ed"])
    top_mass = (_number(ed, "HubMass", files["ed"]) + nacelle["mass"].value
                + ed["NumBl"] * structure["reference_mass"].value)
    definition = {
        "name": Sourced(fst.stem, f"{fst.name}: the deck's name"),
        "source": Sourced(f"OpenFAST deck {fst.name} ({deck.vt['description'].strip()}), imported by hawt turbine "
                          "import", f"{fst.name} title line"),
        "environment": _environment(main, ad, files),
        "rotor": _rotor(ed, files["ed"]),
        "nacelle": nacelle,
        "blade": {"aerodynamics": aerodynamics, "structure": structure},
        "tower": _tower(ed, tower, ad, files, substructure, top_mass, _number(main, "Gravity", files["fst"])),
        "drivetrain": _drivetrain(ed, torsion, files["ed"]),
        "generator": _generator(sd, discon, files["sd"]),
        "pitch_actuator": _pitch_actuator(discon),
        "operation": _operation(discon, _number(ed, "GBRatio", files["ed"]), files["ed"]),
    }
    aero = aerodynamic_options(ad, definition["rotor"].get("position") is not None, files["ad"])
    definition["aerodynamics"] = aero.section
    return ImportedTurbine(deck=fst, definition=definition, airfoils=airfoils,
                           approximations=tuple(_approximations(ed, torsion, ad, discon, substructure, files))
                           + aero.approximations,
                           not_modelled=tuple(_not_modelled(main, ed, ad, ad_blade, sd, substructure, files))
                           + aero.not_modelled)


_UNSUPPORTED = {
    "CompElast": ({1}, {2: "BeamDyn blades", 3: "SimpleElastoDyn"}, "the plant's blade and tower are ElastoDyn's "
                  "(CompElast = 1; a deck with an ElastoDyn blade file may switch to it)"),
    "CompAero": ({2}, {0: "no aerodynamics", 1: "AeroDisk", 3: "external loads"},
                 "the plant needs AeroDyn's blade and polars (CompAero = 2)"),
    "CompServo": ({1}, {0: "no ServoDyn"}, "the limits and rated values come from ServoDyn's ROSCO controller "
                  "(CompServo = 1)"),
    "MHK": ({0}, {1: "fixed MHK turbine", 2: "floating MHK turbine"}, "the plant is a wind turbine in air (MHK = 0)"),
}


def _check_main(main: Mapping[str, Any], file: str) -> None:
    for key, (allowed, meanings, reason) in _UNSUPPORTED.items():
        if main[key] not in allowed:
            meaning = f" ({meanings[main[key]]})" if main[key] in meanings else ""
            raise DeckError(f"{file}: {key}: {main[key]}{meaning} is not supported: {reason}")


def _same_per_blade(values: Mapping[str, Any], keys: Sequence[str], blades: int, file: str, what: str) -> None:
    first = values[keys[0]]
    for key in keys[1:blades]:
        if values[key] != first:
            raise DeckError(f"{file}: {_key(key)}: {values[key]!r} differs from {_key(keys[0])} {first!r}: the "
                            f"plant's blades have one {what}")


def _read_elastodyn(deck: _Deck, main: Mapping[str, Any], files: Dict[str, str]) -> Tuple[dict, dict, dict]:
    """ElastoDyn's main, blade and tower inputs (the names of their files into ``files``)."""
    ed_path = deck.existing(files["fst"], "EDFile", "", main["EDFile"])
    files["ed"] = deck.name(ed_path)
    deck.read(files["ed"], lambda: deck.reader.read_ElastoDyn(str(ed_path)))
    ed = deck.vt["ElastoDyn"]
    blades = ed["NumBl"]
    if not 2 <= blades <= 3:
        raise DeckError(f"{files['ed']}: NumBl: {blades} is not supported: the plant has 2 or 3 blades")
    _same_per_blade(ed, ("PreCone(1)", "PreCone(2)", "PreCone(3)"), blades, files["ed"], "precone")
    _same_per_blade(ed, ("BldFile1", "BldFile2", "BldFile3"), blades, files["ed"], "blade file")
    blade_path = deck.existing(files["ed"], "BldFile1", ed_path.parent, ed["BldFile1"])
    tower_path = deck.existing(files["ed"], "TwrFile", ed_path.parent, ed["TwrFile"])
    files["blade"], files["tower"] = deck.name(blade_path), deck.name(tower_path)
    deck.read(files["blade"], lambda: deck.reader.read_ElastoDynBlade(str(blade_path)))
    deck.read(files["tower"], lambda: deck.reader.read_ElastoDynTower(str(tower_path)))
    return ed, deck.vt["ElastoDynBlade"][0], deck.vt["ElastoDynTower"]


def _read_aerodyn(deck: _Deck, main: Mapping[str, Any], ed: Mapping[str, Any],
                  files: Dict[str, str]) -> Tuple[dict, dict]:
    """AeroDyn's input with its blade file and polars (the names of the files into ``files``)."""
    ad_path = deck.existing(files["fst"], "AeroFile", "", main["AeroFile"])
    files["ad"] = deck.name(ad_path)
    deck.read(files["ad"], deck.reader.read_AeroDyn)
    ad = deck.vt["AeroDyn"]
    _same_per_blade(ad, ("ADBlFile1", "ADBlFile2", "ADBlFile3"), ed["NumBl"], files["ad"], "blade file")
    files["ad_blade"] = deck.name(Path(ad_path.parent, ad["ADBlFile1"]))
    if ad["AFTabMod"] != 1:
        raise DeckError(f"{files['ad']}: AFTabMod: {ad['AFTabMod']} is not supported: the plant's polars are one "
                        "table per airfoil over the angle of attack (AFTabMod = 1)")
    for key in ("InCol_Alfa", "InCol_Cl", "InCol_Cd"):
        if ad[key] < 1:
            raise DeckError(f"{files['ad']}: {key}: {ad[key]}: the plant needs the angle of attack, lift and drag")
    blade = deck.vt["AeroDynBlade"]
    return ad, blade[0] if isinstance(blade, list) else blade


def _read_servodyn(deck: _Deck, main: Mapping[str, Any], files: Dict[str, str]) -> Tuple[dict, _Discon]:
    """ServoDyn's input and the ROSCO DISCON.IN its controller reads (the names of the files into ``files``)."""
    sd_path = deck.existing(files["fst"], "ServoFile", "", main["ServoFile"])
    files["sd"] = deck.name(sd_path)
    deck.read(files["sd"], deck.reader.read_ServoDyn)
    sd = deck.vt["ServoDyn"]
    for key in ("PCMode", "VSContrl"):
        if sd[key] != 5:
            raise DeckError(f"{files['sd']}: {key}: {sd[key]} is not supported: the limits and rated values come "
                            f"from the ROSCO controller's DISCON.IN ({key} = 5)")
    discon_path = deck.existing(files["sd"], "DLL_InFile", "", sd["DLL_InFile"])
    files["discon"] = deck.name(discon_path)
    discon = _Discon(discon_path, files["discon"])
    for key in RELATIVE_PATH_SETTINGS:  # the files hawt turbine import copies beside the turbine's DISCON.IN
        value = discon.settings.get(key, "").strip('"')
        if value and value != "unused":
            deck.existing(files["discon"], key, discon_path.parent, value)
    return sd, discon


def _environment(main: Mapping[str, Any], ad: Mapping[str, Any], files: Mapping[str, str]) -> Dict[str, Sourced]:
    if isinstance(ad["AirDens"], float):
        density = Sourced(_number(ad, "AirDens", files["ad"]), f"{files['ad']} AirDens")
    else:
        density = Sourced(_number(main, "AirDens", files["fst"]),
                          f"{files['fst']} AirDens ({files['ad']} AirDens = {ad['AirDens']})")
    return {"air_density": density, "gravity": Sourced(_number(main, "Gravity", files["fst"]),
                                                       f"{files['fst']} Gravity")}


def _rotor(ed: Mapping[str, Any], file: str) -> Dict[str, Sourced]:
    overhang = _number(ed, "OverHang", file)
    downwind = overhang > 0.0
    side, where = (1.0, "downwind rotor: kept") if downwind else (-1.0, "upwind rotor: negated")
    cone, tilt = _number(ed, "PreCone(1)", file), _number(ed, "ShftTilt", file)
    rotor = {
        "number_of_blades": Sourced(int(ed["NumBl"]), f"{file} NumBl"),
        "hub_radius": Sourced(_number(ed, "HubRad", file), f"{file} HubRad"),
        "tip_radius": Sourced(_number(ed, "TipRad", file), f"{file} TipRad"),
        "cone_angle": Sourced(side * math.radians(cone), f"{file} PreCone(1) = {cone:g} deg ({where})"),
        "shaft_tilt": Sourced(side * math.radians(tilt), f"{file} ShftTilt = {tilt:g} deg ({where})"),
        "overhang": Sourced(side * overhang, f"{file} OverHang = {overhang:g} m ({where})"),
        "hub_mass": Sourced(_number(ed, "HubMass", file), f"{file} HubMass"),
        "hub_inertia": Sourced(_number(ed, "HubIner", file), f"{file} HubIner, about the shaft"),
    }
    if downwind:
        rotor["position"] = Sourced("downwind", f"{file} OverHang > 0")
    return rotor


def _nacelle(ed: Mapping[str, Any], file: str) -> Dict[str, Sourced]:
    nacelle, bearing = _number(ed, "NacMass", file), _number(ed, "YawBrMass", file)
    mass = nacelle + bearing
    share = nacelle / mass if mass else 1.0
    lumped = f" x NacMass / (NacMass + YawBrMass = {bearing:g} kg)" if bearing else ""
    return {
        "mass": Sourced(mass, f"{file} NacMass + YawBrMass" if bearing else f"{file} NacMass"),
        "cm_downwind": Sourced(share * _number(ed, "NacCMxn", file), f"{file} NacCMxn{lumped}"),
        "cm_above_tower_top": Sourced(share * _number(ed, "NacCMzn", file), f"{file} NacCMzn{lumped}"),
        "yaw_inertia": Sourced(_number(ed, "NacYIner", file), f"{file} NacYIner (also used for nodding and rolling)"),
        "shaft_above_tower_top": Sourced(_number(ed, "Twr2Shft", file), f"{file} Twr2Shft"),
    }


def node_widths(spans: np.ndarray, length: float) -> np.ndarray:
    """The width of blade each of AeroDyn's blade nodes acts over in the plant: halfway to its neighbours, to the
    root and the tip at the ends (AeroDyn 15's trapezoidal rule for loads that vary linearly between nodes).

    Parameters
    ----------
    spans : ndarray, shape (N,)
        AeroDyn's node positions BlSpn along the blade from the root [m], increasing.
    length : float
        Blade length [m].

    Returns
    -------
    ndarray, shape (N,)
        Widths [m], adding up to ``length``.
    """
    return np.diff(np.concatenate(([0.0], 0.5 * (spans[1:] + spans[:-1]), [length])))


def _blade_aerodynamics(deck: _Deck, ad: Mapping[str, Any], blade: Mapping[str, Any], length: float,
                        files: Mapping[str, str]) -> Tuple[Dict[str, Sourced], Tuple[ImportedAirfoil, ...]]:
    file = files["ad_blade"]
    spans = _array(blade, "BlSpn", file)
    if np.any(np.diff(spans) <= 0.0) or spans[0] < 0.0 or spans[-1] > length + _LENGTH_TOLERANCE:
        raise DeckError(f"{file}: BlSpn: expected increasing spans within the blade's {length:g} m "
                        f"(ElastoDyn TipRad - HubRad), found {spans[0]:g} .. {spans[-1]:g} m")
    width = node_widths(spans, length)
    ids = _array(blade, "BlAFID", file).astype(int)
    count = len(ad["AFNames"])
    if np.any(ids < 1) or np.any(ids > count):
        raise DeckError(f"{file}: BlAFID: expected airfoil numbers 1..{count} (NumAFfiles of {files['ad']})")
    used = sorted(set(ids.tolist()))
    airfoils = {index: _airfoil(deck, ad, index, files["ad"]) for index in used}
    names = [airfoil.name for airfoil in airfoils.values()]
    if len(set(names)) < len(names):
        raise DeckError(f"{files['ad']}: AFNames: two airfoil files have the same name; the plant names polars by "
                        "file name")
    section = {
        "span": Sourced(spans, f"{file} BlSpn: the {spans.size} nodes, root and tip included"),
        "width": Sourced(width, "from the spans: halfway to the neighbouring nodes (AeroDyn 15's trapezoidal rule)"),
        "chord": Sourced(_array(blade, "BlChord", file), f"{file} BlChord"),
        "twist": Sourced(np.radians(_array(blade, "BlTwist", file)), f"{file} BlTwist [deg]"),
        "airfoil": Sourced([airfoils[i].name for i in ids], f"{file} BlAFID -> {files['ad']} AFNames"),
    }
    return section, tuple(airfoils.values())


def _airfoil(deck: _Deck, ad: Mapping[str, Any], index: int, ad_file: str) -> ImportedAirfoil:
    """Airfoil ``index`` (1-based) of AFNames: its first table."""
    path = Path(ad["AFNames"][index - 1])
    file = deck.name(path)
    polar = ad["af_data"][index - 1][0]
    alpha = _array(polar, "Alpha", file)
    columns = [alpha, _array(polar, "Cl", file), _array(polar, "Cd", file)]
    columns.append(_array(polar, "Cm", file) if ad["InCol_Cm"] > 0 else np.zeros(alpha.size))
    if np.any(np.diff(alpha) <= 0.0):
        raise DeckError(f"{file}: Alpha: angles of attack must increase strictly (AFNames({index}) of {ad_file})")
    if abs(alpha[0] + 180.0) > _ALPHA_TOLERANCE or abs(alpha[-1] - 180.0) > _ALPHA_TOLERANCE:
        raise DeckError(f"{file}: Alpha: the plant's polars run from -180 to 180 deg, this one from {alpha[0]:g} "
                        f"to {alpha[-1]:g} deg")
    table = np.column_stack(columns)
    table[:, 0] = np.radians(alpha)
    table[0, 0], table[-1, 0] = -math.pi, math.pi
    lines = path.read_text(errors="replace").splitlines()
    description = lines[1].strip().lstrip("!").strip() if len(lines) > 1 else ""
    unsteady = [polar.get(key) for key in ("alpha0", "C_nalpha", "Cd0")] if polar["InclUAdata"] else []
    usable = len(unsteady) == 3 and all(isinstance(value, float) for value in unsteady) and unsteady[1] > 0.0
    if not usable:
        return ImportedAirfoil(name=path.stem, table=table, source=file, description=description, unsteady=None)
    lags, defaulted = {}, []
    for key, name in _UA_LAGS:
        value = polar.get(key)
        if isinstance(value, str) and value.strip('"').lower() == "default":
            defaulted.append(name)
        elif isinstance(value, (int, float)) and not isinstance(value, bool):
            lags[name] = float(value)
        else:
            raise DeckError(f"{file}: {key}: expected a number or \"Default\", found {value!r}")
    try:
        parameters = UnsteadyAirfoilParameters(math.radians(unsteady[0]), unsteady[1], unsteady[2], **lags)
    except ValueError as err:
        raise DeckError(f"{file}: UA coefficients: {err}") from None
    return ImportedAirfoil(name=path.stem, table=table, source=file, description=description, unsteady=parameters,
                           defaulted=tuple(defaulted))


_UA_LAGS = (("A1", "a1"), ("A2", "a2"), ("b1", "b1"), ("b2", "b2"), ("T_p", "pressure_lag"),
            ("T_f0", "separation_lag"))
"""AeroDyn's UA coefficient -> :class:`hawt_plant.turbine.UnsteadyAirfoilParameters` field, beyond alpha0, C_nalpha
and Cd0."""


def _blade_structure(blade: Mapping[str, Any], length: float, file: str, edgewise: bool) -> Dict[str, Sourced]:
    """The blade's structure; its edgewise mode where the deck's ElastoDyn has it (``edgewise``, EdgeDOF)."""
    fraction = _array(blade, "BlFract", file)
    factor = _number(blade, "AdjBlMs", file)
    density = _array(blade, "BMassDen", file)
    flap_factor = _number(blade, "AdjFlSt", file) * _number(blade, "FlStTunr1", file)
    edge_factor = _number(blade, "AdjEdSt", file)
    s = fraction * length
    mass = float(np.trapezoid(factor * density, s))
    cg = float(np.trapezoid(factor * density * s, s)) / mass if mass > 0.0 else 0.0
    return {
        "mass_density_factor": Sourced(factor, f"{file} AdjBlMs"),
        "flap_damping_ratio": Sourced(_number(blade, "BldFlDmp1", file) / 100.0, f"{file} BldFlDmp(1) [%]"),
        "flap_mode_shape": Sourced(_array(blade, "BldFl1Sh", file), f"{file} BldFl1Sh(2..6), x^2..x^6"),
        **({"edge_damping_ratio": Sourced(_number(blade, "BldEdDmp1", file) / 100.0, f"{file} BldEdDmp(1) [%]"),
            "edge_mode_shape": Sourced(_array(blade, "BldEdgSh", file), f"{file} BldEdgSh(2..6), x^2..x^6")}
           if edgewise else {}),
        "span_fraction": Sourced(fraction, f"{file} BlFract"),
        "structural_twist": Sourced(np.radians(_array(blade, "StrcTwst", file)), f"{file} StrcTwst [deg]"),
        "mass_density": Sourced(density, f"{file} BMassDen"),
        "flap_stiffness": Sourced(flap_factor * _array(blade, "FlpStff", file),
                                  f"{file} FlpStff x AdjFlSt x FlStTunr(1) (= {flap_factor:g})"),
        "edge_stiffness": Sourced(edge_factor * _array(blade, "EdgStff", file),
                                  f"{file} EdgStff x AdjEdSt (= {edge_factor:g})"),
        "reference_mass": Sourced(mass, f"integral of {file} BMassDen x AdjBlMs (the deck states no blade mass)"),
        "reference_cg_from_root": Sourced(cg, f"from {file} BMassDen, as reference_mass"),
    }


@dataclass(frozen=True, eq=False)
class _Monopile:
    """A deck's SubDyn monopile as stations of the tower's beam below the tower's base (:func:`_monopile`): heights
    [m] from its clamp up to 1 mm below the interface, each with its section (linear between stations, as the plant
    takes every distributed property), the number of its members, and its concentrated masses [kg]."""

    height: np.ndarray
    mass_density: np.ndarray
    stiffness: np.ndarray
    members: int
    point_mass: float


def _monopile(deck: _Deck, main: Mapping[str, Any], base: float, files: Dict[str, str]) -> _Monopile | str:
    """The deck's SubDyn substructure if it is a monopile the plant can make part of the tower's beam (a vertical
    line of circular beams, MType 1, joined rigidly from one reaction joint clamped in all six directions without
    soil file to one interface joint at TowerBsHt = ``base``); otherwise why the tower stands on a rigid base."""
    if main["CompSub"] != 1:
        return f"{files['fst']} CompSub = {main['CompSub']}: no SubDyn substructure"
    path = deck.existing(files["fst"], "SubFile", "", main["SubFile"])
    files["sub"] = file = deck.name(path)
    try:
        deck.read(file, lambda: deck.reader.read_SubDyn(str(path)))
    except DeckError as error:
        return str(error)
    sd = deck.vt["SubDyn"]
    joints = {joint: (x, y, z) for joint, x, y, z in zip(sd["JointID"], sd["JointXss"], sd["JointYss"],
                                                          sd["JointZss"])}
    sections = {index: (modulus, density, diameter, thickness) for index, modulus, density, diameter, thickness in
                zip(sd["PropSetID1"], sd["YoungE1"], sd["MatDens1"], sd["XsecD"], sd["XsecT"])}
    locked = [sd[key][0] for key in ("RctTDXss", "RctTDYss", "RctTDZss", "RctRDXss", "RctRDYss", "RctRDZss")] \
        if sd["NReact"] == 1 else []
    members = sorted((sorted(((joints[j1][2], p1), (joints[j2][2], p2))) for j1, j2, p1, p2 in
                      zip(sd["MJointID1"], sd["MJointID2"], sd["MPropSetID1"], sd["MPropSetID2"])))
    chained = all(lower[1][0] == upper[0][0] for lower, upper in zip(members, members[1:]))
    vertical = len({(x, y) for x, y, _ in joints.values()}) == 1 and set(sd["JointType"]) == {1}
    if not (sd["NReact"] == 1 and locked == [1] * 6 and sd["Rct_SoilFile"][0].strip('"') == ""
            and sd["NInterf"] == 1 and vertical and set(sd["MType"]) == {1} and members and chained
            and members[0][0][0] == joints[sd["RJointID"][0]][2] and members[-1][1][0] == joints[sd["IJointID"][0]][2]
            and abs(members[-1][1][0] - base) <= _LENGTH_TOLERANCE):
        return (f"{file} is not a monopile the plant can bend with the tower: one vertical line of circular beams "
                "(MType 1, cantilever joints) from one reaction joint clamped in all six directions without soil "
                f"file to one interface joint at TowerBsHt = {base:g} m")
    # Each member's section at its lower joint, and the last one's at its top 1 mm below the tower's base (the
    # step to the tower's section, as the deck's own 1 mm members step between sections).
    ends = [lower for lower, _ in members] + [(members[-1][1][0] - _LENGTH_TOLERANCE, members[-1][1][1])]
    height = np.array([z for z, _ in ends])
    modulus, density, diameter, thickness = (np.array([sections[index][k] for _, index in ends]) for k in range(4))
    inner = diameter - 2.0 * thickness
    keep = np.concatenate((np.diff(height) > 0.0, [True]))  # a zero-length member gives way to the next one
    return _Monopile(height=height[keep], mass_density=(density * math.pi / 4.0 * (diameter**2 - inner**2))[keep],
                     stiffness=(modulus * math.pi / 64.0 * (diameter**4 - inner**4))[keep], members=len(members),
                     point_mass=float(np.sum(sd["JMass"])) if sd["NCmass"] else 0.0)


def _tower(ed: Mapping[str, Any], tower: Mapping[str, Any], ad: Mapping[str, Any], files: Mapping[str, str],
           substructure: _Monopile | str, top_mass: float, gravity: float) -> Dict[str, Sourced]:
    """The tower: on the ground (TowerBsHt = 0), on a rigid base at TowerBsHt, or on the deck's monopile as a
    flexible base (``substructure``, :func:`_monopile`; a string says why the base is rigid, or that the tower
    stands on the ground). ``top_mass`` [kg] is the rotor's and nacelle's, for a flexible base's first modes."""
    ed_file, file, ad_file = files["ed"], files["tower"], files["ad"]
    base = _number(ed, "TowerBsHt", ed_file)
    top = _number(ed, "TowerHt", ed_file)
    elevation = _array(ad, "TwrElev", ad_file)
    diameter = _array(ad, "TwrDiam", ad_file)
    above = elevation >= -_LENGTH_TOLERANCE
    drag = _array(ad, "TwrCd", ad_file)
    factors = {key: _number(tower, key, file) for key in ("AdjTwMa", "AdjFASt", "FAStTunr1", "AdjSSSt", "SSStTunr1")}
    fa_factor, ss_factor = factors["AdjFASt"] * factors["FAStTunr1"], factors["AdjSSSt"] * factors["SSStTunr1"]
    fraction = _array(tower, "HtFract", file)
    mass = factors["AdjTwMa"] * _array(tower, "TMassDen", file)
    fa = fa_factor * _array(tower, "TwFAStif", file)
    ss = ss_factor * _array(tower, "TwSSStif", file)
    section = {
        "height": Sourced(top, f"{ed_file} TowerHt"),
        "fa_damping_ratio": Sourced(_number(tower, "TwrFADmp1", file) / 100.0, f"{file} TwrFADmp(1) [%]"),
        "ss_damping_ratio": Sourced(_number(tower, "TwrSSDmp1", file) / 100.0, f"{file} TwrSSDmp(1) [%]"),
        "fa_mode_shape": Sourced(_array(tower, "TwFAM1Sh", file), f"{file} TwFAM1Sh(2..6)"),
        "ss_mode_shape": Sourced(_array(tower, "TwSSM1Sh", file), f"{file} TwSSM1Sh(2..6)"),
        "height_fraction": Sourced(fraction, f"{file} HtFract"),
        "mass_density": Sourced(mass, f"{file} TMassDen x AdjTwMa (= {factors['AdjTwMa']:g})"),
        "fa_stiffness": Sourced(fa, f"{file} TwFAStif x AdjFASt x FAStTunr(1) (= {fa_factor:g})"),
        "ss_stiffness": Sourced(ss, f"{file} TwSSStif x AdjSSSt x SSStTunr(1) (= {ss_factor:g})"),
        "outline_elevation": Sourced(np.maximum(elevation[above], 0.0), f"{ad_file} TwrElev"),
        "outline_diameter": Sourced(diameter[above], f"{ad_file} TwrDiam"),
        "drag_coefficient": Sourced(float(np.mean(drag)), f"{ad_file} TwrCd" + (
            "" if np.all(drag == drag[0]) else f", the mean of {drag.min():g} .. {drag.max():g}")),
    }
    if not base:
        return section
    section["base_height"] = Sourced(base, f"{ed_file} TowerBsHt")
    if isinstance(substructure, str):
        section["clamp_height"] = Sourced(base, f"{ed_file} TowerBsHt: a rigid base ({substructure})")
        return section
    sub_file, clamp = files["sub"], float(substructure.height[0])
    length = top - clamp
    stations = np.concatenate((substructure.height, base + fraction * (top - base)))
    section["clamp_height"] = Sourced(clamp, f"{sub_file} JointZss of the reaction joint: the monopile's clamp")
    section["height_fraction"] = Sourced((stations - clamp) / length, f"{sub_file} JointZss of each member's lower "
                                         "joint and 1 mm below TowerBsHt (the last member's top section), then "
                                         f"TowerBsHt + {file} HtFract x (TowerHt - TowerBsHt); over the length from "
                                         "the clamp to TowerHt")
    section["mass_density"] = Sourced(np.concatenate((substructure.mass_density, mass)),
                                      f"{sub_file} MatDens x pi/4 (XsecD^2 - (XsecD - 2 XsecT)^2) below TowerBsHt, "
                                      f"then {file} TMassDen x AdjTwMa (= {factors['AdjTwMa']:g})")
    for key, values, name, factor in (("fa", fa, "TwFAStif x AdjFASt x FAStTunr(1)", fa_factor),
                                      ("ss", ss, "TwSSStif x AdjSSSt x SSStTunr(1)", ss_factor)):
        stiffness = np.concatenate((substructure.stiffness, values))
        shape, frequency = beam_first_mode(section["height_fraction"].value, section["mass_density"].value,
                                           stiffness, length, top_mass, gravity)
        section[f"{key}_stiffness"] = Sourced(stiffness, f"{sub_file} YoungE x pi/64 (XsecD^4 - (XsecD - 2 XsecT)^4) "
                                                         f"below TowerBsHt, then {file} {name} (= {factor:g})")
        section[f"{key}_mode_shape"] = Sourced(shape, f"the first mode of the monopile and tower as one beam with the "
                                                      f"rotor and nacelle's {top_mass:.6g} kg on top, {frequency:.4f} "
                                                      "Hz (hawt_plant.modal.beam_first_mode; the deck's "
                                                      f"{'TwFAM1Sh' if key == 'fa' else 'TwSSM1Sh'} is the tower's "
                                                      "alone, clamped at TowerBsHt)")
    return section


def _torsion_frequency(ed: Mapping[str, Any], blade: Mapping[str, Any], files: Mapping[str, str]) -> float:
    """Free-free torsion frequency [Hz] of rotor and generator on the deck's low-speed shaft (DTTorSpr), the
    rotor's inertia that of the hub and the coned blades' distributed mass (as the plant sums it)."""
    ed_file, blade_file = files["ed"], files["blade"]
    stiffness = _number(ed, "DTTorSpr", ed_file)
    hub_radius = _number(ed, "HubRad", ed_file)
    span = _array(blade, "BlFract", blade_file) * _blade_length(ed, ed_file)
    density = _number(blade, "AdjBlMs", blade_file) * _array(blade, "BMassDen", blade_file)
    cone = math.radians(_number(ed, "PreCone(1)", ed_file))
    rotor = _number(ed, "HubIner", ed_file) + ed["NumBl"] * math.cos(cone) ** 2 * float(
        np.trapezoid(density * (hub_radius + span) ** 2, span))
    generator = _number(ed, "GenIner", ed_file) * _number(ed, "GBRatio", ed_file) ** 2
    return math.sqrt(stiffness * (1.0 / rotor + 1.0 / generator)) / (2.0 * math.pi)


def _drivetrain(ed: Mapping[str, Any], frequency: float, file: str) -> Dict[str, Sourced]:
    """The drivetrain; ``frequency`` [Hz] is the deck's shaft torsion (:func:`_torsion_frequency`)."""
    stiffness = _number(ed, "DTTorSpr", file)
    spring = Sourced(stiffness, f"{file} DTTorSpr")
    if not ed["DrTrDOF"] and frequency > RIGID_TORSION_FREQUENCY:
        spring = Sourced(stiffness * (RIGID_TORSION_FREQUENCY / frequency) ** 2,
                         f"{file} DTTorSpr = {stiffness:g} N m/rad (torsion at {frequency:.3g} Hz) with DrTrDOF = "
                         f"False (rigid): lowered to the stiffness of a {RIGID_TORSION_FREQUENCY:g} Hz torsion")
    return {
        "gearbox_ratio": Sourced(_number(ed, "GBRatio", file), f"{file} GBRatio"),
        "gearbox_efficiency": Sourced(_number(ed, "GBoxEff", file) / 100.0, f"{file} GBoxEff [%]"),
        "generator_inertia": Sourced(_number(ed, "GenIner", file), f"{file} GenIner, about the high-speed shaft"),
        "torsional_stiffness": spring,
        "torsional_damping": Sourced(_number(ed, "DTTorDmp", file), f"{file} DTTorDmp"),
    }


def _generator(sd: Mapping[str, Any], discon: _Discon, file: str) -> Dict[str, Sourced]:
    return {
        "efficiency": Sourced(_number(sd, "GenEff", file) / 100.0, f"{file} GenEff [%]"),
        "rated_power": Sourced(discon.number("VS_RtPwr"), f"{discon.name} VS_RtPwr (electrical)"),
        "rated_torque": Sourced(discon.number("VS_RtTq"), f"{discon.name} VS_RtTq, high-speed shaft"),
        "max_torque": Sourced(discon.number("VS_MaxTq"), f"{discon.name} VS_MaxTq"),
        "max_torque_rate": Sourced(discon.number("VS_MaxRat"), f"{discon.name} VS_MaxRat"),
    }


def _pitch_actuator(discon: _Discon) -> Dict[str, Sourced]:
    name = discon.name
    lowest, fine = discon.number("PC_MinPit"), discon.number("PC_FinePit")
    minimum = (Sourced(lowest, f"{name} PC_MinPit") if lowest >= fine else
               Sourced(fine, f"{name} PC_FinePit (above PC_MinPit = {lowest:g} rad: the plant's lower limit is "
                             "also its below-rated pitch)"))
    mode = int(discon.number("PA_Mode"))
    if mode == 2:
        dynamics = (Sourced(discon.number("PA_CornerFreq"), f"{name} PA_CornerFreq (PA_Mode = 2)"),
                    Sourced(discon.number("PA_Damping"), f"{name} PA_Damping"))
    elif mode == 1:
        dynamics = (Sourced(discon.number("PA_CornerFreq"), f"{name} PA_CornerFreq (PA_Mode = 1, first order)"),
                    Sourced(1.0 / math.sqrt(2.0), "1/sqrt(2): the second order with the first order's -3 dB "
                                                  "bandwidth"))
    else:
        dynamics = (Sourced(DEFAULT_ACTUATOR[0], f"{name} PA_Mode = {mode}: the deck has no actuator dynamics; "
                                                 "hawt's default, Odgaard, Stoustrup & Kinnaert (2013)"),
                    Sourced(DEFAULT_ACTUATOR[1], "hawt's default, as natural_frequency"))
    return {
        "min_angle": minimum,
        "max_angle": Sourced(discon.number("PC_MaxPit"), f"{name} PC_MaxPit"),
        "max_rate": Sourced(discon.number("PC_MaxRat"), f"{name} PC_MaxRat"),
        "natural_frequency": dynamics[0],
        "damping_ratio": dynamics[1],
    }


def _operation(discon: _Discon, gearbox_ratio: float, ed_file: str) -> Dict[str, Sourced]:
    name = discon.name
    speeds = discon.array("WE_FOPoles_v")
    count, above = int(discon.number("WE_FOPoles_N")), int(discon.number("PC_GS_n"))
    if speeds.size != count or not 1 <= count - above <= count - 1:
        raise DeckError(f"{name}: WE_FOPoles_v: expected ROSCO's WE_FOPoles_N = {count} wind speeds from v_min to "
                        f"v_max, v_rated the (WE_FOPoles_N - PC_GS_n)th, found {speeds.size} (PC_GS_n = {above})")
    tuning = "ROSCO's tuning wind speeds"
    return {
        "cut_in_wind_speed": Sourced(float(speeds[0]), f"{name} WE_FOPoles_v(1) ({tuning}: v_min)"),
        "rated_wind_speed": Sourced(float(speeds[count - above - 1]),
                                    f"{name} WE_FOPoles_v({count - above}) (WE_FOPoles_N - PC_GS_n: v_rated)"),
        "cut_out_wind_speed": Sourced(float(speeds[-1]), f"{name} WE_FOPoles_v({count}) (v_max)"),
        "min_rotor_speed": Sourced(discon.number("VS_MinOMSpd") / gearbox_ratio,
                                   f"{name} VS_MinOMSpd / {ed_file} GBRatio"),
        "rated_rotor_speed": Sourced(discon.number("PC_RefSpd") / gearbox_ratio,
                                     f"{name} PC_RefSpd / {ed_file} GBRatio"),
        "optimal_tip_speed_ratio": Sourced(discon.number("VS_TSRopt"), f"{name} VS_TSRopt"),
    }


_UA_MODELS = {2: "B-L Gonzalez", 3: "B-L Minnema/Pierce", 4: "B-L HGM 4-states", 5: "B-L HGM+vortex 5 states",
               6: "Oye", 7: "Boeing-Vertol"}
_DBEMT_MODELS = {-1: "frozen wake, for linearisation", 0: "no dynamic wake", 1: "constant tau1",
                 2: "time-dependent tau1", 3: "constant tau1, continuous formulation"}


def _is_default(value: Any) -> bool:
    """An AeroDyn input given as ``default`` (openfast-io keeps the word, quoted or not)."""
    return isinstance(value, str) and value.strip('"').lower() == "default"


def aerodynamic_options(ad: Mapping[str, Any], downwind: bool, file: str) -> AerodynamicMapping:
    """The plant's aerodynamic options for an AeroDyn input as openfast-io reads it (``fst_vt['AeroDyn']``).

    Parameters
    ----------
    ad : mapping
        AeroDyn's inputs: Wake_Mod, DBEMT_Mod, tau1_const, TwrPotent, TwrShadow, TwrAero, Skew_Mod, SkewMomCorr,
        SkewRedistr_Mod, SkewRedistrFactor, UA_Mod, UAStartRad, UAEndRad, TipLoss, HubLoss, TanInd, AIDrag,
        TIDrag, BEM_Mod, SectAvg.
    downwind : bool
        The rotor is downwind of the tower (ElastoDyn OverHang > 0).
    file : str
        The AeroDyn file's name, for the sources.

    Returns
    -------
    AerodynamicMapping

    Notes
    -----
    - tower_shadow: an upwind rotor's is AeroDyn's potential flow, TwrPotent > 0 (2, Bak's correction: the
      baseline potential flow); the downstream shadow (TwrShadow > 0) does not reach its blades. A downwind
      rotor's is the potential flow and Powles' wake together, TwrPotent > 0 or TwrShadow > 0.
    - tower_drag: TwrAero.
    - skewed_wake: Skew_Mod = 1 with SkewRedistr_Mod = 1 (Pitt & Peters, the default) or 2 (a vortex cylinder:
      Pitt & Peters instead).
    - unsteady_airfoil: UA_Mod > 0; the plant's is Hansen-Gaunaa-Madsen's (UA_Mod 4), any other an approximation.
    - dynamic_inflow: Wake_Mod = 1 with DBEMT_Mod > 0 (OpenFAST 4), or Wake_Mod = 2 (the DBEMT of older inputs);
      the plant's is Øye's, as DBEMT_Mod = 2 (time-dependent tau1). Wake_Mod 0 (no induction) and 3 (OLAF) are
      not modelled: the plant's induction is BEM's, quasi-steady.
    - The plant's BEM always has Prandtl's tip and hub losses and the tangential induction and leaves the drag
      out of the induction (TipLoss = HubLoss = TanInd = True, AIDrag = TIDrag = False): another setting is an
      approximation.
    """
    section: Dict[str, Sourced] = {}
    approximations: List[str] = []
    not_modelled: List[str] = []

    def option(name: str, value: bool, source: str) -> None:
        section[name] = Sourced(bool(value), f"{file} {source}", in_file=True)

    potent, shadow = int(ad["TwrPotent"]), int(ad["TwrShadow"])
    if not downwind:
        option("tower_shadow", potent > 0, f"TwrPotent = {potent}" + (" (potential flow)" if potent else ""))
        if potent == 2:
            approximations.append(f"{file} TwrPotent = 2 (potential flow with Bak's correction): the plant's tower "
                                  "shadow is the baseline potential flow (TwrPotent = 1)")
        if shadow:
            not_modelled.append(f"the tower's downstream shadow ({file} TwrShadow = {shadow}): the blades of the "
                                "upwind rotor stay ahead of the tower")
    else:
        option("tower_shadow", potent > 0 or shadow > 0,
               f"TwrPotent = {potent}, TwrShadow = {shadow} (downwind rotor: potential flow and wake)")
        if (potent > 0 or shadow > 0) and (potent, shadow) != (1, 1):
            approximations.append(f"{file} TwrPotent = {potent}, TwrShadow = {shadow}: behind the tower the plant has "
                                  "the baseline potential flow and Powles' wake together (TwrPotent = TwrShadow = 1)")
    option("tower_drag", ad["TwrAero"], f"TwrAero = {ad['TwrAero']}")

    skew, redistribution = int(ad["Skew_Mod"]), ad["SkewRedistr_Mod"]
    redistribution = 1 if _is_default(redistribution) else int(redistribution)
    option("skewed_wake", skew == 1 and redistribution > 0,
           f"Skew_Mod = {skew}" + (f", SkewRedistr_Mod = {ad['SkewRedistr_Mod']} (Pitt & Peters)"
                                   if skew == 1 and redistribution == 1 else
                                   f", SkewRedistr_Mod = {ad['SkewRedistr_Mod']}" if skew == 1 else ""))
    if skew == 1 and redistribution == 2:
        approximations.append(f"{file} SkewRedistr_Mod = 2 (vortex cylinder): the plant's skewed wake is Pitt & "
                              "Peters' (SkewRedistr_Mod = 1)")
    factor = ad.get("SkewRedistrFactor")
    if skew == 1 and redistribution > 0 and not _is_default(factor) and \
            not math.isclose(float(factor), 15.0 * math.pi / 32.0, rel_tol=1e-6):
        approximations.append(f"{file} SkewRedistrFactor = {float(factor):g}: the plant's Pitt & Peters constant "
                              "is 15 pi/32")
    if skew == 1 and ad.get("SkewMomCorr"):
        not_modelled.append(f"the skew momentum correction ({file} SkewMomCorr = True)")

    ua = int(ad["UA_Mod"])
    option("unsteady_airfoil", ua > 0, f"UA_Mod = {ua}" + (f" ({_UA_MODELS.get(ua, 'unknown')})" if ua else ""))
    if ua:
        model = "its model" if ua == 4 else "Hansen-Gaunaa-Madsen's (UA_Mod = 4) in its place"
        approximations.append(f"{file} UA_Mod = {ua} ({_UA_MODELS.get(ua, 'unknown')}): the plant's unsteady airfoil "
                              f"is {model}, from each table's alpha0, C_nalpha and Cd0; the tables' other UA "
                              "coefficients are not used")
        start, end = float(ad.get("UAStartRad", 0.0)), float(ad.get("UAEndRad", 1.0))
        if (start, end) != (0.0, 1.0):
            approximations.append(f"{file} UAStartRad = {start:g}, UAEndRad = {end:g}: the plant's unsteady airfoil "
                                  "acts on every element whose polar has UA coefficients")

    wake, dbemt = int(ad["Wake_Mod"]), int(ad["DBEMT_Mod"])
    if wake == 1:
        option("dynamic_inflow", dbemt > 0,
               f"Wake_Mod = 1 (BEMT), DBEMT_Mod = {dbemt} ({_DBEMT_MODELS.get(dbemt, 'unknown')})")
        if dbemt > 0:
            constant = f", not the constant tau1 = {float(ad['tau1_const']):g} s" if dbemt in (1, 3) else ""
            approximations.append(f"{file} DBEMT_Mod = {dbemt} ({_DBEMT_MODELS.get(dbemt, 'unknown')}): the plant's "
                                  "dynamic inflow is Øye's filter on each element's axial induction (Hansen 2008 "
                                  f"§10.2), tau1 from the element's induction and inflow{constant}; the tangential "
                                  "induction stays quasi-steady")
        elif dbemt == -1:
            approximations.append(f"{file} DBEMT_Mod = -1 (frozen wake, for linearisation): the plant's induction is "
                                  "quasi-steady")
    elif wake == 2:
        option("dynamic_inflow", True, f"Wake_Mod = 2 (DBEMT, the older inputs' switch), DBEMT_Mod = {dbemt}")
        approximations.append(f"{file} Wake_Mod = 2 (DBEMT): the plant's dynamic inflow is Øye's filter on each "
                              "element's axial induction (Hansen 2008 §10.2); the tangential induction stays "
                              "quasi-steady")
    else:
        option("dynamic_inflow", False, f"Wake_Mod = {wake}")
        not_modelled.append(f"{file} Wake_Mod = {wake} ({'no induction' if wake == 0 else 'OLAF free vortex wake'}): "
                            "the plant's induction is BEM's, quasi-steady")

    always = [f"{key} = False" for key in ("TipLoss", "HubLoss", "TanInd") if not ad[key]]
    if always:
        approximations.append(f"{file} {', '.join(always)}: the plant's BEM always has Prandtl's tip and hub losses "
                              "and the tangential induction")
    drag = [f"{key} = True" for key in ("AIDrag", "TIDrag") if ad[key] and (key == "AIDrag" or ad["TanInd"])]
    if drag:
        approximations.append(f"{file} {', '.join(drag)}: the plant's induction leaves the drag out (as AIDrag = "
                              "TIDrag = False); the loads include it")
    if int(ad.get("BEM_Mod", 1)) != 1:
        approximations.append(f"{file} BEM_Mod = {ad['BEM_Mod']}: the plant's BEM is the legacy one (BEM_Mod = 1)")
    if ad.get("SectAvg"):
        not_modelled.append(f"sector averaging ({file} SectAvg = True): each element sees the wind at its own "
                            "position")
    return AerodynamicMapping(section, tuple(approximations), tuple(not_modelled))


def _approximations(ed: Mapping[str, Any], torsion: float, ad: Mapping[str, Any], discon: _Discon,
                    substructure: _Monopile | str, files: Mapping[str, str]) -> List[str]:
    """How values were approximated where the plant's definition has no place for the deck's (``torsion``: the
    shaft's frequency [Hz], :func:`_torsion_frequency`; ``substructure``: the tower's base, :func:`_tower`)."""
    ed_file, out = files["ed"], []
    base = ed["TowerBsHt"]
    if base and isinstance(substructure, str):
        out.append(f"the tower stands on a rigid base {base:g} m high ({ed_file} TowerBsHt; {substructure}): the "
                   "plant's tower is clamped there, the hub at the deck's height; its first modes are the tower's "
                   "alone (the deck's TwFAM1Sh, TwSSM1Sh)")
    elif base:
        out.append(f"the tower stands on the deck's monopile, a flexible base ({files['sub']}: "
                   f"{substructure.members} members from {substructure.height[0]:g} m, clamped, to TowerBsHt = "
                   f"{base:g} m): the plant's tower is one beam from the monopile's clamp to the tower top, the "
                   "monopile's sections below the tower's, the hub at the deck's height; its first modes are that "
                   "beam's, by Rayleigh-Ritz (hawt turbine show gives their frequencies), in place of the deck's "
                   "TwFAM1Sh and TwSSM1Sh of the tower clamped at its base, with SubDyn's Timoshenko beams as "
                   "Euler-Bernoulli ones")
    if ed["YawBrMass"]:
        out.append(f"the yaw bearing's {ed['YawBrMass']:g} kg ({ed_file} YawBrMass) is lumped into the nacelle")
    if not ed["DrTrDOF"]:
        out.append(f"{ed_file} DrTrDOF = False (a rigid drivetrain): the plant's shaft twists, with DTTorSpr or the "
                   f"stiffness of a {RIGID_TORSION_FREQUENCY:g} Hz torsion, whichever is softer")
    elif torsion > RIGID_TORSION_FREQUENCY:
        out.append(f"the shaft torsion ({ed_file} DTTorSpr) is at {torsion:.3g} Hz: the plant integrates it stably "
                   f"with dt <= {1.0 / (2.0 * math.pi * torsion):.2g} s (its dt parameter)")
    for dof, what in (("TwFADOF1", "tower fore-aft"), ("TwSSDOF1", "tower side-side"), ("FlapDOF1", "blade flap")):
        if not ed[dof]:
            out.append(f"{ed_file} {dof} = False: the plant's first {what} mode moves")
    if int(discon.number("PA_Mode")) == 0:
        out.append(f"{discon.name} PA_Mode = 0 (no actuator dynamics): the plant's actuator is hawt's default "
                   f"{DEFAULT_ACTUATOR[0]:g} rad/s, damping {DEFAULT_ACTUATOR[1]:g}")
    drag = np.asarray(ad["TwrCd"], dtype=float)
    if np.any(drag != drag[0]):
        out.append(f"{files['ad']} TwrCd varies along the tower: the plant's tower drag and wake use its mean")
    return out


def _not_modelled(main: Mapping[str, Any], ed: Mapping[str, Any], ad: Mapping[str, Any], ad_blade: Mapping[str, Any],
                  sd: Mapping[str, Any], substructure: _Monopile | str, files: Mapping[str, str]) -> List[str]:
    """What of the deck the plant does not model (it has the first flap and edgewise modes per blade, first tower modes,
    drivetrain torsion, second-order pitch actuators, quasi-steady or Øye BEM; ``substructure``: the tower's base,
    :func:`_tower`)."""
    ed_file, blade_file, tower_file, ad_file = files["ed"], files["blade"], files["tower"], files["ad"]
    out = []
    if ed["FlapDOF2"]:
        out.append(f"blade second flap mode ({ed_file} FlapDOF2 = True; {blade_file} BldFl2Sh, BldFlDmp(2)): the first "
                   "flap and edgewise modes per blade")
    if ed["TwFADOF2"] or ed["TwSSDOF2"]:
        out.append(f"tower second fore-aft and side-side modes ({ed_file} TwFADOF2 = {ed['TwFADOF2']}, TwSSDOF2 = "
                   f"{ed['TwSSDOF2']}; {tower_file} TwFAM2Sh, TwSSM2Sh)")
    if ed["YawDOF"] or sd["YCMode"]:
        out.append(f"nacelle yaw ({ed_file} YawDOF = {ed['YawDOF']}; {files['sd']} YCMode = {sd['YCMode']})")
    out.append(f"the deck's inflow ({main['InflowFile']}): the plant's wind comes from its own parameters")
    out.append(f"the controller's tuning ({files['discon']}: gains, filters, set points); ROSCO itself reads it (the "
               "discon controller)")
    modules = [f"{key} = {main[key]}" for key in ("CompSeaSt", "CompHydro", "CompSub", "CompMooring", "CompIce",
                                                   "CompSoil") if main[key]]
    dofs = [f"{key} = True" for key in ("PtfmSgDOF", "PtfmSwDOF", "PtfmHvDOF", "PtfmRDOF", "PtfmPDOF", "PtfmYDOF")
            if ed[key]]
    parts = ([f"{files['fst']} " + ", ".join(modules)] if modules else []) + \
        ([f"{ed_file} " + ", ".join(dofs)] if dofs else [])
    if parts and isinstance(substructure, str):
        out.append(f"substructure and platform ({'; '.join(parts)}): the tower is clamped at its base")
    elif parts:
        lumped = f"its {substructure.point_mass:g} kg of concentrated masses ({files['sub']} JMass), " \
            if substructure.point_mass else ""
        out.append(f"substructure and platform ({'; '.join(parts)}): the monopile bends with the tower, clamped at "
                   f"{substructure.height[0]:g} m; {lumped}the water around and in it, waves, currents and soil are "
                   "not modelled")
    if ed["TeetDOF"] or ed["TeetMod"]:
        out.append(f"teeter ({ed_file} TeetDOF = {ed['TeetDOF']}, TeetMod = {ed['TeetMod']})")
    masses = [key for key in ("TipMass(1)", "PBrIner(1)", "BlPIner(1)", "NacCMyn", "HubCM", "UndSling", "Delta3")
              if ed[key]]
    if masses:
        out.append(f"{ed_file} " + ", ".join(f"{key} = {ed[key]:g}" for key in masses))
    bend = max(np.max(np.abs(ad_blade["BlCrvAC"])), np.max(np.abs(ad_blade["BlSwpAC"])))
    if bend:
        out.append(f"blade prebend and sweep ({files['ad_blade']} BlCrvAC, BlSwpAC: up to {bend:.3g} m)")
    if ad["NacelleDrag"]:
        out.append(f"nacelle drag ({ad_file} NacelleDrag = True)")
    if sd["HSSBrMode"]:
        out.append(f"the high-speed shaft brake ({files['sd']} HSSBrMode = {sd['HSSBrMode']})")
    dampers = [key for key in ("NumBStC", "NumNStC", "NumTStC", "NumSStC") if sd.get(key)]
    if dampers:
        out.append(f"structural control ({files['sd']} " + ", ".join(f"{key} = {sd[key]}" for key in dampers) + ")")
    return out


def _yaml_number(value: float) -> str:
    """A float YAML reads back as a float (PyYAML wants a dot in the mantissa: ``1.0e+10``, not ``1e+10``)."""
    text = f"{value:.10g}"
    mantissa, e, exponent = text.partition("e")
    if e and "." not in mantissa:
        text = f"{mantissa}.0e{exponent}"
    return text


def _yaml_value(value: Any) -> str:
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, (bool, int, np.integer)):
        return str(value).lower() if isinstance(value, bool) else str(int(value))
    if isinstance(value, (np.ndarray, list, tuple)):
        return "[" + ", ".join(_yaml_value(item) for item in value) + "]"
    return _yaml_number(float(value))


def _section_lines(section: Mapping[str, Any], indent: str) -> List[str]:
    lines = []
    for key, item in section.items():
        if isinstance(item, Sourced) and item.in_file:
            lines.append(f"{indent}{key}: {{value: {_yaml_value(item.value)}, source: {_yaml_value(item.source)}}}")
        elif isinstance(item, Sourced):
            lines.append(f"{indent}{key}: {_yaml_value(item.value)}  # {item.source}")
        else:
            lines.append(f"{indent}{key}:")
            lines.extend(_section_lines(item, indent + "  "))
    return lines


def turbine_text(turbine: ImportedTurbine) -> str:
    """The ``turbine.yaml`` of an imported deck: every value followed by its source file and key."""
    version = importlib.metadata.version("openfast-io")
    header = [
        f"# {turbine.definition['name'].value}: imported by hawt turbine import from the OpenFAST deck",
        f"# {turbine.deck.resolve()} (openfast-io {version}), in the hawt turbine-definition format.",
        "# SI units throughout: m, kg, s, rad. Each value names its source file (relative to the deck) and key;",
        "# angles given in degrees there are converted with pi/180, percentages divided by 100.",
        "# Sign conventions of this format (they differ from ElastoDyn's):",
        "#   cone_angle > 0 tilts the blades upwind (away from the tower),",
        "#   shaft_tilt > 0 raises the upwind end of the shaft (the rotor apex),",
        "#   overhang > 0 puts the rotor apex upwind of the tower centreline;",
        "#   with position: downwind the three point away from the tower, downwind.",
    ]
    notes = [f"#   - {line}" for line in turbine.approximations]
    missing = [f"#   - {line}" for line in turbine.not_modelled]
    return "\n".join(header + _section_lines(turbine.definition, "")
                     + (["# Approximations:"] + notes if notes else [])
                     + ["# Not modelled by the plant:"] + missing) + "\n"


def _airfoil_text(airfoil: ImportedAirfoil, deck: str) -> str:
    rows = "\n".join("  - [" + ", ".join(_yaml_number(float(v)) for v in row) + "]" for row in airfoil.table)
    unsteady = ""
    if airfoil.unsteady:
        p = airfoil.unsteady
        unsteady = ("# Unsteady aerodynamics (hawt_plant.unsteady_airfoil), from the table's UA coefficients.\n"
                    f"unsteady:\n  alpha0: {_yaml_number(p.alpha0)}  # alpha0 = {math.degrees(p.alpha0):g} deg\n"
                    f"  lift_slope: {_yaml_number(p.lift_slope)}  # C_nalpha [1/rad]\n"
                    f"  cd0: {_yaml_number(p.cd0)}  # Cd0\n"
                    + "".join(f"  {name}: {_yaml_number(getattr(p, name))}  # {key}"
                              + (" (\"Default\": AeroDyn's)" if name in airfoil.defaulted else "") + "\n"
                              for key, name in _UA_LAGS))
    return (f"# Airfoil polar {airfoil.name}, imported by hawt turbine import from the OpenFAST deck {deck}.\n"
            f"# Source: {airfoil.source} (relative to the deck), its first table: {airfoil.description}\n"
            "# Columns: angle of attack [rad] (source deg x pi/180), lift, drag and pitching-moment\n"
            "# coefficients [-] (verbatim). One row per source row, in the source's order.\n"
            f"name: {json.dumps(airfoil.name)}\nsource: {json.dumps(airfoil.source)}\n{unsteady}"
            f"columns: [alpha, cl, cd, cm]\ntable:\n{rows}\n")


def _refusal(turbine: ImportedTurbine, error: TurbineDefinitionError) -> DeckError:
    """The loader's refusal of the imported definition (``FILE: KEY.PATH: problem``) as the deck's: its file and
    key (the value's source), the problem, and the definition's key."""
    file, _, rest = str(error).partition(": ")
    path, _, problem = rest.partition(": ")
    if file == "turbine.yaml":
        item: Any = turbine.definition
        for key in path.split("."):
            item = item.get(key) if isinstance(item, dict) else None
        if isinstance(item, Sourced):
            return DeckError(f"{item.source}: {problem} ({path} of the turbine definition)")
    source = next((airfoil.source for airfoil in turbine.airfoils if f"{airfoil.name}.yaml" == file), turbine.deck.name)
    return DeckError(f"{source}: {problem} ({path} of the imported {file})")


def write_turbine(turbine: ImportedTurbine, directory: str | os.PathLike) -> Path:
    """Check the definition and write ``directory/turbine.yaml`` and ``directory/airfoils/<name>.yaml`` (replacing
    files of those names).

    The files are written into a temporary folder and loaded from there (:func:`hawt_plant.turbine.load_turbine`:
    the definition's ranges and rules); only a definition that loads is copied into ``directory``, which is made
    then.

    Returns
    -------
    Path
        The ``turbine.yaml`` written.

    Raises
    ------
    DeckError
        The definition is refused: one line naming the deck's file and key of the value and the allowed range;
        ``directory`` is left as it was.
    """
    with tempfile.TemporaryDirectory(prefix="hawt-turbine-import-") as staging:
        staged = Path(staging)
        (staged / "airfoils").mkdir()
        for airfoil in turbine.airfoils:
            (staged / "airfoils" / f"{airfoil.name}.yaml").write_text(_airfoil_text(airfoil, turbine.deck.name))
        (staged / "turbine.yaml").write_text(turbine_text(turbine))
        try:
            load_turbine(staged / "turbine.yaml")
        except TurbineDefinitionError as error:
            raise _refusal(turbine, error) from None
        shutil.copytree(staged, directory, dirs_exist_ok=True)
    return Path(directory) / "turbine.yaml"
