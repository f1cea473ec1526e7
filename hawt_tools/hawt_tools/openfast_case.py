"""OpenFAST inputs for one case written from a turbine's own deck, and OpenFAST run with progress (``hawt validate``).

A turbine's deck is the OpenFAST input it was made from: for the packaged NREL 5 MW the rosco wheel's
``Examples/Test_Cases/NREL-5MW/NREL-5MW.fst`` (the deck the packaged definition was checked against), for a
turbine that ``hawt turbine import`` wrote the copy it keeps in ``DIR/openfast/`` (:func:`keep_deck`). The deck
is read and written with NREL's openfast-io (``InputReader_OpenFAST``, ``InputWriter_OpenFAST``); a case changes
only what :class:`CaseInputs` names — TMax, the inflow, the initial conditions, the controller library and its
input, the output channels — and the module switches that the plant cannot follow (:data:`FIXED_BOTTOM`), each
listed by :func:`write_case` so a report can say so.

OpenFAST itself is the user's: :func:`openfast_executable` takes ``--openfast PATH`` or ``$HAWT_OPENFAST``.
"""
from __future__ import annotations

import importlib.metadata
import math
import os
import re
import shutil
import subprocess
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, List, Optional, Tuple

from openfast_io.FAST_reader import InputReader_OpenFAST
from openfast_io.FAST_writer import InputWriter_OpenFAST

__all__ = ["CaseInputs", "DeckNotFound", "FIXED_BOTTOM", "OpenFastFailed", "PLANT_UA_MODEL", "WrittenCase", "deck_hub_height",
           "deck_of", "keep_deck", "openfast_executable", "output_of", "read_deck", "run_openfast", "write_case"]

OPENFAST_ENVIRONMENT = "HAWT_OPENFAST"
"""The environment variable that names an OpenFAST executable when ``--openfast`` is not given."""

DECK_FOLDER = "openfast"
"""Where ``hawt turbine import`` keeps a copy of the deck, inside the turbine's folder."""

FIXED_BOTTOM = {("Fst", "CompHydro"): 0, ("Fst", "CompSub"): 0, ("Fst", "CompMooring"): 0, ("Fst", "CompSeaSt"): 0,
                ("Fst", "CompIce"): 0, ("Fst", "CompSoil"): 0, ("ElastoDyn", "YawDOF"): False,
                **{("ElastoDyn", f"Ptfm{dof}DOF"): False for dof in ("Sg", "Sw", "Hv", "R", "P", "Y")}}
"""Switches a case sets whatever the deck says: the plant stands on a rigid base (no substructure, waves,
mooring, ice or soil, and no platform motion: without them a platform DOF would be free) and has no yaw degree of
freedom."""

PLANT_UA_MODEL = 4
"""AeroDyn's UA_Mod of the plant's unsteady airfoil model (Hansen-Gaunaa-Madsen, :mod:`hawt_plant.unsteady_airfoil`).
A deck with another model on runs this one: the Beddoes-Leishman models 2 and 3 with the UA parameters of many
decks shift the mean lift itself in steady flow (OpenFAST r-test issue 20; the NREL 5 MW's DU21 at 3.8 deg: c_l
0.87 against the polar's 0.97), which is the deck's inconsistency, not the aerodynamics both sides model."""


class DeckNotFound(ValueError):
    """A turbine without an OpenFAST deck, or a deck openfast-io cannot read; the message says which and why."""


class OpenFastFailed(RuntimeError):
    """OpenFAST ended with an error; the message names the case folder and gives OpenFAST's last lines."""


def openfast_executable(given: Optional[str]) -> Path:
    """The OpenFAST executable: ``given`` (``--openfast``), else ``$HAWT_OPENFAST``.

    Raises
    ------
    ValueError
        One line: none given, no such file, or not executable.
    """
    path = given or os.environ.get(OPENFAST_ENVIRONMENT)
    if not path:
        raise ValueError(f"no OpenFAST executable: give --openfast PATH or set ${OPENFAST_ENVIRONMENT}")
    source = "--openfast" if given else f"${OPENFAST_ENVIRONMENT}"
    resolved = Path(shutil.which(path) or path)
    if not resolved.is_file():
        raise ValueError(f"{source} {path}: no such file")
    if not os.access(resolved, os.X_OK):
        raise ValueError(f"{source} {path}: not executable")
    return resolved.resolve()


