"""Running an installed graph with a fault, and reading what its bag shows.

A run is ``hawt launch <graph> --record`` in a child process (real nodes, real DDS,
in this test run's reserved ROS domain); a probe node in the test process follows
the plant's steps and can publish commands; the bag is read into columns afterwards.
"""
import math
import signal
import subprocess
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Dict, Iterable, List, Mapping, Optional

import numpy as np
import psutil
import yaml
from hawt_bag.reader import BagReader
from hawt_bag.topic_columns import TopicColumns, read_topic_columns
from hawt_msgs.msg import BladeLoads, CollectivePitch, ControlEvent, HarmonicPitch, PitchCommand
from rclpy.qos import QoSProfile, ReliabilityPolicy

from hawt_node.recording import unrecorded_topics
from hawt_plant.turbine import nrel_5mw
from hawt_tools.graph_file import find_graph
from ros_probe import ProbeNode

ACTUATOR = nrel_5mw().pitch_actuator
"""Pitch limits of the plant the installed graphs run (the packaged NREL 5 MW)."""
DT = 0.01
"""Plant step of the installed graphs [s]."""
LAUNCH_TIMEOUT = 120.0
"""Longest wait [s] for a launch to end or a step to appear: a hung graph fails the test instead of the suite."""

_PROBE_QOS = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)


def graph_outliving(folder: Path, graph: str, *nodes: str) -> Path:
    """The installed ``graph`` written into ``folder`` with ``nodes`` allowed to die while the rest runs on.

    ``hawt launch`` stops a whole graph when one of its nodes dies unexpectedly. A
    respawn whose delay outlasts any test is how a graph file says "note it and keep
    going"; nothing else of the graph changes.
    """
    content = yaml.safe_load(find_graph(graph).read_text())
    for entry in content["launch"]:
        if entry.get("node", {}).get("name") in nodes:
            entry["node"].update(respawn=True, respawn_delay=3600.0)
    path = folder / f"{graph}_outliving_{'_'.join(nodes)}.yaml"
    path.write_text(yaml.safe_dump(content, sort_keys=False))
    return path


