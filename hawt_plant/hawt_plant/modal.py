"""Generalized (modal) properties of the blade's first flap and edgewise modes and the tower's first modes.

The mode shapes are ElastoDyn's sixth-order polynomials phi(x) = sum_{k=2..6} c_k x^k with
x the fraction of the beam length and phi(1) = 1 (Jonkman 2009 model files, BldFl1Sh,
TwFAM1Sh, TwSSM1Sh). Generalized mass and stiffness follow the assumed-modes method as in
ElastoDyn (Jonkman 2003, FAST theory): m = int mu phi^2, k = int EI phi''^2, the rotating
blade adds the centrifugal stiffening int N(s) phi'^2 and the tower loses the gravity
stiffness g int m_above(h) phi'^2. Integrals use the trapezoidal rule on a fine grid with
linear interpolation of the distributed properties.

:func:`blade_edgewise_frequency` estimates the first edgewise frequency from the blade's edge stiffness alone, with
no mode shape given, for what needs it before a plant exists (the speed filter of a controller design).
:func:`beam_first_mode` gives a tower's first mode shape where no deck does: a tower on a flexible base (its
substructure's sections below the tower's) as the import builds it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hawt_plant.turbine import Turbine

__all__ = [
    "BladeMode",
    "BladeModalProperties",
    "TowerModalProperties",
    "beam_first_mode",
    "blade_edge_mode",
    "blade_edgewise_frequency",
    "blade_modal_properties",
    "polynomial_mode",
    "tower_modal_properties",
    "twisted_tip_angle",
]

_GRID_POINTS = 2001


@dataclass(frozen=True)
class BladeMode:
    """Integrals of one blade mode, flap or edgewise, of shape phi (phi = 1 at the tip).

    Distances ``s`` run along the blade from its root [m].

    Attributes
    ----------
    modal_mass : float
        Generalized mass int mu phi^2 ds [kg].
    modal_first_moment : float
        int mu phi ds [kg].
    modal_moment_arm : float
        int mu phi s ds [kg m].
    stiffness : float
        Generalized stiffness int EI phi''^2 ds [N/m], EI the stiffness in the mode's plane.
    centrifugal_stiffness : float
        Centrifugal stiffening per rotor speed squared, int N(s)/Omega^2 phi'^2 ds [kg]
        with N the axial force of the coned rotating blade.
    damping_ratio : float
        Structural damping ratio [-].
    twist_angle : float
        How far the structural twist turns the mode's tip deflection from the direction the pitch alone gives it [rad],
        positive towards feather like the pitch (:func:`twisted_tip_angle`).
    """

    modal_mass: float
    modal_first_moment: float
    modal_moment_arm: float
    stiffness: float
    centrifugal_stiffness: float
    damping_ratio: float
    twist_angle: float = 0.0

    @property
    def natural_frequency(self) -> float:
        """Non-rotating frequency [rad/s]."""
        return float(np.sqrt(self.stiffness / self.modal_mass))


@dataclass(frozen=True)
class BladeModalProperties(BladeMode):
    """Mass moments of one blade and the integrals of its first flap mode (the :class:`BladeMode` fields).

    Attributes
    ----------
    mass : float
        int mu ds [kg].
    first_moment : float
        int mu s ds [kg m]; ``first_moment / mass`` is the centre of mass from the root.
    second_moment : float
        int mu s^2 ds [kg m^2].
    """

    mass: float = 0.0
    first_moment: float = 0.0
    second_moment: float = 0.0


@dataclass(frozen=True)
class TowerModalProperties:
    """Integrals of one first tower bending mode (fore-aft or side-side), heights h above the ground.

    The generalized mass and stiffness run over the whole beam, from its clamp; the moments that give the
    tower-base loads run over the tower above its base h_b (``Tower.base_height``), about it.

    Attributes
    ----------
    modal_mass : float
        Tower's own generalized mass int mu phi^2 dh [kg] (phi = 1 at the top).
    modal_first_moment : float
        int mu phi dh above the base [kg].
    modal_height_moment : float
        int mu phi (h - h_b) dh above the base [kg m].
    base_shape : float
        phi at the base [-]: how far the tower's base moves per metre of tower-top motion (0 unless the base
        is flexible).
    mass_above_base : float
        int mu dh above the base [kg].
    stiffness : float
        Generalized stiffness int EI phi''^2 dh - g int m_above phi'^2 dh [N/m], the top
        mass included in m_above.
    top_slope : float
        phi'(H) [1/m]: tower-top rotation per metre of tower-top displacement.
    damping : float
        Generalized structural damping [N s/m], ElastoDyn's (``ElastoDyn.f90``, CTFA/CTSS): the deck's damping
        ratio zeta of the tower's own mode, c = 2 zeta k_b / omega_t = 2 zeta sqrt(k_b m_t) with k_b the bending
        stiffness int EI phi''^2 dh and m_t ``modal_mass``, without the top mass or gravity. The mode with the rotor
        and nacelle on top is slower, so it gets a smaller ratio: zeta sqrt(m_t / (m_t + m_top)).
    """

    modal_mass: float
    modal_first_moment: float
    modal_height_moment: float
    stiffness: float
    top_slope: float
    damping: float
    base_shape: float = 0.0
    mass_above_base: float = 0.0


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
    _, s, mu = _blade_stations(turbine)
    flap = _blade_mode(turbine, structure.flap_mode_shape, structure.flap_stiffness, structure.flap_damping_ratio)
    trapezoid = np.trapezoid
    return BladeModalProperties(**vars(flap), mass=float(trapezoid(mu, s)), first_moment=float(trapezoid(mu * s, s)),
                                second_moment=float(trapezoid(mu * s**2, s)))


def blade_edge_mode(turbine: Turbine) -> BladeMode | None:
    """The integrals of the blade's first edgewise mode (``edge_mode_shape``, bending with the edge stiffness);
    None for a blade rigid edgewise (no mode shape in its definition)."""
    structure = turbine.blade_structure
    if structure.edge_mode_shape is None:
        return None
    return _blade_mode(turbine, structure.edge_mode_shape, structure.edge_stiffness, structure.edge_damping_ratio)


def _blade_mode(turbine: Turbine, coefficients: np.ndarray, stiffness: np.ndarray, damping_ratio: float) -> BladeMode:
    """The assumed-modes integrals (module notes) of the mode of these ElastoDyn coefficients, bending with this
    distributed stiffness [N m^2] at the blade's stations."""
    length = turbine.blade_length
    x, s, mu = _blade_stations(turbine)
    ei = np.interp(x, turbine.blade_structure.span_fraction, stiffness)
    phi, d1, d2 = polynomial_mode(coefficients, x)
    cos_cone = np.cos(turbine.rotor.cone_angle)
    # Axial force per Omega^2: int_s^L mu (r_hub + s') cos^2(cone) ds' (radius from the shaft
    # times the component of the centrifugal force along the coned blade).
    integrand = mu * (turbine.rotor.hub_radius + s) * cos_cone**2
    segment = 0.5 * (integrand[1:] + integrand[:-1]) * np.diff(s)
    axial = np.concatenate((np.cumsum(segment[::-1])[::-1], [0.0]))
    trapezoid = np.trapezoid
    return BladeMode(
        modal_mass=float(trapezoid(mu * phi**2, s)),
        modal_first_moment=float(trapezoid(mu * phi, s)),
        modal_moment_arm=float(trapezoid(mu * phi * s, s)),
        stiffness=float(trapezoid(ei * (d2 / length**2) ** 2, s)),
        centrifugal_stiffness=float(trapezoid(axial * (d1 / length) ** 2, s)),
        damping_ratio=damping_ratio,
        twist_angle=twisted_tip_angle(d2, np.interp(x, turbine.blade_structure.span_fraction,
                                                    turbine.blade_structure.structural_twist), s),
    )


