"""The DISCON bridge (issue 33): a hawt graph as the controller of any simulator that calls a DISCON library.

``libhawt_discon.so`` (``hawt_tools/discon_bridge/hawt_discon.c``, built by ``scripts/setup.sh``) is a Bladed-style
DISCON library. OpenFAST's ServoDyn (or Bladed, HAWC2, QBlade, hawt's own ``discon`` host) loads it and calls
``DISCON`` once per communication interval; each call sends the swap array's records 1-129 over a Unix domain
socket to the bridge, which steps the graph once and answers that step's commands: pitch per blade (records
42-44), collective pitch (45, the blades' mean) and generator torque (47).

The bridge is the graph's plant: a :class:`BridgeModel` in place of hawt's turbine model, whose output of step k is
what the simulator measured at call k (:func:`measurements`) and whose ``step`` sends the command of step k back
and waits for call k + 1 (:func:`bridge_plant` builds it from the plant's parameters). On the simulator's first
call :func:`bridged_graph` checks the bridge file, the graph and the simulator for both engines the model runs on:

- **the ROS graph** (the default; hawt_tools.bridge_launch, hawt_tools.bridge_node): the graph launched as
  ``hawt launch`` launches it, its plant node replaced by the bridge plant node, a plant node with this model. It
  is the default because it is the graph as it runs everywhere else: live switches (``hawt switch``), parameter
  sets, ``hawt list`` and ``hawt view`` during the simulator's run, the recorder, the nodes that would run beside a
  real turbine. A call costs a lockstep round trip over DDS through the graph's nodes (``./hawt bench bridge``).
- **in process** (``--in-process``, :func:`serve`): the graph's cores stepped by the in-process runner
  (:func:`hawt_tools.in_process.build_run` with :func:`bridge_plant`), as ``hawt run`` runs them: the same commands
  to the bit, several times cheaper per call, without live switching; for speed.

**The bridge file** (``accINFILE``, ``key = value`` lines, ``#`` comments)::

    socket = /tmp/hawt-bridge.sock      # where the bridge listens (required; at most 107 characters)
    graph = ipc                         # a graph file (relative to this file's folder) or an installed graph's name
    arguments = wind_speed:=18          # the graph's launch arguments, NAME:=VALUE, space-separated
    parameters = ipc_h1.active:=false   # more NODE.PARAM:=VALUE, space-separated (as -p)
    timeout = 10                        # [s] the library's bound on waiting for an answer (default 10)
    start_timeout = 60                  # [s] and for the bridge to listen and answer the first call (default 60)
    record = run.mcap                   # record the graph's topics into this new bag (optional)

The library reads ``socket``, ``timeout`` and ``start_timeout``; the bridge reads the rest (and checks them
all). The plant's ``dt`` is the simulator's communication interval (record 3); the turbine is the graph's plant's
(its limits, gearbox and blades): the simulator's blade count (record 61) and, once the rotor turns faster than
0.1 rad/s at the first call, its generator-to-rotor speed ratio (records 20, 21) must be the turbine's (within 1 %).

**What the plant output has.** From the simulator: time (2), azimuth (60), rotor speed (21), generator speed (20)
and torque (23), electrical power (15), hub wind speed (27), measured pitch (4, 33, 34), blade-root out-of-plane
(30-32) and in-plane (69-71) moments, tower-top fore-aft and side-side acceleration (53, 54), hub tilt and yaw
moments (75, 76). Not in the interface, so NaN (:data:`MISSING_FIELDS`): aerodynamic torque and thrust, tower-top
displacements, tower-base and yaw-bearing moments, the blade-effective wind. A controller that reads one of them
gets NaN and refuses the step as on any plant (``update_or_hold``).

**The start.** The graph's controllers start from the first call's measurements, as on any plant. OpenFAST's
first call reports generator torque 0 (nothing was commanded yet), so the baseline graph's torque starts at 0 and
reaches rated at cpc's torque rate limit (15 kN*m/s) within 2.9 s; ROSCO sets its torque from its own law at once.

**No plant protection.** The simulator is the plant, and its safety system is the simulator's: the bridge does not
run hawt's plant protection (:class:`hawt_plant.safety_system.Protection`) on the simulator's measurements. Those
are another plant's signals: OpenFAST extrapolates ServoDyn's pitch demand into ElastoDyn quadratically
(``InterpOrder 2`` in the NREL 5 MW deck), so where the ipc graph's command turns at the pitch rate limit, the
measured pitch jumps by up to 0.15 deg in one 6.25 ms step (17-29 deg/s), and the protection, whose trip level is
8.8 deg/s, feathered the turbine 7.5 s into a turbulent run.

**The channel.** A Unix domain socket of type ``SOCK_SEQPACKET``: one message per call and per answer, message
boundaries kept (no framing code on either side), and a peer that dies is seen at once as a closed connection on
both sides, which shared memory with a semaphore would have to detect with a separate liveness check. Both ends
are on one machine, the messages are small (1.5 kB, 1.1 kB), and the cost of the round trip is measured by
``./hawt bench bridge``.

**Failure.** A bad bridge file, a graph that cannot be built (one line, :class:`BridgeError`) or a simulator
that does not match the graph's turbine is answered with ``fail < 0`` and that line, which the library puts in
``avcMSG`` with ``aviFAIL = -1``; the bridge then stops (``hawt bridge``: exit 2), on either engine before a graph
starts. The library's own safety (no answer within the timeout, a bridge that died) is in the C file's notes; the
bridge plant node's watchdog and its end when the simulator goes away are hawt_tools.bridge_node's.
"""
from __future__ import annotations

