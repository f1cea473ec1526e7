"""Turbulent full-field inflow: IEC 61400-1 NTM and ETM boxes from pyconturb, and their fast sampling.

A turbulent field is a regular grid in the rotor plane (lateral ``y``, vertical
``z``) holding the three velocity components over time. :class:`TurbulentWind`
samples such a grid (generated here, or read from a TurbSim ``.bts`` file by
:mod:`hawt_plant.bts`) as a :class:`~hawt_plant.wind_field.WindField`.
Generation uses the maintained generator pyconturb (Veers' method with the
IEC 61400-1 Kaimal spectra and exponential coherence) and is slow, so
:func:`cached_turbulence` keeps generated fields on disk, keyed by a hash of
everything that determines them.
"""
import dataclasses
import hashlib
import importlib.metadata
import json
import math
import time
import warnings
from pathlib import Path
from types import MappingProxyType
from typing import Callable

import numpy as np
from threadpoolctl import threadpool_limits

from hawt_plant.disk_cache import cache_root, store

__all__ = [
    "REFERENCE_TURBULENCE_INTENSITY",
    "REFERENCE_WIND_SPEED",
    "TURBULENCE_MODELS",
    "TurbulenceSpec",
    "TurbulentWind",
    "cached_turbulence",
    "rotor_grid_size",
    "default_cache_dir",
    "etm_standard_deviation",
    "generate_turbulence",
    "longitudinal_length_scale",
    "ntm_standard_deviation",
]

#: I_ref of the IEC 61400-1 Ed. 3 turbulence categories (expected turbulence
#: intensity at 15 m/s); anchor_windcontrol.md §3.7, pyconturb ``iec_sig``.
REFERENCE_TURBULENCE_INTENSITY = MappingProxyType({"A": 0.16, "B": 0.14, "C": 0.12})

#: V_ref of the IEC 61400-1 Ed. 3 wind turbine classes [m/s] (anchor_windcontrol.md §3.7).
REFERENCE_WIND_SPEED = MappingProxyType({"I": 50.0, "II": 42.5, "III": 37.5})

#: The turbulence models of IEC 61400-1 Ed. 3: normal (§6.3.1.3) and extreme (§6.3.2.3).
TURBULENCE_MODELS = ("NTM", "ETM")

_CACHE_FORMAT = 2  # bump when the cached array layout or the generation procedure changes
_FREQUENCY_CHUNK = 64  # frequencies per pyconturb coherence chunk: speed vs. memory (~8 MB at 11x11)
_COMPONENT_SIGMA_RATIOS = np.array([1.0, 0.8, 0.5])  # sigma_k / sigma_1 of u, v, w, IEC 61400-1 Ed. 3 Annex B


def ntm_standard_deviation(hub_speed: float, turbulence_class: str) -> float:
    """Longitudinal turbulence standard deviation of the normal turbulence model [m/s].

    Parameters
    ----------
    hub_speed : float
        10-min mean wind speed at hub height V_hub [m/s], > 0.
    turbulence_class : str
        IEC turbulence category, ``"A"``, ``"B"`` or ``"C"``.

    Returns
    -------
    float
        sigma_1 = I_ref (0.75 V_hub + 5.6) [m/s].

    Notes
    -----
    IEC 61400-1 Ed. 3 §6.3.1.3 (NTM), as quoted in anchor_windcontrol.md §3.7;
    the turbulence intensity of Fratini (2019) eq. 2.4 is sigma_1 / V_hub.

    Examples
    --------
    >>> round(ntm_standard_deviation(11.4, "A"), 4)
    2.264
    """
    if turbulence_class not in REFERENCE_TURBULENCE_INTENSITY:
        raise ValueError(f"turbulence_class: expected one of A, B, C, found {turbulence_class!r}")
    if not hub_speed > 0.0:
        raise ValueError(f"hub_speed: expected > 0 m/s, found {hub_speed}")
    return REFERENCE_TURBULENCE_INTENSITY[turbulence_class] * (0.75 * hub_speed + 5.6)


