"""Every node's parameters checked against its table before a graph starts (``hawt launch``, ``hawt run``, and
``hawt campaign`` for every case before any worker starts).

Each node gets exactly the values rcl will give it (hawt_tools.node_parameters: the graph's
``{name, value}`` entries, ``{from: FILE}`` files with wildcards, ``-p`` overrides), and
each value is checked against the node's declarative parameter table (hawt_core.parameter_table rows): its
registered role's (hawt_tools.node_registry; a controller's from its type), without ROS; for a node no package
registers, its class's ``PARAMETERS``, found through the executable's entry point, when ``hawt launch`` asks for it
(hawt_tools.launcher.class_role).
Refused, as one line naming the graph file (or the ``-p``
option, or the parameter file the value came from), the node and the parameter:

- a name neither the table nor rclpy itself declares (a did-you-mean);
- a value of another type than the row's (as rcl refuses it), a NaN or infinity, one
  outside the row's range or choices;
- values that break a rule across parameters, or name a file that cannot serve, if the role
  has a cheap ``check_parameters(values)`` (e.g. the plant's ``command_timeout >
  resend_period``; a ``discon`` controller's library that is no ELF shared object of this
  machine exporting ``DISCON``, hawt_controllers.discon.library.check_library).

Not checked: an unregistered node whose class has no ``PARAMETERS`` table, or whose executable is no
Python entry point with a ``node_class`` (a C++ node, a script) — it gets its values
unchecked, as before. The launcher's global parameters (``wait_for_recorder``) apply only to
nodes whose table has them: every node is given them, and rclpy ignores what a node never
declares.

Then, the rules that need the plant, but not its model (:func:`check_against_plant`, run by ``hawt launch`` and
``hawt run`` after the table check, and by ``hawt campaign`` once per controller configuration before any wind is
generated): the plant's turbine file loaded and every controller core built against its description, as each engine
configures it — a tuning for another turbine, a ``dt`` that is not the plant's. The plant model (its operating point)
is not built.
"""
from typing import Any, Callable, Dict, Mapping, Optional, Sequence, Tuple

from hawt_core.node_role import NodeRole
from hawt_core.parameter_table import ParameterError, ParameterSpec
from hawt_tools.graph_file import Graph, GraphError, NodeSpec, did_you_mean
from hawt_tools.node_parameters import Origin, node_parameter_sources
from hawt_tools.node_registry import node_role

__all__ = ["RCLPY_PARAMETERS", "check_against_plant", "check_graph_parameters", "check_node_parameters",
           "checked_role", "takes_parameter", "unchecked"]

RCLPY_PARAMETERS = (
    ParameterSpec("use_sim_time", False, "follow /clock (rclpy.time_source.USE_SIM_TIME_NAME)"),
    ParameterSpec("start_type_description_service", True, "start the ~/get_type_description service "
                  "(rclpy.type_description_service.START_TYPE_DESCRIPTION_SERVICE_PARAM)", read_only=True),
)
"""What every rclpy node declares itself (rclpy.node.Node in Kilted: its time source and its type description
service), with the types rclpy gives them; a value for these is never an unknown name. Spelled out rather than
imported, so that the check loads no rclpy (tests/hawt_tools/test_parameter_check.py compares them with rclpy's)."""

Overrides = Mapping[str, Sequence[Tuple[str, Any]]]


RoleOf = Callable[[Graph, NodeSpec], Optional[NodeRole]]
"""Where the check finds the role of a node no package registers (``hawt launch`` passes
hawt_tools.launcher.class_role, which reads the node's class); by default such a node is unchecked."""


def unchecked(graph: Graph, spec: NodeSpec) -> None:
    """The default :data:`RoleOf`: a node no package registers has no role, and its values are not checked."""
    return None


def checked_role(graph: Graph, spec: NodeSpec, overrides: Overrides = (),
                 unregistered: RoleOf = unchecked) -> Optional[NodeRole]:
    """What ``spec``'s values are checked against: its registered role (hawt_tools.node_registry), else what
    ``unregistered`` finds; None for a node that cannot be checked."""
    role = node_role(graph, spec, overrides)
    return role if role is not None else unregistered(graph, spec)


def takes_parameter(graph: Graph, spec: NodeSpec, name: str, unregistered: RoleOf = unchecked) -> bool:
    """True if the node's table has ``name``, or the node has no table (it is given everything, unchecked)."""
    role = checked_role(graph, spec, (), unregistered)
    return role is None or any(row.name == name for row in role.parameters)


