"""Blade-element momentum theory: induction factors, steady inflow solution, rotor performance.

The induction follows Ning (2014), "A simple solution method for the blade element momentum
equations with guaranteed convergence", Wind Energy 17:1327: for an inflow angle phi the
axial and tangential induction factors are explicit (eqs. 18-23 below), with Prandtl's tip
and hub losses and Buhl's (2005) high-induction (empirical Glauert) correction, so the
steady equations reduce to one residual in phi per element, solved here by bisection.
As in the NREL 5 MW AeroDyn input (AIDrag = TIDrag = False), drag is left out of the
induction and kept in the loads.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from hawt_plant.airfoil_table import ElementPolars, grid_point, interpolated
from hawt_plant.compiled import flat, njit
from hawt_plant.turbine import Turbine

__all__ = [
    "BemBlade",
    "RotorPerformance",
    "induction",
    "induction_factors",
    "loss_factor",
    "pitch_sensitivity",
    "prandtl_loss",
    "rotor_performance",
    "skew_factor",
    "skewed_wake_factor",
    "solve_inflow_angle",
]

PITT_PETERS = 15.0 * math.pi / 32.0
"""The skewed-wake correction's constant K (Pitt & Peters 1981; AeroDyn's default yawCorrFactor)."""

_SIN_FLOOR = 1e-6  # |sin(phi)| used in the loss and induction formulas is at least this
_EDGE = 1e-3  # [m] a node this close to the tip or the hub along the blade is at it


@dataclass(frozen=True, eq=False)
class BemBlade:
    """Per-element constants of one blade for the BEM equations.

    Attributes
    ----------
    radius : ndarray, shape (N,)
        Element distance from the shaft axis [m] (coned).
    width : ndarray, shape (N,)
        Element width along the blade [m].
    chord, twist : ndarray, shape (N,)
        [m], [rad].
    local_solidity : ndarray, shape (N,)
        B c / (2 pi r) [-].
    hub_radius, tip_radius : float
        Root and tip distance from the shaft axis [m] (coned).
    number_of_blades : int
    polars : ElementPolars
    loss_exponents : ndarray, shape (2, N)
        Prandtl exponents times |sin phi|: B/2 (R - r)/r (tip) and B/2 (r - R_hub)/R_hub
        (hub; infinite, i.e. no hub loss, when R_hub = 0); exactly 0 for a node at the tip or at the hub
        (within 1 mm along the blade), whose loss factor is then 0.

    The per-element arrays may also have a row per blade, shape (B, N) (and
    ``loss_exponents`` (2, B, N)), as :meth:`tiled` makes them: evaluating all blades at
    once then combines arrays of one shape, which numpy does faster than broadcasting.
    """

    radius: np.ndarray
    width: np.ndarray
    chord: np.ndarray
    twist: np.ndarray
    local_solidity: np.ndarray
    hub_radius: float
    tip_radius: float
    number_of_blades: int
    polars: ElementPolars
    loss_exponents: np.ndarray

    @classmethod
    def from_turbine(cls, turbine: Turbine) -> "BemBlade":
        """The BEM constants of a turbine's blade."""
        aero = turbine.blade_aerodynamics
        rotor = turbine.rotor
        cos_cone = math.cos(rotor.cone_angle)
        radius = (rotor.hub_radius + aero.span) * cos_cone
        hub, tip = rotor.hub_radius * cos_cone, rotor.tip_radius * cos_cone
        half_b = 0.5 * rotor.number_of_blades
        hub_exponent = half_b * (radius - hub) / hub if hub > 0.0 else np.full(radius.shape, np.inf)
        tip_exponent = half_b * (tip - radius) / radius
        # A node at the tip or at the hub (to _EDGE, as AeroDyn 15 decks place their end nodes) has no loss
        # exponent: its loss factor is 0 (prandtl_loss, induction_factors).
        tip_exponent[aero.span >= turbine.blade_length - _EDGE] = 0.0
        if hub > 0.0:
            hub_exponent[aero.span <= _EDGE] = 0.0
        return cls(
            radius=radius,
            width=aero.width,
            chord=aero.chord,
            twist=aero.twist,
            local_solidity=rotor.number_of_blades * aero.chord / (2.0 * math.pi * radius),
            hub_radius=hub,
            tip_radius=tip,
            number_of_blades=rotor.number_of_blades,
            polars=ElementPolars(turbine.airfoils, aero.airfoil),
            loss_exponents=np.stack((tip_exponent, hub_exponent)),
        )

    @property
    def at_ends(self) -> np.ndarray:
        """Per element: True for a node at the tip or the hub (its loss exponent 0), where the loss factor is 0 and
        AeroDyn's a = 1, a' = 0 hold (:func:`induction_factors`)."""
        return (self.loss_exponents == 0.0).any(axis=0)

    def tiled(self, rows: int) -> "BemBlade":
        """The same blade with every per-element array repeated in ``rows`` rows, shape (rows, N)."""
        def tile(values: np.ndarray) -> np.ndarray:
            return np.repeat(values[..., None, :], rows, axis=-2)

        return replace(self, radius=tile(self.radius), width=tile(self.width), chord=tile(self.chord),
                       twist=tile(self.twist), local_solidity=tile(self.local_solidity),
                       loss_exponents=tile(self.loss_exponents))


