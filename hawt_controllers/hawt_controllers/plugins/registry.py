"""Controllers found by type: the ``hawt.controllers`` entry points, TYPE -> Controller class (as pluginlib and a
controller's ``type`` find it in ros2_control).

A package adds a controller type with one entry point in its setup::

    entry_points={"hawt.controllers": ["my_type = my_package.my_module:MyController"]}

and a graph runs it with the generic executable, on every engine (``hawt launch``, ``--composed``, ``hawt run``,
campaigns)::

    - node: {pkg: hawt_controllers, exec: controller, name: mine, param: [{name: type, value: my_type}]}

hawt's own types also have an executable named after the type (``exec: ipc``): an alias of the generic one, kept
for existing graphs, whose type is its name.
"""
from __future__ import annotations

import difflib
import importlib.metadata
from typing import Dict, Tuple

from hawt_controllers.plugins.controller import Controller, controller_parameters
from hawt_core.node_role import AWAIT_SCHEDULE, WAIT_FOR_RECORDER, NodeRole, entry_points
from hawt_core.parameter_table import ParameterError, ParameterSpec

__all__ = ["CONTROLLERS_GROUP", "TYPE", "controller_class", "controller_role", "controller_types", "node_parameters"]

CONTROLLERS_GROUP = "hawt.controllers"
"""The entry-point group of controller types."""

TYPE = ParameterSpec("type", "", "the controller type: an entry point of hawt.controllers ('' = the executable's "
                     "name, for the executables named after a type)", read_only=True)
"""The parameter that names a controller node's type."""


def controller_types() -> Dict[str, importlib.metadata.EntryPoint]:
    """Every registered controller type and its entry point (the distributions on ``sys.path``)."""
    return {entry.name: entry for entry in entry_points(CONTROLLERS_GROUP)}


def controller_class(type_name: str) -> type:
    """The Controller class registered as ``type_name``.

    Raises
    ------
    ParameterError
        ``type: ...``: no such type (with the registered ones and a did-you-mean), or an entry point that is not a
        Controller of that TYPE.
    """
    types = controller_types()
    if type_name not in types:
        close = difflib.get_close_matches(type_name, list(types), n=1)
        raise ParameterError(f"type: no controller type {type_name!r}" + (f" (did you mean {close[0]!r}?)" if close
                                                                          else "")
                             + f"; registered ({CONTROLLERS_GROUP} entry points): {', '.join(sorted(types))}")
    cls = types[type_name].load()
    if not (isinstance(cls, type) and issubclass(cls, Controller)) or cls.TYPE != type_name:
        raise ParameterError(f"type: the {CONTROLLERS_GROUP} entry point {type_name} = {types[type_name].value} is "
                             f"not a hawt_controllers Controller whose TYPE is {type_name!r}")
    return cls


def node_parameters(controller: type) -> Tuple[ParameterSpec, ...]:
    """The whole parameter table of a controller's node: ``type``, the controller's rows and ``active``, then
    ``wait_for_recorder`` and ``await_schedule``."""
    return (TYPE, *controller_parameters(controller), WAIT_FOR_RECORDER, AWAIT_SCHEDULE)


def controller_role(type_name: str) -> NodeRole:
    """The role of a controller node of type ``type_name`` (the ``hawt.nodes`` entry of the ``controller``
    executable and its aliases); ParameterError as :func:`controller_class`."""
    controller = controller_class(type_name)
    return NodeRole("controller", node_parameters(controller), controller.check_values, controller)