import os
import shlex
import socket
import struct
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, TypeVar

import numpy as np

from hawt_controllers.discon.library import Record
from hawt_core.node_role import NodeRole
from hawt_core.parameter_table import ParameterSpec
from hawt_plant.model import TurbineOutput
from hawt_plant.plant_setup import PARAMETERS as PLANT_PARAMETERS
from hawt_plant.plant_setup import check_parameters
from hawt_plant.safety_system import SafetySystem
from hawt_plant.turbine import Turbine

__all__ = ["BRIDGE_PLANT", "BridgeError", "BridgeFile", "BridgeModel", "BridgeClosed", "BridgeRun", "BridgedGraph",
           "HANDOVER", "MISSING_FIELDS", "REQUEST", "REPLY", "SENT_RECORDS", "bridge_library", "bridge_plant",
           "bridged_graph", "build_bridged_run", "checked_first_call", "encode_reply", "first_call", "listen",
           "measurements", "parse_request", "read_bridge_file", "run_bridge", "serve", "simulator_turbine",
           "without_protection"]

T = TypeVar("T")
"""What a first call's check makes of it."""

SENT_RECORDS = 129
"""Records 1-129 of the swap array go to the bridge with every call."""
REQUEST = struct.Struct(f"<4si{SENT_RECORDS}f1024s")
"""The library's message: magic ``HWB1``, status, records 1-129 (float32), the bridge file's path (first call)."""
REPLY = struct.Struct("<4si3fffff1024s")
"""The bridge's answer: magic ``HWR1``, fail (0 or -1), pitch of blades 1-3, collective pitch [rad], generator
torque [N*m], the turbine's largest pitch angle [rad] and rate [rad/s] (the library's safe commands), message."""
MISSING_FIELDS = ("aero_torque", "rotor_thrust", "tower_top_fa_disp", "tower_top_ss_disp", "tower_base_fa_moment",
                  "tower_base_ss_moment", "yaw_bearing_tilt_moment", "yaw_bearing_yaw_moment", "effective_wind_mean",
                  "effective_wind_cos", "effective_wind_sin")
"""The plant output's fields that the DISCON interface does not carry: NaN in every step of a bridged run."""
HANDOVER = ParameterSpec("handover", "", "the Unix socket on which hawt bridge hands this node the simulator's "
                         "connection and first call (hawt_tools.bridge_launch; hawt bridge sets it)", read_only=True)