def etm_standard_deviation(hub_speed: float, turbulence_class: str, turbine_class: str) -> float:
    """Longitudinal turbulence standard deviation of the extreme turbulence model [m/s].

    Parameters
    ----------
    hub_speed : float
        10-min mean wind speed at hub height V_hub [m/s], > 0.
    turbulence_class : str
        IEC turbulence category, ``"A"``, ``"B"`` or ``"C"`` (I_ref).
    turbine_class : str
        IEC wind turbine class, ``"I"``, ``"II"`` or ``"III"``: the annual mean speed at hub height
        V_ave = 0.2 V_ref (IEC 61400-1 Ed. 3 eq. 9).

    Returns
    -------
    float
        sigma_1 = c I_ref (0.072 (V_ave / c + 3) (V_hub / c - 4) + 10), c = 2 m/s.

    Notes
    -----
    IEC 61400-1 Ed. 3 §6.3.2.3 eq. 19 (ETM), checked against NREL WEIS's IEC case generator (its ETM turbulence
    intensity is this sigma_1 / V_hub). Ed. 4 (2019) lists no change to the ETM among its technical changes.

    Examples
    --------
    >>> round(etm_standard_deviation(18.0, "B", "I"), 4)  # 2 * 0.14 * (0.072 * 8 * 5 + 10)
    3.6064
    """
    ntm_standard_deviation(hub_speed, turbulence_class)  # checks both
    if turbine_class not in REFERENCE_WIND_SPEED:
        raise ValueError(f"turbine_class: expected one of I, II, III, found {turbine_class!r}")
    c, annual_mean = 2.0, 0.2 * REFERENCE_WIND_SPEED[turbine_class]
    return c * REFERENCE_TURBULENCE_INTENSITY[turbulence_class] * (
        0.072 * (annual_mean / c + 3.0) * (hub_speed / c - 4.0) + 10.0)


def longitudinal_length_scale(hub_height: float) -> float:
    """Turbulence scale parameter Lambda_1 of IEC 61400-1 Ed. 3 [m].

    Parameters
    ----------
    hub_height : float
        Hub height z_hub [m], > 0.

    Returns
    -------
    float
        0.7 z_hub for z_hub <= 60 m, otherwise 42 m (anchor_windcontrol.md §3.7).
    """
    if not hub_height > 0.0:
        raise ValueError(f"hub_height: expected > 0 m, found {hub_height}")
    return 0.7 * hub_height if hub_height <= 60.0 else 42.0


def rotor_grid_size(tip_radius: float, hub_height: float) -> tuple[float, float]:
    """Width and height [m] of the turbulence grid for a rotor of ``tip_radius`` [m] on a hub at ``hub_height`` [m].

    The rotor disc with 10 % margin, rounded up to whole metres each side (TurbSim's user guide asks for a grid
    that covers the rotor with some margin; InflowWind clamps nothing inside it). The NREL 5 MW's 63 m gives the
    140 m x 140 m of :class:`TurbulenceSpec`'s defaults. The height is limited so that the bottom row stays 1 m
    above the ground.
    """
    size = 2.0 * math.ceil(1.1 * tip_radius)
    return size, min(size, 2.0 * (hub_height - 1.0))


