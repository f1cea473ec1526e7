"""Start a checked node graph: each node in its own OS process, or all composed in one.

Each node becomes ``EXECUTABLE [args] --ros-args -r __node:=NAME -r __ns:=NS
--params-file F ... -r FROM:=TO ... -p NAME:=VALUE ...`` as launch_ros builds it
(``launch_ros/actions/node.py``); rcl then applies names, parameters (wildcards
included) and remappings itself.
"""
import importlib.metadata
import logging
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Dict, Iterable, Iterator, List, Mapping, Optional, Sequence, TextIO, Tuple

import psutil
import yaml
from ament_index_python.packages import get_packages_with_prefixes

from rclpy.task import Future

from hawt_core.node_role import NodeRole
from hawt_core.stop_signals import LAUNCHER_PID, stop_signals
from hawt_tools.graph_file import (Graph, GraphError, NodeSpec, ParameterFile, ParameterValues, ProgramSpec,
                                   did_you_mean, package_prefix)
from hawt_tools.node_parameters import typed_override
from hawt_tools.node_registry import implied_parameters
from hawt_node.node_main import first_done, run_nodes

__all__ = [
    "LaunchFailure",
    "executable_path",
    "launcher_parameters",
    "class_role",
    "describe_exit",
    "ros_arguments",
    "ProcessGraph",
    "run_composed",
]

Overrides = Dict[str, List[Tuple[str, str]]]

FOLDER_PREFIX = "hawt_launch_"
"""Name prefix of a launcher's temporary folder (then its process id)."""


class LaunchFailure(RuntimeError):
    """The graph started but could not run to its end (a node died, a process would not stop)."""


def executable_path(graph: Graph, spec: NodeSpec) -> Path:
    """The file that runs ``spec``: ``<prefix>/lib/<pkg>/<exec>`` (GraphError naming the line if absent)."""
    where = f"{graph.path}:{spec.line}"
    prefix = package_prefix(spec.package)
    if prefix is None:
        raise GraphError(f"{where}: node {spec.name!r}: package {spec.package!r} not found"
                         + did_you_mean(spec.package, sorted(get_packages_with_prefixes())))
    folder = Path(prefix) / "lib" / spec.package
    path = folder / spec.executable
    if not (path.is_file() and os.access(path, os.X_OK)):
        available = sorted(p.name for p in folder.iterdir() if os.access(p, os.X_OK)) if folder.is_dir() else []
        raise GraphError(f"{where}: node {spec.name!r}: package {spec.package!r} has no executable "
                         f"{spec.executable!r}" + (did_you_mean(spec.executable, available) if available else ""))
    return path


@contextmanager
def parameter_folder() -> Iterator[str]:
    """A temporary folder for the nodes' parameter files, named after this launcher's process id.

    A launcher killed with SIGKILL cannot remove its folder; the next launch removes every such
    folder whose launcher no longer runs.
    """
    for stale in Path(tempfile.gettempdir()).glob(f"{FOLDER_PREFIX}*_*"):
        pid = stale.name[len(FOLDER_PREFIX):].split("_")[0]
        if pid.isdigit() and not psutil.pid_exists(int(pid)):
            shutil.rmtree(stale, ignore_errors=True)
    with tempfile.TemporaryDirectory(prefix=f"{FOLDER_PREFIX}{os.getpid()}_") as folder:
        yield folder


def _report_event(events: Optional[Callable[[str, int, str, str], None]], namespaces: Iterable[str], level: int,
                  kind: str, detail: str) -> None:
    """Give ``events`` (hawt_tools.launch_events, if any) one event for each namespace, once each."""
    if events is not None:
        for namespace in sorted(set(namespaces)):
            events(namespace, level, kind, detail)


def launcher_parameters(graph: Graph, recorded: bool, record_optional: bool = False) -> Dict[str, object]:
    """The parameters ``hawt launch`` gives every node (a node that does not declare one ignores it).

    ``wait_for_recorder`` when the run is recorded (no message is sent before the recorder reads it), and
    ``recorder_required`` unless the recording is optional (a held plant waits for a respawned recorder);
    ``await_schedule`` when the graph has a controller_manager (no step is answered before its schedule is
    known, so every scheduled switch comes at its step in every node).
    """
    values: Dict[str, object] = {"wait_for_recorder": True} if recorded else {}
    if recorded and not record_optional:
        values["recorder_required"] = True
    if any(spec.executable == "controller_manager" for spec in graph.nodes):
        values["await_schedule"] = True
    return values


