"""Unsteady airfoil aerodynamics: the Hansen-Gaunaa-Madsen dynamic stall model on every blade element.

The model of Hansen, Gaunaa & Madsen (2004), "A Beddoes-Leishman type dynamic stall model in
state-space and indicial formulations", Risø-R-1354(EN), which AeroDyn runs as UA_Mod = 4
("B-L HGM 4 states"): the shed wake lags the effective angle of attack (two states), the
leading-edge pressure lags the potential lift (one state) and the trailing-edge separation point
lags its static value (one state); lift and drag follow from the static polar through Kirchhoff's
separation function. Equation numbers are those of the report as independent implementations of
it cite them.

The model runs for every element of every blade at once, states of shape (B, N), and is advanced
once per time step by :meth:`UnsteadyAirfoil.step`. Elements whose airfoil has no unsteady parameters
(:class:`~hawt_plant.turbine.UnsteadyAirfoilParameters`, e.g. the NREL 5 MW's cylinders) stay
quasi-steady: for them the model's constants make it return the static polar exactly.
"""
from __future__ import annotations

import math
from typing import Mapping, Sequence

import numpy as np

from hawt_plant.airfoil_table import ElementPolars, grid_point, interpolated
from hawt_plant.compiled import njit
from hawt_plant.turbine import AirfoilPolar

__all__ = ["STATES", "UnsteadyAirfoil", "hgm_settle", "hgm_step", "separation_function", "zero_lift_angle"]

_ATTACHED = 1.0 - 1e-6  # f_st above this is taken as 1 (fully attached)


def zero_lift_angle(polar: AirfoilPolar, near: float) -> float:
    """The angle of attack [rad] nearest ``near`` at which the polar's linearly interpolated lift is zero.

    Raises
    ------
    ValueError
        Naming the polar, if its lift never changes sign.
    """
    cl, alpha = polar.cl, polar.alpha
    lower = np.flatnonzero((cl[:-1] <= 0.0) & (cl[1:] > 0.0) | (cl[:-1] >= 0.0) & (cl[1:] < 0.0))
    if lower.size == 0:
        raise ValueError(f"{polar.name}: the lift never changes sign, no zero-lift angle")
    crossings = alpha[lower] - cl[lower] * (alpha[lower + 1] - alpha[lower]) / (cl[lower + 1] - cl[lower])
    return float(crossings[np.argmin(np.abs(crossings - near))])


