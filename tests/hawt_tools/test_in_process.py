"""The in-process runner (DESIGN §6): the graph's cores without middleware, equal to the lockstep graph bit for bit."""
import subprocess

import numpy as np
import pytest

from hawt_bag.step_comparison import rows_by_step, step_differences
from hawt_tools.graph_file import NodeSpec, ParameterFile, ParameterValues
from hawt_tools.node_parameters import node_parameters

SCHEDULE = "schedule:=['500 +ipc_h1', '1500 +ipc_h4 +blade_sine', '2500 +ipc_h1_retuned -ipc_h1', " \
           "'4000 -blade_sine -ipc_h4']"
ROSCO_SCHEDULE = "schedule:=['800 +cpc +ipc_h1 +ipc_h2 -rosco', '1400 +rosco -cpc -ipc_h1 -ipc_h2']"


def test_node_parameters_follow_rcl_order_files_then_node_overrides(tmp_path):
    """A node's own pattern beats '/**' whatever file order; -p overrides beat every file; other nodes' keys don't apply."""
    first = tmp_path / "a.yaml"
    first.write_text("/**/ipc_h1:\n  ros__parameters: {gain: 1.0, harmonic: 1}\n"
                     "/**/ipc_h2:\n  ros__parameters: {gain: 2.0}\n")
    spec = NodeSpec("hawt_controllers", "ipc", "ipc_h1", "wt1",
                    parameters=(ParameterFile(first), ParameterValues((("gain", 5.0), ("active", False)))))
    assert node_parameters(spec) == {"gain": 5.0, "harmonic": 1, "active": False}
    assert node_parameters(spec, {"/wt1/ipc_h1": [("gain", "7.5")]})["gain"] == 7.5


@pytest.mark.ros
@pytest.mark.parametrize("order", [("a", "b"), ("b", "a"), ("a", "c"), ("c",)])
def test_node_parameters_agree_with_rcl_for_any_order_of_wildcard_and_named_files(tmp_path, order):
    """What node_parameters says a node gets equals what an rclpy node declares from the same files."""
    import rclpy
    from rclpy.node import Node

    texts = {"a": "/**/ipc_h1:\n  ros__parameters: {gain: 1.0}\n", "b": "/**:\n  ros__parameters: {gain: 5.0}\n",
             "c": "/wt1/ipc_h1:\n  ros__parameters: {gain: 7.0}\n/**:\n  ros__parameters: {gain: 9.0}\n"}
    files = []
    for name in order:
        files.append(tmp_path / f"{name}.yaml")
        files[-1].write_text(texts[name])
    spec = NodeSpec("hawt_controllers", "ipc", "ipc_h1", "wt1", parameters=tuple(ParameterFile(f) for f in files))
    context = rclpy.Context()
    rclpy.init(context=context)
    try:
        arguments = ["--ros-args", "-r", "__node:=ipc_h1", "-r", "__ns:=/wt1"]
        node = Node("probe", context=context, cli_args=[*arguments, *(a for f in files for a in ("--params-file",
                                                                                              str(f)))])
        assert node.declare_parameter("gain", 0.0).value == node_parameters(spec)["gain"]
        node.destroy_node()
    finally:
        rclpy.shutdown(context=context)


@pytest.mark.ros
@pytest.mark.parametrize("graph, arguments, seconds", [("ipc", [], 60), ("switching", [SCHEDULE], 60), ("lqg", [], 20),
                                                      ("rosco_ipc", [ROSCO_SCHEDULE], 20), ("two_bladed", [], 20)],
                         ids=["ipc", "switching", "lqg", "rosco_ipc", "two_bladed"])
def test_hawt_run_equals_the_lockstep_graph_in_every_field_at_every_step(hawt_cli, tmp_path, graph, arguments,
                                                                          seconds):
    """Turbulence: plant/blade_loads, plant/state and control/pitch_command of `hawt run` and of the lockstep ROS
    graph (one process per node) are equal in every field at every step; so is lqg_ipc's wind estimate."""
    common = [graph, "wind_type:=turbulent", f"duration:={seconds}", "seed:=3", *arguments]
    launched, ran = tmp_path / "launched.mcap", tmp_path / "ran.mcap"
    for command, path in (("launch", launched), ("run", ran)):
        result = subprocess.run([*hawt_cli, command, *common, "--record", str(path)], capture_output=True, text=True,
                                timeout=600)
        assert result.returncode == 0, result.stderr[-2000:]
    topics = ("/wt1/plant/blade_loads", "/wt1/plant/state", "/wt1/control/pitch_command")
    if graph == "lqg":
        topics += ("/wt1/control/lqg_ipc/wind_estimate",)
    assert all(len(rows["step"]) == seconds * 100 for rows in rows_by_step(launched, topics).values())
    assert step_differences(launched, ran, topics) == []
    if graph == "switching":  # the schedule switched something: IPC, 4P and the blade sine moved the blades
        individual = rows_by_step(ran, topics[2:])[topics[2]]["individual"]
        assert np.abs(individual[:500]).max() == 0.0 and np.abs(individual[2000:4000]).max() > 0.01


def test_hawt_run_refuses_a_graph_without_a_duration_in_one_line(hawt_cli):
    """No simulated duration: one line naming what is missing, exit 2."""
    result = subprocess.run([*hawt_cli, "run", "ipc", "duration:=0"], capture_output=True, text=True, timeout=120)
    assert result.returncode == 2
    assert "duration" in result.stderr and len(result.stderr.strip().splitlines()) == 1
