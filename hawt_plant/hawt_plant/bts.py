"""TurbSim binary full-field files (``.bts``): read into, and write from, :class:`TurbulentWind`.

The layout is the one TurbSim writes (``WrBinTURBSIM``, TurbSim ``TS_FileIO.f90``)
and OpenFAST InflowWind reads (``Read_TurbSim_FF``, ``IfW_TSFFWind.f90``), all
little-endian::

    int16    file id: 7 = not periodic, 8 = periodic
    int32    n_z, n_y, n_tower, n_t
    float32  dz [m], dy [m], dt [s], u_hub [m/s], z_hub [m], z_bottom [m]
    float32  slope_u, offset_u, slope_v, offset_v, slope_w, offset_w
    int32    n_char, then n_char bytes of ASCII description
    int16    per time step: grid (z, y, component), then tower points (point, component)

A value is stored as ``round(slope * v + offset)``, so ``v = (stored - offset) / slope``.
Grid node (iz, iy) lies at y = (iy - (n_y - 1) / 2) dy, z = z_bottom + iz dz;
tower point i at y = 0, z = z_bottom - i dz.
"""
import math
import struct
from pathlib import Path

import numpy as np

from hawt_plant.turbulence import TurbulentWind

__all__ = ["read_bts", "write_bts"]

_HEADER = struct.Struct("<h4i6f6fi")  # up to and including n_char
_PERIODIC_ID, _NON_PERIODIC_ID = 8, 7
_INT16_MIN, _INT16_MAX = -32768.0, 32767.0


def _inflowwind_x_offset(periodic: bool, grid_y: np.ndarray) -> float:
    """InflowWind's ``InitXPosition``: 0 for periodic files, half the grid width otherwise."""
    return 0.0 if periodic else 0.5 * float(grid_y[-1] - grid_y[0])


def read_bts(path: Path | str) -> TurbulentWind:
    """Read a TurbSim ``.bts`` full-field file.

    Parameters
    ----------
    path : Path or str
        The ``.bts`` file.

    Returns
    -------
    TurbulentWind
        Grid velocities in float32 as InflowWind scales them; periodic for file
        id 8; ``x_offset`` as InflowWind sets it (0 if periodic, else half the
        grid width), so sampling matches OpenFAST's time shift. Tower points
        are read (the file is checked whole) but not kept: the wind field ends
        at the grid, and points below it see the bottom row.

    Raises
    ------
    ValueError
        One line naming the file and what is wrong, for a truncated or malformed file.
    """
    path = Path(path)
    content = path.read_bytes()
    if len(content) < _HEADER.size:
        raise ValueError(f"{path}: truncated .bts header: {len(content)} bytes, expected at least {_HEADER.size}")
    (file_id, n_z, n_y, n_tower, n_t, dz, dy, dt, u_hub, z_hub, z_bottom, *scaling,
     n_char) = _HEADER.unpack_from(content)
    if file_id not in (_PERIODIC_ID, _NON_PERIODIC_ID):
        raise ValueError(f"{path}: not a TurbSim .bts file: file id {file_id}, expected 7 or 8")
    if n_z < 1 or n_y < 1 or n_tower < 0 or n_t < 2 or n_char < 0:
        raise ValueError(f"{path}: malformed .bts header: n_z={n_z}, n_y={n_y}, n_tower={n_tower}, "
                         f"n_t={n_t}, n_char={n_char}")
    if not (dt > 0.0 and u_hub > 0.0 and z_hub > 0.0 and (dz > 0.0 or n_z == 1) and (dy > 0.0 or n_y == 1)):
        raise ValueError(f"{path}: malformed .bts header: dz={dz}, dy={dy}, dt={dt}, u_hub={u_hub}, z_hub={z_hub}")
    slopes, offsets = np.array(scaling[0::2], dtype=np.float32), np.array(scaling[1::2], dtype=np.float32)
    if not np.all(np.isfinite(scaling)) or np.any(slopes == 0.0):
        raise ValueError(f"{path}: malformed .bts scaling: slopes {slopes}, offsets {offsets}")
    data_start = _HEADER.size + n_char
    values_per_step = 3 * (n_z * n_y + n_tower)
    expected, found = 2 * values_per_step * n_t, len(content) - data_start
    if found != expected:
        problem = "truncated" if found < expected else "malformed (trailing bytes)"
        raise ValueError(f"{path}: {problem} .bts file: {max(found, 0)} bytes of velocity data after the "
                         f"header, expected {expected} for n_t={n_t} steps of {n_z}x{n_y} grid + "
                         f"{n_tower} tower points")
    stored = np.frombuffer(content, dtype="<i2", offset=data_start).reshape(n_t, values_per_step)
    grid = stored[:, :3 * n_z * n_y].reshape(n_t, n_z, n_y, 3)
    velocity = (grid.astype(np.float32) - offsets) / slopes
    grid_y = (np.arange(n_y) - 0.5 * (n_y - 1)) * float(dy)
    periodic = file_id == _PERIODIC_ID
    return TurbulentWind(velocity, time_step=float(dt), grid_y=grid_y,
                         grid_z=float(z_bottom) + np.arange(n_z) * float(dz), mean_speed=float(u_hub),
                         hub_height=float(z_hub), periodic=periodic,
                         x_offset=_inflowwind_x_offset(periodic, grid_y))


