"""Node graphs in the ROS 2 YAML launch format, and ROS 2 parameter files, read and checked.

A graph file has one root key ``launch`` holding a list of actions (launch_yaml's
format, see ``ros2/launch`` ``launch_yaml/parser.py``)::

    launch:
    - arg: {name: rate, default: "100.0"}
    - node:
        pkg: hawt_tools
        exec: relay
        name: relay
        namespace: wt1
        param:
        - {name: gain, value: 2.0}
        - {from: "$(dirname)/relay.yaml"}
        remap:
        - {from: in, to: loads}

Supported actions: ``arg``, ``node`` and ``executable``. A ``node`` runs an executable its package installs
(``pkg``/``exec``, no path); any other program needs an explicit ``executable`` action, as in ROS 2 launch::

    - executable: {cmd: "$(find-pkg-prefix my_tools)/bin/logger --out $(var out)", name: logger}

Its ``cmd`` is split into words as a shell would (``shlex``) but run without a shell, so no shell syntax is
interpreted; the program must exist when the graph is read. Only ``hawt launch`` (separate processes) runs
``executable`` actions; ``hawt run``, ``--composed`` and campaigns, which run ROS nodes in one process, refuse
such a graph. Supported substitutions: ``$(var NAME)``,
``$(env NAME [DEFAULT])``, ``$(find-pkg-share PKG)``, ``$(find-pkg-prefix PKG)``,
``$(dirname)``, ``$(filename)`` and hawt's ``$(turbine-tuning TURBINE KIND)`` (a turbine's controller
tuning file, :func:`hawt_controllers.design.tunings.tuning_file`, as an absolute path: a TURBINE folder or file is
relative to the working directory, :func:`resolve_turbine`); a substitution may hold others, e.g.
``$(turbine-tuning $(var turbine) cpc)``, expanded innermost first. Everything is checked before a process starts;
an error is a :class:`GraphError` whose one-line message names the file, the line
and the key at fault.
"""
import difflib
import os
import re
import shlex
import shutil
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple

import yaml

from hawt_core.yaml_text import SAFE_LOADER, safe_load

__all__ = [
    "GraphError",
    "NodeSpec",
    "Graph",
    "ParameterValues",
    "ParameterFile",
    "load_graph",
    "check_parameter_file",
    "did_you_mean",
    "load_marked_yaml",
    "ProgramSpec",
    "ArgumentSpec",
    "declared_arguments",
    "resolve_turbine",
]

NODE_KEYS = (
    "pkg", "exec", "name", "namespace", "param", "remap", "args", "ros_args", "respawn",
    "respawn_delay", "respawn_max_retries", "on_exit", "output", "env", "sigterm_timeout",
)
PROGRAM_KEYS = ("cmd", "name", "cwd", "env", "respawn", "respawn_delay", "respawn_max_retries", "on_exit",
                "sigterm_timeout", "output", "shell")
ACTIONS = ("arg", "node", "executable")
_PARAMETER_SCALARS = (bool, int, float, str)


class GraphError(ValueError):
    """A graph or parameter file that cannot be run; the message names file, line and key."""


@dataclass(frozen=True)
class ParameterValues:
    """Inline ``{name, value}`` parameters of a node, in file order."""

    values: Tuple[Tuple[str, Any], ...]


@dataclass(frozen=True)
class ParameterFile:
    """A ``{from: FILE}`` parameter file of a node (checked by :func:`check_parameter_file`)."""

    path: Path


@dataclass(frozen=True)
class NodeSpec:
    """One ``node`` action: what to start and with which ROS arguments."""

    package: str
    executable: str
    name: str
    namespace: str
    parameters: Tuple[Any, ...] = ()
    remaps: Tuple[Tuple[str, str], ...] = ()
    arguments: Tuple[str, ...] = ()
    ros_arguments: Tuple[str, ...] = ()
    respawn: bool = False
    respawn_delay: float = 0.0
    respawn_max_retries: int = -1
    shutdown_on_exit: bool = False
    sigterm_timeout: float = 5.0
    env: Tuple[Tuple[str, str], ...] = ()
    line: int = 0

    @property
    def full_namespace(self) -> str:
        """The node's namespace, fully qualified (``/wt1``, or ``/`` for none)."""
        return "/" + self.namespace.strip("/")

    @property
    def label(self) -> str:
        """The node's fully qualified name, as ``hawt list`` shows it."""
        return f"{self.full_namespace.rstrip('/')}/{self.name}"