@dataclasses.dataclass(frozen=True)
class TurbulenceSpec:
    """Everything that determines a generated turbulent field (and its cache key).

    The defaults give an IEC 61400-1 DLC 1.2 style box for the NREL 5 MW: a
    600 s, 11 x 11 grid of 140 m x 140 m centred on the 90 m hub (rotor radius
    63 m, NREL 5 MW ElastoDyn ``TipRad``), 0.05 s time step (TurbSim's usual),
    IEC normal wind profile exponent 0.2, turbulence category A (the default of
    ROSCO ``CaseGen_IEC``, anchor_windcontrol.md §3.7).

    Attributes
    ----------
    mean_speed : float
        Mean longitudinal speed at hub height V_hub [m/s], > 0.
    turbulence_class : str
        IEC turbulence category ``"A"``, ``"B"`` or ``"C"`` (I_ref 0.16/0.14/0.12).
    seed : int
        Random seed, 0 <= seed < 2**32; the same spec gives the same field.
    hub_height : float
        Hub height [m]; the grid is centred on it.
    shear_exponent : float
        Power-law exponent alpha of the mean profile, Fratini (2019) eq. 2.2.
    duration : float
        Length of the field [s]; the field is periodic with this period.
    time_step : float
        Time step [s]; ``duration`` must be a whole multiple of it.
    grid_width, grid_height : float
        Lateral and vertical extent of the grid [m].
    n_y, n_z : int
        Number of grid points laterally and vertically (odd puts a node on the hub).
    scale_to_hub_sigma : bool
        Scale the turbulence of each component, uniformly over the grid, so that
        the hub node has exactly the standard deviations sigma_1, 0.8 sigma_1,
        0.5 sigma_1 (TurbSim ``ScaleIEC = 1``); needs odd n_y and n_z. Without it,
        the 10-min hub sigma of a coherent grid scatters by ~10 % between seeds.
    turbulence_model : str
        ``"NTM"`` (sigma_1 of :func:`ntm_standard_deviation`) or ``"ETM"`` (of :func:`etm_standard_deviation`).
    turbine_class : str
        IEC wind turbine class ``"I"``, ``"II"`` or ``"III"``, whose V_ref sets the ETM's V_ave; the NTM ignores it.
        Neither enters an NTM field's cache key, so NTM fields cached before the ETM existed are found again.
    """

    mean_speed: float
    turbulence_class: str = "A"
    seed: int = 0
    hub_height: float = 90.0
    shear_exponent: float = 0.2
    duration: float = 600.0
    time_step: float = 0.05
    grid_width: float = 140.0
    grid_height: float = 140.0
    n_y: int = 11
    n_z: int = 11
    scale_to_hub_sigma: bool = True
    turbulence_model: str = "NTM"
    turbine_class: str = "I"

    def __post_init__(self) -> None:
        if self.turbulence_model not in TURBULENCE_MODELS:
            raise ValueError(f"turbulence_model: expected one of NTM, ETM, found {self.turbulence_model!r}")
        etm_standard_deviation(self.mean_speed, self.turbulence_class, self.turbine_class)  # checks all three
        longitudinal_length_scale(self.hub_height)
        if not 0 <= self.seed < 2**32:
            raise ValueError(f"seed: expected 0 <= seed < 2**32, found {self.seed}")
        if not (self.duration > 0.0 and self.time_step > 0.0):
            raise ValueError(f"duration, time_step: expected > 0 s, found {self.duration}, {self.time_step}")
        steps = self.duration / self.time_step
        if abs(steps - round(steps)) > 1e-6 * steps or round(steps) < 2:
            raise ValueError(f"duration: expected a whole multiple (>= 2) of time_step={self.time_step} s, "
                             f"found {self.duration} s")
        if self.n_y < 1 or self.n_z < 1:
            raise ValueError(f"n_y, n_z: expected >= 1 grid points, found {self.n_y}, {self.n_z}")
        if self.scale_to_hub_sigma and not (self.n_y % 2 and self.n_z % 2):
            raise ValueError(f"n_y, n_z: scale_to_hub_sigma needs a node at the hub (odd counts), "
                             f"found {self.n_y}, {self.n_z}")
        if self.grid_width < 0.0 or not 0.0 <= self.grid_height < 2.0 * self.hub_height:
            raise ValueError(f"grid_height: expected a grid above ground, in [0, 2 hub_height), "
                             f"found width {self.grid_width} m, height {self.grid_height} m")

    @property
    def sigma_1(self) -> float:
        """Longitudinal standard deviation sigma_1 of the field's turbulence model at hub height [m/s]."""
        if self.turbulence_model == "ETM":
            return etm_standard_deviation(self.mean_speed, self.turbulence_class, self.turbine_class)
        return ntm_standard_deviation(self.mean_speed, self.turbulence_class)

    @property
    def n_t(self) -> int:
        """Number of time steps of the field."""
        return round(self.duration / self.time_step)

    @property
    def grid_y(self) -> np.ndarray:
        """Lateral grid coordinates [m], shape (n_y,), centred on the tower (y = 0)."""
        return np.linspace(-0.5, 0.5, self.n_y) * self.grid_width if self.n_y > 1 else np.zeros(1)

    @property
    def grid_z(self) -> np.ndarray:
        """Vertical grid coordinates [m], shape (n_z,), centred on the hub."""
        offsets = np.linspace(-0.5, 0.5, self.n_z) * self.grid_height if self.n_z > 1 else np.zeros(1)
        return self.hub_height + offsets


