"""The aerodynamics of every blade element in one step of the plant, compiled.

One loop over the B x N elements does what the stepping model needs of blade-element momentum theory, from
the inflow without induction (vx, vy) to each blade's load sums:

1. the relative inflow ((1 - a) vx, (1 + a') vy) and its angle phi, with the induction carried from the
   last step;
2. lift and drag: the static polars (:mod:`hawt_plant.airfoil_table`) or the Hansen-Gaunaa-Madsen dynamic
   stall step (:func:`hawt_plant.unsteady_airfoil.hgm_step`);
3. when the step updates the induction: Prandtl's losses and Ning's induction factors with Buhl's correction
   (:func:`hawt_plant.bem.loss_factor`, :func:`hawt_plant.bem.induction`, Ning 2014 eqs. 13-23), bounded so
   that no transient runs away (a in [-1, 0.99], a' in [-1, 1]; a = 1, a' = 0 at a node at the tip or the hub),
   Pitt & Peters's skewed wake (:func:`hawt_plant.bem.skew_factor`), then either a relaxed fixed-point update
   a <- a + r (a_qs - a), repeated ``iterations`` times, or Øye's dynamic inflow filter (Hansen, Aerodynamics
   of Wind Turbines, 2008, §10.2) as AeroDyn's DBEMT_Mod = 2 runs it (``DBEMT.f90``): the axial and the
   tangential induced velocity each filtered, one time constant tau_1 for the rotor from its disk-averaged
   induction and inflow, the skewed wake's correction after the filter. (AeroDyn filters the converged steady
   BEM solution at the step's inflow, ``BEMT_UpdateStates``; the filter here takes BEM's induction at the
   filtered state, one evaluation: the converged one, measured at 8 m/s against OpenFAST, moved the blade's 1P,
   the hub tilt and the hub yaw mean by 1.0, 0.9 and 3.4 % of OpenFAST's, at twice the step's cost);
4. the element loads dF_n = q (c_l cos phi + c_d sin phi), dF_t = q (c_l sin phi - c_d cos phi),
   q = 1/2 rho W^2 c dr, and their sums per blade against the span functions (the model's 1, s and mode shapes).

Each element is independent of the others within a step, so iterating per element gives what iterating over
all elements at once would. The formulas themselves live in the modules named above, as scalar compiled
functions that their array interfaces call too: this module holds only the order of a step.
"""
from __future__ import annotations

import math

import numpy as np

from hawt_plant.airfoil_table import grid_point, interpolated
from hawt_plant.bem import induction, loss_factor, skew_factor
from hawt_plant.compiled import njit
from hawt_plant.unsteady_airfoil import hgm_settle, hgm_step

__all__ = ["MIN_INFLOW", "blade_element_loads", "disk_weights"]

MIN_INFLOW = 0.1
"""[m/s] The normal inflow used in the dynamic-inflow time constants is at least this."""


