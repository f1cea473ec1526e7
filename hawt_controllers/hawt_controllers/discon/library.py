"""A Bladed-style DISCON controller library called through ctypes: the swap array in, the demands out.

Wind-turbine controllers ship as shared libraries with one entry point (the "external controller"
interface of Bladed, kept by OpenFAST's ServoDyn and by NREL's ROSCO)::

    void DISCON(float *avrSWAP, int *aviFAIL, char *accINFILE, char *avcOUTNAME, char *avcMSG);

``avrSWAP`` is one float32 array both ways; its records are numbered from 1. The simulator fills the
measurements and calls once per communication interval; the library writes its demands into the same
array. ``aviFAIL`` is 0 on success, > 0 with a warning in ``avcMSG``, < 0 on failure (the run must stop).
:data:`RECORDS` lists every record this module reads or writes. Sources: the Bladed User Manual,
Appendix A ("DLL interface", record numbers as filled by OpenFAST ``modules/servodyn/src/
BladedInterface.f90``, ``Fill_avrSWAP``/``Retrieve_avrSWAP``), and what ROSCO 2.10 reads
(``rosco/controller/src/ReadSetParameters.f90``, ``ReadAvrSWAP``) and writes (``Controllers.f90``,
``PitchControl`` and ``VariableSpeedControl``; ``DISCON.F90``). The blade records exist for blades
1-3 only: the interface is three-bladed at most.

:func:`check_library` is what a library file must pass before anything starts (the controller's
``check_values``, run by every engine's parameter check): a regular file, an ELF shared object
(``ET_DYN``) of this process's class, byte order and architecture (the first 20 bytes of its ELF header,
read with :mod:`struct`, against those of ``/proc/self/exe``), that the dynamic loader loads with its
dependencies, and that exports ``DISCON``. The symbol is looked up by loading the library (uncalled,
once per process: the load every instance needs anyway) rather than by reading its symbol table: the
load also finds a missing dependency, and no ELF reader is among hawt's dependencies. Loading runs the
library's constructors; ROSCO's are the compiler's (``frame_dummy``) and its Fortran runtime's set-up,
which write nothing.

Each :class:`DisconLibrary` loads its **own copy** of the library file (a private temporary file),
because a library keeps its state in static memory: ROSCO refuses a second first call in one loaded
image ("This ROSCO dynamic library has already been loaded"), and two turbines or two tunings in one
process must not share a state. The copy's own dependencies (ROSCO's bundled Fortran runtime, found
through the original's ``$ORIGIN`` run path) are loaded once from the original file, without calling
it, so the copy finds them by name. The copy's file is removed when the instance is closed or
collected; its image stays mapped until the process ends (closing a loaded Fortran library is not safe).

Units are those of the interface, which are hawt's (SI: rad, rad/s, N*m, W, m/s); generator speed and
torque on the high-speed shaft; azimuth of blade 1, zero with blade 1 up, increasing with rotation
(the OpenFAST rotor azimuth ``LSSTipPxa`` and hawt's convention alike).
"""
from __future__ import annotations

import ctypes
import enum
import functools
import platform
import shutil
import struct
import tempfile
import weakref
from dataclasses import dataclass
from pathlib import Path
from typing import Optional, Sequence, Tuple

import numpy as np

__all__ = ["Record", "RECORDS", "DisconInputs", "DisconDemands", "DisconLibrary", "DisconLoadError",
           "DisconFailure", "SWAP_LENGTH", "MESSAGE_LENGTH", "MAX_BLADES", "check_library"]

SWAP_LENGTH = 2048
"""Records in the swap array: beyond ROSCO's extended interface (records 1001-1018, platform motion)."""
MESSAGE_LENGTH = 1024
"""Characters in ``avcMSG``, the terminating NUL included (record 49)."""
MAX_BLADES = 3
"""The interface carries pitch and root moments of blades 1-3."""