class TurbulentWind:
    """Full-field wind on a regular (t, z, y) grid, sampled by trilinear interpolation.

    One class serves generated fields (:func:`generate_turbulence`) and TurbSim
    files (:func:`hawt_plant.bts.read_bts`). Implements
    :class:`~hawt_plant.wind_field.WindField`.

    Parameters
    ----------
    velocity : np.ndarray
        Total wind velocity (mean + turbulence) [m/s], shape (n_t, n_z, n_y, 3):
        time, height, lateral position, component (u, v, w) along (x, y, z).
        This is the record order of a ``.bts`` file. Stored as float32.
    time_step : float
        Time between samples [s], > 0.
    grid_y : np.ndarray
        Lateral node coordinates [m], shape (n_y,), increasing and evenly spaced.
    grid_z : np.ndarray
        Vertical node coordinates [m], shape (n_z,), increasing and evenly spaced.
    mean_speed : float
        Mean longitudinal speed at hub height [m/s] (> 0), also the convection speed.
    hub_height : float
        Height the mean speed refers to [m].
    periodic : bool
        True if sample n_t would equal sample 0 (FFT-generated fields, TurbSim
        file id 8): the period is n_t * time_step and the last sample is
        interpolated towards the first. False (TurbSim file id 7): the period is
        (n_t - 1) * time_step and the field jumps from the last sample back to
        the first when it wraps.
    x_offset : float
        At t = 0 the plane x = x_offset sees field time 0 [m]. OpenFAST
        InflowWind uses 0 for periodic files and half the grid width for
        non-periodic ones (``InitXPosition``, InflowWind ``IfW_TSFFWind``).

    Notes
    -----
    Taylor's frozen turbulence: a point at x sees, at time t, the grid at field
    time t_f = t + (x_offset - x) / mean_speed. Points outside the grid take the
    value of the nearest grid edge (clamping, no extrapolation; so a point below
    the grid sees the bottom row). Times beyond the field wrap periodically
    (t_f modulo the period), so any simulation length can be sampled.
    Interpolation is linear in t, z and y (8 nodes), as InflowWind does with
    ``VelInterpCubic = False``.
    """

    def __init__(self, velocity: np.ndarray, *, time_step: float, grid_y: np.ndarray,
                 grid_z: np.ndarray, mean_speed: float, hub_height: float,
                 periodic: bool = True, x_offset: float = 0.0) -> None:
        velocity = np.asarray(velocity)
        grid_y = _even_grid(grid_y, "grid_y")
        grid_z = _even_grid(grid_z, "grid_z")
        if velocity.ndim != 4 or velocity.shape[1:] != (grid_z.size, grid_y.size, 3):
            raise ValueError(f"velocity: expected shape (n_t, n_z={grid_z.size}, n_y={grid_y.size}, 3), "
                             f"found {velocity.shape}")
        if velocity.shape[0] < 2:
            raise ValueError(f"velocity: expected at least 2 time steps, found {velocity.shape[0]}")
        if not np.all(np.isfinite(velocity)):
            raise ValueError("velocity: NaN or infinite values in the field")
        if not (time_step > 0.0 and mean_speed > 0.0 and hub_height > 0.0):
            raise ValueError(f"time_step, mean_speed, hub_height: expected > 0, "
                             f"found {time_step}, {mean_speed}, {hub_height}")
        self._grid_y, self._grid_z = grid_y, grid_z
        self._time_step = float(time_step)
        self._mean_speed = float(mean_speed)
        self._hub_height = float(hub_height)
        self._periodic = bool(periodic)
        self._x_offset = float(x_offset)

        n_t, n_z, n_y, _ = velocity.shape
        # Own float32 copy, one plane per component with the nodes ordered (t, z, y), so that
        # the 8 corners of n points gather into (3, n, 8), ready for a dot product with their
        # weights; a periodic field stores sample 0 again after the last one.
        self._planes = np.empty((3, (n_t + self._periodic) * n_z * n_y), dtype=np.float32)
        stored = self._planes.T.reshape(n_t + self._periodic, n_z, n_y, 3)  # a view
        stored[:n_t] = velocity
        stored[n_t:] = velocity[:1]  # empty slice unless periodic
        self._planes.flags.writeable = stored.flags.writeable = False
        self._velocity = stored[:n_t]
        t_cells = stored.shape[0] - 1
        self._period = t_cells * self._time_step
        # Fractional grid index of a point, per axis (t, z, y): (coordinate * scale + shift),
        # the time row adding t / time_step. A single-node axis has scale 0 (always node 0).
        inv_dz = 1.0 / (grid_z[1] - grid_z[0]) if n_z > 1 else 0.0
        inv_dy = 1.0 / (grid_y[1] - grid_y[0]) if n_y > 1 else 0.0
        inv_dt = 1.0 / self._time_step
        self._inv_dt, self._t_cells = inv_dt, float(t_cells)
        self._scale = np.array([-inv_dt / self._mean_speed, inv_dz, inv_dy])
        self._shift = np.array([self._x_offset * inv_dt / self._mean_speed, -grid_z[0] * inv_dz, -grid_y[0] * inv_dy])
        # Fractional indices are clamped to [0, upper] with the upper edge just inside the last
        # cell, so that truncation gives a cell index and weight 1 (to rounding) at the edge.
        upper = np.array([t_cells, n_z - 1, n_y - 1], dtype=float)
        self._upper = np.nextafter(upper, 0.0)
        self._strides = np.array([n_z * n_y, n_y, 1])
        corners = np.array([(it, iz, iy) for it in (0, 1) for iz in (0, 1) for iy in (0, 1)])
        neighbour_strides = self._strides * (upper > 0)  # no neighbour on a 1-node axis
        self._corner_offsets = corners @ neighbour_strides  # (8,)
        from hawt_plant.compiled import unchecked  # compiled: numba's import is not part of this module's
        from hawt_plant.grid_sampling import trilinear

        # without the check of its arguments' types: the field's own arrays, and the points made flat float64 (velocity)
        self._trilinear = unchecked(trilinear)

    @property
    def mean_speed(self) -> float:
        """Mean longitudinal speed at hub height [m/s]."""
        return self._mean_speed

    @property
    def hub_height(self) -> float:
        """Reference height of the mean speed [m]."""
        return self._hub_height

    @property
    def velocity_grid(self) -> np.ndarray:
        """The grid values [m/s], read-only, shape (n_t, n_z, n_y, 3)."""
        return self._velocity

    @property
    def grid_y(self) -> np.ndarray:
        """Lateral node coordinates [m], shape (n_y,)."""
        return self._grid_y.copy()

    @property
    def grid_z(self) -> np.ndarray:
        """Vertical node coordinates [m], shape (n_z,)."""
        return self._grid_z.copy()

    @property
    def time_step(self) -> float:
        """Time between samples [s]."""
        return self._time_step

    @property
    def periodic(self) -> bool:
        """Whether the field is periodic with period n_t * time_step."""
        return self._periodic

    @property
    def x_offset(self) -> float:
        """Downwind position that sees field time 0 at t = 0 [m]."""
        return self._x_offset

    @property
    def period(self) -> float:
        """Time after which sampling wraps to the start of the field [s]."""
        return self._period

    def velocity(self, t: float, x: np.ndarray, y: np.ndarray, z: np.ndarray) -> np.ndarray:
        """Wind velocity at the points (x, y, z) [m] at time t [s].

        Parameters
        ----------
        t : float
            Simulation time [s].
        x, y, z : np.ndarray
            Point coordinates in the inertial frame [m], all of the same shape.

        Returns
        -------
        np.ndarray
            Shape ``(3,) + x.shape``: (u, v, w) [m/s], trilinear in (t_f, z, y),
            clamped to the grid edges, periodic in time (see class Notes).
        """
        x, y, z = np.asarray(x, dtype=float), np.asarray(y, dtype=float), np.asarray(z, dtype=float)
        if not x.shape == y.shape == z.shape:
            raise ValueError(f"x, y, z: expected equal shapes, found {x.shape}, {y.shape}, {z.shape}")
        out = np.empty((3, x.size))
        self._trilinear(float(t), x.reshape(-1), y.reshape(-1), z.reshape(-1), self._planes, self._scale, self._shift,
                        self._inv_dt, self._t_cells, self._upper, self._strides, self._corner_offsets, out)
        return out.reshape((3,) + x.shape)


