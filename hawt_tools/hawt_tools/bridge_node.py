"""The bridge plant node: the plant node of a bridged graph, whose model is a simulator's DISCON calls.

``hawt bridge GRAPH --file F`` (hawt_tools.bridge_launch) starts the graph with this node in place of its plant node
(same name, namespace and parameters, ``dt`` the simulator's DT, ``duration`` 0) and hands it the library's connection
and first call over its ``handover`` socket. It is the plant node (hawt_plant.plant_node.PlantNode) with the
DISCON bridge's model (hawt_tools.discon_bridge.bridge_plant): step k's ``plant/blade_loads``, ``plant/state`` and
``/clock`` are call k's measurements (the fields the interface lacks NaN), ``plant/description`` (latched) has the
simulator's dt and the graph's turbine; the command of step k (``control/pitch_command`` from the plant's
``command_sources`` only, as the plant obeys it) answers call k, and the model then waits for call k + 1. So the
lockstep handshake, the command-source guard, the recorder's back-pressure and the finish once the recorder has
written the last step are the plant node's own.

What differs from the plant node:

- **The end**: the simulator's last call (status -1, answered with the last command) ends the run as ``duration``
  ends the plant's, once the recorder has written the last step sent; the process exits 0 and, through ``on_exit:
  shutdown``, ends the graph.
- **No plant protection** (hawt_tools.discon_bridge, "No plant protection"): the simulator's own applies.
- **The watchdog fails the library instead of feathering**: a step unanswered for ``command_timeout`` from the arrival
  of its call (before the first command ``startup_timeout``) is answered with ``fail = -1`` and the watchdog's reason,
  so the library gives the simulator its safe commands and the simulator stops with that line. A simulator that
  pauses between calls is not the controllers' fault: the clock restarts at each call. The library's own ``timeout``
  bounds the same wait from its side, and also a hold for the recorder, which the watchdog does not count.
- **The simulator gone** (a closed connection, seen within 0.1 s while the node waits for the graph, at once while it
  waits for a call) ends the node with one line and exit 1, and the launcher stops the graph.
"""
import sys
import time
from typing import List, Optional

from hawt_node.node_main import first_done, run_nodes
from hawt_plant.plant_node import PlantNode
from hawt_tools.bridge_launch import take_over
from hawt_tools.discon_bridge import (BRIDGE_PLANT, MISSING_FIELDS, BridgeClosed, BridgeError, BridgeModel,
                                      bridge_plant, parse_request, without_protection)

__all__ = ["BridgePlantNode", "main"]

GONE_CHECK_PERIOD = 0.1
"""Wall time [s] between checks that the simulator's connection is still open while the node waits for the graph."""


class BridgePlantNode(PlantNode):
    """The plant node with a simulator's DISCON calls as its model (module notes)."""

    PARAMETERS = BRIDGE_PLANT.parameters
    """The plant's parameter table and ``handover`` (hawt_tools.discon_bridge.BRIDGE_PLANT)."""

    def __init__(self, **node_kwargs) -> None:
        self.failure: Optional[str] = None
        super().__init__(**node_kwargs)
        self.safety = without_protection(self.safety)
        self.create_timer(GONE_CHECK_PERIOD, self._check_the_simulator)

    def _build_plant(self, values: dict) -> tuple:
        """The graph's turbine checked against the simulator, a BridgeModel on the handed-over connection, and the
        first call's measurements as step 0's output."""
        connection, first = take_over(values["handover"])
        _, swap, _ = parse_request(first)
        return bridge_plant(connection, swap)(values, self.get_logger().info)

    def _start_line(self, turbine) -> str:
        model: BridgeModel = self.model
        return (f"{turbine.name}: bridged to a simulator's DISCON calls, lockstep at dt {self.values['dt']:g} s, "
                f"{model.blades} blades, {'individual' if model.individual else 'collective'} pitch; fields without "
                f"a measurement (NaN): {', '.join(MISSING_FIELDS)}")

    def _at_end(self) -> bool:
        return self.model.finished

    def _advance(self) -> None:
        """Answer the call with the step's command and wait for the next call (the model's step), then publish it. The
        wait for the simulator does not count against the controllers: the watchdog's clock restarts once the call
        is there (a simulator may pause between calls, as a held plant does)."""
        try:
            super()._advance()
        except (BridgeClosed, BridgeError) as error:  # the simulator went away, or cannot apply the command
            self._fail(str(error))
            return
        self.safety.command_applied(time.monotonic())

    def _watch(self) -> bool:
        """The watchdog's trip fails the library with its reason (module notes); the node never steps on alone."""
        if super()._watch():
            self.model.fail(f"hawt bridge: {self.safety.reason}")
            self._fail(f"{self.safety.reason}: the simulator's call answered with a failure")
        return False

    def _check_the_simulator(self) -> None:
        if not self.done.done() and not self.model.finished and self.model.gone():  # (after the last call, it may)
            self._fail(f"the simulator closed the connection at step {self.step_index} (t={self.output.time:.2f} s), "
                       "before its last call")

    def _fail(self, reason: str) -> None:
        """End the node with ``reason`` (exit 1, :func:`main`)."""
        if self.done.done():
            return
        self.failure = reason
        self.get_logger().error(reason)
        self.done.set_result(False)


def main(args: Optional[List[str]] = None) -> None:
    """The ``bridge_plant`` executable: run the node until the simulator's last call (exit 0) or a failure (its line,
    exit 1)."""
    nodes: List[BridgePlantNode] = []

    def make() -> List[BridgePlantNode]:
        nodes.append(BridgePlantNode())
        return nodes

    try:
        run_nodes(make, first_done, args)
    except (BridgeError, BridgeClosed) as error:
        print(f"hawt bridge: {error}", file=sys.stderr)
        raise SystemExit(1) from None
    if nodes and nodes[0].failure:
        print(f"hawt bridge: {nodes[0].failure}", file=sys.stderr)
        raise SystemExit(1)


main.node_class = BridgePlantNode