class Probe(ProbeNode):
    """A node in the test process that follows one turbine's steps (the plant's, the collective's and the loop
    assembler's commands, which close the loop) and events, and can publish on any topic.

    ``steps[topic]`` is the newest step seen on each followed topic (-1 before the first); ``published`` counts the
    pitch commands it has sent.
    """

    def __init__(self, namespace: str, harmonics: Iterable[int] = ()) -> None:
        super().__init__("fault_probe")
        self.namespace = namespace
        followed = {"plant/blade_loads": BladeLoads, "control/collective": CollectivePitch,
                    "control/pitch_command": PitchCommand, **{f"control/ipc/h{n}": HarmonicPitch for n in harmonics}}
        self.steps: Dict[str, int] = dict.fromkeys(followed, -1)
        for topic, message_type in followed.items():
            self.node.create_subscription(message_type, f"/{namespace}/{topic}",
                                          lambda msg, topic=topic: self._on_step(topic, msg.step), _PROBE_QOS)
        self.events: List[ControlEvent] = []
        self.node.create_subscription(ControlEvent, f"/{namespace}/control/events", self.events.append, _PROBE_QOS)
        self.publishers = {"control/pitch_command": self.node.create_publisher(
            PitchCommand, f"/{namespace}/control/pitch_command", _PROBE_QOS)}
        self.published = 0

    def _on_step(self, topic: str, step: int) -> None:
        self.steps[topic] = max(self.steps[topic], step)

    @property
    def plant_step(self) -> int:
        """The newest step the plant has sent."""
        return self.steps["plant/blade_loads"]

    def wait_while_launched(self, condition: Callable[[], bool], launcher: subprocess.Popen, what: str) -> None:
        """Spin until ``condition()`` holds; fails if the launch ends or LAUNCH_TIMEOUT passes first."""
        self.wait_until(condition, what, alive=launcher, timeout=LAUNCH_TIMEOUT)

    def wait_for_step(self, step: int, launcher: subprocess.Popen) -> None:
        """Spin until the plant has sent step ``step`` or a later one."""
        self.wait_while_launched(lambda: self.plant_step >= step, launcher, f"plant step {step}")

    def wait_for_answer(self, step: int, launcher: subprocess.Popen, topic: str = "control/collective") -> None:
        """Spin until ``topic`` has answered plant step ``step`` or a later one."""
        self.wait_while_launched(lambda: self.steps[topic] >= step, launcher, f"answer of step {step} on {topic}")

    def wait_until_recorded(self, launcher: subprocess.Popen, margin: int = 50) -> None:
        """Spin until the recorder subscribes to the followed and event topics; then ``margin`` steps more on each
        followed topic (the loop is closed: the loop assembler answers).

        In realtime the plant does not wait for controllers that start after it, so the
        recorder may discover a controller's topic while the loop already runs.
        """
        topics = [f"/{self.namespace}/{topic}" for topic in (*self.steps, "control/events")]
        self.wait_while_launched(lambda: not unrecorded_topics(self.node, topics), launcher, "the recorder's subscriptions")
        for topic, step in dict(self.steps).items():
            self.wait_while_launched(lambda: self.steps[topic] >= step + margin, launcher, f"{margin} answers more on {topic}")

    def wait_for_event(self, kind: str, launcher: subprocess.Popen) -> None:
        """Spin until an event of ``kind`` has arrived."""
        self.wait_while_launched(lambda: self.reported(kind), launcher, f"event {kind!r}")

    def reported(self, kind: str, part_of_detail: str = "") -> bool:
        """True once an event of ``kind`` whose detail contains ``part_of_detail`` has arrived."""
        return any(event.kind == kind and part_of_detail in event.detail for event in self.events)

    def publish_until(self, commands: Mapping[str, Callable[[int], Any]], condition: Callable[[], bool],
                      launcher: subprocess.Popen, what: str) -> None:
        """Publish ``command(plant step)`` on each ``topic: command`` (topics of this namespace) every 10 ms until
        ``condition()`` holds; ``published`` counts the messages.

        The plant reads control/pitch_command keeping the latest sample only, so one
        injected message can be overwritten by the next command before it is taken.
        """
        for topic, command in commands.items():
            if topic not in self.publishers:
                self.publishers[topic] = self.node.create_publisher(type(command(0)), f"/{self.namespace}/{topic}",
                                                                    _PROBE_QOS)

        def published_and_holds() -> bool:
            if condition():
                return True
            for topic, command in commands.items():
                self.publishers[topic].publish(command(self.plant_step))
                self.published += 1
            return False
        self.wait_while_launched(published_and_holds, launcher, what)


@dataclass
class GraphRun:
    """One ``hawt launch GRAPH --record BAG`` in a child process, its output in a file."""

    launcher: subprocess.Popen
    bag: Path
    output: Path
    namespace: str

    def process_of(self, node: str) -> psutil.Process:
        """The OS process of ``node`` (the launcher names it by ``__node:=`` on its command line)."""
        for child in psutil.Process(self.launcher.pid).children(recursive=True):
            if f"__node:={node}" in child.cmdline() and f"__ns:=/{self.namespace}" in child.cmdline():
                return child
        raise AssertionError(f"no process of node {node} under the launcher")

    def kill(self, node: str) -> None:
        """SIGKILL ``node``'s process, as a crash would end it."""
        self.process_of(node).kill()

    def interrupt(self) -> None:
        """Ctrl-C: the launcher stops the graph and the recorder finishes the bag."""
        self.launcher.send_signal(signal.SIGINT)

    def finish(self) -> str:
        """Wait for the launch to end; its output. Fails unless it exits 0."""
        code = self.launcher.wait(timeout=LAUNCH_TIMEOUT)
        text = self.output.read_text()
        assert code == 0, text[-4000:]
        return text


def run_in_process(hawt_cli: List[str], folder: Path, graph: str, namespace: str, *arguments: str) -> Path:
    """``hawt run GRAPH namespace:=NAMESPACE ARGUMENTS --record BAG`` (the in-process engine, whose topics equal the
    lockstep graph's in every field at every step: tests/hawt_tools/test_in_process.py); the bag's path. The run a
    faulted lockstep graph is compared with, at a fraction of a graph's cost."""
    bag = folder / f"{namespace}.mcap"
    result = subprocess.run([*hawt_cli, "run", graph, f"namespace:={namespace}", *arguments, "--record", str(bag)],
                            capture_output=True, text=True, timeout=LAUNCH_TIMEOUT)
    assert result.returncode == 0, result.stderr[-2000:]
    return bag


