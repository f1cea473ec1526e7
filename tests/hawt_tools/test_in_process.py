"""The in-process runner (DESIGN §6): the graph's cores without middleware, equal to the lockstep graph bit for bit."""
import math
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
import yaml

from hawt_bag.step_comparison import rows_by_step, step_differences
from hawt_tools.graph_file import NodeSpec, ParameterFile, ParameterValues
from hawt_tools.node_parameters import node_parameters

SCHEDULE = "schedule:=['200 +ipc_h1', '500 +ipc_h4 +blade_sine', '800 +ipc_h1_retuned -ipc_h1', " \
           "'1200 -blade_sine -ipc_h4']"
PACKAGED_NREL_5MW = Path(__file__).resolve().parents[2] / "hawt_plant" / "hawt_plant" / "turbines" / "nrel_5mw"
ROSCO_SCHEDULE = "schedule:=['400 +cpc +ipc_h1 +ipc_h2 -rosco', '800 +rosco -cpc -ipc_h1 -ipc_h2']"


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
@pytest.mark.parametrize("graph, arguments, seconds", [("ipc", [], 12), ("switching", [SCHEDULE], 15), ("lqg", [], 10),
                                                      ("rosco_ipc", [ROSCO_SCHEDULE], 12), ("two_bladed", [], 10)],
                         ids=["ipc", "switching", "lqg", "rosco_ipc", "two_bladed"])
def test_hawt_run_equals_the_lockstep_graph_in_every_field_at_every_step(hawt_cli, tmp_path, graph, arguments,
                                                                          seconds):
    """Turbulence: plant/blade_loads, plant/state and control/pitch_command of `hawt run` and of the lockstep ROS
    graph (one process per node) are equal in every field at every step; so is lqg_ipc's wind estimate."""
    common = [graph, "wind_type:=turbulent", f"duration:={seconds}", "seed:=3", *arguments]
    launched, ran = tmp_path / "launched.mcap", tmp_path / "ran.mcap"
    output = {}
    for command, path in (("launch", launched), ("run", ran)):
        result = subprocess.run([*hawt_cli, command, *common, "--record", str(path)], capture_output=True, text=True,
                                timeout=600)
        assert result.returncode == 0, result.stderr[-2000:]
        output[command] = result.stdout + result.stderr
    topics = ("/wt1/plant/blade_loads", "/wt1/plant/state", "/wt1/control/pitch_command")
    if graph == "lqg":
        topics += ("/wt1/control/lqg_ipc/wind_estimate",)
    assert all(len(rows["step"]) == seconds * 100 for rows in rows_by_step(launched, topics).values())
    warnings = [line for line in output["launch"].splitlines() if "[WARN]" in line or "[ERROR]" in line]
    assert step_differences(launched, ran, topics) == [], "\n".join(warnings[:20])
    if graph == "switching":  # the schedule switched something: IPC, 4P and the blade sine moved the blades
        individual = rows_by_step(ran, topics[2:])[topics[2]]["individual"]
        assert np.abs(individual[:200]).max() == 0.0 and np.abs(individual[700:1200]).max() > 0.01


def test_hawt_run_refuses_a_graph_without_a_duration_in_one_line(hawt_cli):
    """No simulated duration: one line naming what is missing, exit 2."""
    result = subprocess.run([*hawt_cli, "run", "ipc", "duration:=0"], capture_output=True, text=True, timeout=120)
    assert result.returncode == 2
    assert "duration" in result.stderr and len(result.stderr.strip().splitlines()) == 1


def _baseline_run(*options: str, turbine_file: str = ""):
    from hawt_tools.graph_file import find_graph
    from hawt_tools.graph_file import load_graph
    from hawt_tools.in_process import build_run
    from hawt_tools.graph_file import package_prefix
    from hawt_tools.node_parameters import parse_overrides

    graph = load_graph(find_graph("baseline"), {"wind_speed": "14.0"}, package_prefix)
    given = [*options, *([f"plant.turbine_file:={turbine_file}"] if turbine_file else [])]
    return build_run(graph, parse_overrides(graph, given))


