"""The in-process runner (DESIGN §6): a graph's cores stepped in lockstep order with no middleware.

``hawt run GRAPH`` reads the same graph and parameter files as ``hawt launch``, finds what each node is through
the registry (hawt_tools.node_registry: node roles and controller types, no ROS), gives each
node the parameters rcl would give it (hawt_tools.node_parameters), builds the same cores —
the plant model (hawt_plant.plant_setup), every controller plug-in (hawt_controllers.plugins), the loop assembler
(hawt_controllers.plugins.loop_assembly) and the controller manager's switch schedule
(hawt_controllers.plugins.switching, whose switch_effect the controller node applies too) — and steps them in
the order the lockstep graph does: at step k every controller updates on the plant's output of step k
(active or not), the assembler sums what the active ones contribute, limits it, and the
plant advances with that command. The result equals the lockstep ROS graph bit for bit,
for the same graph, arguments and seed. A run can be written to MCAP with the topics the
graph publishes, so ``hawt analyze`` and ``hawt compare`` read it unchanged.

The plant's protection (hawt_plant.safety_system.Protection) runs here as in the plant node:
a trip is a ``protection_trip`` event and the plant feathers from the next step on. The plant's
faults (hawt_plant.faults) act at the same points as in the plant node, each a ``fault`` event.
Input a controller refuses is an ``invalid_input`` event at the first of consecutive refused
steps (the controller node reports every one).
What the runner does not do, since nothing can happen there that the schedule did not
say: live switches and parameter sets, lost contributors, realtime.
"""
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple

import numpy as np

from hawt_controllers.plugins.controller import (CollectiveContribution, Contribution, Controller,
                                                HarmonicContribution, contribution_topic, update_or_hold)
from hawt_controllers.plugins.loop_assembly import ASSEMBLER, LoopAssembler, assembly_problem, pitch_limits
from hawt_controllers.plugins.switching import (ControllerInfo, Switch, SwitchRefused, parse_schedule, plan_switch,
                                                planned_states, switch_effect)
from hawt_core.command_interfaces import parse_interface
from hawt_core.node_role import NodeRole
from hawt_core.parameter_table import ParameterError, resolve_values
from hawt_core.topics import estimate_topic
from hawt_plant.faults import fault_event, make_faults
from hawt_plant.model import STATE_FIELDS
from hawt_plant.plant_setup import PARAMETERS as PLANT_PARAMETERS
from hawt_plant.plant_setup import aerodynamics_line, make_plant, make_safety_system
from hawt_plant.safety_system import command_rejection, protection_event
from hawt_tools.graph_file import Graph, GraphError, NodeSpec
from hawt_tools.node_registry import node_role
from hawt_tools.node_parameters import node_parameters

__all__ = ["InProcessRun", "PlantFactory", "build_run", "plant_node", "plant_parameters", "RunRecord", "write_run",
           "run_graph", "step_run"]

Overrides = Mapping[str, Sequence[Tuple[str, Any]]]
PlantFactory = Callable[[Mapping[str, Any], Callable[[str], None]], Tuple[Any, Any, Any]]
"""What builds the plant from the plant node's parameter values (and a progress callback): the turbine, a model
whose ``step(pitch, generator_torque)`` applies a step's command and returns the next step's output, and the
output of step 0. :func:`hawt_plant.plant_setup.make_plant` by default; the DISCON bridge
(hawt_tools.discon_bridge) gives one whose outputs are a simulator's measurements."""


@dataclass
class RunRecord:
    """What a run published, by topic, one row per step (columns of hawt_bag.column_writing)."""

    rows: Dict[str, List[dict]] = field(default_factory=dict)
    types: Dict[str, str] = field(default_factory=dict)
    """Message type of a topic that is not one of the loop's (``_TYPES``), e.g. a controller's estimate."""

    def add(self, topic: str, row: dict, type_name: Optional[str] = None) -> None:
        self.rows.setdefault(topic, []).append(row)
        if type_name is not None:
            self.types[topic] = type_name