def write_bts(path: Path | str, wind: TurbulentWind, description: str = "Written by hawt_plant",
              tower: bool = False) -> None:
    """Write a field as a TurbSim ``.bts`` file that OpenFAST InflowWind reads (WindType = 3).

    Parameters
    ----------
    path : Path or str
        Output file; overwritten.
    wind : TurbulentWind
        The field. Its grid must be centred laterally on y = 0 and its
        ``x_offset`` must be InflowWind's for its periodicity (0 if periodic,
        half the grid width if not), since a ``.bts`` file stores neither.
    description : str
        ASCII text stored in the header.
    tower : bool
        Also write tower points (y = 0, every dz from the grid's bottom down to the ground) holding the bottom row's
        velocity at y = 0: what the field gives there (points below the grid take the bottom row's value), so that
        InflowWind, which refuses a point below a grid without tower points (AeroDyn's tower nodes), sees the same
        wind on the tower.

    Notes
    -----
    Scaling as TurbSim's ``WrBinTURBSIM``: per component, the range
    [min, max] of the field is mapped onto [-32768, 32767], so the
    quantisation error is at most (max - min) / 65535 / 2.
    """
    grid_y, grid_z = wind.grid_y, wind.grid_z
    if abs(grid_y[0] + grid_y[-1]) > 1e-6 * max(1.0, abs(grid_y[0])):
        raise ValueError(f"wind: a .bts grid is centred on y = 0, found y from {grid_y[0]} to {grid_y[-1]} m")
    if abs(wind.x_offset - _inflowwind_x_offset(wind.periodic, grid_y)) > 1e-9:
        raise ValueError(f"wind.x_offset: a {'periodic' if wind.periodic else 'non-periodic'} .bts file "
                         f"implies x_offset {_inflowwind_x_offset(wind.periodic, grid_y)} m, found {wind.x_offset}")
    try:
        text = description.encode("ascii")
    except UnicodeEncodeError as error:
        raise ValueError(f"description: expected ASCII text, found {description!r}") from error
    velocity = wind.velocity_grid
    n_t, n_z, n_y, _ = velocity.shape
    low = velocity.min(axis=(0, 1, 2)).astype(np.float64)
    high = velocity.max(axis=(0, 1, 2)).astype(np.float64)
    span = high - low
    slopes = np.where(span > 0.0, (_INT16_MAX - _INT16_MIN) / np.where(span > 0.0, span, 1.0), 1.0)
    slopes = slopes.astype(np.float32)
    offsets = (_INT16_MIN - slopes.astype(np.float64) * low).astype(np.float32)
    stored = np.rint(np.clip(slopes * velocity + offsets, _INT16_MIN, _INT16_MAX)).astype("<i2")
    scaling = [float(value) for pair in zip(slopes, offsets) for value in pair]
    dz = float(grid_z[1] - grid_z[0]) if n_z > 1 else 0.0
    dy = float(grid_y[1] - grid_y[0]) if n_y > 1 else 0.0
    n_tower = int(math.floor(float(grid_z[0]) / dz + 1e-9)) + 1 if tower and dz > 0.0 else 0
    centre = stored[:, 0, (n_y - 1) // 2: n_y // 2 + 1, :].astype(np.float64).mean(axis=1)  # (n_t, 3) at y = 0
    columns = np.repeat(np.rint(centre)[:, None, :], n_tower, axis=1).astype("<i2")  # (n_t, n_tower, 3)
    header = _HEADER.pack(_PERIODIC_ID if wind.periodic else _NON_PERIODIC_ID, n_z, n_y, n_tower, n_t, dz, dy,
                          wind.time_step, wind.mean_speed, wind.hub_height, float(grid_z[0]), *scaling, len(text))
    with open(path, "wb") as handle:
        handle.write(header + text)
        handle.write(np.concatenate((stored.reshape(n_t, -1), columns.reshape(n_t, -1)), axis=1).tobytes())
