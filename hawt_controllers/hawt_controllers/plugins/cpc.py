"""The ``cpc`` controller: generator torque and collective pitch of the NREL 5 MW baseline (Jonkman 2009).

Claims ``collective_pitch`` and ``generator_torque``; steps on ``plant/state`` (generator
speed and torque) and ``plant/blade_loads`` (measured pitch). The law is
:class:`hawt_controllers.laws.collective.BaselineCollectiveController`, tuned from
``controller_file``; it starts bumplessly at the first step's measured operating point, or, when it
replaces another collective controller (a swap: it is never switched off alone), at that
controller's last command. :class:`hawt_controllers.plugins.repetitive_cpc.RepetitiveCollectiveController`
is this controller with its own gains and an added term (:meth:`extra`).
"""
from __future__ import annotations

import math
from typing import Any, Mapping, Optional, Sequence, Tuple

from hawt_core.command_interfaces import COLLECTIVE_PITCH, GENERATOR_TORQUE
from hawt_core.parameter_table import ParameterError, ParameterSpec
from hawt_core.plant_description import DescriptionMismatch, PlantDescription

from hawt_controllers.laws.collective import (DEFAULT_BASELINE_FILE, BaselineCollectiveConfig, BaselineCollectiveController,
                         gain_correction_factor, load_baseline_config)
from hawt_controllers.plugins.controller import CollectiveContribution, Contribution, Controller, mean_pitch
from hawt_core.exceptions import InputError

__all__ = ["CollectivePitchController"]

RATED_SPEED_TOLERANCE = 0.01
"""Largest relative difference between the tuning's and the plant's rated generator speed."""


class CollectivePitchController(Controller):
    """The baseline collective controller as a plug-in (see the module notes)."""

    TYPE = "cpc"
    PARAMETERS = (
        ParameterSpec("controller_file", str(DEFAULT_BASELINE_FILE),
                      "baseline controller tuning (YAML of BaselineCollectiveConfig fields)", read_only=True),
    )
    INPUTS = ("blade_loads", "turbine_state")
    SWITCHABLE = False

    def __init__(self, values: Mapping[str, Any], plant: PlantDescription) -> None:
        super().__init__(values, plant)
        try:
            config = load_baseline_config(self.values["controller_file"])
        except (OSError, ValueError) as error:
            raise ParameterError(f"controller_file: {error}") from None
        plant_speed = plant.rated_rotor_speed * plant.gearbox_ratio
        if abs(config.rated_generator_speed / plant_speed - 1.0) > RATED_SPEED_TOLERANCE:
            raise DescriptionMismatch(
                f"controller_file: rated generator speed {config.rated_generator_speed:g} rad/s conflicts with "
                f"plant/description {plant_speed:g} rad/s ({plant.turbine}): a tuning for another turbine")
        self.law = BaselineCollectiveController(self.tuned(config))
        self.started = False
        self.start: Optional[CollectiveContribution] = None

    def tuned(self, config: BaselineCollectiveConfig) -> BaselineCollectiveConfig:
        """The law's tuning from the file's (a subclass's parameters may change it)."""
        return config

    @classmethod
    def claimed(cls, values: Mapping[str, Any]) -> Tuple[str, ...]:
        return (COLLECTIVE_PITCH, GENERATOR_TORQUE)

    def update(self, step: int, loads: Any, state: Any = None) -> Tuple[CollectiveContribution, ...]:
        pitch = mean_pitch(loads.pitch)
        if not (math.isfinite(state.generator_speed) and math.isfinite(pitch)):
            raise InputError("measurements", f"generator_speed={state.generator_speed}, mean pitch={pitch}: "
                                              "not finite")
        if not self.started:
            start = self.start
            if start is None:
                self.restart(state.generator_speed, pitch, state.generator_torque, 0.0)
            else:
                config = self.law.config
                proportional = gain_correction_factor(start.pitch, config.gain_doubling_pitch) \
                    * config.proportional_gain * (state.generator_speed - config.rated_generator_speed)
                self.restart(state.generator_speed, start.pitch, start.generator_torque, proportional)
            self.started = True
        out = self.law.step(state.generator_speed, pitch, self.plant.dt, self.extra(loads, state))
        return (CollectiveContribution(out.pitch, out.generator_torque, out.generator_speed_filtered,
                                       int(out.region), out.wind_speed_estimate),)

    def restart(self, generator_speed: float, pitch: float, generator_torque: float, proportional: float) -> None:
        """Bumpless start of the law at this operating point (BaselineCollectiveController.reset): the first
        command is ``pitch``, its ``proportional`` part [rad] (the current speed error's, in a handover) included."""
        self.law.reset(generator_speed, pitch, generator_torque)
        if proportional:
            self.law.pitch_integrator.reset(
                (pitch - proportional) / gain_correction_factor(pitch, self.law.config.gain_doubling_pitch))

    def extra(self, loads: Any, state: Any) -> float:
        """Pitch [rad] added to the law's PI demand before the limits (the baseline adds none)."""
        return 0.0

    def on_activate(self, ramp_time: Optional[float], initial: Sequence[Contribution], loads: Any) -> None:
        """Start again bumplessly at the next step: from the replaced controller's last command, or the plant's."""
        self.start = next((c for c in initial if isinstance(c, CollectiveContribution)), None)
        self.started = False