@dataclass(frozen=True)
class RotorPerformance:
    """Steady aerodynamic performance of the rotor in uniform axial wind.

    Attributes
    ----------
    power : float
        Aerodynamic (shaft) power [W].
    torque : float
        Aerodynamic torque [N m].
    thrust : float
        Thrust along the shaft [N].
    power_coefficient, thrust_coefficient : float
        Referred to the swept area pi R^2, R the tip radius along the blade [-]; NaN in
        vacuum (air density 0).
    tip_speed_ratio : float
        Omega R / V [-].
    """

    power: float
    torque: float
    thrust: float
    power_coefficient: float
    thrust_coefficient: float
    tip_speed_ratio: float


def prandtl_loss(sin_phi: np.ndarray, blade: BemBlade) -> np.ndarray:
    """Prandtl tip-loss times hub-loss factor F of each element.

    Parameters
    ----------
    sin_phi : ndarray, shape (..., N)
        Sine of the inflow angle; (..., B, N) for a :meth:`BemBlade.tiled` blade.
    blade : BemBlade

    Returns
    -------
    ndarray, shape of ``sin_phi``
        ``F = (2/pi)^2 acos(exp(-f_tip)) acos(exp(-f_hub))`` with
        ``f_tip = B/2 (R - r) / (r |sin phi|)``, ``f_hub = B/2 (r - R_hub) / (R_hub |sin phi|)``
        (Ning 2014 eqs. 13-15; Hansen, Aerodynamics of Wind Turbines, eq. 6.34); no hub
        loss when the hub radius is 0. At least 1e-4, except exactly 0 at a node at the tip or the hub.
    """
    shape, (s, tip, hub) = flat(sin_phi, blade.loss_exponents[0], blade.loss_exponents[1])
    return _losses(s, tip, hub).reshape(shape)


@njit
def loss_factor(sin_phi: float, tip_exponent: float, hub_exponent: float) -> float:
    """:func:`prandtl_loss` of one element: its ``sin(phi)`` and its two :attr:`BemBlade.loss_exponents`."""
    s = np.maximum(abs(sin_phi), _SIN_FLOOR)
    loss = math.acos(math.exp(-tip_exponent / s)) * math.acos(math.exp(-hub_exponent / s)) * (4.0 / math.pi**2)
    return np.maximum(loss, 1e-4) if loss > 0.0 else 0.0


@njit
def _losses(sin_phi, tip, hub):  # flat arrays of one length
    out = np.empty_like(sin_phi)
    for i in range(out.size):
        out[i] = loss_factor(sin_phi[i], tip[i], hub[i])
    return out


