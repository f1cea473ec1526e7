"""The extreme wind conditions of IEC 61400-1 Ed. 3 §6.3.2 besides the EOG: direction changes, shear and the EWM.

- EDC, the extreme direction change (§6.3.2.4), and ECD, the extreme coherent gust with direction change
  (§6.3.2.5): a :class:`DirectionChange` each (:func:`extreme_direction_change`, :func:`extreme_coherent_gust`);
- EWS, the extreme wind shear (§6.3.2.6), vertical or horizontal: :class:`ExtremeWindShear`;
- EWM, the steady extreme wind model (§6.3.2.1), 50-year or 1-year: :func:`steady_extreme_wind`.

Each is a :class:`~hawt_plant.wind_field.WindField`. The extreme operating gust (§6.3.2.2) is
:class:`hawt_plant.gusts.ExtremeOperatingGust`; the extreme turbulence model (§6.3.2.3) is a turbulent field's
``turbulence_model`` (:class:`hawt_plant.turbulence.TurbulenceSpec`). As in :mod:`hawt_plant.gusts`, a transient
starts at ``start_time`` at x = 0 and is convected downwind at the hub speed: a point at x sees the hub history of
time t - x / V_hub. A direction theta turns the horizontal wind about the vertical axis from +x towards +y
(counter-clockwise seen from above; y points to the left looking downwind): (u, v) = V (cos theta, sin theta).

The equations are IEC 61400-1 Ed. 3's (2005); the standard was not accessible, so they are checked against NREL
WEIS's IEC wind generators (``IEC_CoherentGusts`` and its DLC case generator, whose comments number the
equations). Ed. 4 (2019) lists as its technical changes new classes for tropical cyclones and high turbulence, a
Weibull distribution of the NTM's sigma and updated load cases, none of these conditions; Ashes' documentation of
Ed. 4 quotes the same EWM and EDC equations.
"""
import math

import numpy as np

from hawt_plant.gusts import TransientWind, _check_points, _size_reduction, extreme_wind_speed
from hawt_plant.shear_wind import PowerLawWind
from hawt_plant.turbulence import longitudinal_length_scale, ntm_standard_deviation

__all__ = [
    "ECD_DURATION",
    "ECD_GUST_SPEED",
    "EDC_DURATION",
    "EWM_SHEAR_EXPONENT",
    "EWS_BETA",
    "EWS_DURATION",
    "EWS_ORIENTATIONS",
    "DirectionChange",
    "ExtremeWindShear",
    "cosine_pulse",
    "cosine_ramp",
    "ecd_direction_change",
    "edc_direction_change",
    "ews_amplitude",
    "extreme_coherent_gust",
    "extreme_direction_change",
    "steady_extreme_wind",
]

#: Rise time T of the extreme direction change [s], IEC 61400-1 Ed. 3 §6.3.2.4.
EDC_DURATION = 6.0
#: Rise time T of the extreme coherent gust [s], IEC 61400-1 Ed. 3 §6.3.2.5.
ECD_DURATION = 10.0
#: Magnitude V_cg of the extreme coherent gust [m/s], IEC 61400-1 Ed. 3 eq. 22.
ECD_GUST_SPEED = 15.0
#: Duration T of the extreme wind shear [s], IEC 61400-1 Ed. 3 §6.3.2.6.
EWS_DURATION = 12.0
#: beta of the extreme wind shear [-], IEC 61400-1 Ed. 3 eq. 26-27.
EWS_BETA = 6.4
#: Power-law exponent of the extreme wind model [-], IEC 61400-1 Ed. 3 eq. 14.
EWM_SHEAR_EXPONENT = 0.11
#: The two extreme wind shears: across the height (eq. 26) and across the width (eq. 27) of the rotor.
EWS_ORIENTATIONS = ("vertical", "horizontal")


def cosine_ramp(phase: np.ndarray | float) -> np.ndarray:
    """0.5 (1 - cos(pi s)) of the phase s = tau / T clipped to [0, 1]: 0 before the transient, rising smoothly to 1
    at its end and holding 1 after it; the time shape of the EDC (eq. 21) and of the ECD's speed and direction
    (eq. 23, 25)."""
    return 0.5 * (1.0 - np.cos(math.pi * np.clip(phase, 0.0, 1.0)))


def cosine_pulse(phase: np.ndarray | float) -> np.ndarray:
    """1 - cos(2 pi s) of the phase s = tau / T in [0, 1], 0 outside: a pulse peaking at 2 at s = 1/2, the time shape
    of the EWS (eq. 26, 27)."""
    phase = np.asarray(phase, dtype=float)
    return np.where((phase >= 0.0) & (phase <= 1.0), 1.0 - np.cos(2.0 * math.pi * phase), 0.0)


