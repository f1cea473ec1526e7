"""Tilt/yaw coupling of the rotor in the Coleman frame, and the azimuth offset that removes it (Disario 2018).

For a rotor whose blade matrix is circulant (equal blades, equal coupling), inverse MBC →
blades → forward MBC is time invariant, and from the pitch demands (θ_tilt, θ_yaw) to the
moments (M_tilt, M_yaw) it is (Disario eq. 2-19, with s∓ = s ∓ jω0)::

    P(s) = [[ a,  b],      a = (e^{−jψ} g(s−jω0) + e^{jψ} g(s+jω0)) / 2
            [−b,  a]],     b = j (e^{−jψ} g(s−jω0) − e^{jψ} g(s+jω0)) / 2

where g is the rotor's cyclic eigen-transfer function — g_b for decoupled equal blades,
g_b − g_c for equal blade-to-blade coupling g_c (eq. 2-23) — and ψ the azimuth offset of the
inverse transform (an offset in the forward transform acts as −ψ, eq. 2-15). For harmonic n,
ω0 → nω0 and ψ → nψ_n: the phase offset φ_n of DESIGN §3 is nψ_n.

At DC the plant is a scaled rotation, P(0) = r [[cos(ψ+α), sin(ψ+α)], [−sin(ψ+α), cos(ψ+α)]] with
g(jω0) = r e^{jα}, so ψ = −∠g(jω0) decouples tilt from yaw (for a first-order blade
K/(τs + 1) this is Disario's ψ_d = atan(τω0), eq. 3-7; for equal coupling, eq. 3-20); measured
with ψ = 0 the same offset is atan2(P21(0), P11(0)) (:func:`offset_from_dc_response`). No single
offset decouples every frequency: near ω0 a first-order blade needs ½ atan(2τω0), far above none.
The band metric η(ψ) (eq. 4-4: the mean |P12| over 0.1–1 rad/s) and the relative gain array
(eq. 3-16) measure what is left.
"""
from __future__ import annotations

import math
from typing import Callable, Tuple

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import minimize_scalar

__all__ = ["BladeModel", "first_order", "coleman_plant", "relative_gain_array", "dc_decoupling_offset",
           "first_order_offsets", "equal_coupling_offset", "offset_from_dc_response", "coupling_metric",
           "optimal_offset"]

BladeModel = Callable[[np.ndarray], np.ndarray]
"""The rotor's cyclic eigen-transfer function g(s) of the pitch → root-moment blade matrix, vectorised over s."""


def first_order(gain: float, time_constant: float) -> BladeModel:
    """g(s) = K / (τ s + 1), Disario's first-order blade (eq. 3-1)."""
    return lambda s: gain / (time_constant * np.asarray(s) + 1.0)


def coleman_plant(blade: BladeModel, s: ArrayLike, rotor_speed: float, offset: float) -> np.ndarray:
    """P(s) of the module notes (Disario eq. 2-19), shape ``s.shape + (2, 2)``; inputs (θ_tilt, θ_yaw).

    Parameters
    ----------
    blade : BladeModel
        g(s).
    s : array_like
        Laplace variable(s), e.g. ``1j * omega``.
    rotor_speed : float
        ω0 [rad/s] (nω0 for harmonic n).
    offset : float
        ψ [rad] in the inverse transform (nψ_n for harmonic n).
    """
    s = np.asarray(s, dtype=complex)
    lower = np.exp(-1j * offset) * blade(s - 1j * rotor_speed)
    upper = np.exp(1j * offset) * blade(s + 1j * rotor_speed)
    a, b = (lower + upper) / 2.0, 1j * (lower - upper) / 2.0
    return np.stack([np.stack([a, b], axis=-1), np.stack([-b, a], axis=-1)], axis=-2)


def relative_gain_array(plant: np.ndarray) -> np.ndarray:
    """RGA(P) = P ∘ (P⁻¹)ᵀ (Disario eq. 3-16), for one or a stack of square matrices."""
    plant = np.asarray(plant)
    return plant * np.swapaxes(np.linalg.inv(plant), -1, -2)


def dc_decoupling_offset(blade: BladeModel, rotor_speed: float) -> float:
    """ψ = −∠g(jω0) [rad]: P12(0) = 0 (the general form of Disario eqs. 3-7 and 3-20)."""
    return -float(np.angle(blade(np.array(1j * rotor_speed))))


def first_order_offsets(time_constant: float, rotor_speed: float) -> Tuple[float, float, float]:
    """Disario eq. 3-7 for K/(τs + 1): the offsets [rad] that decouple ω ≪ ω0 (ψ_d = atan(τω0)), ω ≈ ω0
    (½ atan(2τω0)) and ω ≫ ω0 (0)."""
    return math.atan(time_constant * rotor_speed), 0.5 * math.atan(2.0 * time_constant * rotor_speed), 0.0


def equal_coupling_offset(blade_gain: float, blade_time_constant: float, coupling_gain: float,
                          coupling_time_constant: float, rotor_speed: float) -> float:
    """Disario eq. 3-20 [rad]: the DC-decoupling offset of first-order blades g_b with equal first-order
    coupling g_c."""
    kb, tb, kc, tc, w = blade_gain, blade_time_constant, coupling_gain, coupling_time_constant, rotor_speed
    numerator = w * (kb * tb * (1 + tc * tc * w * w) - kc * tc * (1 + tb * tb * w * w))
    return math.atan2(numerator, kb * (1 + tc * tc * w * w) - kc * (1 + tb * tb * w * w))


def offset_from_dc_response(p11: float, p21: float) -> float:
    """ψ_opt = atan2(P21(0), P11(0)) [rad] from the DC response measured with ψ = 0 (a step or a static demand)."""
    return math.atan2(p21, p11)


def coupling_metric(blade: BladeModel, rotor_speed: float, offsets: ArrayLike,
                    band: Tuple[float, float] = (0.1, 1.0), points: int = 400) -> np.ndarray:
    """η(ψ): the mean of |P12(jω, ψ)| over ``band`` [rad/s] on a linear grid (Disario eq. 4-4), per offset [rad]."""
    omega = np.linspace(band[0], band[1], points)
    return np.array([np.mean(np.abs(coleman_plant(blade, 1j * omega, rotor_speed, float(psi))[..., 0, 1]))
                     for psi in np.atleast_1d(offsets)])


def optimal_offset(blade: BladeModel, rotor_speed: float, band: Tuple[float, float] = (0.1, 1.0)) -> float:
    """The offset in [0, 90°] that minimises η over ``band`` (Disario §4-4-4) [rad]."""
    grid = np.radians(np.arange(0.0, 90.5, 1.0))
    start = float(grid[np.argmin(coupling_metric(blade, rotor_speed, grid, band))])
    result = minimize_scalar(lambda psi: coupling_metric(blade, rotor_speed, [psi], band)[0],
                             bounds=(max(start - math.radians(1.0), 0.0), start + math.radians(1.0)),
                             method="bounded", options={"xatol": 1e-6})
    return float(result.x)