class Record(enum.IntEnum):
    """Swap-array record numbers (1-based) this module uses: ``in`` to the library, ``out`` from it."""

    STATUS = 1                 # in: 0 first call, 1 running, -1 last call [-]
    TIME = 2                   # in: simulation time [s]
    DT = 3                     # in: communication interval [s]
    PITCH_1 = 4                # in: measured pitch, blade 1 [rad]
    MIN_PITCH = 6              # in: minimum pitch angle [rad]
    MAX_PITCH = 7              # in: maximum pitch angle [rad]
    MIN_PITCH_RATE = 8         # in: minimum (most negative) pitch rate [rad/s]
    MAX_PITCH_RATE = 9         # in: maximum pitch rate [rad/s]
    PITCH_ACTUATOR = 10        # in: 0 = pitch position actuator [-]
    SHAFT_POWER = 14           # in: measured shaft power [W]
    ELECTRICAL_POWER = 15      # in: measured electrical power [W]
    GENERATOR_SPEED = 20       # in: measured generator speed, HSS [rad/s]
    ROTOR_SPEED = 21           # in: measured rotor speed [rad/s]
    GENERATOR_TORQUE = 23      # in: measured generator torque, HSS [N*m]
    HUB_WIND_SPEED = 27        # in: hub-height wind speed [m/s]
    PITCH_CONTROL = 28         # in: 0 = collective, 1 = individual pitch [-]
    ROOT_MOOP_1 = 30           # in: blade-root out-of-plane moment, blades 1-3 at 30-32 [N*m]
    PITCH_2 = 33               # in: measured pitch, blade 2 [rad]
    PITCH_3 = 34               # in: measured pitch, blade 3 [rad]
    GENERATOR_CONTACTOR = 35   # in: 1 = main generator on [-]
    DEMANDED_PITCH_1 = 42      # out: pitch demand, blades 1-3 at 42-44 [rad]
    DEMANDED_COLLECTIVE = 45   # out: collective pitch demand [rad]
    DEMANDED_TORQUE = 47       # out: generator torque demand, HSS [N*m]
    MESSAGE_SIZE = 49          # in: characters of avcMSG with its NUL [-]
    INFILE_SIZE = 50           # in: characters of accINFILE with its NUL [-]
    OUTNAME_SIZE = 51          # in: characters of avcOUTNAME with its NUL [-]
    TOWER_TOP_FA_ACCEL = 53    # in: tower-top fore-aft acceleration [m/s^2]
    TOWER_TOP_SS_ACCEL = 54    # in: tower-top side-side acceleration [m/s^2]
    PITCH_OVERRIDE = 55        # out: 0 = the library commands pitch, else the simulator keeps its own [-]
    TORQUE_OVERRIDE = 56       # out: 0 = the library commands torque [-]
    AZIMUTH = 60               # in: azimuth of blade 1, 0 = up, increasing with rotation [rad]
    BLADES = 61                # in: number of blades [-]
    ROOT_MIP_1 = 69            # in: blade-root in-plane moment, blades 1-3 at 69-71 [N*m]
    HUB_TILT_MOMENT = 75       # in: fixed-frame hub My (tilt) [N*m]
    HUB_YAW_MOMENT = 76        # in: fixed-frame hub Mz (yaw) [N*m]
    SWAP_SIZE = 129            # in: records in the swap array [-]


RECORDS = tuple(Record)
"""The one table of records used (name, number); see :class:`Record` for meaning and units."""

_PITCH = (Record.PITCH_1, Record.PITCH_2, Record.PITCH_3)


class DisconLoadError(ValueError):
    """A library that cannot be loaded or an input file that cannot be read (one line, naming the file)."""


class DisconFailure(RuntimeError):
    """The library reported failure (``aviFAIL`` < 0) with its message: the run cannot go on with it."""


@dataclass(frozen=True)
class DisconInputs:
    """The measurements of one call, SI (see :class:`Record` for where each goes)."""

    time: float
    pitch: Sequence[float]
    generator_speed: float
    rotor_speed: float
    generator_torque: float
    electrical_power: float
    shaft_power: float
    hub_wind_speed: float
    root_moment_oop: Sequence[float]
    root_moment_ip: Sequence[float]
    azimuth: float
    tower_top_fa_accel: float = 0.0
    tower_top_ss_accel: float = 0.0
    hub_tilt_moment: float = 0.0
    hub_yaw_moment: float = 0.0