def test_a_plant_parameter_overrides_the_turbines_aerodynamic_option_in_process(tmp_path):
    """The packaged NREL 5 MW runs with its deck's skewed wake and unsteady airfoil; -p plant.skewed_wake:=false
    turns the skew off for that run, the other options staying the turbine's, and the run is, step for step, the
    run of a turbine whose definition says skewed_wake: false."""
    from dataclasses import replace

    from hawt_plant.plant_setup import aerodynamics_line

    default, overridden = _baseline_run(), _baseline_run("plant.skewed_wake:=false")
    assert (default.model.config.skewed_wake, default.model.config.unsteady_airfoil) == (True, True)
    assert (overridden.model.config.skewed_wake, overridden.model.config.unsteady_airfoil) == (False, True)
    assert replace(overridden.model.config, skewed_wake=True) == default.model.config
    assert aerodynamics_line(overridden.turbine, overridden.plant_values).endswith(
        "skewed_wake off, unsteady_airfoil on, dynamic_inflow on (the turbine's; by parameter: skewed_wake)")

    definition = tmp_path / "nrel_5mw" / "turbine.yaml"
    shutil.copytree(PACKAGED_NREL_5MW, definition.parent)
    definition.write_text(definition.read_text().replace("skewed_wake: {value: true,", "skewed_wake: {value: false,"))
    without_skew = _baseline_run(turbine_file=str(definition))
    assert without_skew.model.config == overridden.model.config
    for run in (overridden, without_skew):
        for _ in range(200):
            run.step(None)
    np.testing.assert_array_equal(overridden.output.root_moment_oop, without_skew.output.root_moment_oop)
    assert overridden.output.hub_tilt_moment == without_skew.output.hub_tilt_moment


def test_hawt_run_says_first_which_aerodynamic_options_the_plant_has():
    """The first progress line of a run names the turbine and its options, as the plant node's start-up line does."""
    from hawt_tools.graph_file import find_graph
    from hawt_tools.graph_file import load_graph
    from hawt_tools.in_process import run_graph
    from hawt_tools.graph_file import package_prefix
    from hawt_tools.node_parameters import parse_overrides

    graph = load_graph(find_graph("baseline"), {}, package_prefix)
    lines = []
    run_graph(graph, parse_overrides(graph, ["plant.tower_drag:=false"]), duration=0.05, progress=lines.append)
    assert lines[0] == ("NREL 5MW onshore: aerodynamics: tower_shadow on, tower_drag off, skewed_wake on, "
                        "unsteady_airfoil on, dynamic_inflow on (the turbine's; by parameter: tower_drag)")


def test_the_commanded_pitch_rate_is_the_turbines_whatever_the_graph(hawt_cli, tmp_path):
    """The ipc graph, 30 s in turbulence, on a copy of the NREL 5 MW whose pitch actuator is limited to 2 deg/s (the
    IEA 15 MW's): no step's command moves a blade faster than 2 deg/s, though the graph sets no limit and its
    controllers' tunings are the 8 deg/s turbine's (the loop assembler takes the limits from plant/description)."""
    turbine = tmp_path / "slow_pitch"
    shutil.copytree(PACKAGED_NREL_5MW, turbine)
    definition = yaml.safe_load((turbine / "turbine.yaml").read_text())
    definition["pitch_actuator"]["max_rate"] = math.radians(2.0)
    (turbine / "turbine.yaml").write_text(yaml.safe_dump(definition))
    bag = tmp_path / "run.mcap"
    result = subprocess.run([*hawt_cli, "run", "ipc", "-p", f"plant.turbine_file:={turbine}", "wind_type:=turbulent",
                             "duration:=30", "--record", str(bag)], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr[-3000:]
    pitch = rows_by_step(bag, ("/wt1/control/pitch_command",))["/wt1/control/pitch_command"]["pitch"]
    rate = np.abs(np.diff(pitch, axis=0)) / 0.01
    assert rate.max() <= math.radians(2.0) * (1 + 1e-9)
    assert rate.max() > math.radians(1.9), "the premise: the rate limit acts"