"""The bridge plant node's one parameter beyond the plant's."""
BRIDGE_PLANT = NodeRole("plant", PLANT_PARAMETERS + (HANDOVER,), check_parameters)
"""The bridge plant node's role (entry point ``hawt.nodes: bridge_plant``; hawt_tools.bridge_node): a plant, with the
plant's parameters (those of the model and the wind are unused) and :data:`HANDOVER`."""
_KEYS = ("socket", "graph", "arguments", "parameters", "timeout", "start_timeout", "record")
_PITCH = (Record.PITCH_1, Record.PITCH_2, Record.PITCH_3)


class BridgeError(ValueError):
    """A bridge file, graph or simulator the bridge cannot run with; one line naming what is wrong."""


class BridgeClosed(RuntimeError):
    """The simulator closed the connection before its last call (it stopped or died)."""


def bridge_library(root: Optional[Path] = None) -> Path:
    """``libhawt_discon.so`` as ``scripts/setup.sh`` built it, checked against its source; ``root`` is the
    repository (default: this file's).

    Raises
    ------
    BridgeError
        Not built, or built from another version of ``hawt_discon.c`` (run ``scripts/setup.sh``, which
        ``./hawt`` does): a stale library is never used.
    """
    import hashlib

    root = Path(root) if root is not None else Path(__file__).resolve().parents[2]
    source = "hawt_tools/discon_bridge/hawt_discon.c"
    library, stamp = root / "ros2_ws" / "lib" / "libhawt_discon.so", root / "ros2_ws" / "lib" / ".hawt-discon"
    if not library.is_file() or not stamp.is_file():
        raise BridgeError(f"{library}: not built (run scripts/setup.sh)")
    # scripts/setup.sh's digest: sha256sum of the source, its line hashed again, the first 16 hex digits
    line = f"{hashlib.sha256((root / source).read_bytes()).hexdigest()}  {source}\n"
    if hashlib.sha256(line.encode()).hexdigest()[:16] != stamp.read_text().strip():
        raise BridgeError(f"{library} was built from another version of {source} (run scripts/setup.sh)")
    return library


@dataclass(frozen=True)
class BridgeFile:
    """A bridge file's settings (module notes)."""

    path: Path
    socket: str
    graph: str
    arguments: Tuple[str, ...] = ()
    parameters: Tuple[str, ...] = ()
    timeout: float = 10.0
    start_timeout: float = 60.0
    record: Optional[Path] = None


def read_bridge_file(path: Path, graph_required: bool = True) -> BridgeFile:
    """Read a bridge file; a :class:`BridgeError` naming the file (and line) for anything wrong. Without
    ``graph_required`` (the command line names the graph) the file may leave ``graph`` out."""
    path = Path(path)
    try:
        lines = path.read_text().splitlines()
    except (OSError, UnicodeDecodeError) as error:
        raise BridgeError(f"bridge file {path}: cannot read it: {getattr(error, 'strerror', None) or error}") \
            from None
    found: Dict[str, str] = {}
    for number, line in enumerate(lines, start=1):
        text = line.split("#", 1)[0].strip()
        if not text:
            continue
        key, sep, value = (part.strip() for part in text.partition("="))
        if not sep or key not in _KEYS:
            raise BridgeError(f"bridge file {path}:{number}: expected KEY = VALUE with KEY one of "
                              f"{', '.join(_KEYS)}, found {text!r}")
        found[key] = value
    for key, what in (("socket", "PATH line (where the hawt bridge listens)"), ("graph", "GRAPH line")):
        if not found.get(key) and (key != "graph" or graph_required):
            raise BridgeError(f"bridge file {path}: no {key} = {what}")
    if len(found["socket"].encode()) > 107:
        raise BridgeError(f"bridge file {path}: socket: a path of at most 107 characters")
    seconds = {}
    for key, default in (("timeout", 10.0), ("start_timeout", 60.0)):
        try:
            seconds[key] = float(found.get(key, default))
        except ValueError:
            seconds[key] = -1.0
        if not seconds[key] > 0:
            raise BridgeError(f"bridge file {path}: {key}: expected seconds > 0, found {found[key]}")
    folder = path.resolve().parent
    record = found.get("record")
    return BridgeFile(path, found["socket"], found.get("graph", ""), tuple(shlex.split(found.get("arguments", ""))),
                      tuple(shlex.split(found.get("parameters", ""))), seconds["timeout"], seconds["start_timeout"],
                      (folder / record) if record else None)


