"""LQG individual pitch control with wind-estimate feedforward, per step, and its closed loop (Selvam et al. 2009).

:class:`LqgIpc` runs the designs (:class:`hawt_controllers.laws.lqg_design.LqgDesign`) of one or more operating
points one step at a time (Selvam §3, Fig. 4): the Kalman filter predicts the turbine state x̂ and the cos/sin
blade-effective wind û from the 1P cos/sin blade-root moments, the LQR feeds back -K x̂, and the feedforward adds
-G_inv(H û).
:func:`closed_loop_response` gives the frequency responses Selvam compares (§4, Figs 6-7): from the
cos/sin wind to the cos/sin moments, with no IPC, with the conventional integrator IPC and with FB-FF, and
to the law's cos/sin pitch (the pitch activity of the notes' check 20); :func:`rotor_speed_response` the
wind's effect on the rotor speed with the law closed on the whole Coleman model (check 21).
"""
from __future__ import annotations

import math
from typing import Optional, Sequence, Tuple

import numpy as np
from numpy.typing import ArrayLike

from hawt_controllers.laws.lqg_design import (_MOMENT_UNIT, _PITCH_UNIT, CONTROLLED, DISTURBANCES, MEASURED, DiscreteModel, LqgDesign,
                         discrete_channels)
from hawt_controllers.laws.coleman_models import state_space_response
from hawt_controllers.laws.mbc3 import LinearModel

__all__ = ["LqgIpc", "closed_loop_response", "frequency_response_figure", "integrator_ipc", "rotor_speed_response"]


class LqgIpc:
    """The FB-FF laws of one or more designs, stepped together at their dt: one per operating point of a gain
    schedule, every estimator running, so that a change of schedule needs no restart (the designs must have the
    same dimensions). Estimates start at zero: the operating point. Per step, as arrays over the laws: one batched
    product per matrix of the design, whatever their number."""

    def __init__(self, designs: Sequence[LqgDesign]) -> None:
        self.designs = designs
        first = self.designs[0]
        self.estimate = np.zeros((len(self.designs), first.a_est.shape[0]))
        self.feedforward = np.zeros((len(self.designs), first.ff_a.shape[0]))
        self._measured = np.zeros(2)
        self._pitch: Optional[np.ndarray] = None

    @property
    def designs(self) -> Tuple[LqgDesign, ...]:
        """The laws' designs; set new ones (the same dimensions) at a step boundary, the estimates kept."""
        return self._designs

    @designs.setter
    def designs(self, designs: Sequence[LqgDesign]) -> None:
        designs = tuple(designs)
        if not designs:
            raise ValueError("designs: expected at least one LQG design")
        first = designs[0]
        names = ("a_est", "b_est", "c_est", "k_est", "k_lqr", "ff_a", "ff_b", "ff_c", "ff_d")
        for k, design in enumerate(designs):
            shapes = [getattr(design, name).shape for name in names]
            if shapes != [getattr(first, name).shape for name in names] or design.actuator != first.actuator:
                raise ValueError(f"designs: design {k} has other dimensions than design 0 ({dict(zip(names, shapes))})")
        (self._a_est, self._b_est, self._c_est, self._k_est, self._k_lqr, self._ff_a, self._ff_b, self._ff_c,
         self._ff_d) = (np.stack([getattr(design, name) for design in designs]) for name in names)
        self._designs = designs

    @property
    def wind(self) -> np.ndarray:
        """The estimated cos/sin blade-effective wind [m/s] (Selvam's û_23^cm) of each law, shape (laws, 2)."""
        return self.estimate[:, self._designs[0].states:].copy()

    def track_actuator(self, pitch_cos: float, pitch_sin: float) -> None:
        """Set the estimated actuator states to this step's measured 1P cos/sin blade pitch [rad] and their rates
        to its change since the last call: the estimator runs on the pitch the blades have, whatever limited the
        command on its way (Selvam §3: the filter is fed the applied pitch, not the demanded; the observer form
        of anti-windup). Call before :meth:`demand`."""
        design = self._designs[0]
        pitch = np.array((pitch_cos, pitch_sin))
        angle, rate = list(design.actuator[:2]), list(design.actuator[2:])
        self.estimate[:, angle] = pitch
        if self._pitch is not None:
            self.estimate[:, rate] = (pitch - self._pitch) / design.plant.dt
        self._pitch = pitch

    def demand(self, moment_cos: float, moment_sin: float) -> np.ndarray:
        """Each law's cos/sin 1P pitch demand [rad], shape (laws, 2), for this step's cos/sin root moments [N m];
        then :meth:`advance` with what was applied."""
        states = self._designs[0].states
        self._measured = np.array((moment_cos, moment_sin)) / _MOMENT_UNIT
        x_hat, u_hat = self.estimate[:, :states], self.estimate[:, states:]
        theta = -_each(self._k_lqr, x_hat) + _each(self._ff_c, self.feedforward) + _each(self._ff_d, u_hat)
        self.feedforward = _each(self._ff_a, self.feedforward) + _each(self._ff_b, u_hat)
        return theta * _PITCH_UNIT

    def advance(self, applied: ArrayLike) -> None:
        """The estimators' update with the measurement of :meth:`demand` and the cos/sin pitch ``applied`` [rad]
        this step, one pair for every law or one per law (Selvam: the applied, not the demanded)."""
        theta = np.broadcast_to(np.asarray(applied, dtype=float) / _PITCH_UNIT, self.estimate.shape[:1] + (2,))
        estimate = self.estimate
        self.estimate = (_each(self._a_est, estimate) + _each(self._b_est, theta)
                         + _each(self._k_est, self._measured - _each(self._c_est, estimate)))

    def step(self, moment_cos: float, moment_sin: float) -> np.ndarray:
        """:meth:`demand`, then :meth:`advance` with it: each law alone in its loop."""
        theta = self.demand(moment_cos, moment_sin)
        self.advance(theta)
        return theta


