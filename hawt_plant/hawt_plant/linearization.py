"""Numerical linearisation of the plant about its periodic steady state (OpenFAST's linearisation, for this model).

In steady sheared wind with the commands held (the collective and torque loops open), the plant
settles on a periodic orbit: every state repeats once per revolution. At N azimuths of that orbit
the continuous-time dynamics of :meth:`hawt_plant.model.TurbineModel.continuous_dynamics`
(quasi-steady BEM, actuator limits off) are differentiated by central differences::

    dx/dt = A(psi) dx + B(psi) du,    dy = C(psi) dx + D(psi) du

with the states of ``state_names`` (azimuth excluded), the inputs pitch command of every blade,
generator torque and a change of the longitudinal wind along every blade, and the outputs of
:data:`OUTPUTS`. The result is periodic in psi; Bir's multi-blade coordinate transformation and the
azimuth average (hawt_controllers.laws.mbc3) make it an LTI model in the Coleman frame.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Mapping, Optional, Sequence, Tuple

import numpy as np

from hawt_plant.model import TurbineModel, TurbineOutput

__all__ = ["OUTPUTS", "PeriodicLinearization", "input_names", "linearize_model", "output_names", "periodic_orbit"]

OUTPUTS = ("root_moment_oop", "root_moment_ip", "rotor_speed", "generator_speed", "tower_top_fa_disp",
           "tower_top_ss_disp", "tower_top_fa_accel", "tower_top_ss_accel", "hub_tilt_moment", "hub_yaw_moment",
           "tower_base_fa_moment", "tower_base_ss_moment", "rotor_thrust", "aero_torque")
"""TurbineOutput fields of a linear model's outputs; the per-blade ones give one output per blade."""

_BLADE_OUTPUTS = ("root_moment_oop", "root_moment_ip")

_STATE_STEPS = {"rotor_speed": 1e-3, "generator_speed": 1e-3, "shaft_torsion": 1e-6, "tower": 1e-3,
                "flap": 1e-3, "edge": 1e-3, "pitch": 1e-4}
"""Central-difference half steps per kind of state (rates: the same as their state, per second)."""
_INPUT_STEPS = {"pitch_command": 1e-4, "generator_torque": 10.0, "wind": 1e-2}


def output_names(blades: int) -> Tuple[str, ...]:
    """The outputs of a linear model: per-blade fields as ``<field>_<i>``, i from 1."""
    return tuple(name for field in OUTPUTS for name in
                 ([f"{field}_{i}" for i in range(1, blades + 1)] if field in _BLADE_OUTPUTS else [field]))


def input_names(blades: int) -> Tuple[str, ...]:
    """The inputs of a linear model: pitch command of every blade [rad], generator torque [N m, high-speed
    shaft] and a change of the longitudinal wind along every blade [m/s] (blade-effective wind)."""
    blade = range(1, blades + 1)
    return (*(f"pitch_command_{i}" for i in blade), "generator_torque", *(f"wind_{i}" for i in blade))


def _output_vector(output: TurbineOutput) -> np.ndarray:
    return np.concatenate([np.atleast_1d(np.asarray(getattr(output, field), dtype=float)) for field in OUTPUTS])


def _step_of(name: str, steps: Mapping[str, float]) -> float:
    kind = name.replace("_rate", "").rstrip("0123456789").rstrip("_")
    for prefix, step in steps.items():
        if kind.startswith(prefix):
            return step
    raise KeyError(name)


@dataclass(frozen=True)
class PeriodicLinearization:
    """The plant's linear models at the azimuths of one revolution of its periodic orbit.

    ``a`` (N, n, n), ``b`` (N, n, m), ``c`` (N, p, n), ``d`` (N, p, m) at ``azimuths`` (N,) [rad] of
    blade 1; ``states``, ``inputs``, ``outputs`` name the rows and columns; ``rotor_speed`` [rad/s] is the
    orbit's mean, ``pitch`` [rad] and ``generator_torque`` [N m] the held commands, ``loops`` says so.
    """

    wind_speed: float
    azimuths: np.ndarray
    a: np.ndarray
    b: np.ndarray
    c: np.ndarray
    d: np.ndarray
    states: Tuple[str, ...]
    inputs: Tuple[str, ...]
    outputs: Tuple[str, ...]
    rotor_speed: float
    pitch: float
    generator_torque: float
    loops: str = "open: pitch and generator torque held"