def measurements(swap: np.ndarray, blades: int) -> TurbineOutput:
    """The plant output of one call: records 1-129 (``swap[r - 1]``, float32) in hawt's fields, SI, as float64;
    :data:`MISSING_FIELDS` NaN."""
    s = np.asarray(swap, dtype=np.float64)

    def blade(first: int) -> np.ndarray:
        return s[first - 1:first - 1 + blades].copy()

    nan = float("nan")
    return TurbineOutput(
        time=float(s[Record.TIME - 1]), azimuth=float(s[Record.AZIMUTH - 1]) % (2 * np.pi),
        rotor_speed=float(s[Record.ROTOR_SPEED - 1]), root_moment_oop=blade(Record.ROOT_MOOP_1),
        root_moment_ip=blade(Record.ROOT_MIP_1), pitch=np.array([s[r - 1] for r in _PITCH[:blades]]),
        generator_speed=float(s[Record.GENERATOR_SPEED - 1]), generator_torque=float(s[Record.GENERATOR_TORQUE - 1]),
        electrical_power=float(s[Record.ELECTRICAL_POWER - 1]), hub_wind_speed=float(s[Record.HUB_WIND_SPEED - 1]),
        tower_top_fa_accel=float(s[Record.TOWER_TOP_FA_ACCEL - 1]),
        tower_top_ss_accel=float(s[Record.TOWER_TOP_SS_ACCEL - 1]),
        hub_tilt_moment=float(s[Record.HUB_TILT_MOMENT - 1]), hub_yaw_moment=float(s[Record.HUB_YAW_MOMENT - 1]),
        **{name: nan for name in MISSING_FIELDS})


def encode_reply(pitch: Sequence[float] = (0.0, 0.0, 0.0), torque: float = 0.0,
                 limits: Tuple[float, float] = (0.0, 0.0), fail: int = 0, message: str = "") -> bytes:
    """A bridge answer (:data:`REPLY`): pitch per blade [rad] (their mean as the collective), generator torque
    [N*m], the turbine's largest pitch angle and rate, ``fail`` (-1: the library fails with ``message``)."""
    padded = list(pitch) + [0.0] * (3 - len(pitch))
    collective = float(np.mean(pitch)) if len(pitch) else 0.0
    return REPLY.pack(b"HWR1", fail, *padded, collective, torque, *limits, message.encode()[:1023])


