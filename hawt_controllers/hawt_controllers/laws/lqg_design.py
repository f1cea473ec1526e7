"""Design of LQG individual pitch control with wind-estimate feedforward (Selvam et al. 2009).

From the plant's Coleman-frame linear model (hawt_controllers.design.linear_models) at one wind speed,
discretised at the controller's step (zero-order hold), in the tilt/yaw channels of harmonic 1:

- measured y = (M_cos, M_sin): the 1P cos/sin blade-root out-of-plane moments [MN m];
- control θ = (θ_cos, θ_sin): the 1P cyclic pitch commands [deg];
- disturbance u = (u_cos, u_sin): the cos/sin blade-effective wind [m/s] (Selvam's u_2^cm, u_3^cm
  up to the order and sign of his sin/cos convention).

The units are the scaling of the weights (Selvam's Table II gives none): moments in MN m, pitch in
degrees, wind in m/s.

1. Random-walk wind states (eq. 20) appended to the turbine state (eq. 21, errata E3 and E7 of the
   notes: the augmented output matrix is [C D_u], and only u_cos, u_sin are modelled). One Kalman
   filter estimates both (Q_w on the wind's random walk, Q_v on the measurement; :class:`LqgWeights`).
2. LQR on the turbine states only (the wind states are uncontrollable by construction): state weight
   C^T C (the moments; Selvam's "Q = I" is ambiguous, notes §3.3) plus ``state_weight`` I, input
   weight R.
3. Feedforward θ_ff = -G_inv(H û) (eq. 22 with errata E4-E6: MIMO order G_inv after H, D terms kept),
   G_inv the stable inverse of G (θ -> y) by stable dynamic model inversion (SDMI, George et al.
   1999): a Kalman filter on G with the unknown input as a random walk (Q_η) estimates the input.

The collective and torque loops are open in the design model (the plant's linear model holds pitch
and torque): Selvam closes them first (notes §2.4). On the averaged Coleman model of this plant the
tilt/yaw channels reach the collective ones only through small shear terms.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional, Sequence, Tuple

import numpy as np
from scipy.linalg import solve_discrete_are
from scipy.signal import cont2discrete

from hawt_core.exceptions import ConfigurationError
from hawt_controllers.laws.mbc3 import LinearModel

__all__ = ["DiscreteModel", "LqgDesign", "LqgWeights", "design_lqg", "design_states", "discrete_channels",
           "observability_rank",
           "controllability_rank", "MEASURED", "CONTROLLED", "DISTURBANCES", "ACTUATOR_STATES"]

MEASURED = ("root_moment_oop_cos", "root_moment_oop_sin")
CONTROLLED = ("pitch_command_cos", "pitch_command_sin")
DISTURBANCES = ("wind_cos", "wind_sin")
ACTUATOR_STATES = ("pitch_cos", "pitch_sin", "pitch_rate_cos", "pitch_rate_sin")
"""The cyclic pitch actuator's states (angle [rad], rate [rad/s]), set from the measured pitch each step."""
_MOMENT_UNIT = 1e6  # N m per MN m
_PITCH_UNIT = math.pi / 180.0  # rad per deg


