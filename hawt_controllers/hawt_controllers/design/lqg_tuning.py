"""Selvam's LQG IPC with wind-estimate feedforward designed at one operating point, with what ``hawt design lqg``
shows of it.

:func:`lqg_tuning` designs the law (hawt_controllers.laws.lqg_design) on a Coleman-frame linear model as the
``lqg_ipc`` controller does at start, and returns its checks (observability of the model augmented with the wind
states, controllability of the turbine states, stability of the SDMI inverse) and the closed-loop response from the
cos/sin blade-effective wind to the cos/sin root moments at a low frequency and the 1P, 2P and 3P of the model's
rotor speed, for no IPC, the integrator IPC (``ipc_h1``'s packaged tuning: :func:`integrator_gains`) and FB-FF
(Selvam et al. 2009, Figs 6-7).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Dict, Tuple

import numpy as np
import yaml

from hawt_controllers.design.ipc_design import DEFAULT_FILE
from hawt_controllers.laws.coleman_models import ColemanModel
from hawt_controllers.laws.lqg_design import LqgDesign, LqgWeights, controllability_rank, design_lqg, observability_rank
from hawt_controllers.laws.lqg_ipc import closed_loop_response

__all__ = ["CONTROLLERS", "LqgTuning", "integrator_gains", "lqg_tuning"]

CONTROLLERS = ("none", "integrator", "lqg")
"""The loops :func:`lqg_tuning` closes (hawt_controllers.laws.lqg_ipc.closed_loop_response): no IPC, the
integrator IPC and FB-FF."""


@dataclass(frozen=True)
class LqgTuning:
    """The law designed at one operating point, its checks and its closed-loop responses."""

    design: LqgDesign
    weights: LqgWeights
    observability_rank: int
    """Of the model augmented with the wind states (full: ``design.states + 2``)."""
    controllability_rank: int
    """Of the turbine states (full: ``design.states``)."""
    inverse_radius: float
    """The spectral radius of the SDMI inverse's state matrix (stable below 1)."""
    integrator_gains: Tuple[float, float]
    """The integrator IPC's integral gain and phase offset [rad] the comparison closes."""
    frequencies: Dict[str, float]
    """Name -> frequency [rad/s]: "0.01 rad/s", "1P", "2P", "3P" (of the model's rotor speed)."""
    responses: Dict[str, np.ndarray]
    """Each of :data:`CONTROLLERS` -> |closed loop| from (u_cos, u_sin) to (M_cos, M_sin) [MN m per m/s] at
    ``frequencies``, shape (len(frequencies), 2, 2)."""


def integrator_gains(path: Path = DEFAULT_FILE) -> Tuple[float, float]:
    """``ipc_h1``'s integral gain and phase offset in a parameter file of the ipc graph (default: the packaged
    NREL 5 MW tuning)."""
    ipc_h1 = yaml.safe_load(Path(path).read_text())["/**/ipc_h1"]["ros__parameters"]
    return ipc_h1["integral_gain"], ipc_h1["phase_offset"]


def lqg_tuning(model: ColemanModel, dt: float, weights: LqgWeights = LqgWeights()) -> LqgTuning:
    """The FB-FF law designed on ``model`` at the controller step ``dt`` [s] with ``weights``, checked, and closed
    (see the module notes).

    Raises
    ------
    ConfigurationError
        From :func:`hawt_controllers.laws.lqg_design.design_lqg`, naming what fails.
    """
    design = design_lqg(model.model, dt, weights)
    gains = integrator_gains()
    one_p = model.rotor_speed
    frequencies = {"0.01 rad/s": 0.01, "1P": one_p, "2P": 2 * one_p, "3P": 3 * one_p}
    return LqgTuning(
        design=design, weights=weights,
        observability_rank=observability_rank(design.a_est, design.c_est),
        controllability_rank=controllability_rank(design.plant.a, design.plant.b_theta),
        inverse_radius=float(np.max(np.abs(np.linalg.eigvals(design.inverse[0])))),
        integrator_gains=gains, frequencies=frequencies,
        responses={kind: np.abs(closed_loop_response(design, list(frequencies.values()), kind, *gains))
                   for kind in CONTROLLERS})
