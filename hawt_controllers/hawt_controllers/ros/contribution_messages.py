"""Contributions as messages and back: one message kind per command-interface kind (DESIGN §4.1, §5).

==================================  =========================  ==========================
contribution (hawt_controllers      message                    topic
.controller)
==================================  =========================  ==========================
CollectiveContribution              ``CollectivePitch``        ``control/collective``
HarmonicContribution                ``HarmonicPitch``          ``control/ipc/h<n>``
BladeContribution                   ``BladePitch``             ``control/blade_pitch``
==================================  =========================  ==========================
"""
from typing import Any

from hawt_msgs.msg import BladePitch, CollectivePitch, HarmonicPitch

from hawt_core.command_interfaces import parse_interface

from hawt_controllers.plugins.controller import (BladeContribution, CollectiveContribution, Contribution,
                                                HarmonicContribution)

__all__ = ["message_type", "to_message", "from_message"]

_TYPES = {"collective": CollectivePitch, "harmonic": HarmonicPitch, "blade": BladePitch}


def message_type(interface: str) -> type:
    """The message class that carries ``interface``'s contributions."""
    return _TYPES[parse_interface(interface).kind]


def to_message(contribution: Contribution, step: int, header: Any, controller: str) -> Any:
    """The message of ``contribution`` answering plant step ``step`` (``header`` of that step)."""
    if isinstance(contribution, CollectiveContribution):
        msg = CollectivePitch(pitch=contribution.pitch, generator_torque=contribution.generator_torque,
                              generator_speed_filtered=contribution.generator_speed_filtered,
                              region=contribution.region, wind_speed_estimate=contribution.wind_speed_estimate)
    elif isinstance(contribution, HarmonicContribution):
        msg = HarmonicPitch(harmonic=contribution.harmonic, cos=contribution.cos, sin=contribution.sin,
                            phase_offset=contribution.phase_offset)
    else:
        msg = BladePitch(controller=controller, increment=list(contribution.increment))
    msg.step, msg.header = step, header
    return msg


def from_message(msg: Any) -> Contribution:
    """The contribution a message carries."""
    if isinstance(msg, CollectivePitch):
        return CollectiveContribution(msg.pitch, msg.generator_torque, msg.generator_speed_filtered, msg.region,
                                      msg.wind_speed_estimate)
    if isinstance(msg, HarmonicPitch):
        return HarmonicContribution(int(msg.harmonic), msg.cos, msg.sin, msg.phase_offset)
    return BladeContribution(tuple(msg.increment))
