"""Deterministic transient inflows over power-law shear: a wind step and the IEC extreme operating gust.

Both implement :class:`~hawt_plant.wind_field.WindField`. Like the turbulent
fields, the transient is convected downwind at the initial hub speed: a point
at x sees the hub history of time t - x / mean_speed. The other extreme wind
conditions of IEC 61400-1 are in :mod:`hawt_plant.iec_extreme`.
"""
import math

import numpy as np

from hawt_plant.turbulence import REFERENCE_WIND_SPEED, longitudinal_length_scale, ntm_standard_deviation

__all__ = [
    "EOG_DURATION",
    "REFERENCE_WIND_SPEED",
    "ExtremeOperatingGust",
    "TransientWind",
    "WindStep",
    "eog_amplitude",
    "extreme_wind_speed",
]

#: Duration T of the extreme operating gust [s], IEC 61400-1 Ed. 3 §6.3.2.2.
EOG_DURATION = 10.5


def _power_law_profile(z: np.ndarray, hub_height: float, exponent: float) -> np.ndarray:
    """(z / z_hub)^alpha, Fratini (2019) eq. 2.2; zero at and below the ground."""
    return (np.maximum(z, 0.0) / hub_height) ** exponent


def _check_profile(hub_height: float, shear_exponent: float) -> None:
    """Validate the shear-profile parameters shared by the transient fields."""
    if not hub_height > 0.0:
        raise ValueError(f"hub_height: expected > 0 m, found {hub_height}")
    if not 0.0 <= shear_exponent < 1.0:
        raise ValueError(f"shear_exponent: expected in [0, 1), found {shear_exponent}")


