"""Declaring a parameter table (hawt_core.parameter_table) on a ROS node, and answering parameter sets.

:func:`declare_parameters` declares each row with a ROS descriptor (description with
the SI unit, read-only, ranges) and returns the values the node starts with;
``check_values`` (hawt_core) is what an on-set callback calls before a node builds its
configuration from the new values.
"""
import math
from typing import Any, Dict, Sequence

from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor, SetParametersResult
from rclpy.node import Node

from hawt_core.parameter_table import ParameterError, ParameterSpec, check_values

__all__ = ["ParameterSpec", "ParameterError", "declare_parameters", "check_values", "descriptor", "accepted",
           "rejection"]


def descriptor(spec: ParameterSpec) -> ParameterDescriptor:
    """The ROS descriptor of one row: description with unit, read-only, integer or floating-point range."""
    unit = f" [{spec.unit}]" if spec.unit else ""
    # A float parameter takes an integer too (20 for 20.0), as a user would expect, and a row whose choices mix
    # types ('turbine', true or false) takes each of them; typed() checks and types the value.
    result = ParameterDescriptor(name=spec.name, description=f"{spec.description}{unit}",
                                 read_only=spec.read_only, dynamic_typing=spec.dynamic)
    if spec.choices:
        result.additional_constraints = f"one of: {spec.choices_text()}"
    bounds = dict(from_value=spec.minimum if spec.minimum is not None else -math.inf,
                  to_value=spec.maximum if spec.maximum is not None else math.inf)
    if isinstance(spec.default, float) and (spec.minimum is not None or spec.maximum is not None):
        result.floating_point_range = [FloatingPointRange(**bounds)]
    elif isinstance(spec.default, int) and not isinstance(spec.default, bool) and \
            (spec.minimum is not None or spec.maximum is not None):
        result.integer_range = [IntegerRange(from_value=int(max(bounds["from_value"], -2**63)),
                                             to_value=int(min(bounds["to_value"], 2**63 - 1)))]
    return result


def declare_parameters(node: Node, table: Sequence[ParameterSpec]) -> Dict[str, Any]:
    """Declare every row on the node and return the values it starts with (checked: ParameterError if not)."""
    values = {}
    for spec in table:
        values[spec.name] = spec.typed(node.declare_parameter(spec.name, spec.default, descriptor(spec)).value)
    return values


def accepted() -> SetParametersResult:
    """The answer to a parameter set that passed every check."""
    return SetParametersResult(successful=True)


def rejection(error: Exception) -> SetParametersResult:
    """The answer to a parameter set that is refused, with the reason."""
    return SetParametersResult(successful=False, reason=str(error))
