"""The parameters a node of a graph starts with, resolved as rcl resolves the launcher's parameter files.

One resolution for every engine: the in-process runner builds its cores from it
(hawt_tools.in_process) and the launcher checks each node's values against the node's
table before anything starts (hawt_tools.parameter_check). Each value keeps where it
came from (:class:`Origin`), so a refusal can name the file or the ``-p`` option.
"""
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple


from hawt_core.yaml_text import safe_load
from hawt_tools.graph_file import Graph, GraphError, NodeSpec, ParameterFile, ParameterValues, yaml_value

__all__ = ["Origin", "node_parameters", "node_parameter_sources", "parse_overrides", "typed_override"]

Overrides = Mapping[str, Sequence[Tuple[str, Any]]]


@dataclass(frozen=True)
class Origin:
    """Where a node's parameter value came from.

    ``kind`` is ``graph`` (an inline ``{name, value}`` of the graph file), ``file`` (a
    ``{from: FILE}`` parameter file, ``path``), ``override`` (a ``-p NODE.PARAM:=VALUE``
    option) or ``global`` (a parameter the launcher gives every node, e.g. ``wait_for_recorder``).
    """

    kind: str
    path: Optional[Path] = None


def typed_override(text: str) -> Any:
    """A ``-p`` value with the type YAML gives it, as rcl types it ('' and a null stay the text; 8e-11 a float:
    :func:`~hawt_tools.graph_file.yaml_value`)."""
    value = yaml_value(text) if text else text
    return text if value is None else value


def _pattern(key: str) -> "re.Pattern":
    """rcl's node-name wildcards: ``/**`` any number of namespace tokens, ``*`` one token."""
    key = key if key.startswith("/") else "/" + key
    text = re.escape(key).replace(r"/\*\*", "(?:/[^/]+)*").replace(r"\*", "[^/]*")
    return re.compile(f"^{text}$")


def _flatten(tree: Mapping[str, Any], prefix: str = "") -> Dict[str, Any]:
    flat: Dict[str, Any] = {}
    for name, value in tree.items():
        if isinstance(value, dict):
            flat.update(_flatten(value, f"{prefix}{name}."))
        else:
            flat[f"{prefix}{name}"] = value
    return flat


def node_parameter_sources(spec: NodeSpec, overrides: Overrides = (),
                           global_parameters: Mapping[str, Any] = ()) -> Dict[str, Tuple[Any, Origin]]:
    """Each parameter value a node of the graph starts with, and where it came from (name -> (value, origin)).

    rcl reads every ``--params-file`` into one table keyed by node-name pattern, in the order the
    patterns first appear, a later file overwriting a pattern's earlier values; a node then takes
    the values of every pattern that matches its full name, in that order. The launcher gives
    the graph's global parameters and each inline ``{name, value}`` group as ``/**`` files, each
    ``{from: FILE}`` as it is, and ``-p`` overrides last under the node's full name
    (hawt_tools.launcher.ros_arguments).
    """
    table: Dict[str, Dict[str, Tuple[Any, Origin]]] = {}

    def add(key: str, values: Mapping[str, Any], origin: Origin) -> None:
        table.setdefault(key if key.startswith("/") else "/" + key, {}).update(
            (name, (value, origin)) for name, value in values.items())

    if global_parameters:
        add("/**", dict(global_parameters), Origin("global"))
    for source in spec.parameters:
        if isinstance(source, ParameterValues):
            add("/**", dict(source.values), Origin("graph"))
        elif isinstance(source, ParameterFile):
            for key, body in (safe_load(source.path.read_text()) or {}).items():
                add(key, _flatten(body.get("ros__parameters", {})), Origin("file", source.path))
    overridden = dict(overrides).get(spec.label, ())
    if overridden:
        add(spec.label, {name: typed_override(value) if isinstance(value, str) else value
                         for name, value in overridden}, Origin("override"))
    values: Dict[str, Tuple[Any, Origin]] = {}
    for key, entries in table.items():
        if _pattern(key).match(spec.label):
            values.update(entries)
    return values


def node_parameters(spec: NodeSpec, overrides: Overrides = (), global_parameters: Mapping[str, Any] = ()) -> \
        Dict[str, Any]:
    """The parameter values a node of the graph starts with (:func:`node_parameter_sources` without the origins)."""
    return {name: value for name, (value, _) in node_parameter_sources(spec, overrides, global_parameters).items()}


def parse_overrides(graph: Graph, texts: Sequence[str]) -> Dict[str, List[Tuple[str, str]]]:
    """Turn ``NODE.PARAM:=VALUE`` texts (``-p`` options) into per-node ``(param, value)`` lists."""
    overrides: Dict[str, List[Tuple[str, str]]] = {}
    for text in texts:
        target, sep, value = text.partition(":=")
        node, dot, parameter = target.partition(".")
        if not sep or not dot or not node or not parameter:
            raise GraphError(f"-p {text!r}: expected NODE.PARAM:=VALUE (e.g. -p relay.gain:=2.0)")
        spec = graph.node(node)
        overrides.setdefault(spec.label, []).append((parameter, value))
    return overrides