@dataclass(frozen=True)
class Recording:
    """The topics of one turbine in a bag, as columns."""

    loads: TopicColumns
    state: TopicColumns
    commands: TopicColumns
    collective: TopicColumns
    events: TopicColumns
    ipc: dict

    def events_of(self, kind: str) -> List[dict]:
        """The events of ``kind`` in log order, each as a dict of level, step, source and detail."""
        fields = self.events.fields
        return [dict(level=int(fields["level"][i]), step=int(fields["step"][i]), source=str(fields["source"][i]),
                     detail=str(fields["detail"][i]))
                for i in np.flatnonzero(fields["kind"] == kind)] if len(self.events) else []

    def measured_pitch(self) -> tuple:
        """Steps and measured pitch [rad], one row per step (the first recording of a step sent again)."""
        steps, first = np.unique(self.loads.fields["step"], return_index=True)
        return steps, self.loads.fields["pitch"][first]


def read_recording(bag: Path, namespace: str, harmonics: tuple = ()) -> Recording:
    """Read the plant, command, collective, event and IPC topics of ``/namespace`` from ``bag``."""
    with BagReader(bag) as reader:
        def topic(name: str) -> TopicColumns:
            return read_topic_columns(reader, f"/{namespace}/{name}")
        return Recording(topic("plant/blade_loads"), topic("plant/state"), topic("control/pitch_command"),
                         topic("control/collective"), topic("control/events"),
                         {n: topic(f"control/ipc/h{n}") for n in harmonics})


def assert_plant_published_no_nan(recording: Recording) -> None:
    """Every number the plant published is finite."""
    for topic in (recording.loads, recording.state):
        for name, column in topic.fields.items():
            if column.dtype.kind == "f":
                assert np.all(np.isfinite(column)), f"{topic.topic}: {name} is not finite"


def assert_pitch_within_limits(recording: Recording) -> None:
    """Every finite pitch command and every measured pitch lies within the actuator's angle limits."""
    low, high = ACTUATOR.min_angle - 1e-9, ACTUATOR.max_angle + 1e-9
    commanded = [np.asarray(row, dtype=float) for row in recording.commands.fields.get("pitch", [])]
    for pitch in [row for row in commanded if np.all(np.isfinite(row))] + list(recording.loads.fields["pitch"]):
        assert np.all((low <= pitch) & (pitch <= high)), f"pitch {pitch} outside [{low}, {high}] rad"


def assert_plant_finished(recording: Recording, duration: float) -> None:
    """The plant reported that it ran its whole duration, and sent every step up to the last."""
    finished = recording.events_of("finished")
    steps = int(round(duration / DT))
    assert [event["step"] for event in finished] == [steps], finished
    assert recording.loads.fields["step"].max() == steps - 1


def feather_ramp(recording: Recording, trip_step: int) -> np.ndarray:
    """The measured pitch [rad] of every step after ``trip_step``, shape (steps, B)."""
    steps, pitch = recording.measured_pitch()
    after = steps > trip_step
    assert np.all(np.diff(steps[after]) == 1), "the plant skipped steps after the trip"
    return pitch[after]


def rises_at_rate_limit(pitch: np.ndarray, tolerance: float = 1e-9) -> Optional[str]:
    """Why ``pitch`` (steps × blades) does not rise to feather at the actuator's rate limit, or None."""
    change = np.diff(pitch, axis=0)
    limit = ACTUATOR.max_rate * DT
    if np.any(change > limit + tolerance):
        return f"a blade moved {math.degrees(change.max()):.4f} deg in one step, over {math.degrees(limit):.4f}"
    if np.any(change < -tolerance):
        return f"a blade moved back towards fine pitch by {math.degrees(-change.min()):.4f} deg"
    if not np.any(change > 0.99 * limit):
        return f"the pitch never moved at the rate limit (largest step {math.degrees(change.max()):.4f} deg)"
    return None
