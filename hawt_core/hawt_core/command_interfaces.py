"""Command interfaces a controller claims (DESIGN §4.1), as in ros2_control: names, topics, assembly.

=====================  ======================================  ==========================
interface              contribution                            topic (message)
=====================  ======================================  ==========================
``collective_pitch``   collective pitch angle [rad]            ``control/collective`` (CollectivePitch)
``generator_torque``   generator torque demand, HSS [N·m]      ``control/collective`` (CollectivePitch)
``harmonic/<n>``       cos/sin demand of harmonic n in the     ``control/ipc/h<n>`` (HarmonicPitch)
                       non-rotating frame [rad] + phase offset
``blade_pitch``        per-blade additive increments in the    ``control/blade_pitch`` (BladePitch)
                       rotating frame [rad]
=====================  ======================================  ==========================

A controller claims one or more interfaces; the manager allows one active claimant per
interface. ``collective_pitch`` and ``generator_torque`` travel in one message, so one
controller claims both. Which interfaces a graph can assemble for B blades is the loop
assembler's to say (``hawt_controllers.plugins.loop_assembly.assembly_problem``).
"""
import difflib
from dataclasses import dataclass
from typing import Iterable, Tuple

from hawt_core.topics import COLLECTIVE, blade_pitch_topic, ipc_topic

__all__ = [
    "COLLECTIVE_PITCH", "GENERATOR_TORQUE", "BLADE_PITCH", "HARMONIC_PREFIX", "MAX_HARMONIC", "CommandInterface",
    "InterfaceError", "parse_interface", "harmonic_interface", "join_claims", "split_claims",
]

COLLECTIVE_PITCH = "collective_pitch"
GENERATOR_TORQUE = "generator_torque"
BLADE_PITCH = "blade_pitch"
HARMONIC_PREFIX = "harmonic/"
MAX_HARMONIC = 12
"""Highest harmonic n a ``harmonic/<n>`` interface may name."""

_FIXED = (COLLECTIVE_PITCH, GENERATOR_TORQUE, BLADE_PITCH)


class InterfaceError(ValueError):
    """An interface name that does not exist; the message names it and what was probably meant."""


@dataclass(frozen=True)
class CommandInterface:
    """One command interface: its name, kind (``collective``, ``harmonic``, ``blade``), harmonic n and topic."""

    name: str
    kind: str
    harmonic: int
    topic: str


def harmonic_interface(harmonic: int) -> str:
    """``harmonic/<n>``."""
    return f"{HARMONIC_PREFIX}{int(harmonic)}"


def parse_interface(name: str) -> CommandInterface:
    """The interface called ``name``.

    Raises
    ------
    InterfaceError
        ``blade_pitchh: no such command interface (did you mean blade_pitch?)``.
    """
    if name in (COLLECTIVE_PITCH, GENERATOR_TORQUE):
        return CommandInterface(name, "collective", 0, COLLECTIVE)
    if name == BLADE_PITCH:
        return CommandInterface(name, "blade", 0, blade_pitch_topic())
    if name.startswith(HARMONIC_PREFIX):
        number = name[len(HARMONIC_PREFIX):]
        if number.isdigit() and 1 <= int(number) <= MAX_HARMONIC and str(int(number)) == number:
            return CommandInterface(name, "harmonic", int(number), ipc_topic(int(number)))
        raise InterfaceError(f"{name}: expected harmonic/<n> with n from 1 to {MAX_HARMONIC}")
    close = difflib.get_close_matches(name, (*_FIXED, "harmonic/1"), n=1)
    hint = f" (did you mean {close[0]}?)" if close else ""
    raise InterfaceError(f"{name}: no such command interface{hint}; the interfaces are "
                         f"{', '.join(_FIXED)} and harmonic/<n>")


def join_claims(interfaces: Iterable[str]) -> str:
    """A controller's claims as one message string: the names separated by single spaces."""
    return " ".join(interfaces)


def split_claims(text: str) -> Tuple[str, ...]:
    """The interface names of :func:`join_claims`' string."""
    return tuple(text.split())