def _each(matrices: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """Each law's matrix times its vector: (laws, m, n) by (laws, n) to (laws, m)."""
    return np.matmul(matrices, vectors[:, :, None])[:, :, 0]


def integrator_ipc(integral_gain: float, phase_offset: float, dt: float) -> Tuple[np.ndarray, ...]:
    """The conventional IPC as a discrete system from (M_cos, M_sin) [MN m] to (θ_cos, θ_sin) [deg]: two
    integrators θ = k_i ∫ M (forward Euler, ``integral_gain`` [rad/(N m s)]: a positive moment pitches to
    feather, as hawt_controllers.laws.ipc) through the inverse transform's phase offset φ (θ_i = θ_c cos(ψ_i + φ)
    + θ_s sin(ψ_i + φ)); the law's low-pass and notch are left out."""
    c, s = math.cos(phase_offset), math.sin(phase_offset)
    rotation = np.array([[c, s], [-s, c]])
    gain = integral_gain * _MOMENT_UNIT / _PITCH_UNIT * dt
    return np.eye(2), gain * np.eye(2), rotation, np.zeros((2, 2))


def _feedback(plant: DiscreteModel, controller: Tuple[np.ndarray, ...],
              output: Tuple[np.ndarray, ...]) -> Tuple[np.ndarray, ...]:
    """The plant's wind -> ``output`` in closed loop with ``controller`` (a, b, c, d) from y to θ: states [x; ξ]
    (plant, controller); ``output`` (c_z, d_zθ, d_zu) is z = c_z x + d_zθ θ + d_zu u."""
    p = plant
    ak, bk, ck, dk = controller
    if np.any(dk) and np.any(p.d_theta):
        raise ValueError("an algebraic loop: both the plant and the controller have feedthrough")
    n, q = p.a.shape[0], ak.shape[0]
    theta_state, theta_wind = np.hstack((dk @ p.c, ck)), dk @ p.d_u  # θ = theta_state [x; ξ] + theta_wind u
    into = np.vstack((p.b_theta, bk @ p.d_theta))  # where θ enters [x; ξ]
    a = np.block([[p.a, np.zeros((n, q))], [bk @ p.c, ak]]) + into @ theta_state
    b = np.vstack((p.b_u, bk @ p.d_u)) + into @ theta_wind
    c_z, d_ztheta, d_zu = output
    return (a, b, np.hstack((c_z, np.zeros((c_z.shape[0], q)))) + d_ztheta @ theta_state,
            d_zu + d_ztheta @ theta_wind)


def _lqg_controller(design: LqgDesign) -> Tuple[np.ndarray, ...]:
    """FB-FF as one discrete system from y to θ: states [z; ξ] (estimate, feedforward)."""
    d = design
    n_z, n_f = d.a_est.shape[0], d.ff_a.shape[0]
    theta_z = np.hstack((-d.k_lqr, d.ff_d))  # θ from z = [x̂; û]
    select_u = np.hstack((np.zeros((d.ff_b.shape[1], d.states)), np.eye(n_z - d.states)))
    a = np.block([[d.a_est - d.k_est @ d.c_est + d.b_est @ theta_z, d.b_est @ d.ff_c],
                  [d.ff_b @ select_u, d.ff_a]])
    b = np.vstack((d.k_est, np.zeros((n_f, d.k_est.shape[1]))))
    c = np.hstack((theta_z, d.ff_c))
    return a, b, c, np.zeros((c.shape[0], b.shape[1]))


def _controller(design: LqgDesign, controller: str, integral_gain: float,
                phase_offset: float) -> Tuple[np.ndarray, ...]:
    """The law ``controller`` as a discrete system (a, b, c, d) from (M_cos, M_sin) [MN m] to (θ_cos, θ_sin) [deg]:
    "none" (no IPC: zero), "integrator" (:func:`integrator_ipc`) or "lqg" (the design's FB-FF)."""
    if controller == "none":
        return np.zeros((0, 0)), np.zeros((0, len(MEASURED))), np.zeros((len(CONTROLLED), 0)), \
            np.zeros((len(CONTROLLED), len(MEASURED)))
    if controller == "integrator":
        return integrator_ipc(integral_gain, phase_offset, design.plant.dt)
    if controller == "lqg":
        return _lqg_controller(design)
    raise ValueError(f"controller: expected none, integrator or lqg, found {controller!r}")


def _response(system: Tuple[np.ndarray, ...], omega: ArrayLike, dt: float) -> np.ndarray:
    """The discrete system's (a, b, c, d) frequency response at ``omega`` [rad/s], shape (len(omega), outputs,
    inputs); ValueError for an unstable system (it has none)."""
    radius = float(np.max(np.abs(np.linalg.eigvals(system[0])), initial=0.0))
    if radius >= 1.0:
        raise ValueError(f"the closed loop is unstable (spectral radius {radius:.6f}): it has no frequency response")
    return state_space_response(system, np.exp(1j * np.atleast_1d(omega) * dt))


def closed_loop_response(design: LqgDesign, omega: ArrayLike, controller: str = "lqg",
                         integral_gain: float = 0.0, phase_offset: float = 0.0, output: str = "moments") -> np.ndarray:
    """Frequency response from (u_cos, u_sin) to ``output`` at ``omega`` [rad/s], shape (len(omega), 2, 2), on the
    design's plant closed with ``controller`` "none", "integrator" (:func:`integrator_ipc`) or "lqg".

    ``output`` "moments": (M_cos, M_sin) [MN m per m/s], Selvam's Figs 6-7; "pitch": the law's (θ_cos, θ_sin)
    [deg per m/s], the pitch activity of his check 20 (zero with no IPC).
    """
    p = design.plant
    outputs = {"moments": (p.c, p.d_theta, p.d_u),
               "pitch": (np.zeros((len(CONTROLLED), p.a.shape[0])), np.eye(len(CONTROLLED)),
                         np.zeros((len(CONTROLLED), p.b_u.shape[1])))}
    if output not in outputs:
        raise ValueError(f"output: expected moments or pitch, found {output!r}")
    law = _controller(design, controller, integral_gain, phase_offset)
    return _response(_feedback(p, law, outputs[output]), omega, p.dt)


def _whole_plant(model: LinearModel, dt: float) -> Tuple[DiscreteModel, Tuple[np.ndarray, ...]]:
    """Every state of ``model`` at ``dt`` [s] (zero-order hold) in lqg_design's units, with the design's measured
    and controlled channels and the collective and cos/sin wind as the disturbance; and its rotor speed [rad/s]
    as an output (c_z, d_zθ, d_zu)."""
    whole = discrete_channels(model, dt, model.states, ("wind_collective",) + DISTURBANCES,
                              MEASURED + ("rotor_speed",))
    k = len(MEASURED)
    return (DiscreteModel(whole.a, whole.b_theta, whole.b_u, whole.c[:k], whole.d_theta[:k], whole.d_u[:k], dt),
            (whole.c[k:], whole.d_theta[k:], whole.d_u[k:]))


def rotor_speed_response(model: LinearModel, design: LqgDesign, omega: ArrayLike, controller: str = "lqg",
                         integral_gain: float = 0.0, phase_offset: float = 0.0) -> np.ndarray:
    """Frequency response [rad/s per m/s] from (u_collective, u_cos, u_sin) to the rotor speed at ``omega``
    [rad/s], shape (len(omega), 1, 3): the whole Coleman model ``model`` (every state, not only
    :func:`hawt_controllers.laws.lqg_design.design_states`) at the design's dt, with ``controller`` (as in
    :func:`closed_loop_response`) closed on its cos/sin channels (Selvam's check 21: IPC must not change the
    speed's response). The collective pitch and the generator torque are held, as in the design model."""
    plant, speed = _whole_plant(model, design.plant.dt)
    return _response(_feedback(plant, _controller(design, controller, integral_gain, phase_offset), speed), omega,
                     plant.dt)


def frequency_response_figure(design: LqgDesign, path, rotor_speed: float, integral_gain: float,
                              phase_offset: float) -> None:
    """Selvam's Figs 6-7 in shape: |u_cos, u_sin -> M_cos, M_sin| for no IPC, the integrator IPC and FB-FF, the
    four channels, with the rotor harmonics 1P and 3P marked."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    omega = np.logspace(-2, math.log10(math.pi / design.plant.dt), 400)
    responses = {"no IPC": closed_loop_response(design, omega, "none"),
                 "integrator IPC": closed_loop_response(design, omega, "integrator", integral_gain, phase_offset),
                 "FB-FF (LQG)": closed_loop_response(design, omega, "lqg")}
    figure, axes = plt.subplots(2, 2, figsize=(9, 6), sharex=True, sharey=True)
    for (row, col), axis in np.ndenumerate(axes):
        for (label, response), style in zip(responses.items(), ("-", "-.", "--")):
            axis.loglog(omega / (2 * math.pi), np.abs(response[:, row, col]), style, label=label)
        for n in (1, 3):
            axis.axvline(n * rotor_speed / (2 * math.pi), color="grey", lw=0.6)
            axis.annotate(f"{n}P", (n * rotor_speed / (2 * math.pi), 1.0), fontsize=7,
                          xycoords=("data", "axes fraction"), va="top")
        axis.set_title(f"u_{('cos', 'sin')[col]} -> M_{('cos', 'sin')[row]}", fontsize=9)
        axis.grid(alpha=0.3, which="both")
    for axis in axes[1]:
        axis.set_xlabel("frequency [Hz]")
    for axis in axes[:, 0]:
        axis.set_ylabel("[MN m per m/s]")
    axes[0, 0].legend(fontsize=8)
    figure.suptitle("Closed loop from the cos/sin blade-effective wind to the cos/sin root moments (Coleman frame)",
                    fontsize=10)
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)
