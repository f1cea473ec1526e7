"""The ``plant`` node: the turbine model advanced one step per tick, measurements out, commands in.

Lockstep (default): step k's ``plant/blade_loads``, ``plant/state`` and ``/clock`` go out;
the model advances to k+1 once ``control/pitch_command`` of step k has arrived. If it does
not come within ``resend_period`` (wall clock) the step's measurements are sent again, so
discovery races and restarted controllers do not stall the run. Realtime: the model
ticks on the wall clock and applies the latest valid command (zero-order hold); the loop
latency (measurement sent -> command of that step received) and every late step are
reported. A command with NaN, the wrong length or values out of range is not applied:
the last valid one is held and the rejection is a ``control/events`` message. In
realtime a command older than the last applied one is ignored (one ``stale_input``
event per burst) and one for a step the plant has not reached is refused.

Only the ``command_sources`` (the graph's loop assembler, ``mbc``, by default) command the
plant: each command's publisher is identified by its GID and named through the ROS graph
(hawt_node.command_senders); a command from any other publisher is refused before it is
read, so it never answers a step, and the first from each intruder is an ``intruder``
event naming it (the ``finished`` event counts them all).

The plant's own safety system (:mod:`hawt_plant.safety_system`) watches the commands and
the turbine: with no command applied for ``command_timeout`` (lockstep: step k unanswered
that long, after its resends; before the first command: ``startup_timeout``) it trips and
reports a ``watchdog`` event; on a measurement beyond the turbine's protection levels
(overspeed, tower-top acceleration, pitch asymmetry or rate) it trips and reports a
``protection_trip`` event (an overspeed warning is a ``protection_warning``). Tripped, it
feathers every blade at the actuator's rate limit with the generator torque off, and the
trip latches. After a protection trip a lockstep plant still steps on its controllers'
answers (they are not applied), so the run stays deterministic; after the watchdog it
steps on its own, at the pace the run had, until ``duration``, so the run completes, and
commands that come back are not applied (one ``command_returned`` event).

Faults (the ``faults`` parameter, :mod:`hawt_plant.faults`): from its step a sensor fault changes
what ``plant/blade_loads`` publishes, an actuator or grid fault the command the model gets (after the
safety system's); each is a ``fault`` event at its step. ``hawt run`` applies them at the same points.

Back-pressure to the recorder (lockstep): a recorder that writes this plant's
``plant/blade_loads`` reports how far it has written on ``/recorder/progress``; the plant
does not step more than ``recorder_window`` of simulated time ahead of it. A recorder is a
single-threaded reader that takes one message per topic in turn, so holding the plant's
own topic bounds its backlog on every topic of the loop, far below its queue depth: a
recorded lockstep run is complete however busy the machine is. At ``duration`` the plant
finishes only once the recorder has written its last step, so stopping the graph loses
nothing of the backlog. A hold that lasts a second is logged, and again every 5 s while
it lasts. A held plant is not waiting on its controllers (the safety system's clock
restarts on release). With ``recorder_required`` (``hawt launch --record``) it waits however
long the recorder takes: a recorder that dies is respawned by the launcher, gets back the
steps it missed from the publishers' transient-local history (hawt_node.qos), and releases
the plant. Its progress counts only once it lists every topic of the loop (blade loads, state,
pitch command) that the recorder before it listed: until the new one has subscribed to a topic,
that topic's history must still hold the steps the dead one had not written, so the plant may
not run on (a topic discovered late would otherwise come back only from its last 2000 steps).
Without it, a recorder that writes nothing for ``recorder_timeout`` is given up
with a ``recorder`` event.
"""
import math
import time
from typing import Optional

import numpy as np
from builtin_interfaces.msg import Time
from hawt_msgs.msg import BladeLoads, ControlEvent, PitchCommand, PlantDescription, RecorderProgress, TurbineState
from rclpy.node import Node
from rclpy.task import Future
from rosgraph_msgs.msg import Clock