def deck_of(turbine: str) -> Path:
    """The ``.fst`` file of ``turbine`` (a packaged name, or the folder or ``turbine.yaml`` of an imported one).

    Raises
    ------
    DeckNotFound
        A packaged turbine other than ``nrel_5mw`` (no deck), or an imported turbine without its copy of the deck.
    """
    from hawt_controllers.design.tunings import turbine_folder

    folder = turbine_folder(turbine)
    if folder is None:
        if turbine != "nrel_5mw":
            raise DeckNotFound(f"turbine {turbine}: no OpenFAST deck (the packaged nrel_5mw has the rosco wheel's; "
                               "an imported turbine has a copy of its own)")
        return Path(importlib.metadata.distribution("rosco").locate_file("Examples/Test_Cases/NREL-5MW/NREL-5MW.fst"))
    decks = sorted((folder / DECK_FOLDER).glob("*.fst"))
    if len(decks) != 1:
        raise DeckNotFound(f"turbine {folder}: {'no' if not decks else len(decks)} OpenFAST deck(s) in "
                           f"{folder / DECK_FOLDER} (hawt turbine import DECK.fst -o {folder} keeps one there)")
    return decks[0]


def read_deck(deck: Path) -> Tuple[dict, Tuple[str, ...]]:
    """openfast-io's ``fst_vt`` of the deck (every module's inputs) on a rigid base, and the switches set to get
    there (:data:`FIXED_BOTTOM`): the main input's before the modules are read, so that those of the substructure,
    waves and mooring are not (no case runs them, and openfast-io may not read their versions either), then
    ElastoDyn's. DeckNotFound naming the deck if unreadable.
    """
    deck = Path(deck)
    if not deck.is_file():
        raise DeckNotFound(f"{deck}: no such OpenFAST deck")
    reader = InputReader_OpenFAST()
    reader.FAST_InputFile, reader.FAST_directory = deck.name, str(deck.parent.resolve())
    switched: List[str] = []
    read_main = reader.read_MainInput

    def main_input_on_a_rigid_base() -> None:
        read_main()
        for (module, key), value in FIXED_BOTTOM.items():
            if module == "Fst" and reader.fst_vt["Fst"].get(key, value) != value:
                switched.append(f"Fst {key} = {value} (was {reader.fst_vt['Fst'][key]})")
                reader.fst_vt["Fst"][key] = value

    reader.read_MainInput = main_input_on_a_rigid_base
    try:
        reader.execute()
    except Exception as error:  # openfast-io raises what its parsers meet: ValueError, IndexError, KeyError, ...
        raise DeckNotFound(f"{deck}: openfast-io cannot read it ({type(error).__name__}: {error})") from None
    for (module, key), value in FIXED_BOTTOM.items():
        if module != "Fst" and reader.fst_vt[module].get(key) != value:
            switched.append(f"{module} {key} = {value}")
            reader.fst_vt[module][key] = value
    return reader.fst_vt, tuple(switched)


def _write(fst_vt: dict, folder: Path, name: str) -> Path:
    writer = InputWriter_OpenFAST()
    writer.fst_vt, writer.FAST_runDirectory, writer.FAST_namingOut = fst_vt, str(folder), name
    writer.execute()
    return folder / f"{name}.fst"


def keep_deck(deck: Path, turbine_folder: Path) -> Path:
    """Keep what ``hawt validate`` and the turbine's ``rosco`` graph need of ``deck`` in ``turbine_folder``: the deck
    on a rigid base (:func:`read_deck`) in ``openfast/``, every module written by openfast-io's writer so its paths
    point inside the copy, and the ROSCO input ServoDyn names as ``DISCON.IN`` with its Cp/Ct/Cq file beside it (the
    turbine's ``discon`` tuning, :mod:`hawt_controllers.design.tunings`), which the copy's ServoDyn names. The folder can
    move. Returns the copy's ``.fst``.

    Raises
    ------
    DeckNotFound
        The deck, or a file its ROSCO input names, cannot be read.
    """
    from hawt_controllers.discon.rosco_input import copy_input
    from hawt_controllers.design.tunings import FILE_NAMES

    fst_vt, _ = read_deck(deck)
    turbine_folder = Path(turbine_folder)
    folder = turbine_folder / DECK_FOLDER
    servo = fst_vt["ServoDyn"]
    discon = Path(servo["DLL_InFile"])
    if not discon.is_absolute():
        discon = Path(deck).parent / Path(fst_vt["Fst"]["ServoFile"]).parent / discon
    try:
        turbine_folder.mkdir(parents=True, exist_ok=True)
        copy_input(discon, turbine_folder / FILE_NAMES["discon"])
    except (OSError, FileNotFoundError) as error:
        raise DeckNotFound(f"{deck}: ServoDyn DLL_InFile: {error}") from None
    servo["DLL_InFile"] = f"../{FILE_NAMES['discon']}"
    if folder.exists():
        shutil.rmtree(folder)
    folder.mkdir(parents=True)
    return _write(fst_vt, folder, Path(deck).stem)