@dataclass(frozen=True)
class LqgWeights:
    """The design's weights in this module's units.

    Selvam's Table II (notes §3.4, erratum E8: Q_v 0.01 I, Q_w 0.1 I, Q = I, R 0.8 I, Q_η 0.01) has no units
    and no sample time. Taken as they are here (Q_w 0.1 (m/s)^2 per 10 ms step), the law demanded pitch
    at the actuator's rate limit on 5997 of 6000 steps of a turbulent run at 18 m/s. The defaults are
    tuned on that run (``hawt run lqg``, 60 s, seed 0): no rate-limited step, the blade-root DEL 31-35 %
    lower than the baseline's.

    Attributes
    ----------
    measurement_noise : float
        Q_v of each moment [(MN m)^2]: the 2P/3P content the model does not carry counts as noise.
    wind_walk : float
        Intensity of the wind's random walk [(m/s)^2/s]; Q_w per step is this times dt.
    state_weight : float
        Added to Q = C^T C on every turbine state.
    input_weight : float
        R of each cyclic pitch [deg^2].
    inversion_walk : float
        Q_η of the SDMI inverse's random walk per step.
    """

    measurement_noise: float = 0.1
    wind_walk: float = 1e-3
    state_weight: float = 1e-6
    input_weight: float = 100.0
    inversion_walk: float = 0.01

    def __post_init__(self) -> None:
        for name in ("measurement_noise", "wind_walk", "input_weight", "inversion_walk"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ConfigurationError(name, f"expected a finite value > 0, found {value}")
        if not (math.isfinite(self.state_weight) and self.state_weight >= 0.0):
            raise ConfigurationError("state_weight", f"expected a finite value >= 0, found {self.state_weight}")


@dataclass(frozen=True)
class DiscreteModel:
    """x(k+1) = a x + b_theta θ + b_u u,  y = c x + d_theta θ + d_u u, in this module's units."""

    a: np.ndarray
    b_theta: np.ndarray
    b_u: np.ndarray
    c: np.ndarray
    d_theta: np.ndarray
    d_u: np.ndarray
    dt: float


def design_states(model: LinearModel) -> Tuple[str, ...]:
    """The states of the tilt/yaw design model: the blades' cyclic coordinates and the tower. The drivetrain
    and the collective coordinates are left out: with pitch and torque held they are reached from θ_cos,
    θ_sin only through the shear's small periodic terms, which the azimuth average keeps as weak couplings
    that make the design model nearly unobservable and uncontrollable."""
    return tuple(name for name in model.states if name.endswith(("_cos", "_sin")) or name.startswith("tower_"))


def discrete_channels(model: LinearModel, dt: float, states: Optional[Sequence[str]] = None,
                      disturbances: Sequence[str] = DISTURBANCES, outputs: Sequence[str] = MEASURED) -> DiscreteModel:
    """The tilt/yaw channels of ``model`` on ``states`` (default :func:`design_states`), discretised at ``dt`` [s]
    with a zero-order hold: the cos/sin pitch and ``disturbances`` in, ``outputs`` out (moments in MN m)."""
    keep = [model.states.index(n) for n in (design_states(model) if states is None else states)]
    columns = [model.inputs.index(n) for n in CONTROLLED + tuple(disturbances)]
    rows = [model.outputs.index(n) for n in outputs]
    scale = np.array([_PITCH_UNIT] * len(CONTROLLED) + [1.0] * len(disturbances))
    unit = np.array([_MOMENT_UNIT if n.startswith("root_moment") else 1.0 for n in outputs])[:, None]
    a, b, c, d, _ = cont2discrete((model.a[np.ix_(keep, keep)], model.b[np.ix_(keep, columns)] * scale,
                                   model.c[np.ix_(rows, keep)] / unit,
                                   model.d[np.ix_(rows, columns)] * scale / unit), dt, method="zoh")
    m = len(CONTROLLED)
    return DiscreteModel(a, b[:, :m], b[:, m:], c, d[:, :m], d[:, m:], dt)


def observability_rank(a: np.ndarray, c: np.ndarray) -> int:
    """Rank of the observability matrix [c; c a; ...; c a^(n-1)]."""
    blocks, block = [], c
    for _ in range(a.shape[0]):
        blocks.append(block)
        block = block @ a
    return int(np.linalg.matrix_rank(np.vstack(blocks)))


def controllability_rank(a: np.ndarray, b: np.ndarray) -> int:
    """Rank of the controllability matrix [b, a b, ..., a^(n-1) b]."""
    return observability_rank(a.T, b.T)


def _kalman_gain(a: np.ndarray, c: np.ndarray, process: np.ndarray, measurement: np.ndarray) -> np.ndarray:
    """The steady-state predictor gain K of x(k+1|k) = a x(k|k-1) + ... + K (y - c x(k|k-1) - ...)."""
    p = solve_discrete_are(a.T, c.T, process, measurement)
    return a @ p @ c.T @ np.linalg.inv(c @ p @ c.T + measurement)


@dataclass(frozen=True)
class LqgDesign:
    """The controller's matrices, in this module's units.

    Estimator (predictor form, augmented state z = [x; u]): z(k+1) = a_est z + b_est θ + k_est (y - c_est z).
    Feedback: θ_fb = -k_lqr x̂. Feedforward: a state-space system (ff_a, ff_b, ff_c, ff_d) from û to θ_ff.
    """

    plant: DiscreteModel
    weights: LqgWeights
    a_est: np.ndarray
    b_est: np.ndarray
    c_est: np.ndarray
    k_est: np.ndarray
    k_lqr: np.ndarray
    inverse: Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]
    ff_a: np.ndarray
    ff_b: np.ndarray
    ff_c: np.ndarray
    ff_d: np.ndarray
    actuator: Tuple[int, ...] = ()
    """Indices of ACTUATOR_STATES in the turbine state."""

    @property
    def states(self) -> int:
        return self.plant.a.shape[0]