def _check_points(x: np.ndarray, y: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Points as float arrays of one shape; returns (x, z)."""
    x, y, z = np.asarray(x, dtype=float), np.asarray(y, dtype=float), np.asarray(z, dtype=float)
    if not x.shape == y.shape == z.shape:
        raise ValueError(f"x, y, z: expected equal shapes, found {x.shape}, {y.shape}, {z.shape}")
    return x, z


def _longitudinal(u: np.ndarray) -> np.ndarray:
    """(u, 0, 0) stacked as shape (3,) + u.shape."""
    velocity = np.zeros((3,) + u.shape)
    velocity[0] = u
    return velocity


class TransientWind:
    """What every transient field shares: the hub-height speed before it (also the convection speed: a transient
    starting at t_0 reaches x at t_0 + x / V_hub), its start t_0, and the power-law profile it rides on,
    u = V (z / z_hub)^alpha (Fratini (2019) eq. 2.2). A transient's own ``velocity`` adds what changes."""

    def __init__(self, hub_speed: float, start_time: float, hub_height: float, shear_exponent: float) -> None:
        _check_profile(hub_height, shear_exponent)
        self._hub_speed, self._start_time = float(hub_speed), float(start_time)
        self._hub_height, self._shear_exponent = float(hub_height), float(shear_exponent)

    @property
    def mean_speed(self) -> float:
        """V_hub before the transient [m/s]."""
        return self._hub_speed

    @property
    def hub_height(self) -> float:
        """z_hub [m]."""
        return self._hub_height

    def _profile(self, z: np.ndarray) -> np.ndarray:
        """(z / z_hub)^alpha."""
        return _power_law_profile(z, self._hub_height, self._shear_exponent)


class WindStep(TransientWind):
    """Hub speed stepping (or ramping) from one value to another, over power-law shear.

    Parameters
    ----------
    speed_before : float
        Hub-height speed U_1 before the step [m/s], > 0; also the convection speed.
    speed_after : float
        Hub-height speed U_2 after the step [m/s], >= 0.
    step_time : float
        Time t_0 at which the speed starts changing at x = 0 [s].
    ramp_duration : float
        Time over which the speed changes linearly from U_1 to U_2 [s]; 0 gives
        a step (U_2 from t_0 on).
    hub_height : float
        Reference height of the speeds [m].
    shear_exponent : float
        Power-law exponent alpha: u(z, t) = U(t) (z / z_hub)^alpha, Fratini (2019) eq. 2.2.
    """

    def __init__(self, speed_before: float, speed_after: float, step_time: float, *,
                 ramp_duration: float = 0.0, hub_height: float = 90.0, shear_exponent: float = 0.2) -> None:
        if not (speed_before > 0.0 and speed_after >= 0.0):
            raise ValueError(f"speed_before, speed_after: expected > 0 and >= 0 m/s, "
                             f"found {speed_before}, {speed_after}")
        if not ramp_duration >= 0.0:
            raise ValueError(f"ramp_duration: expected >= 0 s, found {ramp_duration}")
        super().__init__(speed_before, step_time, hub_height, shear_exponent)
        self._speed_after, self._ramp_duration = float(speed_after), float(ramp_duration)

    def hub_speed(self, t: np.ndarray | float) -> np.ndarray:
        """Hub-height speed at x = 0 [m/s], same shape as t [s]."""
        elapsed = np.asarray(t, dtype=float) - self._start_time
        if self._ramp_duration > 0.0:
            fraction = np.clip(elapsed / self._ramp_duration, 0.0, 1.0)
        else:
            fraction = (elapsed >= 0.0).astype(float)
        return self._hub_speed + fraction * (self._speed_after - self._hub_speed)

    def velocity(self, t: float, x: np.ndarray, y: np.ndarray, z: np.ndarray) -> np.ndarray:
        """Wind velocity (u, 0, 0) [m/s], shape ``(3,) + x.shape``, at points (x, y, z) [m] and time t [s]."""
        x, z = _check_points(x, y, z)
        speed = self.hub_speed(t - x / self._hub_speed)
        return _longitudinal(speed * self._profile(z))


def extreme_wind_speed(turbine_class: str, recurrence_period: int) -> float:
    """Steady extreme wind speed at hub height, V_e50 or V_e1, of the IEC 61400-1 Ed. 3 wind turbine class [m/s].

    Parameters
    ----------
    turbine_class : str
        ``"I"``, ``"II"`` or ``"III"`` (V_ref 50, 42.5, 37.5 m/s).
    recurrence_period : int
        50 or 1 [years].

    Returns
    -------
    float
        V_e50 = 1.4 V_ref (eq. 14 at z = z_hub), or V_e1 = 0.8 V_e50 (eq. 15).

    Notes
    -----
    IEC 61400-1 Ed. 3 §6.3.2.1 (EWM, steady model); Ashes' documentation of Ed. 4 (2019) quotes the same.

    Examples
    --------
    >>> round(extreme_wind_speed("I", 50), 9), round(extreme_wind_speed("III", 1), 9)
    (70.0, 42.0)
    """
    if turbine_class not in REFERENCE_WIND_SPEED:
        raise ValueError(f"turbine_class: expected one of I, II, III, found {turbine_class!r}")
    if recurrence_period not in (50, 1):
        raise ValueError(f"recurrence_period: expected 50 or 1 years, found {recurrence_period!r}")
    return (1.4 if recurrence_period == 50 else 0.8 * 1.4) * REFERENCE_WIND_SPEED[turbine_class]


def eog_amplitude(hub_speed: float, turbine_class: str, turbulence_class: str, rotor_diameter: float,
                  hub_height: float) -> float:
    """Gust magnitude V_gust of the IEC 61400-1 Ed. 3 extreme operating gust [m/s].

    Parameters
    ----------
    hub_speed : float
        V_hub [m/s], > 0.
    turbine_class : str
        ``"I"``, ``"II"`` or ``"III"`` (V_ref 50, 42.5, 37.5 m/s).
    turbulence_class : str
        ``"A"``, ``"B"`` or ``"C"``.
    rotor_diameter : float
        D [m], > 0.
    hub_height : float
        z_hub [m]; sets Lambda_1.

    Returns
    -------
    float
        V_gust = min(1.35 (V_e1 - V_hub), 3.3 sigma_1 / (1 + 0.1 D / Lambda_1)), with
        V_e1 of :func:`extreme_wind_speed` and sigma_1 of the NTM.

    Notes
    -----
    IEC 61400-1 Ed. 3 §6.3.2.2 (EOG) and §6.3.2.1 (EWM, V_e50 = 1.4 V_ref at hub
    height); the standard was not accessible, the formula is checked against
    its implementation in NREL WEIS ``IEC_CoherentGusts.EOG`` and the brief.
    Fratini (2019) eq. 2.6 gives the older Ed. 2 form beta sigma_1 / (1 + 0.1 D / Lambda_1).
    Can be negative when V_hub > V_e1 (no such operating point exists).

    Examples
    --------
    >>> round(eog_amplitude(11.4, "I", "A", 126.0, 90.0), 4)  # NREL 5 MW at rated
    5.7471
    """
    extreme_1_year = extreme_wind_speed(turbine_class, 1)
    sigma_1 = ntm_standard_deviation(hub_speed, turbulence_class)
    return min(1.35 * (extreme_1_year - hub_speed), 3.3 * sigma_1 / _size_reduction(rotor_diameter, hub_height))


def _size_reduction(rotor_diameter: float, hub_height: float) -> float:
    """1 + 0.1 D / Lambda_1, the rotor-size factor of the IEC 61400-1 Ed. 3 EOG and EDC magnitudes (§6.3.2.2,
    §6.3.2.4)."""
    if not rotor_diameter > 0.0:
        raise ValueError(f"rotor_diameter: expected > 0 m, found {rotor_diameter}")
    return 1.0 + 0.1 * rotor_diameter / longitudinal_length_scale(hub_height)


class ExtremeOperatingGust(TransientWind):
    """IEC 61400-1 Ed. 3 extreme operating gust (EOG) over power-law shear.

    u(z, t) = V_hub (z / z_hub)^alpha - 0.37 V_gust sin(3 pi tau / T) (1 - cos(2 pi tau / T))
    for 0 <= tau <= T, tau = t - t_0 - x / V_hub, T = 10.5 s; u = V_hub (z / z_hub)^alpha
    otherwise. The speed dips, rises to V_hub + 0.74 V_gust at tau = T / 2, and dips again.

    Parameters
    ----------
    hub_speed : float
        V_hub [m/s], > 0; also the convection speed.
    start_time : float
        t_0, start of the gust at x = 0 [s].
    turbine_class, turbulence_class : str
        IEC classes (see :func:`eog_amplitude`). Defaults I and A.
    rotor_diameter : float
        D [m]; default 126 m (NREL 5 MW, 2 x ElastoDyn ``TipRad`` 63 m).
    hub_height : float
        z_hub [m]; default 90 m (NREL 5 MW).
    shear_exponent : float
        alpha; default 0.2, the IEC normal wind profile.
    """

    def __init__(self, hub_speed: float, start_time: float, *, turbine_class: str = "I",
                 turbulence_class: str = "A", rotor_diameter: float = 126.0, hub_height: float = 90.0,
                 shear_exponent: float = 0.2) -> None:
        super().__init__(hub_speed, start_time, hub_height, shear_exponent)
        self._amplitude = eog_amplitude(hub_speed, turbine_class, turbulence_class, rotor_diameter, hub_height)

    @property
    def gust_amplitude(self) -> float:
        """V_gust [m/s]."""
        return self._amplitude

    def gust(self, t: np.ndarray | float) -> np.ndarray:
        """Gust speed added to the sheared mean at x = 0 [m/s], same shape as t [s]."""
        phase = (np.asarray(t, dtype=float) - self._start_time) / EOG_DURATION
        inside = (phase >= 0.0) & (phase <= 1.0)
        shape = np.sin(3.0 * math.pi * phase) * (1.0 - np.cos(2.0 * math.pi * phase))
        return np.where(inside, -0.37 * self._amplitude * shape, 0.0)

    def velocity(self, t: float, x: np.ndarray, y: np.ndarray, z: np.ndarray) -> np.ndarray:
        """Wind velocity (u, 0, 0) [m/s], shape ``(3,) + x.shape``, at points (x, y, z) [m] and time t [s]."""
        x, z = _check_points(x, y, z)
        mean = self._hub_speed * self._profile(z)
        return _longitudinal(mean + self.gust(t - x / self._hub_speed))