@dataclass(frozen=True)
class CaseInputs:
    """What a case sets in the deck; everything else stays as the deck has it.

    Attributes
    ----------
    duration : float
        TMax [s].
    wind_speed, shear_exponent : float
        Steady power-law inflow at the hub (InflowWind WindType 1, reference height the hub's), unless ``bts_file``.
    bts_file : Path or None
        A TurbSim full field (InflowWind WindType 3).
    rotor_speed : float
        Initial rotor speed [rad/s].
    pitch : tuple of float
        Initial pitch of each blade [rad] (ElastoDyn BlPitch(i)).
    azimuth : float
        Initial azimuth of blade 1 [rad].
    tower_top : (float, float)
        Initial tower-top fore-aft and side-side displacements [m] (TTDspFA, TTDspSS).
    discon_library, discon_input : Path
        The controller (ServoDyn DLL_FileName) and its input (DLL_InFile).
    channels : tuple of str
        Output channels to add to the deck's OutList.
    """

    duration: float
    wind_speed: float
    shear_exponent: float
    rotor_speed: float
    pitch: Tuple[float, ...]
    azimuth: float
    tower_top: Tuple[float, float]
    discon_library: Path
    discon_input: Path
    channels: Tuple[str, ...]
    bts_file: Optional[Path] = None


@dataclass(frozen=True)
class WrittenCase:
    """A case's input written: its ``.fst``, the hub height it used, and what it changed against the deck."""

    fst: Path
    hub_height: float
    changed: Tuple[str, ...] = field(default=())


_OUTPUT_MODULES = ("ElastoDyn", "AeroDyn", "ServoDyn", "InflowWind")


def _hub_height(fst_vt: dict) -> float:
    """The hub's height above the ground as ElastoDyn places it: TowerHt + Twr2Shft + OverHang sin(ShftTilt)."""
    ed = fst_vt["ElastoDyn"]
    return float(ed["TowerHt"] + ed["Twr2Shft"] + ed["OverHang"] * math.sin(math.radians(ed["ShftTilt"])))


def deck_hub_height(deck: Path) -> float:
    """The hub height of ``deck`` [m] (:func:`_hub_height`), where its cases put the reference wind."""
    return _hub_height(read_deck(deck)[0])