@njit
def blade_element_loads(inflow: np.ndarray, induction_factors: np.ndarray, inflow_filter: np.ndarray,
                        pitch_twist: np.ndarray, polar_table: np.ndarray, scale: float, intervals: float,
                        offsets: np.ndarray, loss_exponents: np.ndarray, local_solidity: np.ndarray,
                        bounds: np.ndarray, pressure_to_load: np.ndarray, span_functions: np.ndarray,
                        update: bool, iterations: int, relaxation: float, dynamic_inflow: bool, dt: float,
                        tip_radius: float, tip_ratio: np.ndarray, disk_weights: np.ndarray, skewed: bool,
                        skew_angle: float,
                        cos_azimuth: np.ndarray, unsteady: bool, pitch_rate: np.ndarray,
                        unsteady_states: np.ndarray, unsteady_table: np.ndarray, unsteady_constants: np.ndarray,
                        normals: np.ndarray, sums: np.ndarray) -> None:
    """One step of every blade element (module notes); updates the induction when ``update``.

    Shapes: ``inflow`` (vx, vy), ``induction_factors`` (a, a'): (2, B, N);
    ``inflow_filter`` (2, 3, B, N), axial and tangential: Øye's intermediate and induced velocity and the last
    quasi-steady one;
    ``pitch_twist``, ``local_solidity``, ``pressure_to_load`` (1/2 rho c dr), ``tip_ratio`` (r / R), ``disk_weights``
    (:func:`disk_weights`, for the dynamic inflow's tau_1): (B, N);
    ``loss_exponents`` (2, B, N); ``bounds`` (lower, upper) x (a, a') (2, 2, B, N); ``span_functions`` (N, F);
    ``cos_azimuth`` (B,), each blade's azimuth from the most downwind position of the disk (used when
    ``skewed``); ``polar_table`` and the grid constants of :class:`~hawt_plant.airfoil_table.ElementPolars`, the
    ``unsteady_*`` arguments :attr:`~hawt_plant.unsteady_airfoil.UnsteadyAirfoil.kernel_arrays` and
    ``pitch_rate`` (B,), each blade's pitch rate [rad/s], its sections turning nose-up at minus it (used when
    ``unsteady``). Without
    ``update`` the static polars give the loads (the dynamic stall states are settled at this state). The normal force
    acts along the normal that the deflected blade's out-of-plane slope turns, cos g e_n - sin g e_z (``normals`` (2,
    B, N), tan g and cos g; :func:`hawt_plant.model_step.element_inflow`), as AeroDyn applies it in its BEM frame.
    Writes ``sums`` (3, B, F): each blade's loads along e_n, e_t and e_z summed against each span function.
    """
    blades, elements = pitch_twist.shape
    sums[:] = 0.0
    passes = iterations if update and not dynamic_inflow else 1
    tau_1 = _rotor_time_constant(inflow, inflow_filter, disk_weights, tip_radius) if dynamic_inflow else 0.0
    decay_1 = math.exp(-dt / tau_1) if dynamic_inflow else 0.0  # Øye's first lag over a step, the same everywhere
    for i in range(blades):
        for j in range(elements):
            vx, vy = inflow[0, i, j], inflow[1, i, j]
            for k in range(passes):
                un = vx * (1.0 - induction_factors[0, i, j])
                ut = vy * (1.0 + induction_factors[1, i, j])
                phi = math.atan2(un, ut)
                alpha = phi - pitch_twist[i, j]
                added_mass = 0.0
                if not unsteady:
                    row, fraction = grid_point(alpha, scale, intervals, offsets[j])
                    cl, cd = interpolated(polar_table, row, fraction, 0), interpolated(polar_table, row, fraction, 1)
                elif update:  # the induction follows the circulatory lift (the added mass's sheds no vorticity)
                    cl, added_mass, cd = hgm_step(i, j, alpha, math.hypot(un, ut), -pitch_rate[i], dt,
                                                  k == passes - 1, unsteady_states, unsteady_table,
                                                  unsteady_constants, scale, intervals, offsets)
                else:
                    cl, cd = hgm_settle(i, j, alpha, unsteady_states, unsteady_table, unsteady_constants, scale,
                                        intervals, offsets)
                sin_phi, cos_phi = math.sin(phi), math.cos(phi)
                if update:
                    loss = loss_factor(sin_phi, loss_exponents[0, i, j], loss_exponents[1, i, j])
                    a, a_prime, _, _ = induction(phi, sin_phi, cos_phi, cl, loss, local_solidity[i, j])
                    a = np.minimum(np.maximum(a, bounds[0, 0, i, j]), bounds[1, 0, i, j])
                    a_prime = np.minimum(np.maximum(a_prime, bounds[0, 1, i, j]), bounds[1, 1, i, j])
                    if dynamic_inflow:
                        tau_2 = (0.39 - 0.26 * tip_ratio[i, j] * tip_ratio[i, j]) * tau_1
                        decay_2 = math.exp(-dt / tau_2)
                        a = _oye(inflow_filter[0, :, i, j], a, vx, dt, tau_1, decay_1, decay_2)
                        a_prime = _oye(inflow_filter[1, :, i, j], a_prime, vy, dt, tau_1, decay_1, decay_2)
                    if skewed:
                        a *= skew_factor(a, skew_angle, tip_ratio[i, j], cos_azimuth[i])
                    if dynamic_inflow:
                        induction_factors[0, i, j] = a
                    else:
                        induction_factors[0, i, j] += relaxation * (a - induction_factors[0, i, j])
                        a_prime = induction_factors[1, i, j] + relaxation * (a_prime - induction_factors[1, i, j])
                    induction_factors[1, i, j] = a_prime
            cl += added_mass
            q = (un * un + ut * ut) * pressure_to_load[i, j]
            normal = q * (cl * cos_phi + cd * sin_phi)
            tangential = q * (cl * sin_phi - cd * cos_phi)
            slope, cos_gamma = normals[0, i, j], normals[1, i, j]
            along_n, along_z = normal * cos_gamma, -normal * slope * cos_gamma
            for m in range(span_functions.shape[1]):
                sums[0, i, m] += along_n * span_functions[j, m]
                sums[1, i, m] += tangential * span_functions[j, m]
                sums[2, i, m] += along_z * span_functions[j, m]


