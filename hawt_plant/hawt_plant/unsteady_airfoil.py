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

from hawt_plant.airfoil_table import ElementPolars
from hawt_plant.turbine import AirfoilPolar

__all__ = ["INDICIAL", "LEADING_EDGE_LAG", "SEPARATION_LAG", "UnsteadyAirfoil", "separation_function",
           "zero_lift_angle"]

INDICIAL = (0.165, 0.335, 0.0455, 0.3)
"""A1, A2, b1, b2 of the attached-flow indicial function 1 - A1 exp(-b1 s) - A2 exp(-b2 s) (Jones's fit of
Wagner's function; Hansen et al. 2004), s = 2 V t / c the distance travelled in half-chords."""
LEADING_EDGE_LAG = 1.5
"""T_p: time constant of the lagged potential lift (leading-edge pressure) in units of T_u = c / (2 V)."""
SEPARATION_LAG = 6.0
"""T_f: time constant of the separation point in units of T_u = c / (2 V)."""

_ATTACHED = 1.0 - 1e-6  # f_st above this is taken as 1 (fully attached)
_MIN_SPEED = np.array(0.1)  # [m/s] relative speed used in the time constants is at least this
_ONE, _TWO, _QUARTER = np.array(1.0), np.array(2.0), np.array(0.25)  # 0-d arrays: see hawt_plant.bem


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
    States per element (Hansen et al. 2004, state-space form; AeroDyn UA_Mod 4), with
    T_u = c / (2 V) and V the relative speed:

    - the shed-wake lags of the effective angle of attack, kept as deficits d_i = A_i α - x_i of AeroDyn's
      x1, x2: d_i' = -(b_i / T_u) d_i + A_i α', so that α_E = α - d_1 - d_2 (eq. 12,
      α_E = α (1 - A1 - A2) + x1 + x2);
    - the lagged potential lift, kept as its angle α_F = x3 / cl_α + α0:
      α_F' = (α_E + π T_u α' / cl_α - α_F) / (T_p T_u) (eq. 13, cl_p = cl_α (α_E - α0) + π T_u α');
    - the separation point f'': d f'' / dt = (f_st(α_F) - f'') / (T_f T_u).

    Outputs (eqs. 22, 24, 26)::

        cl = cl_att(α_E) f'' + cl_fs(α_E) (1 - f'') + π T_u α'
           = cl_st(α_E) + (cl_att - cl_fs)(α_E) (f'' - f_st(α_E)) + π T_u α'
        cd = cd_st(α_E) + (α - α_E) cl + (cd_st(α_E) - cd0) [((1 - sqrt f'')/2)^2 - ((1 - sqrt f_st(α_E))/2)^2]

    where the second form of cl follows from the definition of cl_fs (:func:`separation_function`): a
    settled element (α steady, f'' = f_st(α)) returns the static polar bit for bit. The drag adds the
    induced drag of the lagged angle and the change of the separation drag. Static cl, cd, cl_att - cl_fs
    and f_st are tabulated on the polars' uniform grid (:meth:`ElementPolars.tabulate`).

    The zero-lift angle α0 is the polar's (:func:`zero_lift_angle` nearest the parameters' ``alpha0``):
    f_st(α0) = 1 needs cl_st(α0) = 0, and the NREL 5 MW files' "zero Cn angle" is up to 1.7° off their
    tables (corrected for rotational stall delay). The lift slope is the parameters' (their "Cn slope",
    Cn ~ cl near zero lift).

    Time discretisation, exact for every step (stable at any reduced step 2 V dt / c): over a step α changes
    linearly and V and f_st(α_F) are held at their end-of-step values; the shed-wake deficits are then
    integrated exactly (d_i <- e_i d_i + A_i Δα (1 - e_i) / (λ_i dt), e_i = exp(-λ_i dt), λ_i = b_i / T_u),
    α_F and f'' by their exact exponential decay towards the end-of-step target, and α' = Δα / dt.
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
            if polar.unsteady is None:
                per_airfoil[name] = (np.stack((cl, cd, np.zeros_like(cl), np.ones_like(cl), cd), axis=1),
                                     0.0, 0.0)
                continue
            parameters = polar.unsteady
            alpha0 = zero_lift_angle(polar, parameters.alpha0)
            f_st, attached, separated = separation_function(grid, cl, alpha0, parameters.lift_slope)
            per_airfoil[name] = (np.stack((cl, cd, attached - separated, f_st, cd - parameters.cd0), axis=1),
                                 1.0, parameters.lift_slope)
        self._table = polars.tabulate(np.stack([per_airfoil[name][0] for name in element_airfoils]))
        unsteady = np.array([per_airfoil[name][1] for name in element_airfoils])
        slope = np.array([per_airfoil[name][2] for name in element_airfoils])
        a1, a2, b1, b2 = INDICIAL
        self._polars = polars
        self._shape = (blades, n)
        self._lag_gain = np.stack((a1 * unsteady, a2 * unsteady))[:, None, :]  # A_i, 0 where quasi-steady
        # Rates λ V of the four lags per unit speed: b_i 2 / c, 2 / (T_p c), 2 / (T_f c).
        self._rates = np.multiply.outer(np.array((b1, b2, 1.0 / LEADING_EDGE_LAG, 1.0 / SEPARATION_LAG)),
                                        2.0 / chord)[:, None, :]
        # Non-circulatory lift π T_u α' = (π c / 2)(Δα / V) / dt, and its angle in the potential lift.
        self._added_mass = math.pi * chord / 2.0 * unsteady
        with np.errstate(divide="ignore", invalid="ignore"):
            self._added_mass_angle = np.where(unsteady > 0.0, self._added_mass / slope, 0.0)
        self._dt = 0.0
        self.settle(np.zeros(self._shape))

    @property
    def states(self) -> dict[str, np.ndarray]:
        """Copies of the states, shape (B, N) each: ``alpha`` (angle of attack of the last step [rad]),
        ``alpha_effective`` (α_E [rad]), ``alpha_f`` (α_F [rad]) and ``separation`` (f'')."""
        return {"alpha": self._alpha.copy(), "alpha_effective": self._alpha - self._lag[0] - self._lag[1],
                "alpha_f": self._alpha_f.copy(), "separation": self._separation.copy()}

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
        self._alpha = alpha
        self._lag = np.zeros((2,) + self._shape)
        self._alpha_f = alpha.copy()
        self._separation = self._lookup(alpha)[..., 3]
        return self._polars.coefficients(alpha)

    def step(self, alpha: np.ndarray, speed: np.ndarray, dt: float,
             advance: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
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

        Returns
        -------
        circulatory, added_mass, cd : ndarray, shape (B, N)
            The lift is their sum: the circulatory lift (the first two terms of eq. 22) and the non-circulatory
            (added-mass) lift π T_u α', apart because only the first sheds vorticity into the wake.
        """
        if dt != self._dt:
            if not dt > 0.0:
                raise ValueError(f"dt: expected > 0 s, found {dt}")
            self._dt = dt
            self._exponent_rates = -dt * self._rates
            self._added_mass_step = np.array(self._added_mass / dt)
            self._added_mass_angle_step = np.array(self._added_mass_angle / dt)
        speed = np.maximum(speed, _MIN_SPEED)
        exponent = speed * self._exponent_rates  # -λ dt of the four lags, shape (4, B, N)
        decay_minus_one = np.expm1(exponent)
        decay = decay_minus_one + _ONE
        change = alpha - self._alpha
        ramp = decay_minus_one[:2] / exponent[:2]  # (1 - e) / (λ dt)
        ramp *= change
        ramp *= self._lag_gain
        lag = self._lag * decay[:2]
        lag += ramp
        deficit = lag[0] + lag[1]  # α - α_E
        angles = np.empty((2,) + self._shape)
        alpha_e, alpha_f = angles
        np.subtract(alpha, deficit, out=alpha_e)
        rate = change / speed  # Δα / V
        potential = rate * self._added_mass_angle_step
        potential += alpha_e
        np.subtract(self._alpha_f, potential, out=alpha_f)
        alpha_f *= decay[2]
        alpha_f += potential
        values = self._lookup(angles)
        at_e, f_target = values[0], values[1, ..., 3]
        points = np.empty((2,) + self._shape)  # f'' and f_st(α_E)
        separation, f_st = points
        np.subtract(self._separation, f_target, out=separation)
        separation *= decay[3]
        separation += f_target
        f_st[...] = at_e[..., 3]
        circulatory = separation - f_st
        circulatory *= at_e[..., 2]
        circulatory += at_e[..., 0]
        added_mass = rate * self._added_mass_step
        cl = circulatory + added_mass
        roots = np.sqrt(points)
        root_sum = _TWO - roots[0]
        root_sum -= roots[1]
        drag_change = roots[1] - roots[0]  # sqrt f_st - sqrt f''
        drag_change *= root_sum
        drag_change *= _QUARTER
        drag_change *= at_e[..., 4]
        cd = deficit * cl
        cd += at_e[..., 1]
        cd += drag_change
        if advance:
            self._alpha = np.array(alpha, dtype=float)
            self._lag = lag
            self._alpha_f = alpha_f
            self._separation = separation
        return circulatory, added_mass, cd

    def _lookup(self, alpha: np.ndarray) -> np.ndarray:
        """Tabulated cl_st, cd_st, cl_att - cl_fs, f_st and cd_st - cd0 at ``alpha`` (..., N): shape (..., N, 5)."""
        index, fraction = self._polars.locate(alpha)
        rows = self._table.take(index, axis=0)
        values = rows[..., 1, :] * fraction[..., None]
        values += rows[..., 0, :]
        return values