@dataclass(frozen=True)
class DisconDemands:
    """What the library commanded in one call.

    Attributes
    ----------
    pitch : tuple of float
        Pitch demand per blade [rad] (records 42-44; all equal to record 45 unless individual pitch).
    collective : float
        Collective pitch demand [rad] (record 45).
    generator_torque : float
        Generator torque demand, HSS [N*m] (record 47).
    pitch_override, torque_override : int
        0 when the library commands pitch / torque (records 55, 56).
    warning : str
        The library's message when it succeeded with a warning (``aviFAIL`` > 0), else "".
    """

    pitch: Tuple[float, ...]
    collective: float
    generator_torque: float
    pitch_override: int
    torque_override: int
    warning: str = ""


_ELF_TYPES = {1: "a relocatable object", 2: "an executable", 4: "a core dump"}
"""ELF ``e_type`` values other than ET_DYN (3, a shared object), as they are named in a refusal."""


def _elf_header(path: Path) -> Optional[Tuple[int, int, int, int]]:
    """``(class, data, type, machine)`` of an ELF file (EI_CLASS, EI_DATA, e_type, e_machine); None without one."""
    with open(path, "rb") as file:
        header = file.read(20)
    if len(header) < 20 or header[:4] != b"\x7fELF" or header[5] not in (1, 2):
        return None
    e_type, machine = struct.unpack("<HH" if header[5] == 1 else ">HH", header[16:20])
    return header[4], header[5], e_type, machine


@functools.lru_cache(maxsize=None)
def _this_machine() -> Tuple[int, int, int]:
    """``(class, data, machine)`` of this process's own executable: what a library loaded into it must have."""
    elf_class, data, _, machine = _elf_header(Path("/proc/self/exe"))
    return elf_class, data, machine


def _machine_text(elf_class: int, data: int, machine: int) -> str:
    return f"{32 * elf_class}-bit {('little', 'big')[data - 1]}-endian, ELF machine {machine}"


@functools.lru_cache(maxsize=None)
def _load_dependencies(library: Path) -> ctypes.CDLL:
    """Load the original library once, uncalled, so that its dependencies are in the process for every copy."""
    return ctypes.CDLL(str(library), mode=ctypes.RTLD_LOCAL)


def check_library(library: Path) -> None:
    """Refuse a file that cannot be a DISCON library of this process (module notes); it stays loaded, uncalled.

    Raises
    ------
    DisconLoadError
        One line naming the file and what is wrong: missing, not a regular file, unreadable, no ELF header,
        another ELF type than a shared object, another machine's, not loadable (e.g. a missing dependency),
        no ``DISCON`` symbol.
    """
    library = Path(library)
    if not library.exists():
        raise DisconLoadError(f"{library}: no such library file")
    if not library.is_file():
        raise DisconLoadError(f"{library} is not a regular file")
    try:
        header = _elf_header(library)
    except OSError as error:
        raise DisconLoadError(f"{library}: cannot read: {error.strerror}") from None
    if header is None:
        raise DisconLoadError(f"{library} is not a shared library (no ELF header)")
    elf_class, data, e_type, machine = header
    if e_type != 3:
        raise DisconLoadError(f"{library} is not a shared library (ELF type {e_type}: "
                              f"{_ELF_TYPES.get(e_type, 'unknown')}, not a shared object)")
    if (elf_class, data, machine) != _this_machine():
        raise DisconLoadError(f"{library} is built for another machine ({_machine_text(elf_class, data, machine)}; "
                              f"this {platform.machine()} machine is {_machine_text(*_this_machine())})")
    try:
        loaded = _load_dependencies(library.resolve())
    except OSError as error:
        raise DisconLoadError(f"{library}: cannot load: {error}") from None
    if not hasattr(loaded, "DISCON"):
        raise DisconLoadError(f"{library} has no DISCON symbol")


def _c_string(text: str) -> ctypes.Array:
    return ctypes.create_string_buffer(text.encode())