def disk_weights(tip_ratio: np.ndarray) -> np.ndarray:
    """AeroDyn's weights of the rotor's average induction for DBEMT (``BEMT.f90``, IntegrateWeight): a triweight
    kernel (35/32)(1 - u^2)^3, u = (r/R - 0.7) / 0.1 clipped to [-1, 1], over each blade's elements (``tip_ratio``
    (B, N), r/R), normalised per blade and divided by the number of blades (the weights sum to 1)."""
    u = np.clip((tip_ratio / tip_ratio.max() - 0.7) / 0.1, -1.0, 1.0)
    weights = (1.0 - u * u) ** 3
    return weights / weights.sum(axis=1, keepdims=True) / tip_ratio.shape[0]


@njit
def _rotor_time_constant(inflow: np.ndarray, inflow_filter: np.ndarray, weights: np.ndarray,
                         tip_radius: float) -> float:
    """tau_1 = 1.1 R / ((1 - 1.3 a_disk) U_n), at most 100 s (AeroDyn DBEMT_Mod = 2, ``ComputeTau1``): a_disk the
    weighted quasi-steady induction (of the last step, ``inflow_filter[0, 2]``), at most 0.5, U_n the elements' mean
    normal inflow, at least 0.1 m/s."""
    axial, normal = 0.0, 0.0
    for i in range(inflow.shape[1]):
        for j in range(inflow.shape[2]):
            vx = inflow[0, i, j]
            axial += weights[i, j] * inflow_filter[0, 2, i, j] / np.maximum(vx, MIN_INFLOW)
            normal += vx
    normal = np.maximum(normal / (inflow.shape[1] * inflow.shape[2]), MIN_INFLOW)
    return np.minimum(1.1 * tip_radius / ((1.0 - 1.3 * np.minimum(axial, 0.5)) * normal), 100.0)


@njit
def _oye(states: np.ndarray, factor: float, speed: float, dt: float, tau_1: float, decay_1: float,
         decay_2: float) -> float:
    """Øye's dynamic inflow filter of one element's induced velocity, axial or tangential as AeroDyn's DBEMT
    filters both (Hansen 2008 §10.2; ``DBEMT_UpdateStates``, eqs. 1.17-1.25 of its manual): the induced velocity
    ``factor`` x ``speed`` (a vx or a' vy) follows the quasi-steady one through two first-order lags, the rotor's
    tau_1 (:func:`_rotor_time_constant`) and the element's tau_2 = (0.39 - 0.26 (r/R)^2) tau_1, the first with a
    lead 0.6 tau_1; ``decay_1`` and ``decay_2`` are exp(-dt / tau) of each (the caller's: the first is the rotor's,
    the second the same for the axial and the tangential filter). ``states`` (3,): the intermediate and the filtered
    induced velocity, and the last quasi-steady one, updated. Returns the filtered induction factor."""
    speed = np.maximum(speed, MIN_INFLOW)
    quasi_steady = factor * speed
    forcing = quasi_steady + 0.6 * tau_1 * (quasi_steady - states[2]) / dt
    intermediate = forcing + (states[0] - forcing) * decay_1
    induced = intermediate + (states[1] - intermediate) * decay_2
    states[0], states[1], states[2] = intermediate, induced, quasi_steady
    return induced / speed