def _refusal(graph: Graph, spec: NodeSpec, name: str, origin: Optional[Origin], text: str) -> GraphError:
    """One line: the ``-p`` option, or the graph file, the node (and the parameter file); then ``text``.

    ``text`` starts with the parameter's name (``NAME: why``), which the ``-p NODE.NAME`` form names already.
    """
    if origin is not None and origin.kind == "override":
        return GraphError(f"-p {spec.name}.{name}: {text[len(name) + 2:] if text.startswith(name + ': ') else text}")
    place = f"{graph.path}: node {spec.name}"
    if origin is not None and origin.kind == "file":
        place += f" (parameter file {origin.path})"
    return GraphError(f"{place}: {text}")


def check_node_parameters(graph: Graph, spec: NodeSpec, overrides: Overrides = (),
                          global_parameters: Mapping[str, Any] = (),
                          unregistered: RoleOf = unchecked) -> Optional[Dict[str, Any]]:
    """The values one node will run with, each checked against its table; None if the node has no table.

    Raises
    ------
    GraphError
        One line naming where the first bad value came from, the node and the parameter.
    """
    role = checked_role(graph, spec, overrides, unregistered)
    if role is None:
        return None
    table = role.parameters
    rows = {row.name: row for row in (*RCLPY_PARAMETERS, *table)}
    sources = node_parameter_sources(spec, overrides, global_parameters)
    values = {row.name: row.default for row in table}
    for name, (value, origin) in sources.items():
        row = rows.get(name)
        if row is None:
            if origin.kind == "global":
                continue  # given to every node; only the nodes that declare it take it
            raise _refusal(graph, spec, name, origin,
                           f"{name}: no such parameter" + did_you_mean(name, [r.name for r in table]))
        try:
            typed = row.typed(value)
        except ParameterError as error:
            raise _refusal(graph, spec, name, origin, str(error)) from None
        if name in values:
            values[name] = typed
    if role.check_parameters is not None:
        try:
            role.check_parameters(values)
        except ValueError as error:
            name = str(error).split(":", 1)[0]
            raise _refusal(graph, spec, name, sources.get(name, (None, None))[1], str(error)) from None
    return values


def check_graph_parameters(graph: Graph, overrides: Overrides = (), global_parameters: Mapping[str, Any] = (),
                           unregistered: RoleOf = unchecked) -> Dict[str, Optional[Dict[str, Any]]]:
    """Check every node of the graph in file order (:func:`check_node_parameters`); label -> values (None: unchecked).

    Raises GraphError for the first node with a bad value, and for two controllers that would start active on
    one command interface (ros2_control's one claimant per interface, before anything starts).
    """
    checked = {spec.label: check_node_parameters(graph, spec, overrides, global_parameters, unregistered)
               for spec in graph.nodes}
    claimants: Dict[str, NodeSpec] = {}
    for spec in graph.nodes:
        values = checked[spec.label]
        role = node_role(graph, spec, overrides)
        if role is None or role.controller is None or values is None or not values.get("active"):
            continue
        for interface in role.controller.claimed(values):
            if interface in claimants:
                raise GraphError(f"{graph.path}: nodes {claimants[interface].name!r} and {spec.name!r} both start "
                                 f"active and claim {interface}; one controller per interface may be active (start "
                                 f"one with active: false and swap them with hawt switch)")
            claimants[interface] = spec
    return checked


def check_against_plant(graph: Graph, checked: Mapping[str, Optional[Dict[str, Any]]]) -> None:
    """Build every controller core of the graph against the description of its plant's turbine, as each engine does at
    configure, with the values :func:`check_graph_parameters` returned (``checked``).

    Raises
    ------
    GraphError
        One line naming the graph file and the node: the plant's turbine file that cannot be read, or a controller
        whose values contradict the plant (``node cpc: controller_file: rated generator speed 122.91 rad/s conflicts
        with plant/description 76.79 rad/s (…): a tuning for another turbine``). A graph without a plant node is
        not checked.
    """
    from hawt_plant.turbine import turbine_from

    roles = {spec.label: node_role(graph, spec) for spec in graph.nodes}
    plants = [spec for spec in graph.nodes if roles[spec.label] is not None and roles[spec.label].kind == "plant"]
    if len(plants) != 1:
        return
    plant = checked[plants[0].label]
    try:
        description = turbine_from(plant["turbine_file"] or "nrel_5mw").description(plant["dt"])
    except (OSError, ValueError) as error:
        raise GraphError(f"{graph.path}: node {plants[0].name}: turbine_file: {error}") from None
    for spec in graph.nodes:
        controller = roles[spec.label].controller if roles[spec.label] is not None else None
        if controller is not None and checked[spec.label] is not None:
            try:
                controller(checked[spec.label], description)
            except ValueError as error:
                raise GraphError(f"{graph.path}: node {spec.name}: {error}") from None