def twisted_tip_angle(curvature: np.ndarray, structural_twist: np.ndarray, s: np.ndarray) -> float:
    """The angle [rad] of a twisted blade mode's tip deflection from its principal direction at zero twist, as
    ElastoDyn's twisted shape functions give it (``ElastoDyn.f90``, Coeff: TwistedSF): the mode bends along its
    principal axis, which the structural twist theta(s) turns at each station, so its deflection is the curvature
    phi''(s) along (cos theta, sin theta) integrated twice from the clamped root; the angle is that of the tip's
    deflection. Flap and edgewise alike: their principal axes turn together with the section.

    ``curvature`` phi'' (any scale), ``structural_twist`` theta [rad] and ``s`` [m] on the same stations, root to tip.
    """
    def integral(values: np.ndarray) -> np.ndarray:
        return np.concatenate(([0.0], np.cumsum(0.5 * (values[1:] + values[:-1]) * np.diff(s))))
    along = integral(integral(curvature * np.cos(structural_twist)))[-1]
    across = integral(integral(curvature * np.sin(structural_twist)))[-1]
    return float(math.atan2(across, along))


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
    from scipy.linalg import eigh  # here: not imported by a plant's start

    return float(np.sqrt(eigh(stiffness, mass, eigvals_only=True)[0]) / (2.0 * np.pi))