def induction_factors(phi: np.ndarray, cl: np.ndarray, loss: np.ndarray, local_solidity: np.ndarray,
                      sin_phi: np.ndarray | None = None, cos_phi: np.ndarray | None = None,
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Axial and tangential induction factors implied by the inflow angle and lift.

    Parameters
    ----------
    phi : ndarray
        Inflow angle [rad] (between the rotor plane and the relative velocity).
    cl : ndarray
        Lift coefficient [-] (drag is left out of the induction).
    loss : ndarray
        Prandtl loss factor F [-].
    local_solidity : ndarray
        B c / (2 pi r) [-].
    sin_phi, cos_phi : ndarray, optional
        sin(phi) and cos(phi) when already known.

    Returns
    -------
    a, a_prime, k, k_prime : ndarray
        Induction factors and Ning's loading parameters
        ``k = sigma' c_n / (4 F sin^2 phi)``, ``k' = sigma' c_t / (4 F sin phi cos phi)``
        with c_n = c_l cos phi and c_t = c_l sin phi.

    Notes
    -----
    Ning (2014) eqs. 18-23: for phi > 0, ``a = k / (1 + k)`` when k <= 2/3 (momentum
    region), otherwise Buhl's (2005) correction ``a = (g1 - sqrt(g2)) / g3`` with
    ``g1 = 2Fk - (10/9 - F)``, ``g2 = 2Fk - F(4/3 - F)``, ``g3 = 2Fk - (25/9 - 2F)``;
    for phi < 0 (propeller brake) ``a = k / (k - 1)`` when k > 1, else 0;
    ``a' = k' / (1 - k')``.
    Where F = 0, a node at the tip or the hub, a = 1 and a' = 0 (and k = k' = 0), as AeroDyn 15 takes them there:
    the node sees no axial flow, only its rotation.
    """
    phi = np.asarray(phi, dtype=float)
    sin_phi = np.sin(phi) if sin_phi is None else sin_phi
    cos_phi = np.cos(phi) if cos_phi is None else cos_phi
    shape, arrays = flat(phi, sin_phi, cos_phi, cl, loss, local_solidity)
    out = np.empty((4, arrays[0].size))
    _inductions(*arrays, out)
    a, a_prime, k, k_prime = out.reshape((4,) + shape)
    return a, a_prime, k, k_prime


@njit
def induction(phi: float, sin_phi: float, cos_phi: float, cl: float, loss: float,
              local_solidity: float) -> tuple[float, float, float, float]:
    """:func:`induction_factors` of one element: a, a', k, k' (Ning 2014 eqs. 18-23, Buhl 2005)."""
    if loss == 0.0:  # a node at the tip or the hub
        return 1.0, 0.0, 0.0, 0.0
    lift = local_solidity * cl / (4.0 * loss)
    k = lift * cos_phi / np.maximum(sin_phi * sin_phi, _SIN_FLOOR**2)
    k_prime = lift / cos_phi  # cos(phi) of a floating-point phi is never exactly 0
    a = k / np.maximum(1.0 + k, 1e-9)
    if k > 2.0 / 3.0:
        # Buhl: (g1 - sqrt(g2)) / g3 = (2Fk - 4/9) / (g1 + sqrt(g2)), since
        # g1^2 - g2 = g3 (2Fk - 4/9); the second form has no pole where g3 = 0.
        two_fk = 2.0 * loss * k
        root = math.sqrt(np.maximum(two_fk - loss * (4.0 / 3.0 - loss), 0.0))
        a = (two_fk - 4.0 / 9.0) / (two_fk - 10.0 / 9.0 + loss + root)
    if not phi > 0.0:  # propeller brake
        a = k / np.maximum(k - 1.0, 1e-9) if k > 1.0 else 0.0
    return a, k_prime / (1.0 - k_prime), k, k_prime


@njit
def _inductions(phi, sin_phi, cos_phi, cl, loss, local_solidity, out):  # flat arrays of one length, out (4, n)
    for i in range(phi.size):
        out[0, i], out[1, i], out[2, i], out[3, i] = induction(phi[i], sin_phi[i], cos_phi[i], cl[i], loss[i],
                                                               local_solidity[i])


def skewed_wake_factor(axial_induction: np.ndarray, skew_angle: float, tip_ratio: np.ndarray,
                       cos_azimuth: np.ndarray) -> np.ndarray:
    """The factor on the axial induction of a skewed wake, Pitt & Peters (1981) as in AeroDyn (SkewMod = 2):

        a_skew = a (1 + K tan(χ/2) (r/R) cos(ψ - ψ_d)),   χ = (1 + 0.6 a) χ_0,   K = 15π/32,

    χ_0 the angle between the rotor axis and the wind (``skew_angle`` [rad]), r/R the element's share of the tip
    radius (``tip_ratio``), ψ - ψ_d its azimuth from the most downwind position of the disk, where the wind's
    in-plane component points (``cos_azimuth``). Like AeroDyn, |χ| is held at π/2 (tan(χ/2) at most 1).

    Examples
    --------
    >>> float(skewed_wake_factor(np.array(0.3), 0.0, np.array(1.0), np.array(1.0)))
    1.0
    >>> round(float(skewed_wake_factor(np.array(0.0), 0.2, np.array(0.5), np.array(-1.0))), 6)
    0.926122
    """
    shape, (a, ratio, cos) = flat(axial_induction, tip_ratio, cos_azimuth)
    out = np.empty_like(a)
    for i in range(a.size):
        out[i] = skew_factor(a[i], skew_angle, ratio[i], cos[i])
    return out.reshape(shape)


@njit
def skew_factor(axial_induction: float, skew_angle: float, tip_ratio: float, cos_azimuth: float) -> float:
    """:func:`skewed_wake_factor` of one element."""
    chi = np.minimum(np.maximum((1.0 + 0.6 * axial_induction) * skew_angle, -0.5 * math.pi), 0.5 * math.pi)
    return 1.0 + PITT_PETERS * math.tan(0.5 * chi) * tip_ratio * cos_azimuth


def solve_inflow_angle(vx: np.ndarray, vy: np.ndarray, pitch: np.ndarray, blade: BemBlade,
                       iterations: int = 52) -> np.ndarray:
    """Steady BEM solution: the inflow angle of every element.

    Parameters
    ----------
    vx : ndarray, shape (..., N)
        Inflow normal to the rotor plane (coned), without induction [m/s].
    vy : ndarray, shape (..., N)
        In-plane inflow towards the leading edge, without induction [m/s].
    pitch : ndarray, broadcastable to (..., N)
        Blade pitch [rad].
    blade : BemBlade
    iterations : int
        Bisection steps; 52 resolve phi to machine precision.

    Returns
    -------
    ndarray, shape (..., N)
        Inflow angle phi [rad]; the induction factors follow from :func:`induction_factors`.

    Notes
    -----
    Ning (2014) §2.3: the residual of eqs. 24-25 changes sign in (0, pi/2] in the windmill and
    high-induction states; otherwise the propeller-brake bracket [-pi/4, 0) or (pi/2, pi)
    is used. Bisection then converges for every element. Elements without positive vx and
    vy (a parked rotor, reversed flow) get the inflow angle of the undisturbed flow,
    ``arctan2(vx, vy)``; a node at the tip or the hub gets 0 (no axial flow, :func:`induction_factors`).
    """
    shape, arrays = flat(vx, vy, pitch, blade.twist, blade.loss_exponents[0], blade.loss_exponents[1],
                         blade.local_solidity, blade.at_ends)
    scale, intervals, offsets = blade.polars.grid_constants
    out = np.empty(arrays[0].size)
    _inflow_angles(*arrays, blade.polars.table, scale, intervals, np.broadcast_to(offsets, shape).reshape(-1), iterations,
                   out)
    return out.reshape(shape)


@njit
def _inflow_angles(vx, vy, pitch, twist, tip, hub, local_solidity, at_end, table, scale, intervals, offsets,
                   iterations, out):  # flat arrays of one length
    for i in range(out.size):
        out[i] = inflow_angle(vx[i], vy[i], pitch[i] + twist[i], tip[i], hub[i], local_solidity[i], at_end[i] != 0.0,
                              table, scale, intervals, offsets[i], iterations)


@njit
def inflow_angle(vx: float, vy: float, pitch_twist: float, tip_exponent: float, hub_exponent: float,
                 local_solidity: float, at_end: bool, table: np.ndarray, scale: float, intervals: float, offset: int,
                 iterations: int) -> float:
    """:func:`solve_inflow_angle` of one element, its pitch and twist summed, its polar in ``table``
    (:attr:`ElementPolars.table`) from row ``offset``."""
    if not (vx > 1e-6 and vy > 1e-6):
        return math.atan2(vx, vy)
    if at_end:
        return 0.0
    eps = 1e-6
    arguments = (vx, vy, pitch_twist, tip_exponent, hub_exponent, local_solidity, table, scale, intervals, offset)
    if _residual(eps, *arguments) * _residual(math.pi / 2, *arguments) < 0.0:
        lower, upper = eps, math.pi / 2
    elif _residual(-math.pi / 4, *arguments) * _residual(-eps, *arguments) < 0.0:
        lower, upper = -math.pi / 4, -eps
    else:
        lower, upper = math.pi / 2, math.pi - eps
    r_lower = _residual(lower, *arguments)
    for _ in range(iterations):
        middle = 0.5 * (lower + upper)
        r_middle = _residual(middle, *arguments)
        if r_middle * r_lower > 0.0:
            lower, r_lower = middle, r_middle
        else:
            upper = middle
    return 0.5 * (lower + upper)


@njit
def _residual(phi, vx, vy, pitch_twist, tip_exponent, hub_exponent, local_solidity, table, scale, intervals, offset):
    """Ning (2014) eqs. 24-25: the residual of the BEM equations in the inflow angle."""
    row, fraction = grid_point(phi - pitch_twist, scale, intervals, offset)
    sin_phi, cos_phi = math.sin(phi), math.cos(phi)
    loss = loss_factor(sin_phi, tip_exponent, hub_exponent)
    a, _, k, k_prime = induction(phi, sin_phi, cos_phi, interpolated(table, row, fraction, 0), loss, local_solidity)
    tangential = cos_phi * (vx / vy) * (1.0 - k_prime)
    if phi > 0.0:
        return sin_phi / (1e-12 if abs(1.0 - a) < 1e-12 else 1.0 - a) - tangential
    return sin_phi * (1.0 - k) - tangential


def _axial_inflow(turbine: Turbine, blade: BemBlade, wind_speed: float, rotor_speed: float
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Each element's inflow without induction in uniform wind along the shaft: normal V cos(cone), in plane
    Omega r."""
    return np.full(blade.radius.shape, wind_speed * math.cos(turbine.rotor.cone_angle)), rotor_speed * blade.radius


def _element_loads(turbine: Turbine, blade: BemBlade, vx: np.ndarray, vy: np.ndarray, phi: np.ndarray,
                   pitch: float, induction_pitch: float) -> tuple[np.ndarray, np.ndarray]:
    """Normal and tangential load [N] of each element at inflow angle ``phi`` with the blade at ``pitch``: the
    induction from the lift at ``induction_pitch`` (the pitch itself, or, for a frozen wake, the one the wake is
    frozen at), dF_n = 1/2 rho W^2 c (c_l cos phi + c_d sin phi) dr, dF_t = 1/2 rho W^2 c (c_l sin phi - c_d cos phi)
    dr."""
    cl, cd = blade.polars.coefficients(phi - pitch - blade.twist)
    lift = cl if induction_pitch == pitch else blade.polars.coefficients(phi - induction_pitch - blade.twist)[0]
    a, a_prime, _, _ = induction_factors(phi, lift, prandtl_loss(np.sin(phi), blade), blade.local_solidity)
    w2 = (vx * (1.0 - a)) ** 2 + (vy * (1.0 + a_prime)) ** 2
    q = 0.5 * turbine.environment.air_density * w2 * blade.chord * blade.width
    return q * (cl * np.cos(phi) + cd * np.sin(phi)), q * (cl * np.sin(phi) - cd * np.cos(phi))


def rotor_performance(turbine: Turbine, wind_speed: float, rotor_speed: float, pitch: float,
                      blade: BemBlade | None = None) -> RotorPerformance:
    """Steady aerodynamic performance of the rotor in uniform wind along the shaft.

    Parameters
    ----------
    turbine : Turbine
    wind_speed : float
        Uniform wind speed along the shaft [m/s], > 0.
    rotor_speed : float
        [rad/s], > 0.
    pitch : float
        Collective pitch [rad].
    blade : BemBlade, optional
        Precomputed :meth:`BemBlade.from_turbine` (saves rebuilding the polar tables).

    Returns
    -------
    RotorPerformance

    Notes
    -----
    Axisymmetric BEM (precone included, shaft tilt and tower left out), each element solved
    with :func:`solve_inflow_angle`; the loads use lift and drag, dF_n = 1/2 rho W^2 c
    (c_l cos phi + c_d sin phi) dr and dF_t = 1/2 rho W^2 c (c_l sin phi - c_d cos phi) dr.
    """
    if not (wind_speed > 0.0 and rotor_speed > 0.0):
        raise ValueError(f"wind_speed, rotor_speed: expected > 0, found {wind_speed}, {rotor_speed}")
    blade = blade or BemBlade.from_turbine(turbine)
    cos_cone = math.cos(turbine.rotor.cone_angle)
    vx, vy = _axial_inflow(turbine, blade, wind_speed, rotor_speed)
    phi = solve_inflow_angle(vx, vy, np.asarray(pitch, dtype=float), blade)
    normal, tangential = _element_loads(turbine, blade, vx, vy, phi, pitch, pitch)
    b = turbine.rotor.number_of_blades
    thrust = float(b * np.sum(normal) * cos_cone)
    torque = float(b * np.sum(tangential * blade.radius))
    radius = turbine.rotor.tip_radius
    dynamic = 0.5 * turbine.environment.air_density * math.pi * radius**2 * wind_speed**2
    return RotorPerformance(
        power=torque * rotor_speed,
        torque=torque,
        thrust=thrust,
        power_coefficient=torque * rotor_speed / (dynamic * wind_speed) if dynamic > 0.0 else math.nan,
        thrust_coefficient=thrust / dynamic if dynamic > 0.0 else math.nan,
        tip_speed_ratio=rotor_speed * radius / wind_speed,
    )


def pitch_sensitivity(turbine: Turbine, wind_speed: float, rotor_speed: float, pitch: float, *, frozen_wake: bool,
                      blade: BemBlade | None = None) -> float:
    """dP/dθ [W/rad] of the aerodynamic power in uniform wind along the shaft, by central difference (±1e-4 rad).

    Parameters
    ----------
    turbine : Turbine
    wind_speed, rotor_speed, pitch : float
        The operating point [m/s], [rad/s], [rad].
    frozen_wake : bool
        True: the induction stays that of ``pitch`` while the pitch changes (a frozen wake, as FAST's
        linearisation with AeroDyn v13 computed it: Jonkman et al. 2009 §7.4); False: it is re-solved at each
        pitch (the equilibrium, slow sensitivity: the derivative of :func:`rotor_performance`'s power).
    blade : BemBlade, optional
        Precomputed :meth:`BemBlade.from_turbine`.

    Notes
    -----
    The power is that of :func:`rotor_performance`: B Ω Σ r dF_t, dF_t = 1/2 rho W^2 c (c_l sin phi - c_d cos phi) dr;
    with a frozen wake the inflow angle phi and the induction factors (a, a') are those of ``pitch``, and only the
    angle of attack phi - theta - twist moves with the pitch.
    """
    blade = blade or BemBlade.from_turbine(turbine)
    vx, vy = _axial_inflow(turbine, blade, wind_speed, rotor_speed)
    frozen = solve_inflow_angle(vx, vy, np.asarray(pitch), blade)

    def power(angle: float) -> float:
        phi = frozen if frozen_wake else solve_inflow_angle(vx, vy, np.asarray(angle), blade)
        induced_by = pitch if frozen_wake else angle  # a frozen wake keeps the unperturbed pitch's induction
        _, tangential = _element_loads(turbine, blade, vx, vy, phi, angle, induced_by)
        return turbine.rotor.number_of_blades * float(np.sum(tangential * blade.radius)) * rotor_speed

    step = 1e-4
    return (power(pitch + step) - power(pitch - step)) / (2.0 * step)