@dataclass(frozen=True)
class ProgramSpec:
    """One ``executable`` action: a program that is not a package's node, run by ``hawt launch`` only."""

    name: str
    command: Tuple[str, ...]
    cwd: str = ""
    env: Tuple[Tuple[str, str], ...] = ()
    respawn: bool = False
    respawn_delay: float = 0.0
    respawn_max_retries: int = -1
    shutdown_on_exit: bool = False
    sigterm_timeout: float = 5.0
    line: int = 0

    @property
    def label(self) -> str:
        """How the launcher names it in its output: ``program NAME``."""
        return f"program {self.name}"


@dataclass(frozen=True)
class Graph:
    """A checked graph file: its nodes and programs (``executable`` actions) in file order."""

    path: Path
    nodes: Tuple[NodeSpec, ...]
    arguments: Dict[str, str] = field(default_factory=dict)
    programs: Tuple[ProgramSpec, ...] = ()

    def refuse_programs(self, engine: str) -> None:
        """Raise GraphError if the graph has an ``executable`` action, which ``engine`` cannot run."""
        if self.programs:
            program = self.programs[0]
            raise GraphError(f"{self.path}:{program.line}: the 'executable' action {program.name!r} runs only "
                             f"under hawt launch (separate processes), not {engine}")

    def node(self, name: str) -> NodeSpec:
        """The node called ``name`` (plain name or fully qualified)."""
        for spec in self.nodes:
            if name in (spec.name, spec.label):
                return spec
        raise GraphError(f"{self.path}: no node named {name!r} in the graph "
                         f"(nodes: {', '.join(s.label for s in self.nodes)})")


@dataclass(frozen=True)
class ArgumentSpec:
    """One ``arg`` action as written: its name, its default (None if it has none) and its description."""

    name: str
    default: Optional[str]
    description: str = ""


class _Map(dict):
    """A YAML mapping that remembers the line of each of its keys."""

    line = 0
    key_lines: Dict[Any, int]


def launch_arguments(words: Sequence[str], where: str = "launch argument") -> Dict[str, str]:
    """``NAME:=VALUE`` words (as ``ros2 launch`` takes them) as a dict; GraphError ``<where> 'word': expected
    NAME:=VALUE`` for one without ``:=`` or a name."""
    arguments = {}
    for word in words:
        name, sep, value = word.partition(":=")
        if not sep or not name:
            raise GraphError(f"{where} {word!r}: expected NAME:=VALUE")
        arguments[name] = value
    return arguments


_EXPONENT_FLOAT = re.compile(r"^[-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)[eE][-+]?[0-9]+$")
"""A float with an exponent but no dot (8e-11, 1E5): YAML 1.2 and rcl's parameter parser read it as a number,
PyYAML's YAML 1.1 as text."""


def yaml_value(text: str) -> Any:
    """The value of a parameter's text as YAML types it (launch_ros reads graph and ``-p`` values so), except that a
    float written with an exponent and no dot, alone or in a list, is a float, as rcl's own parser has it
    (``--ros-args -p gain:=8e-11`` is a double) where PyYAML keeps the text ('8e-11')."""
    def number(value: Any) -> Any:
        if isinstance(value, str) and _EXPONENT_FLOAT.match(value):
            return float(value)
        return [number(item) for item in value] if isinstance(value, list) else value
    return number(safe_load(text))


class _LineLoader(SAFE_LOADER):
    """SafeLoader whose mappings remember their lines and refuse duplicate keys (libyaml's parser where PyYAML has
    it: a graph's files parse several times faster)."""