@dataclass
class _Controller:
    """One controller of the graph and what its node would do around the core."""

    name: str
    core: Controller
    publish_until: float = -math.inf
    last: Tuple[Contribution, ...] = ()
    refusing: bool = False

    def info(self) -> ControllerInfo:
        state = "active" if self.publish_until == math.inf else "inactive"
        return ControllerInfo(self.name, self.core.TYPE, self.core.claims(), state, self.core.SWITCHABLE,
                              self.publish_until if math.isfinite(self.publish_until) else 0.0)


class InProcessRun:
    """A graph's cores, ready to step (build one with :func:`build_run`)."""

    def __init__(self, namespace: str, plant_values: Mapping[str, Any], assembler_values: Mapping[str, Any],
                 controllers: Sequence[Tuple[str, type, Mapping[str, Any]]],
                 schedule: Sequence[str] = (), ramp_time: float = 0.0,
                 progress: Callable[[str], None] = lambda _: None, plant: Optional[PlantFactory] = None) -> None:
        self.namespace = namespace
        self.plant_values = dict(plant_values)
        self.turbine, self.model, output = (plant or make_plant)(plant_values, progress)
        self.faults = make_faults(plant_values, self.turbine)
        self.output = self.faults.measure(0, output)
        self.description = self.turbine.description(plant_values["dt"])
        self.actuator = self.turbine.pitch_actuator
        self.safety = make_safety_system(self.turbine, plant_values)
        self.assembler = LoopAssembler(self.description.blades, pitch_limits(assembler_values, self.description),
                                       self.description.dt)
        self.controllers: List[_Controller] = []
        for name, core_class, values in controllers:
            try:
                controller = _Controller(name, core_class(values, self.description))
            except ValueError as error:
                raise ParameterError(f"{name}: {error}") from None
            if values.get("active", True):
                controller.core.on_activate(None, (), None)
                controller.publish_until = math.inf
            self.controllers.append(controller)
        self.schedule = self._planned(schedule, ramp_time)
        self.step_index = 0
        self.previous: Optional[np.ndarray] = None
        self.command = (np.array(self.output.pitch), float(self.output.generator_torque))
        self.events: List[dict] = []

    def _planned(self, entries: Sequence[str], ramp_time: float) -> List[Switch]:
        """controller_manager's ``schedule`` entries as switches, checked as the manager checks them (STRICT)."""
        known = {c.name: c.info() for c in self.controllers}
        switches = []
        for entry in parse_schedule([e for e in entries if e.strip()]):
            incoming, outgoing, _ = plan_switch(known, entry.activate, entry.deactivate, True, entry.step,
                                                lambda i: assembly_problem(i, self.description.blades))
            switch = Switch(entry.step, tuple((c.name, c.interfaces) for c in incoming),
                            tuple((c.name, c.interfaces) for c in outgoing), ramp_time)
            known.update(planned_states(switch, incoming, outgoing, self.description.dt))
            switches.append(switch)
        return switches

    def _apply(self, switch: Switch, step: int) -> None:
        """What every controller node does with a switch at its step (switching.switch_effect, as the node)."""
        outgoing_last = {contribution_topic(c): c for ctl in self.controllers if ctl.name in dict(switch.deactivate)
                         for c in ctl.last}
        incoming = dict(switch.activate)
        for controller in self.controllers:
            claims = controller.core.claims()
            effect = switch_effect(switch, controller.name, claims, self.description.dt)
            if effect is None:
                continue
            if effect.active:
                initial = tuple(c for t, c in outgoing_last.items() if effect.replaced and
                                any(parse_interface(i).topic == t for i in claims))
                controller.core.on_activate(effect.ramp_time, initial, self.output)
            else:
                controller.core.on_deactivate(effect.ramp_time)
            controller.publish_until = effect.publish_until
        self.events.append({"step": step, "source": "in_process", "level": 20, "kind": "switch",
                            "detail": f"at step {step}: activate {', '.join(incoming) or '-'}; deactivate "
                                      f"{', '.join(dict(switch.deactivate)) or '-'}; ramp {switch.ramp_time:g} s"})

    def step(self, record: Optional[RunRecord] = None) -> None:
        """Step k: controllers, assembly, then the plant advances to k + 1."""
        k, out = self.step_index, self.output
        if record is not None:
            record.add("plant/blade_loads", {"step": k, **{name: getattr(out, name) for name in _LOAD_FIELDS}})
            record.add("plant/state", {"step": k, **{name: getattr(out, name) for name in STATE_FIELDS}})
        while self.schedule and self.schedule[0].step <= k:
            self._apply(self.schedule.pop(0), k)
        collective: Optional[CollectiveContribution] = None
        weighted: List[Tuple[Contribution, float]] = []
        for controller in self.controllers:
            contributions, refusal = update_or_hold(controller.core, k, out, out, controller.last)
            controller.last = contributions
            if refusal is not None and not controller.refusing:
                self.events.append({"step": k, "source": controller.name, "level": 40, "kind": "invalid_input",
                                    "detail": f"step {k}: {refusal}; {controller.core.WITHOUT_INPUT} (reported at "
                                              "the first of consecutive refused steps)"})
            controller.refusing = refusal is not None
            if record is not None and refusal is None and controller.core.ESTIMATE is not None:
                kind, type_name = controller.core.ESTIMATE
                topic = estimate_topic(controller.name.rsplit("/", 1)[-1], kind)
                record.add(topic, {"step": k, **controller.core.estimate()}, type_name)
            if k >= controller.publish_until:
                continue
            for contribution in contributions:
                if record is not None:
                    record.add(contribution_topic(contribution), _contribution_row(contribution, k, controller.name))
                if isinstance(contribution, CollectiveContribution):
                    collective = contribution
                else:
                    weighted.append((contribution, 1.0))
        if collective is None:
            raise RuntimeError(f"step {k}: no controller contributes collective_pitch")
        previous = np.asarray(out.pitch) if self.previous is None else self.previous
        command = self.assembler.assemble(collective.pitch, weighted, out.azimuth, previous)
        self.previous = command.pitch
        if record is not None:
            record.add("control/pitch_command", {
                "step": k, "pitch": command.pitch, "generator_torque": collective.generator_torque,
                "collective": collective.pitch, "individual": command.individual, "flags": int(command.flags)})
        if command_rejection(command.pitch, collective.generator_torque, self.description.blades,
                             self.actuator.min_angle, self.actuator.max_angle,
                             self.turbine.generator.max_torque) is None:
            self.command = (np.asarray(command.pitch, dtype=float), float(collective.generator_torque))
        if self.safety.tripped:
            self.command = self.safety.feather(self.description.dt)
        for fault in self.faults.starting(k):
            level, kind, detail = fault_event(fault, self.description.dt, self.actuator)
            self.events.append({"step": k, "source": "in_process", "level": level, "kind": kind, "detail": detail})
        self.output = self.faults.step(self.model, k, *self.command)
        self.step_index += 1
        for finding in self.safety.protect(self.output, self.faults.grid_connected(k)):
            level, kind, detail = protection_event(finding, self.safety)
            self.events.append({"step": self.step_index, "source": "in_process", "level": level, "kind": kind,
                                "detail": detail})