def _check_sign(sign: int) -> None:
    if sign not in (1, -1):
        raise ValueError(f"sign: expected +1 or -1, found {sign!r}")


def edc_direction_change(hub_speed: float, turbulence_class: str, rotor_diameter: float, hub_height: float) -> float:
    """Magnitude theta_e of the IEC 61400-1 Ed. 3 extreme direction change [rad].

    Parameters
    ----------
    hub_speed : float
        V_hub [m/s], > 0.
    turbulence_class : str
        ``"A"``, ``"B"`` or ``"C"``: sigma_1 of the NTM.
    rotor_diameter : float
        D [m], > 0.
    hub_height : float
        z_hub [m]; sets Lambda_1.

    Returns
    -------
    float
        theta_e = 4 arctan(sigma_1 / (V_hub (1 + 0.1 D / Lambda_1))), limited to pi (180 deg).

    Notes
    -----
    IEC 61400-1 Ed. 3 §6.3.2.4 eq. 20. (An older WEIS ``IEC_CoherentGusts.EDC`` has 0.01 D / Lambda_1; the
    standard, IECWind and the newer WEIS generator have 0.1.)

    Examples
    --------
    >>> round(math.degrees(edc_direction_change(11.4, "A", 126.0, 90.0)), 3)  # NREL 5 MW at rated, class A
    34.743
    """
    sigma_1 = ntm_standard_deviation(hub_speed, turbulence_class)
    return min(4.0 * math.atan(sigma_1 / (hub_speed * _size_reduction(rotor_diameter, hub_height))), math.pi)


def ecd_direction_change(hub_speed: float) -> float:
    """Direction change theta_cg of the IEC 61400-1 Ed. 3 extreme coherent gust [rad]: pi (180 deg) for
    V_hub < 4 m/s, otherwise 720 deg m/s / V_hub (eq. 24), with V_hub [m/s] > 0.

    >>> round(math.degrees(ecd_direction_change(12.0)), 6)
    60.0
    """
    if not hub_speed > 0.0:
        raise ValueError(f"hub_speed: expected > 0 m/s, found {hub_speed}")
    return math.pi if hub_speed < 4.0 else math.radians(720.0 / hub_speed)


def ews_amplitude(hub_speed: float, turbulence_class: str, rotor_diameter: float, hub_height: float) -> float:
    """Shear amplitude of the IEC 61400-1 Ed. 3 extreme wind shear [m/s].

    Returns 2.5 m/s + 0.2 beta sigma_1 (D / Lambda_1)^(1/4), beta = 6.4, sigma_1 of the NTM of ``turbulence_class``
    at ``hub_speed`` [m/s], D = ``rotor_diameter`` [m] and Lambda_1 of ``hub_height`` [m]: the wind at the rotor's
    edge (D/2 from the hub) changes by half of it times the pulse (1 - cos(2 pi t / T)), so by up to this amplitude
    (IEC 61400-1 Ed. 3 §6.3.2.6 eq. 26-27).

    >>> round(ews_amplitude(11.4, "A", 126.0, 90.0), 4)  # 2.5 + 0.2 * 6.4 * 2.264 * 3**0.25
    6.3139
    """
    if not rotor_diameter > 0.0:
        raise ValueError(f"rotor_diameter: expected > 0 m, found {rotor_diameter}")
    sigma_1 = ntm_standard_deviation(hub_speed, turbulence_class)
    return 2.5 + 0.2 * EWS_BETA * sigma_1 * (rotor_diameter / longitudinal_length_scale(hub_height)) ** 0.25


