"""The ``lqg_ipc`` controller: LQG 1P IPC with wind-estimate feedforward (Selvam et al. 2009) as a plug-in.

Claims ``harmonic/1``. At configure it designs one FB-FF law (hawt_controllers.laws.lqg_design) per wind
speed of a file of the plant's Coleman-frame linear models (``linear_models``, written by
``hawt linearize``; default the NREL 5 MW's, ``data/linear_nrel5mw.npz``). Each step it transforms
the blade-root out-of-plane moments to their 1P cos/sin (hawt_core.rotor.mbc), steps every law on
them (the estimators of all operating points run, so a change of schedule needs no restart) and
contributes the demand of the law whose operating pitch is nearest the measured mean pitch (gain
scheduling over the linear models), with phase offset 0: the models' cyclic pitch is the one of the
plain inverse transform. The random-walk wind states take up the orbit's constant 1P moment (shear),
as an integrator would. Its estimators are told its own output after the ramp (what it contributes) and
their actuator states follow the measured 1P cos/sin blade pitch: the pitch applied after the loop
assembler's rate and angle limits, as Selvam's filter must be fed (not the demanded).

Replacing another controller on ``harmonic/1`` (e.g. the integrator IPC), it blends from that one's last
output to its own over ``ramp_time`` (bumpless); the weights can be set live: the new designs are made
and checked for every operating point when the value is set (a failing design is refused with its
reason) and take over at the next step, the estimates kept. Every step it publishes its wind estimate û
and the estimated states on ``control/<name>/wind_estimate`` (hawt_msgs/WindEstimate), beside the plant's
true blade-effective wind on ``plant/state``.
"""
from __future__ import annotations

from pathlib import Path
from typing import Any, List, Mapping, Optional, Sequence, Tuple

import numpy as np

from hawt_core.command_interfaces import harmonic_interface
from hawt_core.parameter_table import ParameterError, ParameterSpec, resolve_values
from hawt_core.plant_description import PlantDescription
from hawt_core.topics import WIND_ESTIMATE

from hawt_controllers.plugins.controller import (Contribution, Controller, HarmonicContribution, MeasuredFactor,
                                                 OutputRamp)
from hawt_core.exceptions import ConfigurationError
from hawt_controllers.laws.coleman_models import load_models
from hawt_controllers.laws.lqg_design import LqgDesign, LqgWeights, design_lqg
from hawt_controllers.laws.lqg_ipc import LqgIpc
from hawt_core.rotor.mbc import mbc_forward_sample
from hawt_controllers.packaged import PACKAGED

__all__ = ["LqgIpcController", "DEFAULT_MODELS"]

DEFAULT_MODELS = PACKAGED["nrel_5mw"]["linear"]
_DEFAULT = LqgWeights()


