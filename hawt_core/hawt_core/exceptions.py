"""Errors raised by the controller cores.

Both subclass :class:`ValueError`, so callers that only care about "bad value"
can catch that; nodes use ``field`` / ``argument`` to name the ROS parameter or
message field at fault.
"""

__all__ = ["ConfigurationError", "InputError"]


class ConfigurationError(ValueError):
    """A configuration value the core cannot honour.

    Parameters
    ----------
    field : str
        Name of the configuration field (dataclass attribute or design argument).
    reason : str
        Why the value is refused, including the value itself.
    """

    def __init__(self, field: str, reason: str) -> None:
        self.field = field
        self.reason = reason
        super().__init__(f"{field}: {reason}")


class InputError(ValueError):
    """A run-time input (measurement, time step) the core refuses.

    Parameters
    ----------
    argument : str
        Name of the argument at fault.
    reason : str
        Why it is refused ("expected length B=3, found 2", "NaN in ...").
    """

    def __init__(self, argument: str, reason: str) -> None:
        self.argument = argument
        self.reason = reason
        super().__init__(f"{argument}: {reason}")