class DirectionChange(TransientWind):
    """Power-law sheared wind whose speed rises by Delta V while its direction turns by Delta theta, both over T with
    the cosine ramp, then holding: the form of the IEC 61400-1 Ed. 3 EDC and ECD.

    V(z, tau) = V_hub (z / z_hub)^alpha + Delta V r(tau / T), theta(tau) = Delta theta r(tau / T),
    (u, v, w) = V (cos theta, sin theta, 0), with r = :func:`cosine_ramp` (0 before the start, 1 after the end) and
    tau = t - t_0 - x / V_hub. Build the IEC conditions with :func:`extreme_direction_change` and
    :func:`extreme_coherent_gust`.

    Parameters
    ----------
    hub_speed : float
        V_hub before the change [m/s], > 0; also the convection speed.
    start_time : float
        t_0, start of the change at x = 0 [s].
    speed_change : float
        Delta V [m/s], >= 0.
    direction_change : float
        Delta theta [rad], in [-pi, pi]; positive turns the wind from +x towards +y.
    duration : float
        T [s], > 0.
    hub_height, shear_exponent : float
        z_hub [m] and alpha [-] of the profile.
    """

    def __init__(self, hub_speed: float, start_time: float, *, speed_change: float, direction_change: float,
                 duration: float, hub_height: float = 90.0, shear_exponent: float = 0.2) -> None:
        if not hub_speed > 0.0:
            raise ValueError(f"hub_speed: expected > 0 m/s, found {hub_speed}")
        if not speed_change >= 0.0:
            raise ValueError(f"speed_change: expected >= 0 m/s, found {speed_change}")
        if not abs(direction_change) <= math.pi:
            raise ValueError(f"direction_change: expected in [-pi, pi] rad, found {direction_change}")
        if not duration > 0.0:
            raise ValueError(f"duration: expected > 0 s, found {duration}")
        super().__init__(hub_speed, start_time, hub_height, shear_exponent)
        self._speed_change, self._direction_change = float(speed_change), float(direction_change)
        self._duration = float(duration)

    @property
    def speed_change(self) -> float:
        """Delta V [m/s]."""
        return self._speed_change

    @property
    def direction_change(self) -> float:
        """Delta theta [rad]."""
        return self._direction_change

    @property
    def duration(self) -> float:
        """T [s]."""
        return self._duration

    def direction(self, t: np.ndarray | float) -> np.ndarray:
        """Wind direction theta at x = 0 [rad], same shape as t [s]."""
        return self._direction_change * self._ramp(t)

    def velocity(self, t: float, x: np.ndarray, y: np.ndarray, z: np.ndarray) -> np.ndarray:
        """Wind velocity (u, v, 0) [m/s], shape ``(3,) + x.shape``, at points (x, y, z) [m] and time t [s]."""
        x, z = _check_points(x, y, z)
        ramp = self._ramp(t - x / self._hub_speed)
        speed = self._hub_speed * self._profile(z) \
            + self._speed_change * ramp
        direction = self._direction_change * ramp
        velocity = np.zeros((3,) + x.shape)
        velocity[0], velocity[1] = speed * np.cos(direction), speed * np.sin(direction)
        return velocity

    def _ramp(self, t: np.ndarray | float) -> np.ndarray:
        return cosine_ramp((np.asarray(t, dtype=float) - self._start_time) / self._duration)


def extreme_direction_change(hub_speed: float, start_time: float, *, sign: int = 1, turbulence_class: str = "A",
                             rotor_diameter: float = 126.0, hub_height: float = 90.0,
                             shear_exponent: float = 0.2) -> DirectionChange:
    """The IEC 61400-1 Ed. 3 extreme direction change (EDC) over the normal wind profile.

    theta(t) = +-0.5 theta_e (1 - cos(pi t / T)) for 0 <= t <= T, +-theta_e after, T = 6 s, theta_e of
    :func:`edc_direction_change`; the speed stays V_hub (z / z_hub)^alpha (§6.3.2.4 eq. 20-21).

    Parameters
    ----------
    hub_speed : float
        V_hub [m/s], > 0.
    start_time : float
        Start of the change at x = 0 [s].
    sign : int
        +1 or -1: the direction turns towards +y or -y.
    turbulence_class : str
        IEC turbulence category of sigma_1; default A.
    rotor_diameter, hub_height : float
        D and z_hub [m]; defaults the NREL 5 MW's, 126 m and 90 m.
    shear_exponent : float
        alpha; default 0.2, the IEC normal wind profile.
    """
    _check_sign(sign)
    angle = edc_direction_change(hub_speed, turbulence_class, rotor_diameter, hub_height)
    return DirectionChange(hub_speed, start_time, speed_change=0.0, direction_change=sign * angle,
                           duration=EDC_DURATION, hub_height=hub_height, shear_exponent=shear_exponent)