def _even_grid(values: np.ndarray, name: str) -> np.ndarray:
    """Validate a 1-D, increasing, evenly spaced grid and return it as float array."""
    values = np.asarray(values, dtype=float)
    if values.ndim != 1 or values.size < 1 or not np.all(np.isfinite(values)):
        raise ValueError(f"{name}: expected a finite 1-D array of node coordinates, found shape {values.shape}")
    if values.size > 1:
        steps = np.diff(values)
        if not (steps[0] > 0.0 and np.allclose(steps, steps[0], rtol=1e-5, atol=0.0)):
            raise ValueError(f"{name}: expected increasing, evenly spaced nodes, found steps {steps}")
    return values


def _kaimal_with_hub_length_scale(f: np.ndarray, spat_df: "pandas.DataFrame", z_ref: float,
                                  **kwargs) -> np.ndarray:
    """pyconturb's IEC Kaimal spectrum with Lambda_1 taken at hub height for every point.

    IEC 61400-1 defines the Kaimal length scales from Lambda_1(z_hub); pyconturb's
    ``kaimal_spectrum`` evaluates Lambda_1 at each point's own height, which
    shortens the scale of points below 60 m.
    """
    at_hub = spat_df.copy()
    at_hub.loc["z"] = z_ref
    from pyconturb.spectral_models import kaimal_spectrum

    return kaimal_spectrum(f, at_hub, **kwargs)


