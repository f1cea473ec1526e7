"""An OpenFAST output file (``.outb`` binary or ``.out`` text) as the channels of a recorded run.

OpenFAST writes its channels in its own names and units; hawt's plant publishes the same quantities with
OpenFAST's sign conventions (:class:`hawt_plant.model.TurbineOutput`) in SI units. :data:`CHANNEL_MAP` says
which OpenFAST channel is which hawt channel, and :func:`read_openfast_output` converts each by the unit the
file gives it (:data:`UNIT_SCALES`), so that :func:`hawt_analysis.summary.summarize` analyses an OpenFAST run as
it analyses a bag (``hawt_bag.plant_run.PlantRun.channels``). The file itself is read with NREL's openfast-io
(``FASTOutputFile``).
"""
from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Dict, Sequence, Tuple

import numpy as np

__all__ = ["CHANNEL_MAP", "BLADE_CHANNEL_MAP", "UNIT_SCALES", "OpenFastOutputError", "openfast_channel_names",
           "read_openfast_output"]

CHANNEL_MAP: Tuple[Tuple[str, str], ...] = (
    ("time", "Time"),
    ("azimuth", "Azimuth"),
    ("rotor_speed", "RotSpeed"),
    ("generator_speed", "GenSpeed"),
    ("generator_torque", "GenTq"),
    ("electrical_power", "GenPwr"),
    ("aero_torque", "RtFldMxh"),
    ("rotor_thrust", "RtFldFxh"),
    ("hub_wind_speed", "Wind1VelX"),
    ("tower_top_fa_accel", "YawBrTAxp"),
    ("tower_top_ss_accel", "YawBrTAyp"),
    ("tower_top_fa_disp", "TTDspFA"),
    ("tower_top_ss_disp", "TTDspSS"),
    ("hub_tilt_moment", "LSSTipMys"),
    ("hub_yaw_moment", "LSSTipMzs"),
    ("yaw_bearing_tilt_moment", "YawBrMyp"),
    ("yaw_bearing_yaw_moment", "YawBrMzp"),
    ("tower_base_fa_moment", "TwrBsMyt"),
    ("tower_base_ss_moment", "TwrBsMxt"),
)
"""hawt channel -> OpenFAST channel (ElastoDyn, AeroDyn, ServoDyn, InflowWind point 1 at the hub), same signs."""

BLADE_CHANNEL_MAP: Tuple[Tuple[str, str], ...] = (
    ("root_moment_oop", "RootMyc{}"),
    ("root_moment_ip", "RootMxc{}"),
    ("pitch", "BldPitch{}"),
)
"""hawt per-blade channel -> OpenFAST channel of blade i (``{}`` the blade number, 1-based)."""

UNIT_SCALES: Dict[str, float] = {
    "s": 1.0, "sec": 1.0, "-": 1.0, "m": 1.0, "m/s": 1.0, "m/s^2": 1.0, "N": 1.0, "N-m": 1.0, "W": 1.0,
    "rad": 1.0, "rad/s": 1.0, "kN": 1e3, "kN-m": 1e3, "kW": 1e3, "MN-m": 1e6,
    "deg": math.pi / 180.0, "deg/s": math.pi / 180.0, "rpm": math.pi / 30.0,
}
"""OpenFAST unit (as the file writes it, without parentheses) -> factor to SI (rad, rad/s, N, N·m, W)."""


class OpenFastOutputError(ValueError):
    """An output file that cannot be read or lacks a channel; the message names the file and the channel."""


def openfast_channel_names(n_blades: int) -> Tuple[str, ...]:
    """Every OpenFAST channel :func:`read_openfast_output` reads for a rotor of ``n_blades`` (``Time`` excluded):
    what a case's OutList must hold."""
    scalars = tuple(name for _, name in CHANNEL_MAP[1:])
    return scalars + tuple(pattern.format(i) for _, pattern in BLADE_CHANNEL_MAP for i in range(1, n_blades + 1))


def _columns(path: Path) -> Tuple[np.ndarray, Sequence[str], Sequence[str]]:
    from openfast_io.FAST_output_reader import FASTOutputFile

    if not path.is_file():
        raise OpenFastOutputError(f"{path}: no such OpenFAST output file")
    if path.suffix not in (".out", ".outb"):
        raise OpenFastOutputError(f"{path}: not an OpenFAST output file (expected .out or .outb)")
    try:
        output = FASTOutputFile(os.fspath(path))
    except Exception as error:  # openfast-io raises a bare Exception on a truncated file, struct.error on a short one
        raise OpenFastOutputError(f"{path}: unreadable OpenFAST output ({error})") from None
    names, units = output.info["attribute_names"], output.info["attribute_units"]
    if output.data.ndim != 2 or output.data.shape[1] != len(names) or len(units) != len(names):
        raise OpenFastOutputError(f"{path}: {len(names)} channel names for {output.data.shape[-1]} columns")
    return np.asarray(output.data, dtype=float), names, units


def read_openfast_output(path: os.PathLike | str, n_blades: int = 3) -> Dict[str, np.ndarray]:
    """The channels of an OpenFAST output file as hawt names them, in SI units.

    Parameters
    ----------
    path : path-like
        ``.outb`` (binary) or ``.out`` (text) written by OpenFAST.
    n_blades : int
        B: per-blade channels are read for blades 1..B.

    Returns
    -------
    dict
        ``time`` [s], the scalar channels of :data:`CHANNEL_MAP` the file has, and the per-blade channels of
        :data:`BLADE_CHANNEL_MAP` as arrays (n, B); ``azimuth`` wrapped to [0, 2π). ``time``, ``azimuth`` and
        ``rotor_speed`` are required, the others are taken when present (a per-blade channel only with all B
        blades).

    Raises
    ------
    OpenFastOutputError
        Naming the file and what is wrong: unreadable or truncated, a required channel missing, a unit this
        module does not know, a value that is not finite.
    """
    path = Path(path)
    data, names, units = _columns(path)
    index = {name: i for i, name in enumerate(names)}

    def column(name: str) -> np.ndarray:
        i = index[name]
        unit = units[i].strip()
        if unit not in UNIT_SCALES:
            raise OpenFastOutputError(f"{path}: channel {name}: unknown unit {unit!r} (known: "
                                      f"{', '.join(UNIT_SCALES)})")
        values = data[:, i] * UNIT_SCALES[unit]
        if not np.all(np.isfinite(values)):
            raise OpenFastOutputError(f"{path}: channel {name} is not finite from sample "
                                      f"{int(np.argmin(np.isfinite(values)))} on")
        return values

    missing = [name for name in ("Time", "Azimuth", "RotSpeed") if name not in index]
    if missing:
        raise OpenFastOutputError(f"{path}: no channel {missing[0]} (the OutList must include it)")
    channels = {ours: column(theirs) for ours, theirs in CHANNEL_MAP if theirs in index}
    channels["azimuth"] = np.mod(channels["azimuth"], 2.0 * math.pi)
    for ours, pattern in BLADE_CHANNEL_MAP:
        blades = [pattern.format(i) for i in range(1, n_blades + 1)]
        if all(name in index for name in blades):
            channels[ours] = np.column_stack([column(name) for name in blades])
    return channels