def extreme_coherent_gust(hub_speed: float, start_time: float, *, sign: int = 1, hub_height: float = 90.0,
                          shear_exponent: float = 0.2) -> DirectionChange:
    """The IEC 61400-1 Ed. 3 extreme coherent gust with direction change (ECD) over the normal wind profile.

    V(z, t) = V_hub (z / z_hub)^alpha + 0.5 V_cg (1 - cos(pi t / T)) and theta(t) = +-0.5 theta_cg (1 - cos(pi t / T))
    for 0 <= t <= T, V_hub (z / z_hub)^alpha + V_cg and +-theta_cg after; V_cg = 15 m/s, T = 10 s, theta_cg of
    :func:`ecd_direction_change` (§6.3.2.5 eq. 22-25). Parameters as :func:`extreme_direction_change`.
    """
    _check_sign(sign)
    return DirectionChange(hub_speed, start_time, speed_change=ECD_GUST_SPEED,
                           direction_change=sign * ecd_direction_change(hub_speed), duration=ECD_DURATION,
                           hub_height=hub_height, shear_exponent=shear_exponent)


class ExtremeWindShear(TransientWind):
    """IEC 61400-1 Ed. 3 extreme wind shear (EWS), vertical or horizontal, over power-law shear.

    u(y, z, t) = V_hub (z / z_hub)^alpha +- (d / D) A (1 - cos(2 pi tau / T)) for 0 <= tau <= T, the normal
    profile otherwise, with d = z - z_hub (vertical, eq. 26) or y (horizontal, eq. 27), A of :func:`ews_amplitude`,
    T = 12 s and tau = t - t_0 - x / V_hub (§6.3.2.6). v = w = 0.

    Parameters
    ----------
    hub_speed : float
        V_hub [m/s], > 0; also the convection speed.
    start_time : float
        t_0, start of the shear at x = 0 [s].
    orientation : str
        ``"vertical"`` or ``"horizontal"``.
    sign : int
        +1: faster above the hub (vertical) or at +y, to the left looking downwind (horizontal); -1 the opposite.
    turbulence_class : str
        IEC turbulence category of sigma_1; default A.
    rotor_diameter, hub_height : float
        D and z_hub [m]; defaults the NREL 5 MW's, 126 m and 90 m.
    shear_exponent : float
        alpha; default 0.2, the IEC normal wind profile.
    """

    def __init__(self, hub_speed: float, start_time: float, *, orientation: str = "vertical", sign: int = 1,
                 turbulence_class: str = "A", rotor_diameter: float = 126.0, hub_height: float = 90.0,
                 shear_exponent: float = 0.2) -> None:
        if orientation not in EWS_ORIENTATIONS:
            raise ValueError(f"orientation: expected vertical or horizontal, found {orientation!r}")
        _check_sign(sign)
        super().__init__(hub_speed, start_time, hub_height, shear_exponent)
        self._amplitude = ews_amplitude(hub_speed, turbulence_class, rotor_diameter, hub_height)
        self._orientation, self._sign, self._rotor_diameter = orientation, sign, float(rotor_diameter)

    @property
    def amplitude(self) -> float:
        """A = 2.5 m/s + 0.2 beta sigma_1 (D / Lambda_1)^(1/4) [m/s]."""
        return self._amplitude

    def velocity(self, t: float, x: np.ndarray, y: np.ndarray, z: np.ndarray) -> np.ndarray:
        """Wind velocity (u, 0, 0) [m/s], shape ``(3,) + x.shape``, at points (x, y, z) [m] and time t [s]."""
        x, z = _check_points(x, y, z)
        offset = z - self._hub_height if self._orientation == "vertical" else np.asarray(y, dtype=float)
        pulse = cosine_pulse((t - x / self._hub_speed - self._start_time) / EWS_DURATION)
        velocity = np.zeros((3,) + x.shape)
        velocity[0] = self._hub_speed * self._profile(z) \
            + self._sign * offset / self._rotor_diameter * self._amplitude * pulse
        return velocity


def steady_extreme_wind(turbine_class: str, recurrence_period: int, *, hub_height: float = 90.0) -> PowerLawWind:
    """The IEC 61400-1 Ed. 3 steady extreme wind model (EWM) of a wind turbine class, for a parked or idling rotor.

    V_e50(z) = 1.4 V_ref (z / z_hub)^0.11 (eq. 14) or V_e1(z) = 0.8 V_e50(z) (eq. 15), §6.3.2.1; ``turbine_class``
    I, II or III, ``recurrence_period`` 50 or 1 [years], ``hub_height`` z_hub [m]. The standard's load cases add a
    yaw misalignment (±15 deg for DLC 6.1 with this model), which this field leaves to the turbine.

    >>> round(steady_extreme_wind("II", 1).mean_speed, 9)  # 0.8 * 1.4 * 42.5
    47.6
    """
    return PowerLawWind(extreme_wind_speed(turbine_class, recurrence_period), hub_height=hub_height,
                        shear_exponent=EWM_SHEAR_EXPONENT)