def _series(first: Sequence[np.ndarray], second: Sequence[np.ndarray]) -> Tuple[np.ndarray, ...]:
    """The system ``second`` after ``first`` (each (a, b, c, d), discrete)."""
    a1, b1, c1, d1 = first
    a2, b2, c2, d2 = second
    a = np.block([[a1, np.zeros((a1.shape[0], a2.shape[0]))], [b2 @ c1, a2]])
    return a, np.vstack((b1, b2 @ d1)), np.hstack((d2 @ c1, c2)), d2 @ d1


def design_lqg(model: LinearModel, dt: float, weights: LqgWeights = LqgWeights()) -> LqgDesign:
    """Selvam's FB-FF IPC for ``model`` at the controller step ``dt`` [s] (see the module notes).

    Raises
    ------
    ConfigurationError
        Naming the failing pair: (A, C) of the augmented model not observable, (A, B_θ) not stabilisable
        by the LQR, or an SDMI inverse that is not stable.
    """
    plant = discrete_channels(model, dt)
    n, m, w = plant.a.shape[0], plant.b_theta.shape[1], plant.b_u.shape[1]
    a_aug = np.block([[plant.a, plant.b_u], [np.zeros((w, n)), np.eye(w)]])
    b_aug = np.vstack((plant.b_theta, np.zeros((w, m))))
    c_aug = np.hstack((plant.c, plant.d_u))
    process = np.zeros((n + w, n + w))
    process[n:, n:] = weights.wind_walk * dt * np.eye(w)
    process[:n, :n] = 1e-9 * np.eye(n)  # "small additional process noise for numerical reasons"
    measurement = weights.measurement_noise * np.eye(len(MEASURED))
    try:
        k_est = _kalman_gain(a_aug, c_aug, process, measurement)
    except (np.linalg.LinAlgError, ValueError) as error:
        raise ConfigurationError("estimator", f"(A_aug, [C D_u]) has no stabilising Kalman gain: {error}") from None
    q = plant.c.T @ plant.c + weights.state_weight * np.eye(n)
    r = weights.input_weight * np.eye(m)
    try:
        p = solve_discrete_are(plant.a, plant.b_theta, q, r)
    except (np.linalg.LinAlgError, ValueError) as error:
        raise ConfigurationError("lqr", f"(A, B_theta) has no stabilising LQR: {error}") from None
    k_lqr = np.linalg.solve(r + plant.b_theta.T @ p @ plant.b_theta, plant.b_theta.T @ p @ plant.a)
    # SDMI: G's state with its input n as a random walk, observed through y.
    a_inv = np.block([[plant.a, plant.b_theta], [np.zeros((m, n)), np.eye(m)]])
    c_inv = np.hstack((plant.c, plant.d_theta))
    process_inv = np.zeros((n + m, n + m))
    process_inv[n:, n:] = weights.inversion_walk * np.eye(m)
    process_inv[:n, :n] = 1e-9 * np.eye(n)
    k_inv = _kalman_gain(a_inv, c_inv, process_inv, 1e-6 * np.eye(len(MEASURED)))
    inverse = (a_inv - k_inv @ c_inv, k_inv, np.hstack((np.zeros((m, n)), np.eye(m))), np.zeros((m, len(MEASURED))))
    radius = float(np.max(np.abs(np.linalg.eigvals(inverse[0]))))
    if radius >= 1.0:
        raise ConfigurationError("inversion", f"the SDMI inverse is not stable (spectral radius {radius:.6f})")
    ff_a, ff_b, ff_c, ff_d = _series((plant.a, plant.b_u, plant.c, plant.d_u), inverse)
    actuator = tuple(design_states(model).index(name) for name in ACTUATOR_STATES)
    return LqgDesign(plant, weights, a_aug, b_aug, c_aug, k_est, k_lqr, inverse, ff_a, ff_b, -ff_c, -ff_d, actuator)
