"""A recorded run as checked numpy arrays, named after the plant's message fields.

Channel names are the field names of DESIGN §5: ``plant/blade_loads`` (``azimuth``,
``rotor_speed``, ``root_moment_oop``, ``root_moment_ip``, ``pitch``) and
``plant/state`` (``electrical_power``, ``hub_tilt_moment``, ``tower_base_fa_moment``,
…), plus ``time``, the ``header.stamp`` in seconds. All channels share the time
base (one row per plant step). Per-blade fields are arrays of shape
(n_samples, n_blades); in results, blade i's column is named ``<field>_<i>``
(blades numbered from 1, DESIGN §3), e.g. ``root_moment_oop_1``.

Derived channels: ``hub_rotating_y_moment`` and ``hub_rotating_z_moment``, the hub moments
m_hy, m_hz in the frame that turns with the rotor (Zalkind & Pao's hub loads, OpenFAST
LSSTipMya/Mza), are computed from ``hub_tilt_moment``, ``hub_yaw_moment`` and ``azimuth``
(the inverse of eq. 13, :func:`hawt_analysis.load_transfer.main_bearing_to_hub`) whenever a
record has those, so that bags recorded before them have them too.
"""
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

import numpy as np
from numpy.typing import ArrayLike

from ._checks import finite_array, same_length
from .load_transfer import main_bearing_to_hub

__all__ = [
    "PER_BLADE_CHANNELS",
    "REQUIRED_CHANNELS",
    "SCALAR_CHANNELS",
    "Record",
    "blade_channel_name",
    "make_record",
]

REQUIRED_CHANNELS = ("time", "azimuth", "rotor_speed")
SCALAR_CHANNELS = (
    "azimuth",
    "rotor_speed",
    "generator_speed",
    "generator_torque",
    "electrical_power",
    "aero_torque",
    "rotor_thrust",
    "hub_wind_speed",
    "tower_top_fa_accel",
    "tower_top_ss_accel",
    "tower_top_fa_disp",
    "tower_top_ss_disp",
    "hub_tilt_moment",
    "hub_yaw_moment",
    "tower_base_fa_moment",
    "tower_base_ss_moment",
    "yaw_bearing_tilt_moment",
    "yaw_bearing_yaw_moment",
    "effective_wind_mean",
    "effective_wind_cos",
    "effective_wind_sin",
    "hub_rotating_y_moment",
    "hub_rotating_z_moment",
)
PER_BLADE_CHANNELS = ("root_moment_oop", "root_moment_ip", "pitch")
_UNIFORM_TOLERANCE = 0.01
"""Largest accepted deviation of a time step from the mean step, as a fraction of it."""


def blade_channel_name(field: str, blade: int) -> str:
    """Name of blade ``blade``'s (1-based) column of a per-blade field: ``f"{field}_{blade}"``."""
    return f"{field}_{blade}"


@dataclass(frozen=True)
class Record:
    """A checked run: uniform time base and finite channels of equal length.

    Attributes
    ----------
    time : numpy.ndarray, shape (n_samples,)
        [s], strictly increasing, uniform within 1 %.
    scalars : Mapping[str, numpy.ndarray]
        Scalar channels present, each of shape (n_samples,), SI units.
    per_blade : Mapping[str, numpy.ndarray]
        Per-blade channels present, each of shape (n_samples, n_blades), SI units.
    """

    time: np.ndarray
    scalars: Mapping[str, np.ndarray]
    per_blade: Mapping[str, np.ndarray]

    @property
    def duration(self) -> float:
        """T = t_end − t_0 [s]."""
        return float(self.time[-1] - self.time[0])

    @property
    def sample_rate(self) -> float:
        """(n_samples − 1) / T [Hz]."""
        return (self.time.size - 1) / self.duration

    @property
    def n_blades(self) -> int | None:
        """B, or None if the record has no per-blade channel."""
        return next((values.shape[1] for values in self.per_blade.values()), None)

    def blade_columns(self, field: str) -> dict[str, np.ndarray]:
        """The columns of per-blade ``field`` by blade channel name (empty if absent)."""
        values = self.per_blade.get(field)
        if values is None:
            return {}
        return {blade_channel_name(field, i + 1): values[:, i] for i in range(values.shape[1])}


def make_record(channels: Mapping[str, ArrayLike]) -> Record:
    """Check a mapping of named channel arrays and return it as a `Record`.

    Parameters
    ----------
    channels : Mapping[str, array_like]
        ``time`` [s], ``azimuth`` [rad] and ``rotor_speed`` [rad/s] are required;
        any of `SCALAR_CHANNELS` (shape (n_samples,)) and `PER_BLADE_CHANNELS`
        (shape (n_samples, n_blades)) may be added. SI units (DESIGN §3).

    Returns
    -------
    Record

    Raises
    ------
    ValueError
        Naming the channel: unknown or missing channel, wrong shape, NaN or
        infinite value, length unlike ``time``, blade counts that differ, time not
        strictly increasing or not uniform, fewer than 3 samples.
    """
    unknown = sorted(set(channels) - {"time", *SCALAR_CHANNELS, *PER_BLADE_CHANNELS})
    if unknown:
        raise ValueError(
            f"{unknown[0]}: unknown channel; expected 'time' or one of "
            f"{', '.join(SCALAR_CHANNELS + PER_BLADE_CHANNELS)}"
        )
    missing = [name for name in REQUIRED_CHANNELS if name not in channels]
    if missing:
        raise ValueError(f"{missing[0]}: required channel missing")
    time = finite_array("time", channels["time"], ndim=1)
    if time.size < 3:
        raise ValueError(f"time: {time.size} samples are too short a record (need 3)")
    step = np.diff(time)
    if np.any(step <= 0.0):
        raise ValueError(f"time: not strictly increasing at sample {int(np.argmax(step <= 0.0)) + 1}")
    mean_step = (time[-1] - time[0]) / (time.size - 1)
    if np.max(np.abs(step - mean_step)) > _UNIFORM_TOLERANCE * mean_step:
        raise ValueError(f"time: sampling not uniform (steps from {step.min():.6g} to {step.max():.6g} s)")

    scalars = {}
    for name in SCALAR_CHANNELS:
        if name in channels:
            scalars[name] = finite_array(name, channels[name], ndim=1)
            same_length(name, scalars[name], time.size, "time")
    if {"hub_tilt_moment", "hub_yaw_moment"} <= set(scalars) and "hub_rotating_y_moment" not in scalars:
        scalars["hub_rotating_y_moment"], scalars["hub_rotating_z_moment"] = main_bearing_to_hub(
            scalars["hub_tilt_moment"], scalars["hub_yaw_moment"], scalars["azimuth"])
    per_blade = {}
    for name in PER_BLADE_CHANNELS:
        if name in channels:
            per_blade[name] = finite_array(name, channels[name], ndim=2)
            same_length(name, per_blade[name], time.size, "time")
            if per_blade[name].shape[1] < 1:
                raise ValueError(f"{name}: expected one column per blade, found none")
    blade_counts = {name: values.shape[1] for name, values in per_blade.items()}
    if len(set(blade_counts.values())) > 1:
        first = next(iter(blade_counts))
        odd = next(name for name, count in blade_counts.items() if count != blade_counts[first])
        raise ValueError(
            f"{odd}: expected B={blade_counts[first]} blades like {first}, found {blade_counts[odd]}"
        )
    return Record(time=time, scalars=MappingProxyType(scalars), per_blade=MappingProxyType(per_blade))