def _nest(values: Sequence[Tuple[str, object]]) -> Dict[str, object]:
    """``[('gains.ki', 1.0)]`` -> ``{'gains': {'ki': 1.0}}``, the parameter-file layout of dotted names."""
    tree: Dict[str, object] = {}
    for name, value in values:
        *parents, leaf = name.split(".")
        level = tree
        for parent in parents:
            level = level.setdefault(parent, {})
        level[leaf] = value
    return tree


def ros_arguments(graph: Graph, spec: NodeSpec, overrides: Overrides, parameter_dir: Path,
                  global_parameters: Mapping[str, object] = ()) -> List[str]:
    """The ``--ros-args ...`` list of node ``spec`` of ``graph``; inline parameters are written to files in
    ``parameter_dir``. The launcher's ``global_parameters`` and what the graph implies for this node
    (hawt_tools.node_registry.implied_parameters) come first, so the graph's own entries win."""
    arguments = ["--ros-args", "-r", f"__node:={spec.name}"]
    if spec.namespace:
        arguments += ["-r", f"__ns:=/{spec.namespace.strip('/')}"]
    given = {**global_parameters, **implied_parameters(graph, spec, overrides)}
    sources = [ParameterValues(tuple(given.items()))] if given else []
    sources += list(spec.parameters)
    for index, source in enumerate(sources):
        if isinstance(source, ParameterFile):
            arguments += ["--params-file", str(source.path)]
        else:
            path = parameter_dir / f"{spec.label.strip('/').replace('/', '__')}_{index}.yaml"
            path.write_text(yaml.safe_dump({"/**": {"ros__parameters": _nest(source.values)}}))
            arguments += ["--params-file", str(path)]
    for source_name, target in spec.remaps:
        arguments += ["-r", f"{source_name}:={target}"]
    arguments += list(spec.ros_arguments)
    if spec.label in overrides:
        # rcl applies the matching node-name keys in the order they first appear over all files
        # (hawt_tools.node_parameters); a last file under a key of its own, the node's
        # full name, makes command-line overrides win over every file of the graph.
        path = parameter_dir / f"{spec.label.strip('/').replace('/', '__')}_overrides.yaml"
        values = [(name, typed_override(value)) for name, value in overrides[spec.label]]
        path.write_text(yaml.safe_dump({spec.label: {"ros__parameters": _nest(values)}}))
        arguments += ["--params-file", str(path)]
    return arguments


def describe_exit(code: int) -> str:
    if code < 0:
        try:
            return f"killed by {signal.Signals(-code).name}"
        except ValueError:
            return f"killed by signal {-code}"
    return f"exit code {code}"


@dataclass
class _Process:
    spec: "NodeSpec | ProgramSpec"
    command: List[str]
    popen: Optional[subprocess.Popen] = None
    pump: Optional[threading.Thread] = None
    retries: int = 0
    restart_at: Optional[float] = None
    finished: bool = False