class BridgeModel:
    """The plant model of a bridged run: each ``step`` answers the simulator's call and returns its next one.

    Parameters
    ----------
    connection : socket.socket
        The library's connection (``SOCK_SEQPACKET``), its first call already read.
    blades : int
        B of the graph's turbine.
    limits : (float, float)
        The turbine's largest pitch angle [rad] and rate [rad/s], sent with every answer.
    individual : bool
        The simulator reads the blades' own demands (record 28 = 1); if not, a step whose blades' commands differ
        fails (the simulator would apply only their mean).
    """

    def __init__(self, connection: socket.socket, blades: int, limits: Tuple[float, float], individual: bool) -> None:
        self.connection = connection
        self.blades = blades
        self.limits = limits
        self.individual = individual
        self.finished = False
        self.calls = 1
        self.dt = 0.0

    def step(self, pitch: np.ndarray, generator_torque: float) -> TurbineOutput:
        """Answer the current call with ``pitch`` [rad] per blade and ``generator_torque`` [N*m]; the measurements
        of the next call. After the last call (status -1, answered with the same command) :attr:`finished` is set
        and its measurements are returned.

        Raises
        ------
        BridgeClosed
            The simulator closed the connection.
        BridgeError
            Commands that differ between blades for a simulator that pitches collectively.
        """
        pitch = np.asarray(pitch, dtype=float)
        if not self.individual and np.ptp(pitch) > 0:
            message = (f"the graph commands individual pitch ({np.degrees(np.ptp(pitch)):.3g} deg between blades at "
                       f"call {self.calls}), but the simulator pitches collectively: set record 28 (ServoDyn "
                       "Ptch_Cntrl = 1)")
            self._send(encode_reply(fail=-1, message=message))
            raise BridgeError(message)
        self._send(encode_reply(tuple(pitch), float(generator_torque), self.limits))
        status, swap = self.receive()
        self.calls += 1
        if status < 0:
            self._send(encode_reply(tuple(pitch), float(generator_torque), self.limits))
            self.finished = True
        return measurements(swap, self.blades)

    def receive(self) -> Tuple[int, np.ndarray]:
        """The next call's status and records 1-129 (also the first call's, with the bridge file's path)."""
        data = self.connection.recv(REQUEST.size + 1)
        if not data:
            raise BridgeClosed(f"the simulator closed the connection after {self.calls} calls, before its last call")
        return parse_request(data)[:2]

    def fail(self, message: str) -> None:
        """Answer the current call with ``fail = -1`` and ``message``: the library fails with it and gives the
        simulator its safe commands (a connection already gone is left as it is)."""
        try:
            self._send(encode_reply(fail=-1, message=message))
        except BridgeClosed:
            pass

    def gone(self) -> bool:
        """True if the simulator has closed the connection while the bridge owes it an answer (never blocks: a peer
        that closed reads as an empty message; the library sends nothing else before it has its answer)."""
        try:
            return not self.connection.recv(REQUEST.size + 1, socket.MSG_PEEK | socket.MSG_DONTWAIT)
        except BlockingIOError:
            return False
        except OSError:
            return True

    def _send(self, data: bytes) -> None:
        try:
            self.connection.sendall(data)
        except OSError as error:
            raise BridgeClosed(f"the simulator's connection failed after {self.calls} calls: {error}") from None


def parse_request(data: bytes) -> Tuple[int, np.ndarray, str]:
    """A library message: status, records 1-129, the bridge file's path ("" after the first call)."""
    if len(data) != REQUEST.size or data[:4] != b"HWB1":
        raise BridgeError(f"a message that is not libhawt_discon's ({len(data)} bytes)")
    magic, status, *rest = REQUEST.unpack(data)
    path = rest[-1].split(b"\0", 1)[0].decode(errors="replace")
    return status, np.asarray(rest[:-1], dtype=np.float32), path


def listen(path: str) -> socket.socket:
    """A listening ``SOCK_SEQPACKET`` socket at ``path`` (a stale socket file there is replaced)."""
    try:
        os.unlink(path)
    except FileNotFoundError:
        pass
    server = socket.socket(socket.AF_UNIX, socket.SOCK_SEQPACKET)
    try:
        server.bind(path)
    except OSError as error:
        server.close()
        raise BridgeError(f"socket {path}: cannot listen there: {error.strerror}") from None
    server.listen(1)
    return server


@dataclass
class BridgeRun:
    """What a bridge did: the in-process run (at its last step; None on the ROS graph), the calls answered (None on
    the ROS graph: its plant node's ``finished`` line counts them), the bag written if any, the in-process run's
    events, and a line saying how it ended."""

    run: Any
    calls: Optional[int]
    record: Optional[Path] = None
    events: List[dict] = field(default_factory=list)
    summary: str = ""


def _round_dt(dt32: float) -> float:
    """The communication interval as the simulator set it: record 3 is float32 (0.00625 arrives 0.0062500000931)."""
    return float(f"{dt32:.7g}")


def _graph_file(bridge: BridgeFile) -> Path:
    """The graph a bridge file names: a file beside the bridge file (or a path relative to its folder), else an
    installed graph's name (whatever folders the bridge's working directory has)."""
    from hawt_tools.graph_file import find_graph, installed_graphs

    local = bridge.path.resolve().parent / bridge.graph
    if local.is_file() or Path(bridge.graph).suffix in (".yaml", ".yml") or "/" in bridge.graph:
        return local
    return installed_graphs().get(bridge.graph) or find_graph(bridge.graph)  # a GraphError naming those there are