def _construct_mapping(loader: _LineLoader, node: yaml.MappingNode) -> _Map:
    loader.flatten_mapping(node)
    mapping = _Map()
    mapping.line = node.start_mark.line + 1
    mapping.key_lines = {}
    for key_node, value_node in node.value:
        key = loader.construct_object(key_node, deep=True)
        line = key_node.start_mark.line + 1
        if key in mapping:
            raise GraphError(f"{loader.name}:{line}: duplicate key {key!r}")
        mapping[key] = loader.construct_object(value_node, deep=True)
        mapping.key_lines[key] = line
    return mapping


_LineLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_mapping)


def load_marked_yaml(path: Path) -> Any:
    """Parse a YAML file whose mappings remember the line of each key (``.line``, ``.key_lines``), refusing
    duplicate keys; syntax errors become one-line GraphErrors with the position."""
    try:
        text = path.read_text()
    except OSError as error:
        raise GraphError(f"{path}: cannot read ({error.strerror})") from None
    loader = _LineLoader(text)
    loader.name = str(path)
    try:
        return loader.get_single_data()
    except yaml.MarkedYAMLError as error:
        mark = error.problem_mark or error.context_mark
        where = f"{path}:{mark.line + 1}:{mark.column + 1}" if mark else str(path)
        raise GraphError(f"{where}: YAML error: {error.problem or error.context}") from None
    finally:
        loader.dispose()


def did_you_mean(word: str, choices: Sequence[str]) -> str:
    """The hint " (did you mean X?)" for the closest choice, else the list of choices."""
    close = difflib.get_close_matches(str(word), choices, n=1)
    return f" (did you mean {close[0]!r}?)" if close else f" (expected one of: {', '.join(choices)})"


def resolve_turbine(turbine: str, where: str) -> str:
    """A turbine as every engine takes it: a packaged turbine's name as it is, else the absolute path of the folder or
    definition file ``turbine`` names relative to the working directory (never to a graph's folder: a tuning file
    found from it is an absolute path, so a graph's ``{from: FILE}`` reads it from where the turbine is).

    Raises
    ------
    GraphError
        ``WHERE: turbine 'iea15': no packaged turbine of that name (packaged: …) and no folder or file /cwd/iea15``,
        or a folder without ``turbine.yaml``.
    """
    from hawt_plant.turbine import PACKAGED_TURBINES

    if turbine in PACKAGED_TURBINES:
        return turbine
    path = Path(turbine).resolve()
    if not path.exists():
        raise GraphError(f"{where}: turbine {turbine!r}: no packaged turbine of that name (packaged: "
                         f"{', '.join(PACKAGED_TURBINES)}) and no folder or file {path}")
    if path.is_dir() and not (path / "turbine.yaml").is_file():
        raise GraphError(f"{where}: turbine {turbine!r}: the folder {path} has no turbine.yaml (hawt turbine import "
                         "writes one)")
    return str(path)


SUBSTITUTIONS = ("var", "env", "find-pkg-share", "find-pkg-prefix", "dirname", "filename", "turbine-tuning")