@dataclass
class ProcessGraph:
    """A graph whose nodes run as separate OS processes, with prefixed output and clean shutdown."""

    graph: Graph
    overrides: Overrides = field(default_factory=dict)
    global_parameters: Mapping[str, object] = field(default_factory=dict)
    output: TextIO = sys.stdout
    environment: Mapping[str, str] = field(default_factory=dict)
    """Variables set for every node process (over this process's environment, under the node's own ``env``)."""
    events: Optional[Callable[[str, int, str, str], None]] = None
    """``events(namespace, level, kind, detail)`` (hawt_tools.launch_events): a death, a respawn and a stop from
    outside (interruption, wall-clock duration) go there too, before any node is stopped; levels as logging's."""

    def __post_init__(self) -> None:
        self._executables = [executable_path(self.graph, spec) for spec in self.graph.nodes]
        self._lock = threading.Lock()
        self._stop_reason: Optional[Tuple[int, str]] = None
        self._stop_event: Optional[Tuple[int, str]] = None

    def _say(self, label: str, line: str) -> None:
        with self._lock:
            self.output.write(f"[{label}] {line}\n")
            self.output.flush()

    def _pump(self, process: _Process) -> None:
        for raw in process.popen.stdout:
            self._say(process.spec.label, raw.decode(errors="replace").rstrip("\n"))

    def _start(self, process: _Process) -> None:
        env = {**os.environ, "PYTHONUNBUFFERED": "1", LAUNCHER_PID: str(os.getpid()), **self.environment,
               **dict(process.spec.env)}
        process.popen = subprocess.Popen(process.command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                         stdin=subprocess.DEVNULL, env=env, start_new_session=True,
                                         cwd=getattr(process.spec, "cwd", "") or None)
        process.pump = threading.Thread(target=self._pump, args=(process,), daemon=True)
        process.pump.start()
        process.finished = False
        process.restart_at = None

    def request_stop(self, code: int = 0, reason: str = "", event: Optional[Tuple[int, str]] = None) -> None:
        """Ask the run loop to shut the graph down and return ``code``; ``event`` (level, kind) is reported to
        every namespace of the graph before the nodes are stopped."""
        if self._stop_reason is None:
            self._stop_reason, self._stop_event = (code, reason), event

    def _namespaces_of(self, spec: "NodeSpec | ProgramSpec") -> List[str]:
        """Where an event about ``spec`` goes: a node's namespace; for a program, every namespace of the graph."""
        return [spec.full_namespace] if isinstance(spec, NodeSpec) else [s.full_namespace for s in self.graph.nodes]

    def _on_exit(self, process: _Process, now: float) -> None:
        spec, code = process.spec, process.popen.returncode
        process.finished = True
        if spec.respawn and (spec.respawn_max_retries < 0 or process.retries < spec.respawn_max_retries):
            process.retries += 1
            process.restart_at = now + spec.respawn_delay
            line = f"{spec.label} ended ({describe_exit(code)}); respawning in {spec.respawn_delay:g} s " \
                   f"(respawn {process.retries})"
            self._say("hawt launch", line)
            _report_event(self.events, self._namespaces_of(spec), logging.WARNING, "node_respawn", line)
        elif code == 0:
            self._say("hawt launch", f"{spec.label} finished")
            if spec.shutdown_on_exit:
                self.request_stop(0, f"{spec.label} finished (on_exit: shutdown)")
        else:
            reason = f"{'node ' if isinstance(spec, NodeSpec) else ''}{spec.label} died unexpectedly " \
                     f"({describe_exit(code)})"
            _report_event(self.events, self._namespaces_of(spec), logging.ERROR, "node_died",
                          f"{reason}; stopping the graph")
            self.request_stop(1, reason)

    def run(self, duration: Optional[float] = None) -> int:
        """Start every node, supervise them until done, then stop them all; returns the exit code.

        Parameters
        ----------
        duration : float, optional
            Wall-clock seconds after which the graph is stopped (None: until a node with
            ``on_exit: shutdown`` finishes, every node has finished, a node dies, or SIGINT/SIGTERM).
        """
        with stop_signals(lambda *_: self.request_stop(0, "interrupted", (logging.WARNING, "interrupted"))), \
                parameter_folder() as parameter_dir:
            processes = [
                _Process(spec, [str(exe), *spec.arguments,
                                *ros_arguments(self.graph, spec, self.overrides, Path(parameter_dir),
                                               self.global_parameters)])
                for spec, exe in zip(self.graph.nodes, self._executables)]
            processes += [_Process(program, list(program.command)) for program in self.graph.programs]
            try:
                for process in processes:
                    self._start(process)
                self._supervise(processes, duration)
                if self._stop_event is not None:
                    _report_event(self.events, (spec.full_namespace for spec in self.graph.nodes), *self._stop_event,
                                  f"hawt launch stopped the graph: {self._stop_reason[1]}")
            finally:
                self._stop_all(processes)
        code, reason = self._stop_reason or (0, "")
        if code:
            raise LaunchFailure(reason)
        if reason:
            self._say("hawt launch", f"stopped: {reason}")
        return code

    def _supervise(self, processes: List[_Process], duration: Optional[float]) -> None:
        deadline = None if duration is None else time.monotonic() + duration
        while self._stop_reason is None:
            now = time.monotonic()
            for process in processes:
                if not process.finished and process.popen.poll() is not None:
                    self._on_exit(process, now)
                if process.restart_at is not None and now >= process.restart_at and self._stop_reason is None:
                    self._start(process)
            if all(p.finished and p.restart_at is None for p in processes):
                self.request_stop(0, "every node finished")
            elif deadline is not None and now >= deadline:
                self.request_stop(0, f"wall-clock --duration of {duration:g} s reached",
                                  (logging.INFO, "wall_clock_stop"))
            time.sleep(0.02)

    def _stop_all(self, processes: List[_Process]) -> None:
        """SIGINT every process group, then SIGTERM after its sigterm_timeout, then SIGKILL."""
        live = [p for p in processes if p.popen is not None and p.popen.poll() is None]
        for sig, timeout in ((signal.SIGINT, None), (signal.SIGTERM, 5.0), (signal.SIGKILL, 5.0)):
            for process in live:
                try:
                    os.killpg(process.popen.pid, sig)
                except ProcessLookupError:
                    pass
            end = time.monotonic() + (timeout if timeout is not None else
                                      max((p.spec.sigterm_timeout for p in live), default=0.0))
            while time.monotonic() < end and any(p.popen.poll() is None for p in live):
                time.sleep(0.02)
            live = [p for p in live if p.popen.poll() is None]
            if not live:
                break
            if sig != signal.SIGKILL:
                self._say("hawt launch", f"{', '.join(p.spec.label for p in live)} did not stop on "
                                         f"{sig.name}; escalating")
        for process in processes:
            if process.popen is not None:
                process.popen.wait()
                if process.pump is not None:
                    process.pump.join(timeout=2.0)