def separation_function(alpha: np.ndarray, cl: np.ndarray, alpha0: float,
                        lift_slope: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Static separation point and the attached and fully separated lift of a static polar.

    Parameters
    ----------
    alpha : ndarray, shape (G,)
        Angles of attack [rad].
    cl : ndarray, shape (G,)
        Static lift coefficient at ``alpha`` [-].
    alpha0 : float
        Zero-lift angle of attack [rad].
    lift_slope : float
        Attached-flow lift slope cl_α [1/rad].

    Returns
    -------
    f_st, attached, separated : ndarray, shape (G,)
        Separation point in [0, 1] (1: attached), and the lift of attached and of fully separated
        flow, with ``cl = attached f_st + separated (1 - f_st)``.

    Notes
    -----
    Kirchhoff's flat-plate relation cl = cl_α (α - α0) ((1 + sqrt f) / 2)^2 inverted (Hansen et al.
    2004, eq. 15): f_st = (2 sqrt(cl / (cl_α (α - α0))) - 1)^2, with 2 sqrt(.) - 1 clipped to [0, 1] (a
    lift below a quarter of the attached line is fully separated, f_st = 0; a lift above the line is
    attached, f_st = 1; f_st(α0) = 1). The fully separated lift is eq. 18,
    cl_fs = (cl - cl_α (α - α0) f_st) / (1 - f_st), and cl / 2 where f_st = 1 (eq. 19; the limit of eq. 18
    as f_st -> 1). The attached lift is the line cl_α (α - α0) where f_st < 1 and, so that the steady
    state is the static polar wherever the polar lies above the line, the static lift itself where
    f_st = 1 (both agree where the polar meets the line).
    """
    line = lift_slope * (alpha - alpha0)
    with np.errstate(divide="ignore", invalid="ignore"):
        root = np.clip(2.0 * np.sqrt(np.maximum(cl / line, 0.0)) - 1.0, 0.0, 1.0)
    f_st = root * root
    f_st[(line == 0.0) | (f_st > _ATTACHED)] = 1.0
    attached = f_st == 1.0
    with np.errstate(divide="ignore", invalid="ignore"):
        separated = np.where(attached, 0.5 * cl, (cl - line * f_st) / (1.0 - f_st))
    return f_st, np.where(attached, cl, line), separated


class UnsteadyAirfoil:
    """The Hansen-Gaunaa-Madsen dynamic stall model of every blade element, advanced one step at a time.

    Parameters
    ----------
    polars : ElementPolars
        The static polars of the N elements; the model's tables use their grid.
    airfoils : mapping of str to AirfoilPolar
    element_airfoils : sequence of str, length N
        Airfoil name of each element.
    chord : ndarray, shape (N,)
        Chord of each element [m].
    blades : int
        B, the number of rows of the states.

    Notes
    -----
    States per element (Hansen et al. 2004, state-space form, as AeroDyn's UA_Mod 4 writes it: OpenFAST
    ``UnsteadyAero.f90``, eqs. 8-19 of its HGM notes), with T_u = c / (2 V), V the relative speed, ω the section's
    nose-up pitching rate (AeroDyn's ``omega``: the blade's pitch rate, the plant's blades having no torsion) and
    α_34 = atan2(sin α + T_u ω, cos α) the angle of attack at the three-quarter chord (AeroDyn's AoA34):

    - the shed-wake lags of the effective angle of attack, kept as deficits d_i = A_i α_34 - x_i of AeroDyn's
      x1, x2: d_i' = -(b_i / T_u) d_i + A_i α_34', so that α_E = α_34 - d_1 - d_2 (eq. 12,
      α_E = α_34 (1 - A1 - A2) + x1 + x2);
    - the lagged potential lift, kept as its angle α_F = x3 / cl_α + α0:
      α_F' = (α_E + π T_u ω / cl_α - α_F) / (T_p T_u) (eq. 13, cl_p = cl_α (α_E - α0) + π T_u ω);
    - the separation point f'': d f'' / dt = (f_st(α_F) - f'') / (T_f0 T_u).

    A1, A2, b1, b2, T_p and T_f0 are the airfoil's (:class:`~hawt_plant.turbine.UnsteadyAirfoilParameters`,
    AeroDyn's defaults where its file has none). Outputs (eqs. 16, 17, 19)::

        cl = cl_att(α_E) f'' + cl_fs(α_E) (1 - f'') + π T_u ω
           = cl_st(α_E) + (cl_att - cl_fs)(α_E) (f'' - f_st(α_E)) + π T_u ω
        cd = cd_st(α_E) + (α_34 - α_E + T_u ω) cl_c
             + (cd_st(α_E) - cd0) [((1 - sqrt f'')/2)^2 - ((1 - sqrt f_st(α_E))/2)^2]

    with cl_c the circulatory part (the first line without π T_u ω), where the second form of cl follows from the
    definition of cl_fs (:func:`separation_function`): a settled element (α steady, ω = 0, f'' = f_st(α)) returns
    the static polar bit for bit. The added-mass lift and the potential lift's lead follow the section's rotation
    ω, not the rate of α: a change of the inflow (a gust, the tower's shadow) moves α without turning the section,
    and AeroDyn gives it no added mass. Static cl, cd, cl_att - cl_fs and f_st are tabulated on the polars'
    uniform grid (:meth:`ElementPolars.tabulate`).

    The zero-lift angle α0 is the polar's (:func:`zero_lift_angle` nearest the parameters' ``alpha0``):
    f_st(α0) = 1 needs cl_st(α0) = 0, and the NREL 5 MW files' "zero Cn angle" is up to 1.7° off their
    tables (corrected for rotational stall delay). The lift slope is the parameters' (their "Cn slope",
    Cn ~ cl near zero lift).

    Time discretisation, exact for every step (stable at any reduced step 2 V dt / c): over a step α_34 changes
    linearly and V, ω and f_st(α_F) are held at their end-of-step values; the shed-wake deficits are then
    integrated exactly (d_i <- e_i d_i + A_i Δα_34 (1 - e_i) / (λ_i dt), e_i = exp(-λ_i dt), λ_i = b_i / T_u),
    α_F and f'' by their exact exponential decay towards the end-of-step target.
    The terms of the speed's rate in the state-space form are left out, as in AeroDyn's documented UA_Mod 4
    equations.
    The angle of attack is taken as continuous: a jump across ±180° (reversed flow) is not unwrapped.
    """

    def __init__(self, polars: ElementPolars, airfoils: Mapping[str, AirfoilPolar], element_airfoils: Sequence[str],
                 chord: np.ndarray, blades: int) -> None:
        chord = np.asarray(chord, dtype=float)
        n = len(element_airfoils)
        if chord.shape != (n,) or not np.all(chord > 0.0):
            raise ValueError(f"chord: expected {n} positive values, found {chord.tolist()}")
        grid = polars.grid
        per_airfoil = {}
        for name in set(element_airfoils):
            polar = airfoils[name]
            cl, cd = np.interp(grid, polar.alpha, polar.cl), np.interp(grid, polar.alpha, polar.cd)
            if polar.unsteady is None:  # no lags, no added mass: the static polar
                per_airfoil[name] = (np.stack((cl, cd, np.zeros_like(cl), np.ones_like(cl), cd), axis=1),
                                     (0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0))
                continue
            p = polar.unsteady
            alpha0 = zero_lift_angle(polar, p.alpha0)
            f_st, attached, separated = separation_function(grid, cl, alpha0, p.lift_slope)
            per_airfoil[name] = (np.stack((cl, cd, attached - separated, f_st, cd - p.cd0), axis=1),
                                 (p.a1, p.a2, p.b1, p.b2, 1.0 / p.pressure_lag, 1.0 / p.separation_lag, 1.0,
                                  math.pi / p.lift_slope))
        self._table = polars.tabulate(np.stack([per_airfoil[name][0] for name in element_airfoils]))
        self._polars = polars
        self._shape = (blades, n)
        # Per element (rows): A_1, A_2 (0 where quasi-steady); the rates λ V of the four lags per unit speed,
        # b_1 2 / c, b_2 2 / c, 2 / (T_p c), 2 / (T_f0 c); the half chord c / 2 = T_u V (0 where quasi-steady: no
        # added mass, α_34 = α); π / cl_α, the angle of the added-mass lift in the potential lift.
        constants = np.array([per_airfoil[name][1] for name in element_airfoils]).T.copy()
        constants[2:6] *= 2.0 / chord
        constants[6] *= chord / 2.0
        self._constants = constants
        self._states = np.empty((STATES,) + self._shape)  # α, the deficits d_1, d_2, α_F, f''
        self.settle(np.zeros(self._shape))

    @property
    def kernel_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The arrays :func:`hgm_step` and :func:`hgm_settle` take: the states (5, B, N), the table (N G, 2, 5)
        on the polars' grid (:attr:`ElementPolars.grid_constants`) and the per-element constants (8, N)."""
        return self._states, self._table, self._constants

    @property
    def states(self) -> dict[str, np.ndarray]:
        """Copies of the states, shape (B, N) each: ``alpha`` (angle of attack of the last step [rad]),
        ``alpha_effective`` (α_E [rad]), ``alpha_f`` (α_F [rad]) and ``separation`` (f'')."""
        alpha, lag_1, lag_2, alpha_f, separation = self._states
        return {"alpha": alpha.copy(), "alpha_effective": alpha - lag_1 - lag_2, "alpha_f": alpha_f.copy(),
                "separation": separation.copy()}

    def settle(self, alpha: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Put every element in the steady state of its angle of attack and return the static coefficients.

        Parameters
        ----------
        alpha : ndarray, shape (B, N)
            Angle of attack [rad].

        Returns
        -------
        cl, cd : ndarray, shape (B, N)
            The static polars at ``alpha``: what :meth:`step` returns while ``alpha`` stays.
        """
        alpha = np.array(alpha, dtype=float)
        if alpha.shape != self._shape:
            raise ValueError(f"alpha: expected shape {self._shape}, found {alpha.shape}")
        out = np.empty((2,) + self._shape)
        _settle_all(alpha, *self.kernel_arrays, *self._polars.grid_constants, out)
        return out[0], out[1]

    def step(self, alpha: np.ndarray, speed: np.ndarray, dt: float, advance: bool = True,
             pitching_rate: np.ndarray | float = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The lift and drag coefficients at the end of a step of ``dt`` that ends at ``alpha``.

        Parameters
        ----------
        alpha : ndarray, shape (B, N)
            Quasi-steady angle of attack at the end of the step [rad].
        speed : ndarray, shape (B, N)
            Relative speed of each element at the end of the step [m/s] (at least 0.1 m/s is used).
        dt : float
            Step [s], > 0.
        advance : bool
            Keep the states at the end of the step (default); False evaluates the step and leaves the
            states as they were (the model's induction iterations before the last).
        pitching_rate : ndarray or float, broadcast to (B, N)
            ω, each section's nose-up rotation rate [rad/s] (class notes); default 0, a section that does not turn.

        Returns
        -------
        circulatory, added_mass, cd : ndarray, shape (B, N)
            The lift is their sum: the circulatory lift (the first two terms of eq. 22) and the non-circulatory
            (added-mass) lift π T_u α', apart because only the first sheds vorticity into the wake.
        """
        if not dt > 0.0:
            raise ValueError(f"dt: expected > 0 s, found {dt}")
        alpha, speed, rate = np.broadcast_arrays(np.asarray(alpha, dtype=float), np.asarray(speed, dtype=float),
                                                 np.asarray(pitching_rate, dtype=float))
        if alpha.shape != self._shape:
            raise ValueError(f"alpha: expected shape {self._shape}, found {alpha.shape}")
        out = np.empty((3,) + self._shape)
        _step_all(np.ascontiguousarray(alpha), np.ascontiguousarray(speed), np.ascontiguousarray(rate), dt, advance,
                  *self.kernel_arrays, *self._polars.grid_constants, out)
        return out[0], out[1], out[2]


STATES = 5
"""Number of states of an element: α_34 of the last step, the shed-wake deficits d_1 and d_2, α_F and f''."""


@njit
def _lookup(table, scale, intervals, offset, alpha, k):
    row, fraction = grid_point(alpha, scale, intervals, offset)
    return interpolated(table, row, fraction, k)


@njit
def hgm_settle(i: int, j: int, alpha: float, states: np.ndarray, table: np.ndarray, constants: np.ndarray,
               scale: float, intervals: float, offsets: np.ndarray) -> tuple[float, float]:
    """:meth:`UnsteadyAirfoil.settle` of element ``j`` of blade ``i``: its states put in the steady state of
    ``alpha``; returns the static cl, cd there."""
    row, fraction = grid_point(alpha, scale, intervals, offsets[j])
    states[0, i, j] = alpha
    states[1, i, j] = 0.0
    states[2, i, j] = 0.0
    states[3, i, j] = alpha
    states[4, i, j] = interpolated(table, row, fraction, 3)
    return interpolated(table, row, fraction, 0), interpolated(table, row, fraction, 1)


@njit
def hgm_step(i: int, j: int, alpha: float, speed: float, pitching_rate: float, dt: float, advance: bool,
             states: np.ndarray, table: np.ndarray, constants: np.ndarray, scale: float, intervals: float,
             offsets: np.ndarray) -> tuple[float, float, float]:
    """:meth:`UnsteadyAirfoil.step` of element ``j`` of blade ``i``: circulatory lift, added-mass lift and drag
    (eqs. 12-19 with the exact step of the class notes)."""
    offset = offsets[j]
    speed = np.maximum(speed, 0.1)
    tu_omega = constants[6, j] * pitching_rate / speed  # T_u ω
    alpha = math.atan2(math.sin(alpha) + tu_omega, math.cos(alpha)) if tu_omega != 0.0 else alpha  # α_34
    change = alpha - states[0, i, j]
    # shed wake: d_i <- e_i d_i + A_i Δα (1 - e_i) / (λ_i dt), e_i = exp(-λ_i dt)
    exponent = speed * (-dt * constants[2, j])
    decay_minus_one = math.expm1(exponent)
    lag_1 = states[1, i, j] * (decay_minus_one + 1.0) + decay_minus_one / exponent * change * constants[0, j]
    exponent = speed * (-dt * constants[3, j])
    decay_minus_one = math.expm1(exponent)
    lag_2 = states[2, i, j] * (decay_minus_one + 1.0) + decay_minus_one / exponent * change * constants[1, j]
    deficit = lag_1 + lag_2  # α_34 - α_E
    alpha_e = alpha - deficit
    potential = alpha_e + constants[7, j] * tu_omega
    alpha_f = (states[3, i, j] - potential) * (math.expm1(speed * (-dt * constants[4, j])) + 1.0) + potential
    f_target = _lookup(table, scale, intervals, offset, alpha_f, 3)
    separation = (states[4, i, j] - f_target) * (math.expm1(speed * (-dt * constants[5, j])) + 1.0) + f_target
    row, fraction = grid_point(alpha_e, scale, intervals, offset)
    f_st = interpolated(table, row, fraction, 3)
    circulatory = (separation - f_st) * interpolated(table, row, fraction, 2) + interpolated(table, row, fraction, 0)
    added_mass = math.pi * tu_omega
    root_separation, root_static = math.sqrt(separation), math.sqrt(f_st)
    drag_change = (root_static - root_separation) * (2.0 - root_separation - root_static) * 0.25 \
        * interpolated(table, row, fraction, 4)
    cd = (deficit + tu_omega) * circulatory + interpolated(table, row, fraction, 1) + drag_change
    if advance:
        states[0, i, j] = alpha
        states[1, i, j] = lag_1
        states[2, i, j] = lag_2
        states[3, i, j] = alpha_f
        states[4, i, j] = separation
    return circulatory, added_mass, cd


@njit
def _settle_all(alpha, states, table, constants, scale, intervals, offsets, out):
    for i in range(alpha.shape[0]):
        for j in range(alpha.shape[1]):
            out[0, i, j], out[1, i, j] = hgm_settle(i, j, alpha[i, j], states, table, constants, scale, intervals,
                                                    offsets)


@njit
def _step_all(alpha, speed, rate, dt, advance, states, table, constants, scale, intervals, offsets, out):
    for i in range(alpha.shape[0]):
        for j in range(alpha.shape[1]):
            out[0, i, j], out[1, i, j], out[2, i, j] = hgm_step(i, j, alpha[i, j], speed[i, j], rate[i, j], dt,
                                                                advance, states, table, constants, scale, intervals,
                                                                offsets)