class _Image:
    """One private loaded copy of a library and the buffers of its calls (what the finaliser needs)."""

    def __init__(self, library: Path, infile: Path, outname: str) -> None:
        self.directory = Path(tempfile.mkdtemp(prefix="hawt-discon-"))
        try:
            copy = self.directory / library.name
            shutil.copyfile(library, copy)
            handle = ctypes.CDLL(str(copy), mode=ctypes.RTLD_LOCAL)
            copy.unlink()
            self.function = handle.DISCON  # the original passed check_library
        except OSError as error:
            self.remove()
            raise DisconLoadError(f"{library}: cannot load: {error}") from None
        self.function.restype = None
        self.function.argtypes = (ctypes.POINTER(ctypes.c_float), ctypes.POINTER(ctypes.c_int), ctypes.c_char_p,
                                  ctypes.c_char_p, ctypes.c_char_p)
        self.swap = np.zeros(SWAP_LENGTH, dtype=np.float32)
        self.fail = ctypes.c_int(0)
        self.infile = _c_string(str(infile))
        self.outname = _c_string(outname)
        self.message = ctypes.create_string_buffer(MESSAGE_LENGTH)
        self.running = False

    def call(self, status: int) -> Tuple[int, str]:
        """Call DISCON with ``status`` in record 1; the fail flag and the message."""
        self.swap[Record.STATUS - 1] = status
        self.fail.value = 0
        self.message.value = b""
        self.function(self.swap.ctypes.data_as(ctypes.POINTER(ctypes.c_float)), ctypes.byref(self.fail),
                      self.infile, self.outname, self.message)
        return self.fail.value, self.message.value.decode(errors="replace").strip()

    def close(self) -> None:
        """The last call (status -1) if the library is running, then remove the private folder."""
        if self.running:
            self.running = False
            self.call(-1)
        self.remove()

    def remove(self) -> None:
        shutil.rmtree(self.directory, ignore_errors=True)