def generate_turbulence(spec: TurbulenceSpec, progress: Callable[[str], None] = lambda _: None) -> TurbulentWind:
    """Generate an IEC 61400-1 NTM or ETM turbulent field with pyconturb (slow: no cache).

    Parameters
    ----------
    spec : TurbulenceSpec
        Field parameters.
    progress : callable, optional
        Gets a line as each of the three components is done.

    Returns
    -------
    TurbulentWind
        Periodic field (period ``spec.duration``), ``x_offset`` 0.

    Notes
    -----
    pyconturb ``gen_turb`` (Veers' method): Kaimal spectra for u, v, w with
    the spec's sigma_1 (:attr:`TurbulenceSpec.sigma_1`, NTM or ETM),
    sigma_2 = 0.8 sigma_1, sigma_3 = 0.5 sigma_1 and length scales 8.1, 2.7,
    0.66 Lambda_1, IEC exponential coherence exp(-12 sqrt((f r / V_hub)^2 +
    (0.12 r / L_c)^2)), L_c = 8.1 Lambda_1, on u only (v and w uncorrelated
    between points), mean profile V_hub (z / z_hub)^alpha on u (Fratini (2019)
    eq. 2.2); IEC 61400-1 Ed. 3 §6.3.1.3 (§6.3.2.3 for the ETM) and Annex B. pyconturb gives every
    point the target variance in expectation; ``spec.scale_to_hub_sigma`` makes
    it exact at the hub. Each component is generated by its own ``gen_turb``
    call, seeded from ``numpy.random.SeedSequence(spec.seed)``. pyconturb seeds
    numpy's global generator; its state is restored afterwards. The linear algebra runs on one BLAS thread
    (threadpoolctl): the same numbers, and on a busy 2-core machine four times faster than OpenBLAS's threads
    (a 600 s field at load 9: 18 s against 71 s).
    """
    import pyconturb  # with pandas about 0.2 s of CPU to import, which only generating a field needs

    grid_y, grid_z = spec.grid_y, spec.grid_z
    velocity = np.empty((spec.n_t, grid_z.size, grid_y.size, 3), dtype=np.float32)
    seeds = np.random.SeedSequence(spec.seed).generate_state(3)  # one pyconturb seed per component
    global_state = np.random.get_state()
    try:
        for component, seed in enumerate(seeds):
            if component:
                progress(f"turbulence component {'uvw'[component - 1]} done ({component} of 3)")
            # The components are mutually uncorrelated, so one call each is the same model
            # with 1/3 of the points per Cholesky factorisation (~5x faster than one call).
            spat_df = pyconturb.gen_spat_grid(grid_y, grid_z, comps=[component])
            with warnings.catch_warnings():
                warnings.filterwarnings("ignore", message="The inplace keyword")  # pyconturb 2.7.4, pandas 3
                with threadpool_limits(1, user_api="blas"):
                    series = pyconturb.gen_turb(
                        spat_df, T=spec.duration, nt=spec.n_t, u_ref=spec.mean_speed, z_ref=spec.hub_height,
                        alpha=spec.shear_exponent, turb_class=spec.turbulence_class, seed=int(seed),
                        spec_func=_kaimal_with_hub_length_scale, sig_func=_iec_sigma, sigma_1=spec.sigma_1,
                        l_c=8.1 * longitudinal_length_scale(spec.hub_height), nf_chunk=_FREQUENCY_CHUNK)
            iy = np.abs(spat_df.loc["y"].to_numpy(dtype=float)[:, None] - grid_y).argmin(axis=1)
            iz = np.abs(spat_df.loc["z"].to_numpy(dtype=float)[:, None] - grid_z).argmin(axis=1)
            velocity[:, iz, iy, component] = series.to_numpy()
    finally:
        np.random.set_state(global_state)
    if spec.scale_to_hub_sigma:
        velocity = _scaled_to_hub_sigma(velocity, spec.sigma_1)
    return _wind_from_spec(spec, velocity)