def write_case(deck: Path, folder: Path, name: str, inputs: CaseInputs) -> WrittenCase:
    """Write the inputs of one case into ``folder`` from ``deck``.

    Raises
    ------
    DeckNotFound
        The deck cannot be read.
    ValueError
        A channel of ``inputs.channels`` that no module of the deck's OutList knows.
    """
    fst_vt, switched = read_deck(deck)
    changed: List[str] = list(switched)

    def put(module: str, key: str, value) -> None:
        if fst_vt[module].get(key) != value:
            changed.append(f"{module} {key} = {value:.6g}" if isinstance(value, float) else f"{module} {key} = {value}")
        fst_vt[module][key] = value

    unsteady = fst_vt["AeroDyn"].get("UA_Mod", 0)
    if unsteady and unsteady != PLANT_UA_MODEL:
        fst_vt["AeroDyn"]["UA_Mod"] = PLANT_UA_MODEL
        changed.append(f"AeroDyn UA_Mod = {PLANT_UA_MODEL} (was {unsteady}: the plant's unsteady airfoil model, "
                       "Hansen-Gaunaa-Madsen; the deck's shifts the mean lift in steady flow)")
    hub = _hub_height(fst_vt)
    put("Fst", "TMax", float(inputs.duration))
    put("Fst", "TStart", 0.0)
    if inputs.bts_file is not None:
        put("InflowWind", "WindType", 3)
        put("InflowWind", "FileName_BTS", str(Path(inputs.bts_file).resolve()))
    else:
        put("InflowWind", "WindType", 1)
        put("InflowWind", "HWindSpeed", float(inputs.wind_speed))
        put("InflowWind", "RefHt", hub)
        put("InflowWind", "PLExp", float(inputs.shear_exponent))
        put("InflowWind", "PropagationDir", 0.0)
        put("InflowWind", "VFlowAng", 0.0)
    put("InflowWind", "NWindVel", 1)
    put("InflowWind", "WindVxiList", ["0"])
    put("InflowWind", "WindVyiList", ["0"])
    put("InflowWind", "WindVziList", [f"{hub:.4f}"])
    put("ElastoDyn", "RotSpeed", inputs.rotor_speed * 30.0 / math.pi)
    for i, angle in enumerate(inputs.pitch, start=1):
        put("ElastoDyn", f"BlPitch{i}", math.degrees(angle))
    put("ElastoDyn", "Azimuth", math.degrees(inputs.azimuth) % 360.0)
    put("ElastoDyn", "TTDspFA", float(inputs.tower_top[0]))
    put("ElastoDyn", "TTDspSS", float(inputs.tower_top[1]))
    put("ServoDyn", "DLL_FileName", str(Path(inputs.discon_library).resolve()))
    put("ServoDyn", "DLL_InFile", str(Path(inputs.discon_input).resolve()))
    put("Fst", "OutFileFmt", 2)  # binary .outb
    for channel in inputs.channels:
        module = next((m for m in _OUTPUT_MODULES if channel in fst_vt["outlist"][m]), None)
        if module is None:
            raise ValueError(f"output channel {channel}: no module of {', '.join(_OUTPUT_MODULES)} has it")
        fst_vt["outlist"][module][channel] = True
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    return WrittenCase(_write(fst_vt, folder, name), hub, tuple(changed))


_PROGRESS = re.compile(rb"Time:\s*([0-9.Ee+-]+)\s+of\s+([0-9.Ee+-]+)\s+seconds")


def run_openfast(executable: Path, fst: Path, progress: Callable[[float, float], None] = lambda t, total: None,
                 log: Optional[Path] = None) -> float:
    """Run OpenFAST on ``fst`` in its folder; ``progress(t, TMax)`` at each time OpenFAST reports; its output goes
    to ``log`` (default: ``<fst>.log``). Returns the wall time [s].

    Raises
    ------
    OpenFastFailed
        A non-zero exit, or an exit without "OpenFAST terminated normally"; the message has OpenFAST's last lines.
    """
    fst = Path(fst)
    log = Path(log) if log is not None else fst.with_suffix(".log")
    start = time.monotonic()
    with open(log, "wb") as sink:
        # gfortran buffers a pipe; unbuffered, OpenFAST's "Time: t of T seconds" lines arrive as it writes them
        process = subprocess.Popen([str(executable), fst.name], cwd=fst.parent, stdout=subprocess.PIPE,
                                   stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                   env={**os.environ, "GFORTRAN_UNBUFFERED_PRECONNECTED": "y"})
        try:
            tail = b""
            while True:
                chunk = process.stdout.read1(65536)
                if not chunk:
                    break
                sink.write(chunk)
                tail = (tail + chunk)[-8192:]
                reports = _PROGRESS.findall(chunk)
                if reports:
                    progress(float(reports[-1][0]), float(reports[-1][1]))
            code = process.wait()
        except BaseException:
            process.kill()
            process.wait()
            raise
    text = tail.decode(errors="replace")
    if code != 0 or "terminated normally" not in text:
        last = [line.strip() for line in text.replace("\r", "\n").splitlines() if line.strip()][-6:]
        said = " | ".join(last) if last else (f"it printed nothing: is {executable} OpenFAST?" if code == 0
                                               else "it printed nothing")
        raise OpenFastFailed(f"OpenFAST failed on {fst} (exit {code}; its output: {log}): {said}")
    return time.monotonic() - start


def output_of(fst: Path) -> Path:
    """The binary output file OpenFAST writes for ``fst``."""
    return Path(fst).with_suffix(".outb")