def simulator_turbine(values: Mapping[str, Any], swap: np.ndarray) -> Turbine:
    """The turbine of the graph's plant (its parameter ``values``), checked against the simulator's first call
    (records 1-129 in ``swap``): the same blade count (record 61) and, once the rotor turns faster than 0.1 rad/s,
    the same generator-to-rotor speed ratio within 1 % (records 20, 21). A :class:`BridgeError` naming both."""
    from hawt_plant.turbine import nrel_5mw, turbine_from

    turbine = turbine_from(values["turbine_file"]) if values["turbine_file"] else nrel_5mw()
    blades = int(round(float(swap[Record.BLADES - 1])))
    if blades != turbine.rotor.number_of_blades:
        raise BridgeError(f"the simulator has {blades} blades (record 61), the graph's turbine "
                          f"{turbine.name} {turbine.rotor.number_of_blades}")
    rotor, generator = float(swap[Record.ROTOR_SPEED - 1]), float(swap[Record.GENERATOR_SPEED - 1])
    gearbox = turbine.drivetrain.gearbox_ratio
    if rotor > 0.1 and abs(generator / rotor / gearbox - 1) > 0.01:
        raise BridgeError(f"the simulator's generator speed is {generator / rotor:.4g} times its rotor "
                          f"speed (records 20, 21), the graph's turbine {turbine.name} has gearbox ratio "
                          f"{gearbox:g}: another turbine")
    return turbine


def bridge_plant(connection: socket.socket, swap: np.ndarray) -> Callable[[Mapping[str, Any], Callable[[str], None]],
                                                                          Tuple[Turbine, BridgeModel, TurbineOutput]]:
    """The plant factory of a bridged graph (hawt_tools.in_process.PlantFactory; the bridge node's too): the
    graph's turbine checked against the simulator (:func:`simulator_turbine`), a :class:`BridgeModel` on
    ``connection`` and the first call's measurements (``swap``) as step 0's output."""
    def plant(values: Mapping[str, Any], _progress: Callable[[str], None]):
        turbine = simulator_turbine(values, swap)
        actuator, blades = turbine.pitch_actuator, turbine.rotor.number_of_blades
        individual = int(round(float(swap[Record.PITCH_CONTROL - 1]))) == 1
        model = BridgeModel(connection, blades, (actuator.max_angle, actuator.max_rate), individual)
        return turbine, model, measurements(swap, blades)

    return plant


def without_protection(safety: SafetySystem) -> SafetySystem:
    """The plant's safety system without its protection (module notes, "No plant protection"): the watchdog on the
    commands stays."""
    return SafetySystem(safety.settings)


@dataclass(frozen=True)
class BridgedGraph:
    """The graph a bridge file names, checked for the simulator's first call: the graph, the ``-p`` texts it runs
    with (the file's, the plant's ``dt`` = the simulator's DT and ``duration`` 0: the simulator ends the run) and
    those texts parsed."""

    graph: Any
    parameters: Tuple[str, ...]
    overrides: Mapping[str, Sequence[Tuple[str, Any]]]
    plant: Any
    """The graph's plant node (hawt_tools.graph_file.NodeSpec)."""


def bridged_graph(bridge: BridgeFile, status: int, swap: np.ndarray, infile: str) -> BridgedGraph:
    """The graph of ``bridge`` checked for the simulator's first call (status, records, its bridge file path), as
    both engines run it: its parameters as ``hawt launch`` checks them, its controllers against the plant, the
    simulator against its turbine (:func:`simulator_turbine`). A :class:`BridgeError` for anything that cannot
    run."""
    from hawt_tools.graph_file import GraphError, launch_arguments, load_graph, package_prefix
    from hawt_tools.in_process import plant_node, plant_parameters
    from hawt_tools.node_parameters import parse_overrides
    from hawt_tools.parameter_check import check_against_plant, check_graph_parameters

    from hawt_core.parameter_table import ParameterError

    if status != 0:
        raise BridgeError(f"the simulator's first call has status {status}, not 0 (a first call)")
    if infile and Path(infile).exists() and not os.path.samefile(infile, bridge.path):
        raise BridgeError(f"the simulator's bridge file {infile} is not this bridge's ({bridge.path})")
    dt = _round_dt(float(swap[Record.DT - 1]))
    try:
        graph = load_graph(_graph_file(bridge), launch_arguments(bridge.arguments, "arguments:"), package_prefix)
        plant = plant_node(graph)
        parameters = bridge.parameters + (f"{plant.label}.dt:={dt!r}", f"{plant.label}.duration:=0.0")
        overrides = parse_overrides(graph, parameters)
        check_against_plant(graph, check_graph_parameters(graph, overrides))
        values = plant_parameters(graph, overrides)
        if any(entry.strip() for entry in values["faults"]):
            raise ParameterError(f"{plant.label}.faults: the simulator is the plant: inject faults there")
        simulator_turbine(values, swap)
    except (GraphError, ParameterError) as error:
        raise BridgeError(f"bridge file {bridge.path}: graph {bridge.graph}: {error}") from None
    return BridgedGraph(graph, parameters, overrides, plant)