def _iec_sigma(spat_df: "pandas.DataFrame", *, sigma_1: float, **_) -> np.ndarray:
    """pyconturb's ``iec_sig`` for any sigma_1 [m/s]: sigma_1, 0.8 sigma_1, 0.5 sigma_1 for the points of component
    k = 0, 1, 2 (u, v, w) of ``spat_df``, IEC 61400-1 Ed. 3 Annex B; shape (n_sp,)."""
    return sigma_1 * _COMPONENT_SIGMA_RATIOS[spat_df.loc["k"].to_numpy(dtype=int)]


def _scaled_to_hub_sigma(velocity: np.ndarray, sigma_1: float) -> np.ndarray:
    """Scale each component's fluctuations by one factor so the hub node has sigma_1 (1, 0.8, 0.5).

    TurbSim ``ScaleIEC = 1``; the hub is the centre node of the (odd) grid.
    IEC 61400-1 Ed. 3 Annex B: sigma_2 = 0.8 sigma_1, sigma_3 = 0.5 sigma_1.
    """
    mean = velocity.mean(axis=0)
    fluctuation = velocity - mean
    hub = fluctuation[:, velocity.shape[1] // 2, velocity.shape[2] // 2, :]
    factor = sigma_1 * _COMPONENT_SIGMA_RATIOS / hub.std(axis=0)
    return (mean + fluctuation * factor).astype(np.float32)


def _wind_from_spec(spec: TurbulenceSpec, velocity: np.ndarray) -> TurbulentWind:
    """Wrap a generated grid of ``spec`` in a TurbulentWind."""
    return TurbulentWind(velocity, time_step=spec.duration / spec.n_t, grid_y=spec.grid_y,
                         grid_z=spec.grid_z, mean_speed=spec.mean_speed, hub_height=spec.hub_height,
                         periodic=True)


def default_cache_dir() -> Path:
    """Directory of cached turbulent fields: ``$HAWT_CACHE_DIR/turbulence``.

    ``HAWT_CACHE_DIR`` is the project's cache root and defaults to ``~/.cache/hawt``.
    """
    return cache_root() / "turbulence"


def _cache_key(spec: TurbulenceSpec) -> str:
    """Hash of every parameter that determines the field, and of the generator version. An NTM spec hashes without
    ``turbulence_model`` and ``turbine_class`` (the NTM does not depend on the turbine class), as before the ETM."""
    fields = dataclasses.asdict(spec)
    if spec.turbulence_model == "NTM":
        del fields["turbulence_model"], fields["turbine_class"]
    identity = {**fields, "generator": "pyconturb", "generator_version":
                importlib.metadata.version("pyconturb"), "cache_format": _CACHE_FORMAT}
    return hashlib.sha256(json.dumps(identity, sort_keys=True).encode()).hexdigest()[:32]


def cached_turbulence(spec: TurbulenceSpec, cache_dir: Path | str | None = None,
                      progress: Callable[[str], None] = lambda _: None) -> TurbulentWind:
    """The field of ``spec``, loaded from the disk cache or generated and stored there.

    Parameters
    ----------
    spec : TurbulenceSpec
        Field parameters; their hash (with pyconturb's version) names the cache file.
    cache_dir : Path or str, optional
        Cache directory; default :func:`default_cache_dir`. Created if missing.
    progress : callable, optional
        Gets a line before a field is generated (what, and the file it goes into) and one when it is done (how
        long it took); nothing when the field comes from the cache.

    Returns
    -------
    TurbulentWind
        The same data as :func:`generate_turbulence` (spec).

    Notes
    -----
    Files are written to a temporary file in the cache directory and renamed
    into place, so a reader never sees a partial file and concurrent writers of
    the same field are harmless. A 600 s 11 x 11 field at 0.05 s takes ~17 MB.
    """
    directory = Path(cache_dir) if cache_dir is not None else default_cache_dir()
    path = directory / f"{_cache_key(spec)}.npy"
    expected_shape = (spec.n_t, spec.n_z, spec.n_y, 3)
    if path.exists():
        velocity = np.load(path)
        if velocity.shape != expected_shape or velocity.dtype != np.float32:
            raise ValueError(f"{path}: cached field has shape {velocity.shape} {velocity.dtype}, expected "
                             f"{expected_shape} float32; delete the file to regenerate it")
        return _wind_from_spec(spec, velocity)
    progress(f"generating a turbulent wind field (class {spec.turbulence_class}, {spec.mean_speed:g} m/s, seed "
             f"{spec.seed}, {spec.duration:g} s) into {path}; cached for the next run")
    start = time.monotonic()
    wind = generate_turbulence(spec, progress)
    progress(f"turbulent wind field generated in {time.monotonic() - start:.1f} s")
    store(path, lambda handle: np.save(handle, wind.velocity_grid))
    return wind
