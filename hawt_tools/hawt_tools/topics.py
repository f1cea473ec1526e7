"""Topic and service names of DESIGN.md §5, relative so a graph runs under a namespace per turbine."""

__all__ = [
    "BLADE_LOADS", "TURBINE_STATE", "COLLECTIVE", "PITCH_COMMAND", "EVENTS", "CLOCK",
    "SWITCH_CONTROLLERS", "LIST_CONTROLLERS", "SWITCHES", "CONTROLLER_STATES", "mbc_topic", "ipc_topic",
]

BLADE_LOADS = "plant/blade_loads"
TURBINE_STATE = "plant/state"
COLLECTIVE = "control/collective"
PITCH_COMMAND = "control/pitch_command"
EVENTS = "control/events"
CLOCK = "/clock"
SWITCH_CONTROLLERS = "controller_manager/switch_controllers"
LIST_CONTROLLERS = "controller_manager/list_controllers"
SWITCHES = "controller_manager/switch"
CONTROLLER_STATES = "controller_manager/controllers"


def mbc_topic(harmonic: int) -> str:
    """The non-rotating blade loads of harmonic n: ``control/mbc/h{n}``."""
    return f"control/mbc/h{harmonic}"


def ipc_topic(harmonic: int) -> str:
    """The pitch demand of the IPC controller of harmonic n: ``control/ipc/h{n}``."""
    return f"control/ipc/h{harmonic}"