def _beam_grid(fraction: np.ndarray, mass_density: np.ndarray, stiffness: np.ndarray,
               length: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A clamped beam's integration grid: x (fraction of its length), s [m] from the clamp, and the mass density
    [kg/m] and bending stiffness [N m^2] of its stations (at ``fraction``) interpolated onto it."""
    x = np.linspace(0.0, 1.0, _GRID_POINTS)
    return x, x * length, np.interp(x, fraction, mass_density), np.interp(x, fraction, stiffness)


def _mass_above(s: np.ndarray, mu: np.ndarray, top_mass: float) -> np.ndarray:
    """The mass above each point of the grid [kg]: the beam's above it (trapezoidal rule) and ``top_mass``."""
    segment = 0.5 * (mu[1:] + mu[:-1]) * np.diff(s)
    return np.concatenate((np.cumsum(segment[::-1])[::-1], [0.0])) + top_mass


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

    Notes
    -----
    The integrals run over the tower's beam, from its clamp to its top (:class:`hawt_plant.turbine.Tower`):
    over a flexible base they include the substructure below the tower's base; a rigid base adds nothing. The
    heights h are above the ground (offshore: mean sea level). The moments for the tower-base loads
    (``modal_first_moment``, ``modal_height_moment``) run over the tower above its base, about the base, where the
    plant takes its tower-base moments (OpenFAST's TwrBsMyt/Mxt point).
    """
    tower = turbine.tower
    if direction == "fa":
        coefficients, stiffness, damping = tower.fa_mode_shape, tower.fa_stiffness, tower.fa_damping_ratio
    elif direction == "ss":
        coefficients, stiffness, damping = tower.ss_mode_shape, tower.ss_stiffness, tower.ss_damping_ratio
    else:
        raise ValueError(f"direction: expected 'fa' or 'ss', found {direction!r}")
    length = tower.length
    x, s, mu, ei = _beam_grid(tower.height_fraction, tower.mass_density, stiffness, length)
    h = tower.clamp_height + s
    phi, d1, d2 = polynomial_mode(coefficients, x)
    mass_above = _mass_above(h, mu, top_mass)
    trapezoid = np.trapezoid
    bending = trapezoid(ei * (d2 / length**2) ** 2, h)
    gravity = turbine.environment.gravity * trapezoid(mass_above * (d1 / length) ** 2, h)
    base = tower.base_height
    at_base = (base - tower.clamp_height) / length
    x_above = np.linspace(at_base, 1.0, _GRID_POINTS)  # the grid itself for a tower on the ground or a rigid base
    h_above = tower.clamp_height + x_above * length
    mu_above, phi_above = np.interp(x_above, tower.height_fraction, tower.mass_density), \
        polynomial_mode(coefficients, x_above)[0]
    modal_mass = float(trapezoid(mu * phi**2, h))
    return TowerModalProperties(
        modal_mass=modal_mass,
        modal_first_moment=float(trapezoid(mu_above * phi_above, h_above)),
        modal_height_moment=float(trapezoid(mu_above * phi_above * (h_above - base), h_above)),
        stiffness=float(bending - gravity),
        top_slope=float(d1[-1] / length),
        damping=float(2.0 * damping * math.sqrt(bending * modal_mass)),
        base_shape=float(phi_above[0]),
        mass_above_base=float(trapezoid(mu_above, h_above)),
    )


def beam_first_mode(fraction: np.ndarray, mass_density: np.ndarray, stiffness: np.ndarray, length: float,
                    top_mass: float, gravity: float) -> tuple[np.ndarray, float]:
    """The first bending mode of a vertical beam clamped at its foot with a point mass on its top, by Rayleigh-Ritz.

    Parameters
    ----------
    fraction : ndarray, shape (T,)
        Station heights as fractions of the beam's length, from 0 (the clamp) to 1 (the top), increasing.
    mass_density : ndarray, shape (T,)
        [kg/m]
    stiffness : ndarray, shape (T,)
        Bending stiffness in the mode's plane [N m^2].
    length : float
        [m]
    top_mass : float
        Mass on the top (a tower's rotor and nacelle) [kg], moving with it and loading the beam in gravity.
    gravity : float
        [m/s^2]

    Returns
    -------
    coefficients : ndarray, shape (5,)
        Of x^2 .. x^6 (x the fraction of the length), adding up to 1: the mode shape in ElastoDyn's form.
    frequency : float
        [Hz]

    Notes
    -----
    The smallest eigenvalue lambda of K q = lambda M q over ElastoDyn's basis phi_i = x^i, i = 2..6 (clamped at
    x = 0), with K_ij = int EI phi_i'' phi_j'' ds - g int m_above phi_i' phi_j' ds and M_ij = int mu phi_i phi_j
    ds + M_top phi_i(1) phi_j(1): the assumed-modes integrals of :func:`tower_modal_properties` with the shape
    left free (Euler-Bernoulli bending, the top mass without rotary inertia). For the IEA 15 MW's tower on its
    monopile, clamped at the mudline, it gives 0.1821 Hz; a finite-element model of the same beam (400 Hermite
    elements) 0.1820 Hz.
    """
    x, s, mu, ei = _beam_grid(fraction, mass_density, stiffness, length)
    shapes = [polynomial_mode(row, x) for row in np.eye(5)]
    mass_above = _mass_above(s, mu, top_mass)
    k = np.array([[np.trapezoid(ei * a[2] * b[2], s) / length**4
                   - gravity * np.trapezoid(mass_above * a[1] * b[1], s) / length**2 for b in shapes] for a in shapes])
    m = np.array([[np.trapezoid(mu * a[0] * b[0], s) for b in shapes] for a in shapes]) + top_mass
    from scipy.linalg import eigh  # here: not imported by a plant's start

    values, vectors = eigh(k, m)
    return vectors[:, 0] / vectors[:, 0].sum(), float(np.sqrt(values[0]) / (2.0 * np.pi))