def build_bridged_run(bridge: BridgeFile, connection: socket.socket, status: int, swap: np.ndarray,
                      infile: str, progress: Callable[[str], None] = lambda _: None):
    """The graph of ``bridge`` built in process on the simulator's first call (:func:`bridged_graph`), with a
    :class:`BridgeModel` on ``connection`` as its plant and no protection. A :class:`BridgeError` for anything
    that cannot run."""
    from hawt_tools.graph_file import GraphError
    from hawt_tools.in_process import build_run

    from hawt_core.parameter_table import ParameterError

    bridged = bridged_graph(bridge, status, swap, infile)
    try:
        run = build_run(bridged.graph, bridged.overrides, progress, bridge_plant(connection, swap))
    except (GraphError, ParameterError) as error:
        raise BridgeError(f"bridge file {bridge.path}: graph {bridge.graph}: {error}") from None
    run.safety = without_protection(run.safety)
    return run


def first_call(bridge: BridgeFile, server: Optional[socket.socket] = None) -> Tuple[socket.socket, bytes]:
    """The library's connection and its first message: accept it on ``server`` (default: listen at the file's
    ``socket``), then remove the socket file. :class:`BridgeClosed` if it closes before its first call."""
    server = server or listen(bridge.socket)
    try:
        connection, _ = server.accept()
    finally:
        server.close()
        try:
            os.unlink(bridge.socket)
        except FileNotFoundError:
            pass
    data = connection.recv(REQUEST.size + 1)
    if not data:
        connection.close()
        raise BridgeClosed("the simulator closed the connection before its first call")
    return connection, data


def checked_first_call(connection: socket.socket, data: bytes, check: Callable[[int, np.ndarray, str], T]) -> T:
    """``check`` of the simulator's first call ``data`` (its status, records and bridge file path), as both engines
    take it: a :class:`BridgeError` it raises is answered with ``fail = -1`` and its line, so the library fails with
    it, and raised."""
    try:
        return check(*parse_request(data))
    except BridgeError as error:
        connection.sendall(encode_reply(fail=-1, message=str(error)))
        raise


def serve(bridge: BridgeFile, server: Optional[socket.socket] = None,
          progress: Callable[[str], None] = lambda _: None) -> BridgeRun:
    """Serve one simulator run: accept the library's connection, build the graph on its first call, step it once
    per call, end at the last call (status -1), write the bag if the file asks for one.

    ``server`` is a socket from :func:`listen` (default: listen at the file's ``socket``).

    Raises
    ------
    BridgeError
        A graph or simulator the bridge cannot run with (also sent to the library, which fails with it).
    BridgeClosed
        The simulator went away before its last call.
    """
    import time

    from hawt_tools.in_process import RunRecord, write_run

    connection, data = first_call(bridge, server)
    with connection:
        run = checked_first_call(connection, data, lambda *call: build_bridged_run(bridge, connection, *call, progress))
        model: BridgeModel = run.model
        progress(f"{run.turbine.name}: bridged, dt {run.description.dt:g} s, {model.blades} blades, "
                 f"{'individual' if model.individual else 'collective'} pitch; fields without a measurement: "
                 f"{', '.join(MISSING_FIELDS)}")
        book = RunRecord() if bridge.record is not None else None
        start = time.monotonic()
        reported = len(run.events)
        while not model.finished:
            run.step(book)
            for event in run.events[reported:]:  # the plant's protection, as hawt run reports it
                if event["level"] >= 30:
                    progress(f"{event['kind']} at t={run.output.time:.2f} s: {event['detail']}")
            reported = len(run.events)
    run.events.append({"step": run.step_index, "source": "bridge", "level": 20, "kind": "finished",
                       "detail": f"finished {model.calls} DISCON calls ({run.output.time:g} s simulated) in "
                                 f"{time.monotonic() - start:.1f} s wall, bridged"})
    if bridge.record is not None:
        write_run(run, book, bridge.record)
    return BridgeRun(run, model.calls, bridge.record, run.events, run.events[-1]["detail"])