class DisconLibrary:
    """One running instance of a DISCON library: its own loaded copy, status sequence and swap array.

    Parameters
    ----------
    library : Path
        The shared library (``.so``) exporting ``DISCON``.
    infile : Path
        The library's input file, passed as ``accINFILE``.
    blades : int
        Number of blades B (1-3: the interface's blade records).
    dt : float
        Communication interval [s] (record 3).
    pitch_limits : (float, float, float)
        Minimum and maximum pitch angle [rad] and maximum pitch rate [rad/s] of the actuator (records 6-9).
    individual_pitch : bool
        Record 28: tell the library the turbine pitches each blade on its own (read records 42-44).
    outname : str
        ``avcOUTNAME``, the root name of any file the library writes (default: in the private folder).

    Raises
    ------
    DisconLoadError
        A library that fails :func:`check_library`, an unreadable input file, B > 3.

    Notes
    -----
    :meth:`step` makes the first call with status 0 and every later one with status 1; :meth:`close`
    makes the last call with status -1 (also when the instance is collected). After a failure
    (:class:`DisconFailure`) the instance makes no more calls.
    """

    def __init__(self, library: Path, infile: Path, blades: int, dt: float,
                 pitch_limits: Tuple[float, float, float], individual_pitch: bool = False,
                 outname: Optional[str] = None) -> None:
        library, infile = Path(library), Path(infile)
        check_library(library)
        try:
            infile.open("rb").close()
        except OSError as error:
            raise DisconLoadError(f"{infile}: cannot read the input file: {error.strerror}") from None
        if not 1 <= blades <= MAX_BLADES:
            raise DisconLoadError(f"blades: the DISCON interface carries 1 to {MAX_BLADES} blades, found {blades}")
        self.library = library
        self.blades = blades
        self.individual_pitch = individual_pitch
        self._image = _Image(library, infile, outname or "")
        if outname is None:
            self._image.outname = _c_string(str(self._image.directory / "discon"))
        self._finalizer = weakref.finalize(self, self._image.close)
        self.calls = 0
        self.failed: Optional[str] = None
        swap = self._image.swap
        minimum, maximum, rate = pitch_limits
        for record, value in ((Record.DT, dt), (Record.MIN_PITCH, minimum), (Record.MAX_PITCH, maximum),
                              (Record.MIN_PITCH_RATE, -rate), (Record.MAX_PITCH_RATE, rate),
                              (Record.PITCH_ACTUATOR, 0), (Record.PITCH_CONTROL, int(individual_pitch)),
                              (Record.GENERATOR_CONTACTOR, 1), (Record.BLADES, blades),
                              (Record.MESSAGE_SIZE, MESSAGE_LENGTH), (Record.INFILE_SIZE, len(self._image.infile)),
                              (Record.OUTNAME_SIZE, len(self._image.outname)), (Record.SWAP_SIZE, SWAP_LENGTH)):
            swap[record - 1] = value

    @property
    def swap(self) -> np.ndarray:
        """The swap array (float32, record r at index r - 1): what the library was given and returned last."""
        return self._image.swap

    def step(self, inputs: DisconInputs) -> DisconDemands:
        """One call with ``inputs`` (status 0 the first time, then 1); the library's demands.

        Raises
        ------
        DisconFailure
            ``aviFAIL`` < 0, with the library's message; or a call after a failure or after :meth:`close`.
        """
        if self.failed is not None:
            raise DisconFailure(f"{self.library.name}: stopped after its failure: {self.failed}")
        if not self._finalizer.alive:
            raise DisconFailure(f"{self.library.name}: called after its last call")
        self._fill(inputs)
        fail, message = self._image.call(0 if self.calls == 0 else 1)
        self.calls += 1
        self._image.running = True
        if fail < 0:
            self.failed = message or f"aviFAIL = {fail} without a message"
            self._image.running = False
            raise DisconFailure(f"{self.library.name} failed at t = {inputs.time:g} s: {self.failed}")
        swap = self._image.swap
        b = self.blades
        return DisconDemands(tuple(float(v) for v in swap[Record.DEMANDED_PITCH_1 - 1:Record.DEMANDED_PITCH_1 - 1 + b]),
                             float(swap[Record.DEMANDED_COLLECTIVE - 1]), float(swap[Record.DEMANDED_TORQUE - 1]),
                             int(round(float(swap[Record.PITCH_OVERRIDE - 1]))),
                             int(round(float(swap[Record.TORQUE_OVERRIDE - 1]))), message if fail > 0 else "")

    def close(self) -> None:
        """The last call (status -1, with the last inputs) if the library ran; remove the private copy."""
        self._finalizer()

    def _fill(self, inputs: DisconInputs) -> None:
        swap, b = self._image.swap, self.blades
        for record, value in ((Record.TIME, inputs.time), (Record.GENERATOR_SPEED, inputs.generator_speed),
                              (Record.ROTOR_SPEED, inputs.rotor_speed),
                              (Record.GENERATOR_TORQUE, inputs.generator_torque),
                              (Record.ELECTRICAL_POWER, inputs.electrical_power),
                              (Record.SHAFT_POWER, inputs.shaft_power), (Record.HUB_WIND_SPEED, inputs.hub_wind_speed),
                              (Record.AZIMUTH, inputs.azimuth), (Record.TOWER_TOP_FA_ACCEL, inputs.tower_top_fa_accel),
                              (Record.TOWER_TOP_SS_ACCEL, inputs.tower_top_ss_accel),
                              (Record.HUB_TILT_MOMENT, inputs.hub_tilt_moment),
                              (Record.HUB_YAW_MOMENT, inputs.hub_yaw_moment)):
            swap[record - 1] = value
        pitch, oop, mip = (np.asarray(a, dtype=float) for a in (inputs.pitch, inputs.root_moment_oop,
                                                                  inputs.root_moment_ip))
        for name, values in (("pitch", pitch), ("root_moment_oop", oop), ("root_moment_ip", mip)):
            if values.shape != (b,):
                raise ValueError(f"{name}: expected length B={b}, found {values.size}")
        for i in range(b):
            swap[_PITCH[i] - 1] = pitch[i]
            swap[Record.ROOT_MOOP_1 - 1 + i] = oop[i]
            swap[Record.ROOT_MIP_1 - 1 + i] = mip[i]
