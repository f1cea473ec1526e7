"""The ``cpc`` node: generator torque and collective pitch of the NREL 5 MW baseline (Jonkman 2009).

Inputs of step k: ``plant/state`` (generator speed, torque) and ``plant/blade_loads``
(measured pitch). Output: ``control/collective`` for step k. The law is
:class:`hawt_controllers.collective.BaselineCollectiveController`; its tuning comes
from the ``controller_file`` (default: the NREL 5 MW baseline data file).
"""
import math

from hawt_msgs.msg import BladeLoads, CollectivePitch, ControllerState, ControlEvent, TurbineState
from rclpy.node import Node

from hawt_controllers.collective import DEFAULT_BASELINE_FILE, BaselineCollectiveController, load_baseline_config
from hawt_controllers.switch_listener import SwitchListener
from hawt_tools.events import EventPublisher
from hawt_tools.node_main import node_entry_point
from hawt_tools.parameters import ParameterSpec, declare_parameters
from hawt_tools.qos import CONTROL_LOOP, CONTROL_LOOP_HISTORY
from hawt_tools.step_sync import StepAnswer, StepJoin
from hawt_tools.topics import BLADE_LOADS, COLLECTIVE, TURBINE_STATE

__all__ = ["CollectivePitchNode", "PARAMETERS", "main"]

PARAMETERS = (
    ParameterSpec("controller_file", str(DEFAULT_BASELINE_FILE),
                  "baseline controller tuning (YAML of BaselineCollectiveConfig fields)", read_only=True),
    ParameterSpec("dt", 0.01, "plant step the controller runs at", "s", minimum=1e-4, maximum=1.0, read_only=True),
)


class CollectivePitchNode(Node):
    """Thin node around BaselineCollectiveController: step k's plant measurements in, step k's command out."""

    def __init__(self, **node_kwargs) -> None:
        super().__init__("cpc", **node_kwargs)
        self.values = declare_parameters(self, PARAMETERS)
        self.controller = BaselineCollectiveController(load_baseline_config(self.values["controller_file"]))
        self.events = EventPublisher(self)
        self.answer = StepAnswer(self.create_publisher(CollectivePitch, COLLECTIVE, CONTROL_LOOP_HISTORY).publish)
        self.join = StepJoin(("state", "loads"))
        self.create_subscription(TurbineState, TURBINE_STATE, lambda m: self._input("state", m), CONTROL_LOOP)
        self.create_subscription(BladeLoads, BLADE_LOADS, lambda m: self._input("loads", m), CONTROL_LOOP)
        self.switches = SwitchListener(self, "cpc", switchable=False)
        self.switches.announce(ControllerState.ACTIVE, 0)

    def _input(self, name: str, msg) -> None:
        if self.answer.handled(msg.step):
            return
        inputs = self.join.add(name, msg.step, msg)
        if inputs is not None:
            self._step(inputs["state"], inputs["loads"])

    def _step(self, state: TurbineState, loads: BladeLoads) -> None:
        pitch = sum(loads.pitch) / len(loads.pitch) if len(loads.pitch) else math.nan
        if not (math.isfinite(state.generator_speed) and math.isfinite(pitch)):
            self.events(ControlEvent.ERROR, "invalid_input",
                        f"generator_speed={state.generator_speed}, mean pitch={pitch}: not finite; command held",
                        step=state.step, stamp=state.header.stamp)
            if self.answer.last is not None:
                held = self.answer.last
                self.answer.send(CollectivePitch(header=state.header, step=state.step, pitch=held.pitch,
                                                 generator_torque=held.generator_torque,
                                                 generator_speed_filtered=held.generator_speed_filtered,
                                                 region=held.region, wind_speed_estimate=held.wind_speed_estimate))
            return
        if self.answer.last is None:
            self.controller.reset(state.generator_speed, pitch, state.generator_torque)
        out = self.controller.step(state.generator_speed, pitch, self.values["dt"])
        msg = CollectivePitch(step=state.step, pitch=out.pitch, generator_torque=out.generator_torque,
                              generator_speed_filtered=out.generator_speed_filtered, region=int(out.region),
                              wind_speed_estimate=out.wind_speed_estimate)
        msg.header = state.header
        self.answer.send(msg)


main = node_entry_point(CollectivePitchNode)