def run_bridge(path: Path, graph: Optional[str] = None, arguments: Sequence[str] = (),
               parameters: Sequence[str] = (), record: Optional[Path] = None,
               listening: Callable[[str], None] = lambda _: None,
               progress: Callable[[str], None] = lambda _: None, in_process: bool = False) -> BridgeRun:
    """Serve one simulator run of the bridge file at ``path`` (what ``hawt bridge`` does): on the ROS graph
    (hawt_tools.bridge_launch.serve_graph), or with ``in_process`` on the in-process engine (:func:`serve`).

    ``graph`` with its launch ``arguments`` replaces the file's graph and arguments; ``parameters``
    (``NODE.PARAM:=VALUE``) are added to the file's; ``record`` replaces the file's bag. ``listening`` gets a line
    once the bridge listens (the simulator may start), ``progress`` the bridge's stage lines.

    Raises
    ------
    BridgeError
        The bridge file, the graph or the simulator (one line; also sent to the library if it called).
    BridgeClosed
        The simulator went away before its last call.
    RuntimeError
        On the ROS graph: the graph failed once started (the launcher's line names the node).
    """
    from dataclasses import replace

    bridge = read_bridge_file(Path(path), graph_required=not graph)
    if graph:
        bridge = replace(bridge, graph=graph, arguments=tuple(arguments))
    bridge = replace(bridge, parameters=bridge.parameters + tuple(parameters),
                     record=Path(record) if record is not None else bridge.record)
    server = listen(bridge.socket)
    listening(f"listening on {bridge.socket} for {bridge.graph} ({'in process' if in_process else 'ROS graph'})")
    if in_process:
        return serve(bridge, server, progress)
    from hawt_tools.bridge_launch import serve_graph

    return serve_graph(bridge, server, progress)


def main(argv: Optional[Sequence[str]] = None) -> int:
    """``python -m hawt_tools.discon_bridge [--in-process] FILE``: serve one simulator run of the bridge file FILE
    (as ``hawt bridge [--in-process] --file FILE``).

    Exit 0 after the simulator's last call, 2 with one line for a bad bridge file, graph or simulator, 1 with
    one line when the simulator went away or the graph failed.
    """
    import sys

    args = list(sys.argv[1:] if argv is None else argv)
    in_process = "--in-process" in args
    args = [a for a in args if a != "--in-process"]
    if len(args) != 1:
        print("usage: python -m hawt_tools.discon_bridge [--in-process] BRIDGE_FILE", file=sys.stderr)
        return 2

    def say(line: str) -> None:
        print(f"hawt bridge: {line}", file=sys.stderr, flush=True)

    try:
        result = run_bridge(Path(args[0]), listening=say, progress=say, in_process=in_process)
    except BridgeError as error:
        print(f"hawt bridge: {error}", file=sys.stderr)
        return 2
    except (BridgeClosed, RuntimeError) as error:
        print(f"hawt bridge: {error}", file=sys.stderr)
        return 1
    print(result.summary + (f"; recorded into {result.record}" if result.record else ""))
    return 0


if __name__ == "__main__":
    # this module's own classes, not __main__'s copies: hawt_tools.bridge_launch raises hawt_tools.discon_bridge's
    from hawt_tools.discon_bridge import main as module_main

    raise SystemExit(module_main())
