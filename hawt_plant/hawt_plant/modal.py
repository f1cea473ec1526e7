"""Generalized (modal) properties of the blade's first flap mode and the tower's first modes.

The mode shapes are ElastoDyn's sixth-order polynomials phi(x) = sum_{k=2..6} c_k x^k with
x the fraction of the beam length and phi(1) = 1 (Jonkman 2009 model files, BldFl1Sh,
TwFAM1Sh, TwSSM1Sh). Generalized mass and stiffness follow the assumed-modes method as in
ElastoDyn (Jonkman 2003, FAST theory): m = int mu phi^2, k = int EI phi''^2, the rotating
blade adds the centrifugal stiffening int N(s) phi'^2 and the tower loses the gravity
stiffness g int m_above(h) phi'^2. Integrals use the trapezoidal rule on a fine grid with
linear interpolation of the distributed properties.

The plant has no edgewise degree of freedom; :func:`blade_edgewise_frequency` estimates the first edgewise
frequency from the blade's edge stiffness for what needs it (the speed filter of a controller design).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.linalg import eigh

from hawt_plant.turbine import Turbine

__all__ = [
    "BladeModalProperties",
    "TowerModalProperties",
    "blade_edgewise_frequency",
    "blade_modal_properties",
    "polynomial_mode",
    "tower_modal_properties",
]

_GRID_POINTS = 2001


@dataclass(frozen=True)
class BladeModalProperties:
    """Mass moments and first-flap-mode integrals of one blade.

    Distances ``s`` run along the blade from its root [m].

    Attributes
    ----------
    mass : float
        int mu ds [kg].
    first_moment : float
        int mu s ds [kg m]; ``first_moment / mass`` is the centre of mass from the root.
    second_moment : float
        int mu s^2 ds [kg m^2].
    modal_mass : float
        Generalized mass of the flap mode, int mu phi^2 ds [kg] (phi = 1 at the tip).
    modal_first_moment : float
        int mu phi ds [kg].
    modal_moment_arm : float
        int mu phi s ds [kg m].
    stiffness : float
        Generalized stiffness int EI phi''^2 ds [N/m].
    centrifugal_stiffness : float
        Centrifugal stiffening per rotor speed squared, int N(s)/Omega^2 phi'^2 ds [kg]
        with N the axial force of the coned rotating blade.
    damping_ratio : float
        Structural damping ratio [-].
    """

    mass: float
    first_moment: float
    second_moment: float
    modal_mass: float
    modal_first_moment: float
    modal_moment_arm: float
    stiffness: float
    centrifugal_stiffness: float
    damping_ratio: float

    @property
    def natural_frequency(self) -> float:
        """Non-rotating first flap frequency [rad/s]."""
        return float(np.sqrt(self.stiffness / self.modal_mass))


@dataclass(frozen=True)
class TowerModalProperties:
    """Integrals of one first tower bending mode (fore-aft or side-side), heights h from ground.

    Attributes
    ----------
    modal_mass : float
        Tower's own generalized mass int mu phi^2 dh [kg] (phi = 1 at the top).
    modal_first_moment : float
        int mu phi dh [kg].
    modal_height_moment : float
        int mu phi h dh [kg m].
    stiffness : float
        Generalized stiffness int EI phi''^2 dh - g int m_above phi'^2 dh [N/m], the top
        mass included in m_above.
    top_slope : float
        phi'(H) [1/m]: tower-top rotation per metre of tower-top displacement.
    damping_ratio : float
        Structural damping ratio [-].
    """

    modal_mass: float
    modal_first_moment: float
    modal_height_moment: float
    stiffness: float
    top_slope: float
    damping_ratio: float


def polynomial_mode(coefficients: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """ElastoDyn polynomial mode shape and its first two derivatives with respect to x.

    Parameters
    ----------
    coefficients : ndarray, shape (5,)
        Coefficients of x^2 .. x^6.
    x : ndarray
        Fraction of the beam length [-].

    Returns
    -------
    phi, dphi_dx, d2phi_dx2 : ndarray, same shape as x
    """
    x = np.asarray(x, dtype=float)
    powers = np.arange(2, 7)
    xk = x[..., None] ** (powers - 2)
    c = np.asarray(coefficients, dtype=float)
    phi = (xk * x[..., None] ** 2) @ c
    d1 = (xk * x[..., None]) @ (c * powers)
    d2 = xk @ (c * powers * (powers - 1))
    return phi, d1, d2


def _blade_stations(turbine: Turbine) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The blade's integration grid: x (fraction of the length), s [m] from the root and the mass density [kg/m]."""
    structure = turbine.blade_structure
    x = np.linspace(0.0, 1.0, _GRID_POINTS)
    return x, x * turbine.blade_length, np.interp(x, structure.span_fraction, structure.mass_density)