def node_class(graph: Graph, spec: NodeSpec) -> type:
    """The node class behind an executable, from its console-script entry point's ``node_class``."""
    where = f"{graph.path}:{spec.line}"
    try:
        entry_points = importlib.metadata.distribution(spec.package.replace("_", "-")).entry_points
    except importlib.metadata.PackageNotFoundError:
        raise GraphError(f"{where}: node {spec.name!r}: package {spec.package!r} is not a Python package "
                         "and cannot run composed") from None
    for entry_point in entry_points:
        if entry_point.group == "console_scripts" and entry_point.name == spec.executable:
            node_class = getattr(entry_point.load(), "node_class", None)
            if node_class is None:
                break
            return node_class
    raise GraphError(f"{where}: node {spec.name!r}: executable {spec.executable!r} of {spec.package!r} "
                     "cannot run composed (its entry point has no node_class)")


def class_role(graph: Graph, spec: NodeSpec) -> Optional[NodeRole]:
    """The role of a node no package registers, read off its class (``PARAMETERS``, ``check_parameters``), for the
    parameter check of ``hawt launch`` (hawt_tools.parameter_check); None for a node without a table."""
    try:
        cls = node_class(graph, spec)
    except GraphError:
        return None  # not a Python node with a node_class: started unchecked
    table = getattr(cls, "PARAMETERS", None)
    return None if table is None else NodeRole("other", tuple(table), getattr(cls, "check_parameters", None))


def run_composed(graph: Graph, overrides: Overrides, duration: Optional[float] = None,
                 global_parameters: Mapping[str, object] = (),
                 events: Optional[Callable[[str, int, str, str], None]] = None) -> int:
    """Run every node of the graph in this process on one executor; returns the exit code.

    Stops when a node with ``on_exit: shutdown`` is done, after ``duration`` wall
    seconds, or on SIGINT/SIGTERM; the last two are reported to ``events`` (as ProcessGraph does).
    """
    graph.refuse_programs("--composed")
    classes = [node_class(graph, spec) for spec in graph.nodes]
    for spec in graph.nodes:
        executable_path(graph, spec)
    with parameter_folder() as parameter_dir:
        def make_nodes() -> list:
            return [node_class(cli_args=ros_arguments(graph, spec, overrides, Path(parameter_dir), global_parameters))
                    for spec, node_class in zip(graph.nodes, classes)]

        def ending(nodes) -> Optional[Future]:
            return first_done([n for n, s in zip(nodes, graph.nodes) if s.shutdown_on_exit])
        ended = run_nodes(make_nodes, ending, timeout=duration)
    stop = {"signal": (logging.WARNING, "interrupted", "interrupted"),
            "timeout": (logging.INFO, "wall_clock_stop", f"wall-clock --duration of {duration or 0:g} s reached")
            }.get(ended)
    if stop is not None:
        level, kind, reason = stop
        _report_event(events, (spec.full_namespace for spec in graph.nodes), level, kind,
                f"hawt launch stopped the graph: {reason}")
        print(f"[hawt launch] stopped: {reason}", flush=True)
    return 0
