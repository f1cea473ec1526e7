"""The ``lqg_ipc`` controller: LQG 1P IPC with wind-estimate feedforward (Selvam et al. 2009) as a plug-in.

Claims ``harmonic/1``. At configure it designs one FB-FF law (hawt_controllers.lqg_design) per wind
speed of a file of the plant's Coleman-frame linear models (``linear_models``, written by
``hawt linearize``; default the NREL 5 MW's, ``config/linear_nrel5mw.npz``). Each step it transforms
the blade-root out-of-plane moments to their 1P cos/sin (hawt_controllers.mbc), steps every law on
them (the estimators of all operating points run, so a change of schedule needs no restart) and
contributes the demand of the law whose operating pitch is nearest the measured mean pitch (gain
scheduling over the linear models), with phase offset 0: the models' cyclic pitch is the one of the
plain inverse transform. The random-walk wind states take up the orbit's constant 1P moment (shear),
as an integrator would. Its estimators are fed its own output after the ramp: what it contributes.
"""
from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping, Optional, Sequence, Tuple

from hawt_core.command_interfaces import harmonic_interface
from hawt_core.parameter_table import ParameterError, ParameterSpec
from hawt_core.plant_description import PlantDescription

from .controller import Contribution, Controller, HarmonicContribution, OutputRamp, mean_pitch
from .exceptions import ConfigurationError
from .linear_models import load_models
from .lqg_design import LqgWeights, design_lqg
from .lqg_ipc import LqgIpc
from .mbc import mbc_forward_sample

__all__ = ["LqgIpcController", "DEFAULT_MODELS"]

DEFAULT_MODELS = Path(__file__).resolve().parent.parent / "config" / "linear_nrel5mw.npz"
_DEFAULT = LqgWeights()


class LqgIpcController(Controller):
    """Selvam's FB-FF IPC on harmonic 1 (see the module notes)."""

    TYPE = "lqg_ipc"
    PARAMETERS = (
        ParameterSpec("linear_models", "", "the plant's linear models (.npz of hawt linearize; empty: the "
                      "NREL 5 MW's)", read_only=True),
        ParameterSpec("measurement_noise", _DEFAULT.measurement_noise, "Q_v of the moments", "(MN*m)^2",
                      minimum=1e-9, read_only=True),
        ParameterSpec("wind_walk", _DEFAULT.wind_walk, "intensity of the wind's random walk (Q_w per step: this "
                      "times dt)", "(m/s)^2/s",
                      minimum=1e-9, read_only=True),
        ParameterSpec("input_weight", _DEFAULT.input_weight, "R of the LQR", "deg^2", minimum=1e-9,
                      read_only=True),
        ParameterSpec("inversion_walk", _DEFAULT.inversion_walk, "Q_eta of the SDMI inverse", minimum=1e-9,
                      read_only=True),
        ParameterSpec("ramp_time", 2.0, "time to ramp the output in or out", "s", minimum=0.0, maximum=600.0),
    )

    def __init__(self, values: Mapping[str, Any], plant: PlantDescription) -> None:
        super().__init__(values, plant)
        v = self.values
        path = Path(v["linear_models"]) if v["linear_models"] else DEFAULT_MODELS
        try:
            models = load_models(path)
            weights = LqgWeights(v["measurement_noise"], v["wind_walk"], _DEFAULT.state_weight, v["input_weight"],
                                 v["inversion_walk"])
            self.laws = [LqgIpc(design_lqg(m.model, plant.dt, weights)) for m in models]
        except (OSError, KeyError) as error:
            raise ParameterError(f"linear_models: cannot read {path}: {error}") from None
        except ConfigurationError as error:
            raise ParameterError(str(error)) from None
        self.pitches = [m.pitch for m in models]
        self.ramp = OutputRamp(plant.dt)
        self.active_law = 0

    @classmethod
    def claimed(cls, values: Mapping[str, Any]) -> Tuple[str, ...]:
        return (harmonic_interface(1),)

    def update(self, step: int, loads: Any, state: Any = None) -> Tuple[HarmonicContribution, ...]:
        moments = mbc_forward_sample(loads.root_moment_oop, loads.azimuth, 1)
        pitch = mean_pitch(loads.pitch)
        self.active_law = min(range(len(self.pitches)), key=lambda k: abs(self.pitches[k] - pitch))
        factor = self.ramp.advance()
        demands = [law.demand(moments.cos, moments.sin) for law in self.laws]
        cos, sin = demands[self.active_law]
        applied = (factor * cos, factor * sin)
        for law in self.laws:  # every estimator is told what was applied: this controller's contribution
            law.advance(applied)
        return (HarmonicContribution(1, *applied, 0.0),)

    def on_activate(self, ramp_time: Optional[float], initial: Sequence[Contribution], loads: Any) -> None:
        self.ramp.start(self.ramp_time() if ramp_time is None else ramp_time)

    def on_deactivate(self, ramp_time: Optional[float]) -> None:
        self.ramp.stop(self.ramp_time() if ramp_time is None else ramp_time)