def blade_modal_properties(turbine: Turbine) -> BladeModalProperties:
    """Mass moments and first-flap-mode integrals of the turbine's blade.

    Parameters
    ----------
    turbine : Turbine

    Returns
    -------
    BladeModalProperties
    """
    structure = turbine.blade_structure
    length = turbine.blade_length
    x, s, mu = _blade_stations(turbine)
    ei = np.interp(x, structure.span_fraction, structure.flap_stiffness)
    phi, d1, d2 = polynomial_mode(structure.flap_mode_shape, x)
    cos_cone = np.cos(turbine.rotor.cone_angle)
    # Axial force per Omega^2: int_s^L mu (r_hub + s') cos^2(cone) ds' (radius from the shaft
    # times the component of the centrifugal force along the coned blade).
    integrand = mu * (turbine.rotor.hub_radius + s) * cos_cone**2
    segment = 0.5 * (integrand[1:] + integrand[:-1]) * np.diff(s)
    axial = np.concatenate((np.cumsum(segment[::-1])[::-1], [0.0]))
    trapezoid = np.trapezoid
    return BladeModalProperties(
        mass=float(trapezoid(mu, s)),
        first_moment=float(trapezoid(mu * s, s)),
        second_moment=float(trapezoid(mu * s**2, s)),
        modal_mass=float(trapezoid(mu * phi**2, s)),
        modal_first_moment=float(trapezoid(mu * phi, s)),
        modal_moment_arm=float(trapezoid(mu * phi * s, s)),
        stiffness=float(trapezoid(ei * (d2 / length**2) ** 2, s)),
        centrifugal_stiffness=float(trapezoid(axial * (d1 / length) ** 2, s)),
        damping_ratio=structure.flap_damping_ratio,
    )


def hub_centre_moments(turbine: Turbine, blade: BladeModalProperties) -> tuple[float, float, float]:
    """The blade's mass [kg] and its first [kg m] and second [kg m^2] mass moments along the blade about the hub
    centre (r = r_hub + s); ``blade`` is :func:`blade_modal_properties` of ``turbine`` (moments about the root)."""
    rh = turbine.rotor.hub_radius
    return (blade.mass, blade.first_moment + rh * blade.mass,
            blade.second_moment + 2.0 * rh * blade.first_moment + rh * rh * blade.mass)


def rotor_inertia(turbine: Turbine, blade: BladeModalProperties) -> float:
    """J_rotor [kg m^2]: the hub's inertia about the shaft and the coned blades' second mass moments about it
    (``blade`` as in :func:`hub_centre_moments`)."""
    rotor = turbine.rotor
    cb = math.cos(rotor.cone_angle)
    return rotor.hub_inertia + rotor.number_of_blades * cb * cb * hub_centre_moments(turbine, blade)[2]


def blade_edgewise_frequency(turbine: Turbine) -> float:
    """First edgewise bending frequency of the standing blade [Hz], a Rayleigh-Ritz estimate.

    Parameters
    ----------
    turbine : Turbine

    Returns
    -------
    float
        sqrt(lambda_1) / (2 pi), lambda_1 the smallest eigenvalue of K q = lambda M q with
        K_ij = int EI_edge phi_i'' phi_j'' ds and M_ij = int mu phi_i phi_j ds over ElastoDyn's mode-shape basis
        phi_i = x^i, i = 2..6 (x the fraction of the blade length: clamped at the root).

    Notes
    -----
    Euler-Bernoulli bending in the edgewise plane alone: no structural twist coupling with the flap plane, no
    rotation, the hub clamped. For the NREL 5 MW it gives 1.096 Hz, against 1.079 and 1.090 Hz for the first
    asymmetric edgewise modes of FAST (Jonkman et al. 2009, Table 9-1); a Rayleigh quotient with the flap mode's
    shape instead gives 1.29 Hz.
    """
    structure = turbine.blade_structure
    length = turbine.blade_length
    x, s, mu = _blade_stations(turbine)
    ei = np.interp(x, structure.span_fraction, structure.edge_stiffness)
    basis = np.eye(5)
    shapes = [polynomial_mode(row, x) for row in basis]
    stiffness = np.array([[np.trapezoid(ei * a[2] * b[2], s) for b in shapes] for a in shapes]) / length**4
    mass = np.array([[np.trapezoid(mu * a[0] * b[0], s) for b in shapes] for a in shapes])
    return float(np.sqrt(eigh(stiffness, mass, eigvals_only=True)[0]) / (2.0 * np.pi))


def tower_modal_properties(turbine: Turbine, direction: str, top_mass: float) -> TowerModalProperties:
    """Integrals of the tower's first fore-aft or side-side mode.

    Parameters
    ----------
    turbine : Turbine
    direction : {"fa", "ss"}
        Fore-aft or side-side.
    top_mass : float
        Mass carried by the tower top (rotor and nacelle) [kg], for the gravity stiffness.

    Returns
    -------
    TowerModalProperties
    """
    tower = turbine.tower
    if direction == "fa":
        coefficients, stiffness, damping = tower.fa_mode_shape, tower.fa_stiffness, tower.fa_damping_ratio
    elif direction == "ss":
        coefficients, stiffness, damping = tower.ss_mode_shape, tower.ss_stiffness, tower.ss_damping_ratio
    else:
        raise ValueError(f"direction: expected 'fa' or 'ss', found {direction!r}")
    height = tower.height
    x = np.linspace(0.0, 1.0, _GRID_POINTS)
    h = x * height
    mu = np.interp(x, tower.height_fraction, tower.mass_density)
    ei = np.interp(x, tower.height_fraction, stiffness)
    phi, d1, d2 = polynomial_mode(coefficients, x)
    segment = 0.5 * (mu[1:] + mu[:-1]) * np.diff(h)
    mass_above = np.concatenate((np.cumsum(segment[::-1])[::-1], [0.0])) + top_mass
    trapezoid = np.trapezoid
    bending = trapezoid(ei * (d2 / height**2) ** 2, h)
    gravity = turbine.environment.gravity * trapezoid(mass_above * (d1 / height) ** 2, h)
    return TowerModalProperties(
        modal_mass=float(trapezoid(mu * phi**2, h)),
        modal_first_moment=float(trapezoid(mu * phi, h)),
        modal_height_moment=float(trapezoid(mu * phi * h, h)),
        stiffness=float(bending - gravity),
        top_slope=float(d1[-1] / height),
        damping_ratio=damping,
    )