_LOAD_FIELDS = ("azimuth", "rotor_speed", "root_moment_oop", "root_moment_ip", "pitch")
_TYPES = {"plant/blade_loads": "BladeLoads", "plant/state": "TurbineState", "control/pitch_command": "PitchCommand",
          "control/collective": "CollectivePitch", "control/blade_pitch": "BladePitch"}


def write_run(run: InProcessRun, record: RunRecord, path: Path) -> Dict[str, int]:
    """Write what a run published into a new MCAP bag, under the plant's namespace, stamped with simulated time.

    Returns topic -> messages written.
    """
    from hawt_bag.column_writing import TopicData, write_topics
    from hawt_bag.plant_run import topic_in
    from hawt_bag.writer import BagWriter

    dt = run.description.dt
    topics = []
    for relative, rows in record.rows.items():
        columns = {name: np.asarray([row[name] for row in rows]) for name in rows[0]}
        steps = columns["step"].astype(np.int64)
        nanoseconds = np.round(steps * dt * 1e9).astype(np.int64)
        columns["step"] = steps.astype(np.uint64)
        columns["header.stamp.sec"], columns["header.stamp.nanosec"] = nanoseconds // 10**9, nanoseconds % 10**9
        kind = record.types.get(relative) or _TYPES.get(relative, "HarmonicPitch")
        topics.append(TopicData(topic_in(run.namespace, relative), f"hawt_msgs/msg/{kind}", columns, nanoseconds))
    if run.events:
        rows = run.events
        steps = np.asarray([e["step"] for e in rows], dtype=np.int64)
        nanoseconds = np.round(steps * dt * 1e9).astype(np.int64)
        columns = {"step": steps.astype(np.uint64), "level": np.asarray([e["level"] for e in rows], dtype=np.uint8),
                   **{k: np.asarray([str(e[k]) for e in rows]) for k in ("source", "kind", "detail")},
                   "header.stamp.sec": nanoseconds // 10**9, "header.stamp.nanosec": nanoseconds % 10**9}
        topics.append(TopicData(topic_in(run.namespace, "control/events"), "hawt_msgs/msg/ControlEvent", columns,
                                nanoseconds))
    with BagWriter.open(path) as writer:
        return write_topics(writer, topics)


def _contribution_row(contribution: Contribution, step: int, controller: str) -> dict:
    if isinstance(contribution, CollectiveContribution):
        return {"step": step, "pitch": contribution.pitch, "generator_torque": contribution.generator_torque,
                "generator_speed_filtered": contribution.generator_speed_filtered, "region": contribution.region,
                "wind_speed_estimate": contribution.wind_speed_estimate}
    if isinstance(contribution, HarmonicContribution):
        return {"step": step, "harmonic": contribution.harmonic, "cos": contribution.cos, "sin": contribution.sin,
                "phase_offset": contribution.phase_offset}
    return {"step": step, "controller": controller, "increment": np.asarray(contribution.increment)}


def _node_kind(graph: Graph, spec: NodeSpec, overrides: Overrides = ()) -> Tuple[str, Optional[NodeRole]]:
    """What a node is to the runner: its role's kind (plant, assembler, manager, description, controller) and role."""
    role = node_role(graph, spec, overrides)
    if role is None:
        raise GraphError(f"{graph.path}:{spec.line}: node {spec.name!r} ({spec.package}/{spec.executable}) has no "
                         "core the in-process runner can step (plant, mbc, controller_manager or a controller)")
    return role.kind, role


def plant_node(graph: Graph) -> NodeSpec:
    """The graph's one plant node (a GraphError if it has none or several)."""
    plants = [spec for spec in graph.nodes if getattr(node_role(graph, spec), "kind", None) == "plant"]
    if len(plants) != 1:
        raise GraphError(f"{graph.path}: expected exactly one plant node, found {len(plants)}")
    return plants[0]


def plant_parameters(graph: Graph, overrides: Overrides = ()) -> Dict[str, Any]:
    """The parameters the graph's plant node gets (what a campaign's wind preparation builds the plant from)."""
    return _node_values(graph, plant_node(graph), PLANT_PARAMETERS, overrides)


def _node_values(graph: Graph, spec: NodeSpec, table, overrides: Overrides) -> Dict[str, Any]:
    """The values of ``table`` that node ``spec`` gets, a bad one a GraphError naming the node."""
    try:
        return resolve_values(table, node_parameters(spec, overrides))
    except ParameterError as error:
        raise GraphError(f"{graph.path}:{spec.line}: node {spec.name!r}: {error}") from None


def build_run(graph: Graph, overrides: Overrides = (), progress: Callable[[str], None] = lambda _: None,
              plant: Optional[PlantFactory] = None) -> InProcessRun:
    """The cores of ``graph`` with the parameters each node would get; ``progress`` gets the lines of a turbulent
    field's generation, if the plant's field is not in the cache yet. ``plant`` builds the plant instead of
    :func:`~hawt_plant.plant_setup.make_plant` (:data:`PlantFactory`).

    Raises
    ------
    GraphError
        A node the runner cannot step, an ``executable`` action, a graph without exactly one plant and one
        assembler, or a bad parameter (named with the node).
    """
    graph.refuse_programs("in one process (hawt run, campaigns)")
    found: Dict[str, List[Tuple[NodeSpec, NodeRole]]] = {}
    for spec in graph.nodes:
        kind, role = _node_kind(graph, spec, overrides)
        found.setdefault(kind, []).append((spec, role))
    for kind in ("plant", "assembler"):
        if len(found.get(kind, ())) != 1:
            raise GraphError(f"{graph.path}: the in-process runner needs exactly one {kind} node, found "
                             f"{len(found.get(kind, ()))}")

    def values(spec: NodeSpec, table) -> Dict[str, Any]:
        return _node_values(graph, spec, table, overrides)

    plant_spec, assembler_spec = found["plant"][0][0], found["assembler"][0][0]
    controllers = [(spec.label, role.controller, values(spec, role.parameters))
                   for spec, role in found.get("controller", ())]
    managers = [values(spec, role.parameters) for spec, role in found.get("manager", ())]
    schedule, ramp_time = (managers[0]["schedule"], managers[0]["ramp_time"]) if managers else ((), 0.0)
    try:
        return InProcessRun(plant_spec.full_namespace.rstrip("/"), values(plant_spec, PLANT_PARAMETERS),
                            values(assembler_spec, ASSEMBLER.parameters), controllers, schedule, ramp_time,
                            progress, plant)
    except SwitchRefused as refusal:
        raise GraphError(f"{graph.path}: controller_manager schedule: {refusal}") from None



def run_graph(graph: Graph, overrides: Overrides = (), record: Optional[Path] = None,
              duration: Optional[float] = None, progress=None) -> InProcessRun:
    """Run a graph in process to the plant's ``duration`` (or ``duration`` [s] simulated), recording it if asked.

    ``progress(line)`` gets the lines of a turbulent field's generation if it is not cached yet, the plant's
    aerodynamic options (as the plant node's start-up line says them), then a line every 10 % of the run.
    """
    run = build_run(graph, overrides, progress or (lambda _: None))
    seconds = duration if duration is not None else run.plant_values["duration"]
    if not seconds or seconds <= 0:
        raise GraphError(f"{graph.path}: the run needs a simulated duration (the plant's duration parameter or "
                         "--duration S)")
    return step_run(run, seconds, record, progress)


def step_run(run: InProcessRun, seconds: float, record: Optional[Path] = None, progress=None) -> InProcessRun:
    """Step a run built by :func:`build_run` (still at step 0) for ``seconds`` simulated, recording it into
    ``record`` if given; ``progress`` as for :func:`run_graph`."""
    import time

    steps = int(round(seconds / run.description.dt))
    if progress is not None:
        progress(f"{run.turbine.name}: {aerodynamics_line(run.turbine, run.plant_values)}")
    book = RunRecord() if record is not None else None
    start, tenth = time.monotonic(), max(1, steps // 10)
    for k in range(steps):
        run.step(book)
        if progress is not None and (k + 1) % tenth == 0:
            wall = time.monotonic() - start
            progress(f"t={run.output.time:.1f} s of {seconds:g} s ({run.output.time / wall:.1f}x real time)")
    run.events.append({"step": steps, "source": "in_process", "level": 20, "kind": "finished",
                       "detail": f"finished {steps} steps ({seconds:g} s simulated) in "
                                 f"{time.monotonic() - start:.1f} s wall, in process"})
    if record is not None:
        write_run(run, book, Path(record))
    return run
