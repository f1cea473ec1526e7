"""One parameter table per node or controller, without ROS: rows, typing and range checks.

Each node or controller core lists its parameters once as :class:`ParameterSpec` rows
(name, default, SI unit, range, description, read-only), in the shape of
ros2_controllers' ``pid_controller.yaml``. The same table is declared on a ROS node
(``hawt_node.parameters.declare_parameters``), checked by the in-process runner, and
printed as the parameter reference, so ranges have one source.
"""
import math
from dataclasses import dataclass
from typing import Any, Dict, Iterable, Mapping, Optional, Sequence, Tuple

__all__ = ["ParameterSpec", "ParameterError", "check_values", "default_values", "resolve_values"]


class ParameterError(ValueError):
    """A parameter value a node cannot run with; the message starts with the parameter's name."""


@dataclass(frozen=True)
class ParameterSpec:
    """One row of a parameter table."""

    name: str
    default: Any
    description: str
    unit: str = ""
    minimum: Optional[float] = None
    maximum: Optional[float] = None
    choices: Tuple[Any, ...] = ()
    read_only: bool = False

    @property
    def dynamic(self) -> bool:
        """True for a row that takes values of more than one type (rcl's ``dynamic_typing``): a float row (an
        integer too), or one whose choices mix types, e.g. ``('turbine', True, False)``."""
        return isinstance(self.default, float) or self._mixed_choices()

    def _mixed_choices(self) -> bool:
        return len({_kind(choice) for choice in self.choices}) > 1

    def choices_text(self) -> str:
        """The choices as a user writes them: ``lockstep, realtime``; ``turbine, true, false``."""
        return ", ".join(_word(choice) for choice in self.choices)

    def typed(self, value: Any) -> Any:
        """``value`` as this parameter's type (an integer given for a float becomes a float, and so does a string of
        a number in exponent form without a dot, ``8e-11``, which YAML 1.1 and so ``name:=8e-11`` leave a string),
        else ParameterError. A row whose choices mix types takes exactly one of them (``true``, not ``1``)."""
        if self._mixed_choices():
            if not _among(value, self.choices):
                words = [_word(choice) for choice in self.choices]
                raise ParameterError(f"{self.name}: expected {', '.join(words[:-1])} or {words[-1]}, "
                                     f"found {value!r}")
            return value
        if isinstance(self.default, float):
            if isinstance(value, str):
                try:
                    number = float(value)
                except ValueError:
                    number = math.nan
                value = number if math.isfinite(number) else value
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ParameterError(f"{self.name}: expected a number{f' [{self.unit}]' if self.unit else ''}, "
                                     f"found {value!r}")
            value = float(value)
        else:
            self._check_type(value)
        self.check(value)
        return value

    def _check_type(self, value: Any) -> None:
        """Refuse a value of another type than the default's, as rcl refuses it for a statically typed parameter.

        Only a float parameter (it takes an integer) and one whose choices mix types are dynamically typed
        (:attr:`dynamic`, hawt_node.parameters.descriptor); every other one must have its default's type: bool,
        integer, string, or a list of the default's element type (an integer list for a float list included, as
        rcl refuses INTEGER_ARRAY for DOUBLE_ARRAY).
        """
        expected = _kind(self.default)
        if expected is not None and _kind(value) != expected:
            raise ParameterError(f"{self.name}: expected {expected}, found {value!r}")

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
        if self.choices and not _among(value, self.choices):
            raise ParameterError(f"{self.name}: {value!r} is not one of {self.choices_text()}")


_KINDS = ((bool, "true or false", "booleans"), (int, "an integer", "integers"), (float, "a number", "numbers"),
          (str, "a string", "strings"))


def _among(value: Any, choices: Sequence[Any]) -> bool:
    """``value`` is one of ``choices``, of the same type (``True`` is not ``1``)."""
    return any(type(value) is type(choice) and value == choice for choice in choices)


def _word(value: Any) -> str:
    """A value as YAML and ``name:=value`` write it (``true``, not ``True``)."""
    return str(value).lower() if isinstance(value, bool) else str(value)


def _kind(value: Any) -> Optional[str]:
    """The rcl parameter type of a value in words (None: no type rcl can hold)."""
    if isinstance(value, (list, tuple)):
        kinds = {next((plural for kind, _, plural in _KINDS if type(v) is kind), None) for v in value}
        return f"a list of {kinds.pop()}" if len(kinds) == 1 and None not in kinds else None
    return next((words for kind, words, _ in _KINDS if type(value) is kind), None)


def default_values(table: Sequence[ParameterSpec]) -> Dict[str, Any]:
    """Every row's default value."""
    return {spec.name: spec.default for spec in table}


def check_values(table: Sequence[ParameterSpec], current: Mapping[str, Any],
                 changes: Iterable[Any]) -> Dict[str, Any]:
    """The values after ``changes`` (objects with ``name`` and ``value``), each checked against its row.

    Raises ParameterError on the first bad value; names the table does not have are ignored
    (a ROS node also holds parameters of its own, such as ``use_sim_time``).
    """
    rows = {spec.name: spec for spec in table}
    values = dict(current)
    for parameter in changes:
        if parameter.name in rows:
            values[parameter.name] = rows[parameter.name].typed(parameter.value)
    return values


def resolve_values(table: Sequence[ParameterSpec], given: Mapping[str, Any]) -> Dict[str, Any]:
    """The table's defaults updated by ``given`` (name -> value), each checked as a ROS node would on start.

    Names the table does not have are ignored, as a ROS node ignores overrides it never declares.
    """
    values = default_values(table)
    for spec in table:
        if spec.name in given:
            values[spec.name] = spec.typed(given[spec.name])
    return values
