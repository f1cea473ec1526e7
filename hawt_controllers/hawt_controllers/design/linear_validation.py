"""A linear model against the nonlinear plant: small pitch and wind steps, and the error between them.

Two nonlinear runs from the same operating point with the commands held (the loops open, as the
model was linearised): one undisturbed, one with a small step at ``step_time`` — of the collective
pitch command, of the 1P cyclic pitch (tilt or yaw), or of the wind (the plant's ``step`` wind).
Their difference at the same rotor azimuth is the nonlinear step response: the periodic loads of
both runs cancel (at the same time they would not, once the stepped rotor has turned a few degrees
more or less), what is left is what the linear model should predict. The model's response to the
same step (scipy.signal.lsim from rest) is compared on the outputs the step excites; the error of
an output is the largest difference over the response, relative to the largest linear response.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Dict, Mapping, Optional

import numpy as np
from scipy.signal import lsim

from hawt_controllers.laws.coleman_models import ColemanModel

from hawt_controllers.design.linear_models import linearized_plant
from hawt_core.rotor.mbc import blade_azimuths, mbc_forward_sample

__all__ = ["CHANNELS", "StepComparison", "compare_steps"]

CHANNELS = {
    "pitch": ("pitch_command_collective", ("rotor_speed", "root_moment_oop_collective", "tower_top_fa_disp",
                                           "rotor_thrust", "aero_torque")),
    "wind": ("wind_collective", ("rotor_speed", "root_moment_oop_collective", "tower_top_fa_disp",
                                 "rotor_thrust", "aero_torque")),
    "tilt": ("pitch_command_cos", ("root_moment_oop_cos", "root_moment_oop_sin", "hub_tilt_moment",
                                   "hub_yaw_moment")),
    "yaw": ("pitch_command_sin", ("root_moment_oop_cos", "root_moment_oop_sin", "hub_tilt_moment",
                                  "hub_yaw_moment")),
}
"""Per kind of step: the model's input it enters, and the outputs compared (those it excites most)."""

_RECORDED = ("rotor_speed", "root_moment_oop_collective", "root_moment_oop_cos", "root_moment_oop_sin",
             "tower_top_fa_disp", "rotor_thrust", "aero_torque", "hub_tilt_moment", "hub_yaw_moment")


@dataclass(frozen=True)
class StepComparison:
    """Responses [SI units] after the step, sampled at the plant's steps ``time`` [s from the step]."""

    kind: str
    size: float
    time: np.ndarray
    nonlinear: Dict[str, np.ndarray]
    linear: Dict[str, np.ndarray]

    def error(self, output: str, after: float = 0.0) -> float:
        """max |nonlinear - linear| from ``after`` [s] on, relative to max |linear| over the whole response.

        A wind step needs ``after`` of about 0.5 s: the plant's step crosses the coned rotor over a few
        tenths of a second and its induction follows over as many steps, where the quasi-steady model
        jumps at once.
        """
        scale = float(np.max(np.abs(self.linear[output])))
        late = self.time >= after - 1e-9
        return float(np.max(np.abs(self.nonlinear[output][late] - self.linear[output][late]))) / scale


def _row(output: Any) -> list:
    moments = mbc_forward_sample(output.root_moment_oop.tolist(), output.azimuth, 1)
    values = {"root_moment_oop_collective": moments.mean, "root_moment_oop_cos": moments.cos,
              "root_moment_oop_sin": moments.sin}
    return [output.azimuth] + [values[name] if name in values else float(getattr(output, name))
                               for name in _RECORDED]


def _unchanged(azimuth: float) -> float:
    return 0.0


def _nonlinear_run(values: Mapping[str, Any], steps: int, step_index: int,
                   change: Callable[[float], np.ndarray]) -> np.ndarray:
    """Rows [unwrapped azimuth, _RECORDED...] of the plant with the commands held, ``change(azimuth)`` added
    to the pitch commands from ``step_index`` on."""
    from hawt_plant.plant_setup import make_plant

    _, model, output = make_plant(values)
    pitch, torque = np.array(output.pitch, dtype=float), float(output.generator_torque)
    rows = []
    for k in range(steps):
        output = model.step(pitch + change(output.azimuth) if k >= step_index else pitch, torque)
        rows.append(_row(output))
    rows = np.array(rows)
    rows[:, 0] = np.unwrap(rows[:, 0])
    return rows


def compare_steps(model: ColemanModel, sizes: Mapping[str, float], step_time: float = 10.0, duration: float = 30.0,
                  plant: Optional[Mapping[str, Any]] = None) -> Dict[str, StepComparison]:
    """``model`` against the plant it is of (parameters ``plant`` over the node's defaults and quasi-steady
    aerodynamics, as linearised: hawt_controllers.design.linear_models.linearized_plant) for a step of each kind of
    ``sizes`` (kind: size) at ``step_time`` [s], over ``duration`` [s] after it: kind "pitch" (every blade's command
    [rad]), "tilt" or "yaw" (the cos or sin 1P cyclic pitch [rad], theta_i += size cos/sin psi_i at each step), or
    "wind" [m/s]. One undisturbed run serves every kind."""
    from hawt_plant.plant_setup import make_plant

    unknown = [kind for kind in sizes if kind not in CHANNELS]
    if unknown:
        raise ValueError(f"kind: expected one of {', '.join(CHANNELS)}, found {unknown[0]!r}")
    base = linearized_plant(model.wind_speed, plant)
    turbine, plant_model, _ = make_plant(base)
    blades = plant_model.number_of_blades
    dt = base["dt"]
    step_index, steps = round(step_time / dt), round((step_time + duration) / dt)
    undisturbed = _nonlinear_run(base, round(1.2 * steps), step_index, _unchanged)  # ahead of a faster rotor
    after = slice(step_index - 1, steps)
    time = np.arange(steps - step_index + 1) * dt
    columns = {name: i + 1 for i, name in enumerate(_RECORDED)}
    comparisons = {}
    for kind, size in sizes.items():
        if kind == "wind":
            # The plant's step wind is convected downwind: it reaches the rotor apex, overhang * cos(tilt) upwind of
            # the tower, that much earlier than x = 0.
            rotor = turbine.rotor
            arrival = rotor.overhang * math.cos(rotor.shaft_tilt) / model.wind_speed
            stepped = _nonlinear_run({**base, "wind_type": "step", "step_speed": model.wind_speed + size,
                                      "step_time": step_time + arrival}, steps, step_index, _unchanged)
        else:
            trig = {"pitch": lambda angles: np.ones_like(angles), "tilt": np.cos, "yaw": np.sin}[kind]
            stepped = _nonlinear_run(base, steps, step_index,
                                     lambda azimuth: size * trig(blade_azimuths(azimuth, blades)))
        model_input, outputs = CHANNELS[kind]
        inputs = np.zeros((time.size, len(model.model.inputs)))
        inputs[:, model.model.inputs.index(model_input)] = size
        _, response, _ = lsim(model.model.state_space(), inputs, time)
        azimuth = stepped[after, 0]
        nonlinear = {name: stepped[after, columns[name]]
                     - np.interp(azimuth, undisturbed[:, 0], undisturbed[:, columns[name]]) for name in outputs}
        linear = {name: response[:, model.model.outputs.index(name)] for name in outputs}
        comparisons[kind] = StepComparison(kind, size, time, nonlinear, linear)
    return comparisons