from hawt_plant.faults import fault_event, make_faults
from hawt_plant.loop_latency import LoopLatency
from hawt_plant.model import STATE_FIELDS, TurbineOutput
from hawt_plant.plant_setup import PARAMETERS, aerodynamics_line, check_parameters, make_plant, make_safety_system
from hawt_plant.safety_system import CommandOrder, command_rejection, protection_event
from hawt_node.command_senders import GuardedSubscription, Sample
from hawt_node.events import EventPublisher
from hawt_node.node_main import node_entry_point
from hawt_node.parameters import declare_parameters
from hawt_node.qos import CONTROL_LOOP, CONTROL_LOOP_HISTORY, LATCHED
from hawt_node.recording import unmatched_topics, unrecorded_topics
from hawt_node.writer_matching import unmatched_writers
from hawt_core.topics import BLADE_LOADS, CLOCK, PITCH_COMMAND, PLANT_DESCRIPTION, RECORDER_PROGRESS, TURBINE_STATE

__all__ = ["PlantNode", "PARAMETERS", "main"]

def _stamp(seconds: float) -> Time:
    nanoseconds = int(round(seconds * 1e9))
    return Time(sec=nanoseconds // 1_000_000_000, nanosec=nanoseconds % 1_000_000_000)


class PlantNode(Node):
    """Thin node around TurbineModel."""

    PARAMETERS = PARAMETERS
    """The node's parameter table (plant_setup.PLANT, the role the engines and the parameter check read)."""

    def __init__(self, **node_kwargs) -> None:
        super().__init__("plant", **node_kwargs)
        v = self.values = declare_parameters(self, self.PARAMETERS)
        check_parameters(v)
        turbine, self.model, output = self._build_plant(v)
        self.faults = make_faults(v, turbine)
        self.output = self.faults.measure(0, output)
        self.actuator = turbine.pitch_actuator
        self.turbine = turbine
        self.blades = turbine.rotor.number_of_blades
        self.command = (np.array(self.output.pitch), float(self.output.generator_torque))
        self.step_index = 0
        self.last_steps = int(round(v["duration"] / v["dt"])) if v["duration"] > 0 else None
        self.lockstep = v["mode"] == "lockstep"
        self.safety = make_safety_system(turbine, v)
        self.order = CommandOrder(v["stale_burst_gap"])
        self.events = EventPublisher(self)
        self.description_publisher = self.create_publisher(PlantDescription, PLANT_DESCRIPTION, LATCHED)
        self.description_publisher.publish(PlantDescription(**turbine.description(v["dt"]).as_fields()))
        self.loads_publisher = self.create_publisher(BladeLoads, BLADE_LOADS, CONTROL_LOOP_HISTORY)
        self.state_publisher = self.create_publisher(TurbineState, TURBINE_STATE, CONTROL_LOOP_HISTORY)
        self.clock_publisher = self.create_publisher(Clock, CLOCK, CONTROL_LOOP_HISTORY) if self.lockstep else None
        sources = [name for name in v["command_sources"] if name]
        if sources:
            self.guard = GuardedSubscription(self, PitchCommand, PITCH_COMMAND, CONTROL_LOOP, sources,
                                             self._on_command, self._report_intruder)
        else:
            self.guard = None
            self.create_subscription(PitchCommand, PITCH_COMMAND, self._on_command, CONTROL_LOOP)
        self.recorded_until: Optional[float] = None
        self.recorder_given_up = False
        self.recorder_heard_at = self.held_at = self.hold_reported_at = -math.inf
        self.held = self.finishing = self.stopped = False
        self.recorder_matched: dict[str, int] = {}
        self.loop_topics = {self.resolve_topic_name(topic) for topic in (BLADE_LOADS, TURBINE_STATE, PITCH_COMMAND)}
        self.recorded_loop: set[str] = set()  # the loop's topics a recorder has listed: a respawned one must again
        self._progress_subscription = self.create_subscription(RecorderProgress, RECORDER_PROGRESS,
                                                               self._on_recorder_progress, CONTROL_LOOP)
        self.done = Future()
        self.sent_at = time.monotonic()
        self.last_sent: Optional[int] = None
        self.latency = LoopLatency()
        self.started = False
        self.created = self.wall_start = self.answered_at = time.monotonic()
        self.get_logger().info(self._start_line(turbine))
        if self.lockstep:
            self.create_timer(min(v["resend_period"], 0.05), self._resend)
        else:
            self._start_timer = self.create_timer(0.05, self._start_realtime)

    def _build_plant(self, values: dict) -> tuple:
        """The turbine, the model the node steps (``step(pitch, generator_torque)`` -> the next output) and step 0's
        output, from the parameter ``values``: hawt_plant.plant_setup.make_plant (the DISCON bridge's node,
        hawt_tools.bridge_node, gives a simulator's)."""
        return make_plant(values, self.get_logger().info)

    def _start_line(self, turbine) -> str:
        """The node's first log line: the turbine, the wind, the timing, the start and the aerodynamic options."""
        v = self.values
        return (f"{v['turbine_file'] or 'NREL 5 MW'}: {v['wind_type']} wind {v['wind_speed']} m/s, "
                f"{v['mode']} at {1.0 / v['dt']:.0f} Hz, start at {self.output.rotor_speed * 30 / math.pi:.2f} rpm, "
                f"pitch {math.degrees(self.output.pitch[0]):.2f} deg; {aerodynamics_line(turbine, v)}")

    def _at_end(self) -> bool:
        """True once the run has reached its end, after a step: ``duration`` (the bridge's node: the simulator's last
        call)."""
        return self.last_steps is not None and self.step_index >= self.last_steps

    def _publish(self, out: TurbineOutput) -> None:
        stamp = _stamp(out.time)
        loads = BladeLoads(step=self.step_index, azimuth=out.azimuth, rotor_speed=out.rotor_speed,
                           root_moment_oop=out.root_moment_oop.tolist(), root_moment_ip=out.root_moment_ip.tolist(),
                           pitch=out.pitch.tolist())
        loads.header.stamp = stamp
        state = TurbineState(step=self.step_index, **{name: float(getattr(out, name)) for name in STATE_FIELDS})
        state.header.stamp = stamp
        if self.clock_publisher is not None:
            self.clock_publisher.publish(Clock(clock=stamp))
        self.loads_publisher.publish(loads)
        self.state_publisher.publish(state)
        self.last_sent = self.step_index
        self.sent_at = time.monotonic()
        self.latency.sent(self.step_index, self.sent_at)

    def _resend(self) -> None:
        """Send step 0 once enough subscribers are there; send an unanswered step again after resend_period."""
        if self.done.done():
            return
        if self.held:
            self._report_the_hold()
            self._give_up_a_stalled_recorder()
            return
        if self.safety.expired:
            return
        if self.step_index == 0 and not self.started:
            if self._ready_to_start():
                self._begin()
                self._publish(self.output)
        elif self._watch():
            self.create_timer(self._pace(), self._tick)
        elif time.monotonic() - self.sent_at >= self.values["resend_period"]:
            self._publish(self.output)

    def _start_realtime(self) -> None:
        """Start stepping in real time once the awaited subscribers and recorder are there."""
        if self._ready_to_start():
            self._start_timer.cancel()
            self._begin()
            self.create_timer(self.values["dt"], self._tick)

    def _ready_to_start(self) -> bool:
        """True once plant/blade_loads has wait_for_subscribers subscribers and, if awaited, the recorder is ready."""
        if self.loads_publisher.get_subscription_count() < self.values["wait_for_subscribers"]:
            return False
        return not self.values["wait_for_recorder"] or self._recorder_ready()

    def _begin(self) -> None:
        """The run's wall clock and the safety system's startup allowance start now."""
        self.started = True
        self.wall_start = time.monotonic()
        self.safety.start(self.wall_start)

    def _pace(self) -> float:
        """Wall time per step of the lockstep run so far (dt before the first answer): the pace after a trip.

        The plant then no longer waits for commands, but stepping faster than the graph ran
        would outrun the readers that kept up with it (a recorder's backlog is bounded by the
        publishers' history, hawt_node.qos.CONTROL_LOOP_HISTORY).
        """
        if self.step_index == 0:
            return self.values["dt"]
        return (self.answered_at - self.wall_start) / self.step_index

    def _watch(self) -> bool:
        """Let the safety system check the commands; True if it trips now (reported as a watchdog event)."""
        if self.lockstep:
            awaiting = f"control/pitch_command of step {self.step_index}"
        elif self.order.last_applied is None:
            awaiting = f"a first valid control/pitch_command (plant at step {self.step_index})"
        else:
            awaiting = (f"a valid control/pitch_command after step {self.order.last_applied} (plant at step "
                        f"{self.step_index})")
        tripped_before = self.safety.reason
        reason = self.safety.watch(time.monotonic(), self.output.pitch, awaiting)
        if reason is None:
            return False
        consequence = (self.safety.consequence if tripped_before is None else
                       f"the safety system had tripped ({tripped_before}); the plant steps on alone")
        self.events(ControlEvent.ERROR, "watchdog", f"{reason}: {consequence}", step=self.step_index,
                    stamp=_stamp(self.output.time))
        return True

    def _recorder_ready(self) -> bool:
        """True once hawt_recorder subscribes to every topic with a publisher and, by its /recorder/progress, is
        matched with every publisher, and the plant's own writers are matched with every reader (the recorder's
        among them); after 10 s, True with a warning."""
        missing = unrecorded_topics(self) or unmatched_topics(self, self.recorder_matched) or unmatched_writers(
            self, {BLADE_LOADS: self.loads_publisher, TURBINE_STATE: self.state_publisher})
        if missing and time.monotonic() - self.created > 10.0:
            self.events(ControlEvent.WARN, "recorder", f"starting without the recorder on {', '.join(missing)}")
            return True
        return not missing

    def _report_intruder(self, sample: Sample) -> None:
        """The first command of a publisher that is not a command source (the guard counts the rest)."""
        self.events(ControlEvent.ERROR, "intruder", f"control/pitch_command step {sample.message.step} from "
                    f"{sample.who} refused: only {', '.join(sorted(self.guard.allowed))} may command this plant "
                    "(its later commands are refused and counted)", step=self.step_index,
                    stamp=_stamp(self.output.time))

    def destroy_node(self) -> None:
        """Close the command guard and say which step was the last sent (a recording of the run ends there)."""
        if getattr(self, "guard", None) is not None:  # (none if __init__ failed before it)
            self.guard.close()
        if self.last_sent is not None:
            self.get_logger().info(f"stopped: step {self.last_sent} (t={self.last_sent * self.values['dt']:.2f} s) "
                                   "was the last sent")
        super().destroy_node()

    def _on_command(self, msg: PitchCommand) -> None:
        if self.done.done():
            return
        if self.safety.expired:
            if self.safety.command_returned():
                self.events(ControlEvent.WARN, "command_returned", f"control/pitch_command step {msg.step} arrived "
                            f"after the safety system tripped ({self.safety.reason}); the trip is latched, commands "
                            "are not applied", step=self.step_index, stamp=_stamp(self.output.time))
            return
        if self.safety.tripped:
            if self.lockstep and msg.step == self.step_index:
                self._answered()
            return
        reason = command_rejection(msg.pitch, msg.generator_torque, self.blades, self.actuator.min_angle,
                                   self.actuator.max_angle, self.turbine.generator.max_torque)
        if self.lockstep:
            self._refuse(msg, reason)
            if msg.step != self.step_index:
                return
            if reason is None:
                self.command = (np.asarray(msg.pitch, dtype=float), float(msg.generator_torque))
            self._answered()
            return
        verdict = self.order.admit(msg.step, self.step_index, self.output.time) if reason is None else None
        if verdict == CommandOrder.FUTURE:
            reason = f"step ahead of the plant's step {self.step_index}"
        self._refuse(msg, reason)
        if verdict == CommandOrder.STALE and self.order.new_burst:
            self.events(ControlEvent.WARN, "stale_input", f"control/pitch_command step {msg.step} is older than the "
                        f"applied step {self.order.last_applied}: ignored, like every stale command of this burst "
                        "(reported once)", step=self.step_index, stamp=_stamp(self.output.time))
        elif verdict == CommandOrder.APPLY:
            now = time.monotonic()
            self.latency.answered(msg.step, self.step_index, now)
            self.command = (np.asarray(msg.pitch, dtype=float), float(msg.generator_torque))
            self.safety.command_applied(now)

    def _answered(self) -> None:
        """Lockstep: the current step is answered; advance unless the recorder holds the plant."""
        self.answered_at = time.monotonic()
        self.safety.command_applied(self.answered_at)
        if not self._held_for_the_recorder():
            self._advance()

    def _recorder_behind(self) -> bool:
        """Lockstep with a recorder: the plant is more than recorder_window ahead of what it has written or, at the
        end, the recorder has not written the last step sent (``self.output``, one step past it, is never sent)."""
        if self.recorded_until is None:
            return False
        if self.finishing:
            return self.output.time - self.values["dt"] - self.recorded_until > 1e-9
        return self.output.time - self.recorded_until > self.values["recorder_window"] + 1e-9

    def stop_sending(self) -> None:
        """A graph stopped from outside: send no further step (commands still arriving are not applied), so that the
        recorder can catch up with the last one sent (hawt_node.node_main.drain)."""
        self.stopped = True

    def unrecorded(self) -> bool:
        """Lockstep with a recorder that still hears it: the recorder has not written the last step sent. A graph
        stopped from outside spins the plant on, sending nothing more, until it has (hawt_node.node_main.drain), so
        the bag ends where the plant stopped."""
        return (self.recorded_until is not None and self.last_sent is not None
                and self.last_sent * self.values["dt"] - self.recorded_until > 1e-9)

    def _held_for_the_recorder(self) -> bool:
        """Lockstep back-pressure: hold (True) while the recorder is behind; its progress releases the plant."""
        if not self._recorder_behind():
            return False
        self.held, self.held_at, self.hold_reported_at = True, time.monotonic(), -math.inf
        return True

    def _report_the_hold(self) -> None:
        """Log a hold once it has lasted a second, and again every 5 s while it lasts."""
        now = time.monotonic()
        if now - self.held_at < 1.0 or now - self.hold_reported_at < 5.0:
            return
        self.hold_reported_at = now
        what = "the last step" if self.finishing else f"t={self.output.time:.2f} s"
        self.get_logger().info(f"{what}: waiting for the recorder, which has written {BLADE_LOADS} up to "
                               f"t={self.recorded_until:.2f} s (recorder_window {self.values['recorder_window']:g} s)")

    def _on_recorder_progress(self, msg: RecorderProgress) -> None:
        if not self.started:
            self.recorder_matched = dict(zip(msg.topics, msg.publishers))
        topic = self.loads_publisher.topic_name
        if self.recorder_given_up or not (self.lockstep and self.values["recorder_window"] > 0) \
                or topic not in msg.topics:
            return  # (given up: a progress message already queued when its subscription went must not hold again)
        listed = self.loop_topics.intersection(msg.topics)
        self.recorded_loop |= listed
        if self.recorded_loop - listed:
            return  # a respawned recorder not yet on every topic of the loop (module notes): the plant stays held
        stamp = msg.stamps[msg.topics.index(topic)]
        if math.isnan(stamp):
            return
        if self.recorded_until is None or stamp > self.recorded_until:
            self.recorded_until, self.recorder_heard_at = stamp, time.monotonic()
        if self.held and not self._recorder_behind():
            self._release()

    def _release(self) -> None:
        """Advance the held step (or finish); the wait for the recorder does not count against the controllers."""
        self.held = False
        self.safety.command_applied(time.monotonic())
        if self.finishing:
            self._finish()
        else:
            self._advance()

    def _give_up_a_stalled_recorder(self) -> None:
        """A held plant whose recorder has written nothing for recorder_timeout goes on without back-pressure,
        unless the recorder is required."""
        timeout = self.values["recorder_timeout"]
        if self.values["recorder_required"] or time.monotonic() - max(self.recorder_heard_at, self.held_at) < timeout:
            return
        self.events(ControlEvent.WARN, "recorder", f"the recorder has written nothing more of {BLADE_LOADS} for "
                    f"{timeout:g} s (up to t={self.recorded_until:.2f} s, the plant at t={self.output.time:.2f} s): "
                    "going on without waiting for it; the bag may miss steps (hawt bag verify)",
                    step=self.step_index, stamp=_stamp(self.output.time))
        self.destroy_subscription(self._progress_subscription)
        self.recorded_until, self.recorder_given_up = None, True
        self._release()

    def _refuse(self, msg: PitchCommand, reason: Optional[str]) -> None:
        """Report a command that is not applied for ``reason`` (nothing if None)."""
        if reason is not None:
            self.events(ControlEvent.ERROR, "invalid_input", f"control/pitch_command step {msg.step} not applied "
                        f"({reason}); last valid command held", step=self.step_index, stamp=_stamp(self.output.time))

    def _tick(self) -> None:
        if self.done.done() or self.finishing:
            return
        if not self.lockstep:
            self._watch()
        self._advance()

    def _advance(self) -> None:
        if self.stopped:
            return
        if self.safety.tripped:
            self.command = self.safety.feather(self.values["dt"])
        for fault in self.faults.starting(self.step_index):
            self.events(*fault_event(fault, self.values["dt"], self.actuator), step=self.step_index,
                        stamp=_stamp(self.output.time))
        out = self.output = self.faults.step(self.model, self.step_index, *self.command)
        grid = self.faults.grid_connected(self.step_index)
        self.step_index += 1
        for finding in self.safety.protect(out, grid):
            self.events(*protection_event(finding, self.safety), step=self.step_index, stamp=_stamp(out.time))
        if self.step_index % max(1, int(round(self.values["report_period"] / self.values["dt"]))) == 0:
            self._progress()
        if self._at_end():
            self._finish()
            return
        self._publish(self.output)

    def _progress(self) -> None:
        wall = time.monotonic() - self.wall_start
        out = self.output
        self.get_logger().info(
            f"t={out.time:.1f} s ({out.time / wall:.1f}x real time): {out.rotor_speed * 30 / math.pi:.2f} rpm, "
            f"{out.electrical_power / 1e6:.3f} MW, pitch {math.degrees(float(np.mean(out.pitch))):.2f} deg")

    def _finish(self) -> None:
        """End the run, once the recorder (lockstep, if any) has written the last step sent."""
        self.finishing = True
        if self._held_for_the_recorder():
            return
        wall = time.monotonic() - self.wall_start
        summary = f"finished {self.step_index} steps ({self.output.time:.2f} s simulated) in {wall:.1f} s wall"
        latency = "" if self.lockstep else self.latency.summary()
        if latency:
            summary += "; " + latency
        if self.guard is not None and self.guard.refused:
            refused = self.guard.refused
            summary += f"; {sum(refused.values())} commands from {len(refused)} intruders refused"
        self.events(ControlEvent.INFO, "finished", summary, step=self.step_index, stamp=_stamp(self.output.time))
        self.done.set_result(True)


main = node_entry_point(PlantNode)
