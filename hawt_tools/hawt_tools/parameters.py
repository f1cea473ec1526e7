"""One parameter table per node: declared with descriptors and ranges, checked on every set.

Each node lists its parameters once as :class:`ParameterSpec` rows (name, default,
SI unit, range, description, read-only), in the shape of ros2_controllers'
``pid_controller.yaml``. :func:`declare_parameters` declares them with ROS
descriptors and returns their values; :func:`check_values` is what an on-set
callback calls before a node builds its configuration from the new values.
"""
import math
from dataclasses import dataclass
from typing import Any, Dict, Iterable, Mapping, Optional, Sequence, Tuple

from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor, SetParametersResult
from rclpy.node import Node
from rclpy.parameter import Parameter

__all__ = ["ParameterSpec", "ParameterError", "declare_parameters", "check_values", "accepted", "rejection"]


class ParameterError(ValueError):
    """A parameter value a node cannot run with; the message starts with the parameter's name."""


@dataclass(frozen=True)
class ParameterSpec:
    """One row of a node's parameter table."""

    name: str
    default: Any
    description: str
    unit: str = ""
    minimum: Optional[float] = None
    maximum: Optional[float] = None
    choices: Tuple[str, ...] = ()
    read_only: bool = False

    def descriptor(self) -> ParameterDescriptor:
        unit = f" [{self.unit}]" if self.unit else ""
        # A float parameter takes an integer too (20 for 20.0), as a user would expect; check() types it.
        descriptor = ParameterDescriptor(name=self.name, description=f"{self.description}{unit}",
                                         read_only=self.read_only, dynamic_typing=isinstance(self.default, float))
        if self.choices:
            descriptor.additional_constraints = f"one of: {', '.join(self.choices)}"
        bounds = dict(from_value=self.minimum if self.minimum is not None else -math.inf,
                      to_value=self.maximum if self.maximum is not None else math.inf)
        if isinstance(self.default, float) and (self.minimum is not None or self.maximum is not None):
            descriptor.floating_point_range = [FloatingPointRange(**bounds)]
        elif isinstance(self.default, int) and not isinstance(self.default, bool) and \
                (self.minimum is not None or self.maximum is not None):
            descriptor.integer_range = [IntegerRange(from_value=int(max(bounds["from_value"], -2**63)),
                                                     to_value=int(min(bounds["to_value"], 2**63 - 1)))]
        return descriptor

    def typed(self, value: Any) -> Any:
        """``value`` as this parameter's type (an integer given for a float becomes a float), else ParameterError."""
        if isinstance(self.default, float):
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ParameterError(f"{self.name}: expected a number{f' [{self.unit}]' if self.unit else ''}, "
                                     f"found {value!r}")
            value = float(value)
        self.check(value)
        return value

    def check(self, value: Any) -> None:
        """Raise ParameterError naming this parameter if ``value`` is outside its type, range or choices."""
        numbers = value if isinstance(value, (list, tuple)) else [value]
        for number in numbers:
            if isinstance(number, float) and not math.isfinite(number):
                raise ParameterError(f"{self.name}: {number} is not a finite number")
            if isinstance(number, (int, float)) and not isinstance(number, bool):
                if self.minimum is not None and number < self.minimum:
                    raise ParameterError(f"{self.name}: {number} is below its minimum {self.minimum} {self.unit}".rstrip())
                if self.maximum is not None and number > self.maximum:
                    raise ParameterError(f"{self.name}: {number} is above its maximum {self.maximum} {self.unit}".rstrip())
        if self.choices and value not in self.choices:
            raise ParameterError(f"{self.name}: {value!r} is not one of {', '.join(self.choices)}")


def declare_parameters(node: Node, table: Sequence[ParameterSpec]) -> Dict[str, Any]:
    """Declare every row on the node and return the values it starts with (checked: ParameterError if not)."""
    values = {}
    for spec in table:
        values[spec.name] = spec.typed(node.declare_parameter(spec.name, spec.default, spec.descriptor()).value)
    return values


def check_values(table: Sequence[ParameterSpec], current: Mapping[str, Any],
                 changes: Iterable[Parameter]) -> Dict[str, Any]:
    """The values after ``changes``, each checked against its row (ParameterError on the first bad one)."""
    rows = {spec.name: spec for spec in table}
    values = dict(current)
    for parameter in changes:
        if parameter.name in rows:
            values[parameter.name] = rows[parameter.name].typed(parameter.value)
    return values


def accepted() -> SetParametersResult:
    """The answer to a parameter set that passed every check."""
    return SetParametersResult(successful=True)


def rejection(error: Exception) -> SetParametersResult:
    """The answer to a parameter set that is refused, with the reason."""
    return SetParametersResult(successful=False, reason=str(error))