def periodic_orbit(model: TurbineModel, azimuths: Sequence[float], settle_time: float,
                   pitch: np.ndarray, generator_torque: float) -> Tuple[np.ndarray, np.ndarray, float]:
    """States of the open-loop periodic orbit at (about) ``azimuths``, with the commands held.

    Steps ``model`` for ``settle_time`` [s], then through one revolution, taking the state at the
    first step at or past each azimuth. Returns the azimuths reached (N,), the states (N, n) and the
    mean rotor speed over the revolution [rad/s].
    """
    dt = model.config.dt
    for _ in range(round(settle_time / dt)):
        model.step(pitch, generator_torque)
    start = model.output.azimuth
    targets = sorted(float(a) % (2.0 * math.pi) for a in azimuths)
    reached, states, speeds = [], [], []
    travelled = 0.0
    previous = start
    while len(reached) < len(targets):
        output = model.step(pitch, generator_torque)
        travelled += (output.azimuth - previous) % (2.0 * math.pi)
        previous = output.azimuth
        speeds.append(output.rotor_speed)
        angle = (start + travelled) % (2.0 * math.pi)
        while len(reached) < len(targets) and _passed(start, travelled, targets[len(reached)]):
            reached.append(angle)
            states.append(model.state())
        if travelled > 4.0 * math.pi:
            raise RuntimeError(f"periodic_orbit: the rotor did not turn once in {len(speeds) * dt:g} s")
    return np.array(reached), np.array(states), float(np.mean(speeds))


def _passed(start: float, travelled: float, target: float) -> bool:
    """True once the azimuth, from ``start`` after ``travelled`` rad, has reached ``target``."""
    return (target - start) % (2.0 * math.pi) <= travelled


def linearize_model(model: TurbineModel, azimuth_count: int = 36, settle_time: float = 60.0,
                    progress: Optional[Callable[[int, int], None]] = None) -> PeriodicLinearization:
    """Linearise ``model`` (from its operating point, in its wind) at ``azimuth_count`` azimuths of its orbit.

    The commands are held at the operating point's (the model's output now, just after a reset); the
    model is stepped along the orbit and left at a linearisation point. ``progress(k, N)`` is called
    after each azimuth.
    """
    if azimuth_count < 1:
        raise ValueError(f"azimuth_count: expected >= 1, found {azimuth_count}")
    first = model.output
    pitch, torque = np.array(first.pitch, dtype=float), float(first.generator_torque)
    orbit = model
    azimuths, states, rotor_speed = periodic_orbit(
        orbit, 2.0 * math.pi * np.arange(azimuth_count) / azimuth_count, settle_time, pitch, torque)
    blades = model.number_of_blades
    names, inputs, outputs = orbit.state_names(), input_names(blades), output_names(blades)
    u0 = np.concatenate((pitch, (torque,), np.zeros(blades)))
    state_steps = np.array([_step_of(name, _STATE_STEPS) for name in names])
    input_steps = np.array([_step_of(name, _INPUT_STEPS) for name in inputs])
    n, m, p = len(names), len(inputs), len(outputs)
    a, b = np.empty((azimuth_count, n, n)), np.empty((azimuth_count, n, m))
    c, d = np.empty((azimuth_count, p, n)), np.empty((azimuth_count, p, m))

    def evaluate(x: np.ndarray, azimuth: float, u: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        derivative, output = orbit.continuous_dynamics(x, azimuth, u[:blades], u[blades], u[blades + 1:])
        return derivative, _output_vector(output)

    for k, (azimuth, x0) in enumerate(zip(azimuths, states)):
        for j, h in enumerate(state_steps):
            dx = np.zeros(n)
            dx[j] = h
            (f_plus, y_plus), (f_minus, y_minus) = evaluate(x0 + dx, azimuth, u0), evaluate(x0 - dx, azimuth, u0)
            a[k, :, j], c[k, :, j] = (f_plus - f_minus) / (2 * h), (y_plus - y_minus) / (2 * h)
        for j, h in enumerate(input_steps):
            du = np.zeros(m)
            du[j] = h
            (f_plus, y_plus), (f_minus, y_minus) = evaluate(x0, azimuth, u0 + du), evaluate(x0, azimuth, u0 - du)
            b[k, :, j], d[k, :, j] = (f_plus - f_minus) / (2 * h), (y_plus - y_minus) / (2 * h)
        if progress is not None:
            progress(k + 1, azimuth_count)
    return PeriodicLinearization(model.operating_point.wind_speed, azimuths, a, b, c, d, names, inputs, outputs,
                                 rotor_speed, float(np.mean(pitch)), torque)
