"""Topic, service and well-known node names (docs/architecture.md §3), topics relative so a graph runs under a
namespace per turbine."""

__all__ = [
    "BLADE_LOADS", "TURBINE_STATE", "COLLECTIVE", "PITCH_COMMAND", "EVENTS", "CLOCK",
    "SWITCH_CONTROLLERS", "LIST_CONTROLLERS", "SWITCHES", "SCHEDULE", "CONTROLLER_STATES", "PLANT_DESCRIPTION",
    "mbc_topic", "ipc_topic", "blade_pitch_topic", "estimate_topic", "WIND_ESTIMATE", "RECORDER_NODE",
    "RECORDER_PROGRESS",
    "VIEW_NODE",
]

BLADE_LOADS = "plant/blade_loads"
TURBINE_STATE = "plant/state"
PLANT_DESCRIPTION = "plant/description"
COLLECTIVE = "control/collective"
PITCH_COMMAND = "control/pitch_command"
EVENTS = "control/events"
CLOCK = "/clock"
SWITCH_CONTROLLERS = "controller_manager/switch_controllers"
LIST_CONTROLLERS = "controller_manager/list_controllers"
SWITCHES = "controller_manager/switch"
SCHEDULE = "controller_manager/schedule"
CONTROLLER_STATES = "controller_manager/controllers"
RECORDER_NODE = "hawt_recorder"
"""The recorder's node name (``hawt record``, ``hawt launch --record``): what a run waits for before it starts."""
RECORDER_PROGRESS = "/recorder/progress"
"""What the recorder has written so far (hawt_msgs/RecorderProgress): a recorded lockstep plant's back-pressure."""
VIEW_NODE = "hawt_view"
"""The node of ``hawt view`` (``hawt launch --view``), which serves the graph to Foxglove."""


def mbc_topic(harmonic: int) -> str:
    """The non-rotating blade loads of harmonic n: ``control/mbc/h{n}``."""
    return f"control/mbc/h{harmonic}"


def ipc_topic(harmonic: int) -> str:
    """The pitch demand of the IPC controller of harmonic n: ``control/ipc/h{n}``."""
    return f"control/ipc/h{harmonic}"


WIND_ESTIMATE = "wind_estimate"
"""The kind of a controller's multi-blade wind estimate (hawt_msgs/WindEstimate), for ``estimate_topic``."""


def estimate_topic(controller: str, kind: str) -> str:
    """What controller ``controller`` (its node name) estimates, of message kind ``kind`` (e.g. ``wind_estimate``):
    ``control/{controller}/{kind}``."""
    return f"control/{controller}/{kind}"


def blade_pitch_topic() -> str:
    """The per-blade pitch increments of the ``blade_pitch`` interface: ``control/blade_pitch``."""
    return "control/blade_pitch"