class LqgIpcController(Controller):
    """Selvam's FB-FF IPC on harmonic 1 (see the module notes)."""

    TYPE = "lqg_ipc"
    ESTIMATE = (WIND_ESTIMATE, "WindEstimate")
    WITHOUT_INPUT = "output fading out over its ramp time"
    PARAMETERS = (
        ParameterSpec("linear_models", "", "the plant's linear models (.npz of hawt linearize; empty: the "
                      "NREL 5 MW's)", read_only=True),
        ParameterSpec("measurement_noise", _DEFAULT.measurement_noise, "Q_v of the moments", "(MN*m)^2",
                      minimum=1e-9, maximum=1e6 * _DEFAULT.measurement_noise),
        ParameterSpec("wind_walk", _DEFAULT.wind_walk, "intensity of the wind's random walk (Q_w per step: this "
                      "times dt)", "(m/s)^2/s", minimum=1e-9, maximum=1e6 * _DEFAULT.wind_walk),
        ParameterSpec("input_weight", _DEFAULT.input_weight, "R of the LQR", "deg^2", minimum=1e-9,
                      maximum=1e6 * _DEFAULT.input_weight),
        ParameterSpec("inversion_walk", _DEFAULT.inversion_walk, "Q_eta of the SDMI inverse", minimum=1e-9,
                      maximum=1e6 * _DEFAULT.inversion_walk),
        ParameterSpec("ramp_time", 2.0, "time to ramp the output in or out, and to blend from the outgoing "
                      "controller's output when replacing it", "s", minimum=0.0, maximum=600.0),
    )

    def __init__(self, values: Mapping[str, Any], plant: PlantDescription) -> None:
        super().__init__(values, plant)
        v = self.values
        path = Path(v["linear_models"]) if v["linear_models"] else DEFAULT_MODELS
        try:
            self.models = load_models(path)
        except (OSError, KeyError) as error:
            raise ParameterError(f"linear_models: cannot read {path}: {error}") from None
        self.laws = LqgIpc(self._designs(v))  # one per linear model, stepped together
        self.pitches = [m.pitch for m in self.models]
        self.ramp = OutputRamp(plant.dt)
        self.start = (0.0, 0.0)  # what the output blends from as the ramp goes 0 -> 1
        self.measured = MeasuredFactor()  # 1 while the moments are finite (without_input)
        self.unmeasured = (0.0, 0.0)  # the last demand before that factor
        self.active_law = 0

    def _designs(self, values: Mapping[str, Any]) -> List[LqgDesign]:
        """One design per linear model with the weights of ``values``; ParameterError says why one fails."""
        weights = LqgWeights(values["measurement_noise"], values["wind_walk"], _DEFAULT.state_weight,
                             values["input_weight"], values["inversion_walk"])
        try:
            return [design_lqg(m.model, self.plant.dt, weights) for m in self.models]
        except (ConfigurationError, ValueError, np.linalg.LinAlgError) as error:
            raise ParameterError(f"the LQG design fails with these weights: {error}") from None

    @classmethod
    def claimed(cls, values: Mapping[str, Any]) -> Tuple[str, ...]:
        return (harmonic_interface(1),)

    def check(self, values: Mapping[str, Any]) -> None:
        """Live weights are designed for every operating point before they are accepted (a failing design is
        refused with its reason)."""
        super().check(values)
        self._designs(resolve_values(self.PARAMETERS, values))

    def reconfigure(self, values: Mapping[str, Any]) -> None:
        """New weights at a step boundary: every law gets its new design and keeps its estimates."""
        super().reconfigure(values)
        self.laws.designs = self._designs(self.values)

    def update(self, step: int, loads: Any, state: Any = None) -> Tuple[HarmonicContribution, ...]:
        moments = mbc_forward_sample(loads.root_moment_oop, loads.azimuth, 1)
        cyclic = mbc_forward_sample(loads.pitch, loads.azimuth, 1)
        self.active_law = min(range(len(self.pitches)), key=lambda k: abs(self.pitches[k] - cyclic.mean))
        factor = self.ramp.advance()
        self.laws.track_actuator(cyclic.cos, cyclic.sin)  # the pitch the blades have: applied, after every limit
        cos, sin = self.laws.demand(moments.cos, moments.sin)[self.active_law].tolist()
        self.unmeasured = (factor * cos + (1.0 - factor) * self.start[0],
                           factor * sin + (1.0 - factor) * self.start[1])
        measured = self.measured.step(True, self.plant.dt, self.ramp_time())
        applied = (measured * self.unmeasured[0], measured * self.unmeasured[1])
        self.laws.advance(applied)  # every estimator is told what was applied: this controller's contribution
        return (HarmonicContribution(1, *applied, 0.0),)

    def without_input(self, held: Tuple[Contribution, ...]) -> Tuple[HarmonicContribution, ...]:
        """Without the blade-root moments the estimators hold and the last demand fades out over ``ramp_time``."""
        measured = self.measured.step(False, self.plant.dt, self.ramp_time())
        return (HarmonicContribution(1, measured * self.unmeasured[0], measured * self.unmeasured[1], 0.0),)

    def estimate(self) -> Mapping[str, Any]:
        """The wind estimate û and the turbine states of the law in use (hawt_msgs/WindEstimate)."""
        laws, active = self.laws, self.active_law
        wind_cos, wind_sin = laws.wind[active].tolist()
        return {"wind_cos": wind_cos, "wind_sin": wind_sin,
                "operating_wind_speed": self.models[active].wind_speed,
                "states": laws.estimate[active, :laws.designs[active].states].copy()}

    def on_activate(self, ramp_time: Optional[float], initial: Sequence[Contribution], loads: Any) -> None:
        """Ramp in from zero, or, replacing another controller on harmonic/1, blend from its last output to this
        law's over ``ramp_time`` (bumpless transfer: the estimators already run and were told that output)."""
        outgoing = next(((c.cos, c.sin) for c in initial if isinstance(c, HarmonicContribution)), None)
        if outgoing is not None:
            self.start, self.ramp.value = outgoing, 0.0
        self.ramp.start(self.ramp_time() if ramp_time is None or outgoing is not None else ramp_time)

    def on_deactivate(self, ramp_time: Optional[float]) -> None:
        self.start = (0.0, 0.0)
        self.ramp.stop(self.ramp_time() if ramp_time is None else ramp_time)