class _Substitutor:
    """Expands ``$(...)`` substitutions in the strings of one graph file."""

    _PATTERN = re.compile(r"\$\(([a-z-]+)((?:\s+[^)\s$]+)*)\s*\)")  # innermost first: no "$" in its words

    def __init__(self, path: Path, variables: Mapping[str, str],
                 package_prefix: Callable[[str], Optional[str]]) -> None:
        self.path = path
        self.variables = variables
        self.package_prefix = package_prefix

    def __call__(self, value: Any, line: int) -> Any:
        if isinstance(value, str):
            expanded = self._PATTERN.sub(lambda m: self._one(m.group(1), m.group(2).split(), line), value)
            return expanded if expanded == value else self(expanded, line)  # then the ones around them
        if isinstance(value, list):
            return [self(v, line) for v in value]
        return value

    def _one(self, kind: str, words: List[str], line: int) -> str:
        where = f"{self.path}:{line}"
        if kind == "var":
            if len(words) != 1 or words[0] not in self.variables:
                raise GraphError(f"{where}: $(var {' '.join(words)}): no launch argument of that name"
                                 + did_you_mean(' '.join(words), list(self.variables)))
            return self.variables[words[0]]
        if kind == "env":
            if not words or len(words) > 2:
                raise GraphError(f"{where}: $(env NAME [DEFAULT]) takes one or two words")
            if words[0] not in os.environ and len(words) == 1:
                raise GraphError(f"{where}: $(env {words[0]}): environment variable not set and no default")
            return os.environ.get(words[0], words[-1])
        if kind in ("find-pkg-share", "find-pkg-prefix"):
            prefix = self.package_prefix(words[0]) if len(words) == 1 else None
            if prefix is None:
                raise GraphError(f"{where}: $({kind} {' '.join(words)}): package not found")
            return str(Path(prefix) / "share" / words[0]) if kind == "find-pkg-share" else prefix
        if kind == "dirname":
            return str(self.path.parent)
        if kind == "filename":
            return str(self.path)
        if kind == "turbine-tuning":
            if len(words) != 2:
                raise GraphError(f"{where}: $(turbine-tuning TURBINE KIND) takes two words")
            from hawt_controllers.design.tunings import TuningError, tuning_file

            try:
                return str(tuning_file(resolve_turbine(words[0], where), words[1]))
            except TuningError as error:
                raise GraphError(f"{where}: {error}") from None
        raise GraphError(f"{where}: unknown substitution $({kind})" + did_you_mean(kind, SUBSTITUTIONS))


def _expect(value: Any, kind: type, where: str, what: str) -> Any:
    if not isinstance(value, kind) or (kind is int and isinstance(value, bool)):
        raise GraphError(f"{where}: {what} must be {kind.__name__}, found {type(value).__name__} {value!r}")
    return value


def _number(value: Any, where: str, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise GraphError(f"{where}: {what} must be a number, found {value!r}")
    try:
        return float(value)
    except ValueError:
        raise GraphError(f"{where}: {what} must be a number, found {value!r}") from None


def _boolean(value: Any, where: str, what: str) -> bool:
    text = str(value).lower()
    if text not in ("true", "false"):
        raise GraphError(f"{where}: {what} must be true or false, found {value!r}")
    return text == "true"


def _check_parameter_value(value: Any, where: str, name: str) -> None:
    """Refuse what rcl's parameter parser refuses: nested lists, mixed or empty-typed arrays, null."""
    if isinstance(value, _PARAMETER_SCALARS):
        return
    if isinstance(value, list) and value:
        kinds = {float if type(v) is int and any(type(w) is float for w in value) else type(v) for v in value}
        if len(kinds) == 1 and next(iter(kinds)) in _PARAMETER_SCALARS:
            return
    raise GraphError(f"{where}: parameter {name!r} has a value ROS 2 cannot hold ({value!r}): "
                     "use a bool, int, float, string or a non-empty list of one of those")


def check_parameter_file(path: Path) -> None:
    """Check a ROS 2 parameter file (``node: ros__parameters: ...``, wildcards allowed).

    Raises :class:`GraphError` naming the file, line and key of the first problem.
    """
    data = load_marked_yaml(path)
    if not isinstance(data, _Map) or not data:
        raise GraphError(f"{path}: a parameter file must be a mapping of node names to "
                         "'ros__parameters' (e.g. 'relay: {ros__parameters: {gain: 2.0}}')")
    _check_parameter_level(path, data, depth=0)


def _check_parameter_level(path: Path, level: _Map, depth: int) -> None:
    for key, value in level.items():
        where = f"{path}:{level.key_lines[key]}"
        if key == "ros__parameters":
            if depth == 0:
                raise GraphError(f"{where}: 'ros__parameters' needs a node name above it (e.g. '/**:')")
            if not isinstance(value, _Map):
                raise GraphError(f"{where}: 'ros__parameters' must be a mapping of parameter names to values")
            _check_parameters(path, value, prefix="")
        elif isinstance(value, _Map):
            _check_parameter_level(path, value, depth + 1)
        else:
            raise GraphError(f"{where}: {key!r} must hold 'ros__parameters' (or a further namespace level), "
                             f"found {value!r}")


def _check_parameters(path: Path, parameters: _Map, prefix: str) -> None:
    for name, value in parameters.items():
        where = f"{path}:{parameters.key_lines[name]}"
        if isinstance(value, _Map):
            _check_parameters(path, value, prefix=f"{prefix}{name}.")
        else:
            _check_parameter_value(value, where, prefix + str(name))


def _parse_parameters(entries: Any, where: str, line: int, substitute: _Substitutor,
                      path: Path) -> Tuple[Any, ...]:
    if not isinstance(entries, list):
        raise GraphError(f"{where}: 'param' must be a list of {{name, value}} or {{from: FILE}} entries")
    sources: List[Any] = []
    inline: List[Tuple[str, Any]] = []
    for entry in entries:
        entry_where = f"{path}:{getattr(entry, 'line', line)}"
        if not isinstance(entry, _Map):
            raise GraphError(f"{entry_where}: a 'param' entry must be {{name, value}} or {{from: FILE}}, found {entry!r}")
        keys = set(entry)
        if keys == {"from"} or keys == {"from", "allow_substs"}:
            if inline:
                sources.append(ParameterValues(tuple(inline)))
                inline = []
            file = Path(substitute(_expect(entry["from"], str, entry_where, "'from'"), entry.line))
            if not file.is_absolute():
                file = path.parent / file
            if not file.is_file():
                raise GraphError(f"{entry_where}: parameter file {str(file)!r} does not exist")
            check_parameter_file(file)
            sources.append(ParameterFile(file))
        elif keys == {"name", "value"}:
            name = _expect(entry["name"], str, entry_where, "parameter 'name'")
            value = substitute(entry["value"], entry.line)
            if isinstance(entry["value"], str) and "$(" in entry["value"] and value:
                value = yaml_value(value)  # a substituted value gets its type as launch_ros gives it
            _check_parameter_value(value, entry_where, name)
            inline.append((name, value))
        else:
            unknown = sorted(keys - {"name", "value", "from"})
            raise GraphError(f"{entry_where}: a 'param' entry takes 'name' and 'value', or 'from'"
                             + (f"; unknown key {unknown[0]!r}" + did_you_mean(unknown[0], ["name", "value", "from"])
                                if unknown else f"; found only {sorted(keys)}"))
    if inline:
        sources.append(ParameterValues(tuple(inline)))
    return tuple(sources)


def _parse_remaps(entries: Any, where: str, substitute: _Substitutor, path: Path) -> Tuple[Tuple[str, str], ...]:
    if not isinstance(entries, list):
        raise GraphError(f"{where}: 'remap' must be a list of {{from, to}} entries")
    remaps = []
    for entry in entries:
        entry_where = f"{path}:{getattr(entry, 'line', 0)}"
        if not isinstance(entry, _Map) or set(entry) != {"from", "to"}:
            raise GraphError(f"{entry_where}: a 'remap' entry must be {{from: NAME, to: NAME}}, found {dict(entry) if isinstance(entry, dict) else entry!r}")
        remaps.append((str(substitute(entry["from"], entry.line)), str(substitute(entry["to"], entry.line))))
    return tuple(remaps)


def _texts(entry: "_Map", line: int, path: Path, substitute: _Substitutor) -> Tuple[Callable[[str], str],
                                                                                     Callable[..., str]]:
    """``key_where(key)`` (file:line of a key) and ``text(key, default)`` (its substituted string) of an action."""
    def key_where(key: str) -> str:
        return f"{path}:{entry.key_lines.get(key, line)}"

    def text(key: str, default: str = "") -> str:
        value = substitute(entry.get(key, default), entry.key_lines.get(key, line))
        if isinstance(value, bool) or not isinstance(value, (str, int, float)):
            raise GraphError(f"{key_where(key)}: {key!r} must be a string, found {value!r}")
        return str(value)
    return key_where, text


def _process_options(entry: "_Map", line: int, path: Path, substitute: _Substitutor) -> Dict[str, Any]:
    """What a node and a program have alike: respawn, on_exit, sigterm_timeout and env."""
    key_where, text = _texts(entry, line, path, substitute)
    on_exit = text("on_exit")
    if on_exit not in ("", "shutdown"):
        raise GraphError(f"{key_where('on_exit')}: on_exit must be 'shutdown', found {on_exit!r}")
    env_entries = entry.get("env", [])
    if not isinstance(env_entries, list) or not all(isinstance(e, _Map) and set(e) == {"name", "value"}
                                                    for e in env_entries):
        raise GraphError(f"{key_where('env')}: 'env' must be a list of {{name, value}} entries")
    return dict(
        respawn=_boolean(substitute(entry.get("respawn", False), line), key_where("respawn"), "'respawn'"),
        respawn_delay=_number(substitute(entry.get("respawn_delay", 0.0), line), key_where("respawn_delay"),
                              "'respawn_delay'"),
        respawn_max_retries=int(_number(substitute(entry.get("respawn_max_retries", -1), line),
                                        key_where("respawn_max_retries"), "'respawn_max_retries'")),
        shutdown_on_exit=on_exit == "shutdown",
        sigterm_timeout=_number(substitute(entry.get("sigterm_timeout", 5.0), line), key_where("sigterm_timeout"),
                                "'sigterm_timeout'"),
        env=tuple((str(e["name"]), str(substitute(e["value"], e.line))) for e in env_entries),
        line=line,
    )


def _check_keys(entry: Any, line: int, path: Path, kind: str, keys: Sequence[str], required: Sequence[str]) -> None:
    where = f"{path}:{line}"
    if not isinstance(entry, _Map):
        raise GraphError(f"{where}: '{kind}' must be a mapping with at least {' and '.join(map(repr, required))}")
    for key in entry:
        if key not in keys:
            raise GraphError(f"{path}:{entry.key_lines[key]}: unknown key {key!r} in {kind}" + did_you_mean(key, keys))
    for key in required:
        if key not in entry:
            raise GraphError(f"{where}: {kind} is missing {key!r}")


def _parse_node(entry: Any, line: int, path: Path, substitute: _Substitutor) -> NodeSpec:
    _check_keys(entry, line, path, "node", NODE_KEYS, ("pkg", "exec"))
    key_where, text = _texts(entry, line, path, substitute)
    executable = text("exec")
    for key, value in (("pkg", text("pkg")), ("exec", executable)):
        if not re.fullmatch(r"[A-Za-z0-9_][A-Za-z0-9_.-]*", value) or ".." in value:
            raise GraphError(f"{key_where(key)}: {key} {value!r} is not a package or executable name (no path, no "
                             "'..'): a node runs an executable its package installs; another program needs an "
                             "'executable' action")
    name = text("name", executable)
    if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", name):
        raise GraphError(f"{key_where('name')}: node name {name!r} is not a valid ROS name "
                         "(letters, digits and '_', starting with a letter)")
    namespace = text("namespace")
    if namespace and not re.fullmatch(r"/?[A-Za-z][A-Za-z0-9_]*(/[A-Za-z][A-Za-z0-9_]*)*/?", namespace):
        raise GraphError(f"{key_where('namespace')}: namespace {namespace!r} is not a valid ROS namespace")
    arguments = substitute(entry.get("args", ""), line)
    ros_arguments = substitute(entry.get("ros_args", ""), line)
    return NodeSpec(
        package=text("pkg"),
        executable=executable,
        name=name,
        namespace=namespace,
        parameters=_parse_parameters(entry.get("param", []), key_where("param"), line, substitute, path),
        remaps=_parse_remaps(entry.get("remap", []), key_where("remap"), substitute, path),
        arguments=tuple(str(arguments).split()),
        ros_arguments=tuple(str(ros_arguments).split()),
        **_process_options(entry, line, path, substitute),
    )


def _parse_program(entry: Any, line: int, path: Path, substitute: _Substitutor) -> ProgramSpec:
    """An ``executable`` action: ``cmd`` split into words (no shell), its program found now."""
    _check_keys(entry, line, path, "executable", PROGRAM_KEYS, ("cmd",))
    key_where, text = _texts(entry, line, path, substitute)
    if _boolean(substitute(entry.get("shell", False), line), key_where("shell"), "'shell'"):
        raise GraphError(f"{key_where('shell')}: shell: true is not supported: hawt runs an 'executable' action's "
                         "cmd without a shell")
    cmd = text("cmd")
    try:
        command = tuple(shlex.split(cmd))
    except ValueError as error:
        raise GraphError(f"{key_where('cmd')}: cmd: {error}") from None
    if not command:
        raise GraphError(f"{key_where('cmd')}: cmd is empty")
    program = shutil.which(command[0])
    if program is None:
        raise GraphError(f"{key_where('cmd')}: cmd: no program {command[0]!r} (not an executable file, nor on PATH)")
    name = text("name", Path(command[0]).name)
    cwd = text("cwd")
    if cwd and not Path(cwd).is_dir():
        raise GraphError(f"{key_where('cwd')}: cwd {cwd!r} is not a folder")
    return ProgramSpec(name=name, command=(program, *command[1:]), cwd=cwd,
                       **_process_options(entry, line, path, substitute))


def declared_arguments(path: Path) -> Tuple[ArgumentSpec, ...]:
    """The launch arguments a graph file declares (its ``arg`` actions), in file order, defaults unsubstituted.

    Only the ``arg`` actions are read; :func:`load_graph` checks the whole file.
    """
    path = Path(path).resolve()
    data = load_marked_yaml(path)
    actions = data.get("launch") if isinstance(data, _Map) else None
    if not isinstance(actions, list):
        raise GraphError(f"{path}:1: a graph file has one root key 'launch' holding a list of actions")
    declared = []
    for action in actions:
        body = action.get("arg") if isinstance(action, _Map) else None
        if isinstance(body, _Map) and "name" in body:
            default = body.get("default")
            declared.append(ArgumentSpec(str(body["name"]), None if default is None else str(default),
                                         str(body.get("description", ""))))
    return tuple(declared)


def load_graph(path: Path, arguments: Optional[Mapping[str, str]] = None,
               prefix_of: Optional[Callable[[str], Optional[str]]] = None) -> Graph:
    """Read and check a graph file.

    Parameters
    ----------
    path : Path
        The YAML launch file.
    arguments : mapping of str to str, optional
        Launch arguments given on the command line (``NAME:=VALUE``); each must be
        declared by an ``arg`` action of the file.
    prefix_of : callable, optional
        Maps a package name to its install prefix, or None if there is no such package;
        used by ``$(find-pkg-share ...)`` (default: :func:`package_prefix`, the installed packages).

    Raises
    ------
    GraphError
        With the file, line and key of the first problem found.
    """
    path = Path(path).resolve()
    given = dict(arguments or {})
    data = load_marked_yaml(path)
    if not isinstance(data, _Map) or list(data) != ["launch"]:
        found = list(data) if isinstance(data, dict) else type(data).__name__
        raise GraphError(f"{path}:1: a graph file has exactly one root key 'launch', found {found}")
    actions = data["launch"]
    if not isinstance(actions, list):
        raise GraphError(f"{path}:{data.key_lines['launch']}: 'launch' must be a list of actions")
    variables: Dict[str, str] = {}
    declared = []
    substitute = _Substitutor(path, variables, prefix_of or package_prefix)
    nodes: List[NodeSpec] = []
    programs: List[ProgramSpec] = []
    for action in actions:
        if not isinstance(action, _Map) or len(action) != 1:
            raise GraphError(f"{path}:{getattr(action, 'line', data.key_lines['launch'])}: each entry of 'launch' "
                             f"must be one action ({', '.join(ACTIONS)})")
        (kind, body), = action.items()
        line = action.key_lines[kind]
        if kind == "arg":
            if not isinstance(body, _Map) or "name" not in body or set(body) - {"name", "default", "description"}:
                raise GraphError(f"{path}:{line}: 'arg' takes 'name', 'default' and 'description'")
            name = str(body["name"])
            declared.append(name)
            if name in given:
                variables[name] = given[name]
            elif "default" in body:
                variables[name] = str(substitute(body["default"], line))
            else:
                raise GraphError(f"{path}:{line}: launch argument {name!r} has no default and was not given "
                                 f"(pass {name}:=VALUE)")
        elif kind == "node":
            nodes.append(_parse_node(body, line, path, substitute))
        elif kind == "executable":
            programs.append(_parse_program(body, line, path, substitute))
        else:
            raise GraphError(f"{path}:{line}: unsupported action {kind!r}" + did_you_mean(kind, ACTIONS))
    for name in given:
        if name not in declared:
            raise GraphError(f"{path}: launch argument {name!r} is not declared by the graph"
                             + did_you_mean(name, declared))
    seen: Dict[str, int] = {}
    for spec in nodes:
        if spec.label in seen:
            raise GraphError(f"{path}:{spec.line}: a second node named {spec.label!r} (first at line {seen[spec.label]})")
        seen[spec.label] = spec.line
    if not nodes:
        raise GraphError(f"{path}: the graph has no node")
    for program in programs:
        if program.label in seen:
            raise GraphError(f"{path}:{program.line}: a second program named {program.name!r} "
                             f"(first at line {seen[program.label]})")
        seen[program.label] = program.line
    return Graph(path=path, nodes=tuple(nodes), arguments=dict(variables), programs=tuple(programs))


def package_prefix(package: str) -> Optional[str]:
    """The install prefix of a package (its files under ``<prefix>/share/<package>``), or None: the ament index's
    (a ROS workspace, ``AMENT_PREFIX_PATH``), else this Python's prefix if a pip install put the package's index
    marker there (its setup's data files), so a venv without ROS finds the installed graphs too."""
    try:
        from ament_index_python.packages import PackageNotFoundError, get_package_prefix
    except ImportError:
        marker = Path(sys.prefix) / "share" / "ament_index" / "resource_index" / "packages" / package
        return sys.prefix if marker.is_file() else None
    try:
        return get_package_prefix(package)
    except (PackageNotFoundError, ValueError):
        return None


_GRAPH_PACKAGES = ("hawt_tools", "hawt_plant", "hawt_controllers")


def installed_graphs() -> Dict[str, Path]:
    """The installed graph files by name: each ``<name>.yaml`` of a hawt package's ``launch`` folder."""
    graphs: Dict[str, Path] = {}
    for package in _GRAPH_PACKAGES:
        prefix = package_prefix(package)
        folder = Path(prefix) / "share" / package / "launch" if prefix else None
        if folder and folder.is_dir():
            graphs.update((p.stem, p) for p in sorted(folder.glob("*.yaml")) if p.stem not in graphs)
    return graphs


def find_graph(name: str) -> Path:
    """A graph file: the path itself if it exists, else ``<name>.yaml`` in a hawt package's ``launch`` folder."""
    path = Path(name)
    if path.exists() or path.suffix in (".yaml", ".yml"):
        return path
    graphs = installed_graphs()
    if name in graphs:
        return graphs[name]
    raise GraphError(f"{name}: no such graph file, and no installed graph of that name"
                     + (did_you_mean(name, sorted(graphs)) if graphs else ""))


def graph_summary(path: Path) -> str:
    """What a graph file says it is: the first sentence of its leading comment after its title ('' without one); a
    sentence ends at a full stop outside parentheses (an "e.g. " inside them does not end it)."""
    lines = []
    for line in Path(path).read_text().splitlines():
        if not line.startswith("#") or line.startswith("#  "):
            break
        lines.append(line.lstrip("# ").strip())
    text, depth = " ".join(lines) + " ", 0
    for end, character in enumerate(text):
        depth += {"(": 1, ")": -1}.get(character, 0)
        if character == "." and depth == 0 and text[end + 1] == " ":
            text = text[:end]
            break
    return text.split(": ", 1)[-1].rstrip(".").strip()
