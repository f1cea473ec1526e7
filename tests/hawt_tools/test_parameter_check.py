"""Parameters checked before anything starts (issue 12 item 1): one line naming file, node and parameter, exit 2."""
from pathlib import Path

import pytest

from hawt_tools import launcher
from hawt_tools.graph_file import find_graph
from hawt_tools.cli import main
from hawt_tools.graph_file import GraphError, load_graph
from hawt_tools.graph_file import package_prefix
from hawt_tools.launcher import launcher_parameters
from hawt_tools.node_parameters import parse_overrides
from hawt_tools.parameter_check import check_against_plant, check_graph_parameters, checked_role
from turbine_folders import copied_turbine

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(autouse=True)
def nothing_starts(monkeypatch):
    """Any attempt to start a node, a process graph, a composed graph or a recorder fails the test."""
    def refuse(*_args, **_kwargs):
        raise AssertionError("a node was started although a parameter is bad")

    monkeypatch.setattr(launcher.ProcessGraph, "run", refuse)
    monkeypatch.setattr(launcher, "run_composed", refuse)
    monkeypatch.setattr("hawt_tools.recording.start_recorder", refuse)


def _ipc() -> str:
    return str(find_graph("ipc").resolve())


def _refused(capsys, argv) -> str:
    """Run the command; it must exit 2 with exactly one line on stderr and nothing on stdout."""
    code = main(argv)
    out, err = capsys.readouterr()
    assert (code, out) == (2, "")
    assert err.count("\n") == 1
    return err.rstrip("\n")


@pytest.mark.parametrize("command", ["launch", "run"])
def test_a_misspelled_override_is_refused_with_a_did_you_mean(capsys, command):
    """-p plant.wind_sped:=10 names the option and suggests wind_speed."""
    assert _refused(capsys, [command, "ipc", "-p", "plant.wind_sped:=10"]) == (
        f"hawt {command}: -p plant.wind_sped: no such parameter (did you mean 'wind_speed'?)")


@pytest.mark.parametrize("command", ["launch", "run"])
def test_a_misspelled_key_in_a_graph_file_names_the_file_and_the_node(capsys, tmp_path, command):
    """wind_sped in a graph file's {name, value} entries names that graph file and the plant."""
    graph = tmp_path / "graph.yaml"
    graph.write_text("launch:\n- node:\n    pkg: hawt_plant\n    exec: plant\n    name: plant\n    param:\n"
                     "    - {name: wind_sped, value: 10.0}\n"
                     "- node: {pkg: hawt_controllers, exec: cpc, name: cpc}\n"
                     "- node: {pkg: hawt_controllers, exec: mbc, name: mbc}\n")
    assert _refused(capsys, [command, str(graph)]) == (
        f"hawt {command}: {graph.resolve()}: node plant: wind_sped: no such parameter (did you mean 'wind_speed'?)")


@pytest.mark.parametrize("command", ["launch", "run"])
@pytest.mark.parametrize("argument, reason", [
    ("wind_speed:=-5", "wind_speed: -5.0 is below its minimum 3.0 m/s"),
    ("wind_speed:=abc", "wind_speed: expected a number [m/s], found 'abc'"),
    ("wind_speed:=nan", "wind_speed: expected a number [m/s], found 'nan'"),
    ("wind_speed:=.nan", "wind_speed: nan is not a finite number"),
    ("shear_exponent:=5", "shear_exponent: 5.0 is above its maximum 0.99"),
    ("seed:=abc", "seed: expected an integer, found 'abc'"),
    ("mode:=fast", "mode: 'fast' is not one of lockstep, realtime"),
])
def test_a_bad_launch_argument_blames_the_plant_in_the_graph_file(capsys, command, argument, reason):
    """Out of range, NaN, mistyped or not a choice: the graph file, the plant (the first node with it), the parameter."""
    assert _refused(capsys, [command, "ipc", argument]) == f"hawt {command}: {_ipc()}: node plant: {reason}"


@pytest.mark.parametrize("command", ["launch", "run"])
@pytest.mark.parametrize("override, reason", [
    ("ipc_h1.integral_gain:=nan", "expected a number [rad/(N*m*s)], found 'nan'"),
    ("ipc_h1.integral_gain:=.nan", "nan is not a finite number"),
    ("ipc_h1.harmonic:=1.5", "expected an integer, found 1.5"),
    ("ipc_h1.active:=maybe", "expected true or false, found 'maybe'"),
    ("ipc_h1.max_amplitude:=0", "must be > 0, found 0.0"),
    ("plant.skewed_wake:=maybe", "expected turbine, true or false, found 'maybe'"),
    ("plant.unsteady_airfoil:=1", "expected turbine, true or false, found 1"),
    ("plant.command_timeout:=0.1", "0.1 s must exceed resend_period 0.5 s in lockstep (a step is resent before "
                                   "the safety system trips)"),
])
def test_a_bad_override_names_the_option(capsys, command, override, reason):
    """A -p value refused by the node's table (or by its cheap rule across parameters) names -p NODE.PARAM."""
    assert _refused(capsys, [command, "ipc", "-p", override]) == (
        f"hawt {command}: -p {override.split(':=')[0]}: {reason}")


def test_a_bad_value_in_a_wildcard_parameter_file_names_that_file(capsys, tmp_path):
    """A /** parameter file of a node: the graph file, the node and the parameter file the value came from."""
    values = tmp_path / "ipc.yaml"
    values.write_text("/**:\n  ros__parameters:\n    integral_gain: .nan\n")
    graph = tmp_path / "graph.yaml"
    graph.write_text("launch:\n- node: {pkg: hawt_plant, exec: plant, name: plant}\n"
                     "- node: {pkg: hawt_controllers, exec: cpc, name: cpc}\n"
                     "- node: {pkg: hawt_controllers, exec: mbc, name: mbc}\n"
                     "- node:\n    pkg: hawt_controllers\n    exec: ipc\n    name: ipc_h1\n    param:\n"
                     "    - {from: ipc.yaml}\n")
    assert _refused(capsys, ["launch", str(graph), "--composed"]) == (
        f"hawt launch: {graph.resolve()}: node ipc_h1 (parameter file {values}): integral_gain: nan is not a "
        "finite number")


def test_mode_option_and_global_parameters_are_not_refused_by_nodes_without_them(capsys):
    """--mode and wait_for_recorder reach only nodes that have them: the bad value is still the one named."""
    assert _refused(capsys, ["launch", "ipc", "--mode", "realtime", "--record", "never.mcap",
                             "-p", "plant.wind_speed:=-5"]) == (
        "hawt launch: -p plant.wind_speed: -5.0 is below its minimum 3.0 m/s")


def test_rclpy_own_parameters_and_the_launcher_globals_pass_the_check():
    """use_sim_time (declared by rclpy itself), wait_for_recorder (the plant and every node answering its steps
    have it, controller_manager has not) and await_schedule (every node that applies switches has it, in a graph
    with a controller_manager) are accepted."""
    graph = load_graph(find_graph("ipc"), {}, package_prefix)
    overrides = parse_overrides(graph, ["cpc.use_sim_time:=true", "plant.start_type_description_service:=false"])
    assert launcher_parameters(graph, recorded=True) == {"wait_for_recorder": True, "recorder_required": True,
                                                         "await_schedule": True}
    assert "recorder_required" not in launcher_parameters(graph, recorded=True, record_optional=True)
    values = check_graph_parameters(graph, overrides, launcher_parameters(graph, recorded=True))
    assert all(values[f"/wt1/{name}"]["wait_for_recorder"] is True for name in ("plant", "cpc", "mbc", "ipc_h1"))
    assert values["/wt1/plant"]["recorder_required"] is True
    assert all(values[f"/wt1/{name}"]["await_schedule"] is True for name in ("cpc", "mbc", "ipc_h1"))
    assert not {"wait_for_recorder", "await_schedule"} & set(values["/wt1/controller_manager"])
    assert "await_schedule" not in values["/wt1/plant"]


def test_the_parameters_rclpy_declares_itself_are_the_ones_the_check_knows():
    """A bare rclpy node declares exactly use_sim_time and start_type_description_service, with the check's types."""
    import rclpy
    from rclpy.node import Node

    from hawt_tools.parameter_check import RCLPY_PARAMETERS

    context = rclpy.Context()
    rclpy.init(context=context)
    try:
        node = Node("probe", context=context)
        declared = {name: node.get_parameter(name).value
                    for name in node.list_parameters([], 0).names}
        node.destroy_node()
    finally:
        rclpy.shutdown(context=context)
    assert declared == {row.name: row.default for row in RCLPY_PARAMETERS}


def test_an_example_node_refuses_a_misspelled_parameter_too(capsys):
    """hawt_tools' example nodes have tables as well: relay.gian is refused."""
    assert _refused(capsys, ["launch", "example", "-p", "relay.gian:=3"]) == (
        "hawt launch: -p relay.gian: no such parameter (did you mean 'gain'?)")


def test_a_correct_graph_still_runs(capsys):
    """hawt run ipc duration:=1 passes the check and runs to its end."""
    assert main(["run", "ipc", "duration:=1"]) == 0
    assert "finished 100 steps" in capsys.readouterr().out


@pytest.mark.parametrize("command", ["launch", "run"])
def test_two_controllers_that_would_start_active_on_one_interface_are_refused_before_anything_starts(capsys, command):
    """ros2_control's one claimant per interface holds from step 0: cpc and repetitive_cpc both active, or two
    harmonic/1 controllers, are refused naming both nodes and the interface."""
    assert _refused(capsys, [command, "repetitive", "cpc:=true", "repetitive_cpc:=true"]).endswith(
        "repetitive.yaml: nodes 'cpc' and 'repetitive_cpc' both start active and claim collective_pitch; one "
        "controller per interface may be active (start one with active: false and swap them with hawt switch)")
    assert "nodes 'ipc_h1' and 'ipc_h1_retuned' both start active and claim harmonic/1" in _refused(
        capsys, [command, "switching", "-p", "ipc_h1.active:=true", "-p", "ipc_h1_retuned.active:=true"])


def test_a_number_in_exponent_form_without_a_dot_is_a_number():
    """name:=8e-11 (ROSCO's IPC_KI for the IEA 15 MW): YAML 1.1 leaves it a string; a float parameter takes it."""
    from hawt_core.parameter_table import ParameterError, ParameterSpec

    gain = ParameterSpec("integral_gain", 1e-8, "integral gain", "rad/(N*m*s)", minimum=0.0)
    assert gain.typed("8e-11") == 8e-11 and gain.typed("1E3") == 1000.0
    with pytest.raises(ParameterError, match="expected a number"):
        gain.typed("inf")


def test_an_aerodynamic_option_takes_turbine_true_or_false_and_is_dynamically_typed_on_the_node():
    """The plant's five aerodynamic options default to 'turbine' (the turbine definition's) and take true or false
    from -p; their ROS descriptors are dynamically typed (the default is a string, an override a bool)."""
    from hawt_node.parameters import descriptor
    from hawt_plant.plant_setup import PARAMETERS
    from hawt_plant.turbine import AERODYNAMIC_OPTIONS

    graph = load_graph(find_graph("ipc"), {}, package_prefix)
    for text, value in (("turbine", "turbine"), ("true", True), ("false", False)):
        values = check_graph_parameters(graph, parse_overrides(graph, [f"plant.skewed_wake:={text}"]))
        found = values["/wt1/plant"]["skewed_wake"]
        assert (type(found), found) == (type(value), value)
    rows = {row.name: row for row in PARAMETERS}
    for name in AERODYNAMIC_OPTIONS:
        assert rows[name].default == "turbine" and descriptor(rows[name]).dynamic_typing, name
        assert descriptor(rows[name]).additional_constraints == "one of: turbine, true, false"


def test_every_number_a_shipped_graph_takes_has_its_range():
    """Every numeric parameter of every node of the shipped graphs has a minimum and a maximum, which a live set
    is checked against as the start is: no gain, weight, frequency or time is unbounded."""
    unbounded = set()
    for path in sorted((ROOT / "hawt_controllers" / "launch").glob("*.yaml")):
        graph = load_graph(path, {}, package_prefix)
        for spec in graph.nodes:
            for row in getattr(checked_role(graph, spec), "parameters", ()):
                if isinstance(row.default, (int, float)) and not isinstance(row.default, bool) and \
                        (row.minimum is None or row.maximum is None):
                    unbounded.add(f"{spec.package}/{spec.executable}: {row.name}")
    assert not unbounded, sorted(unbounded)


@pytest.mark.parametrize("name", ["baseline", "ipc", "lqg", "rosco", "switching"])
def test_every_controller_is_built_against_the_plants_turbine_before_a_campaign_starts(tmp_path, name):
    """check_against_plant builds each controller core against the description of the plant's turbine: a graph on
    its own turbine passes; on a turbine whose rated speed is not the tuning's, the cpc is refused in one line naming
    the graph file and the node, as configure would refuse it after the start."""
    graph = load_graph(find_graph(name), {}, package_prefix)
    check_against_plant(graph, check_graph_parameters(graph))
    other = copied_turbine(tmp_path / "other")
    definition = other / "turbine.yaml"
    definition.write_text(definition.read_text().replace("rated_rotor_speed: 1.26711", "rated_rotor_speed: 0.79168"))
    overrides = parse_overrides(graph, [f"plant.turbine_file:={other}"])
    with pytest.raises(GraphError, match=rf"^{find_graph(name).resolve()}: node cpc: controller_file: rated generator "
                                         r"speed 122.91 rad/s conflicts with plant/description 76.79\d* rad/s"):
        check_against_plant(graph, check_graph_parameters(graph, overrides))


@pytest.mark.parametrize("command", ["launch", "run"])
def test_a_tuning_for_another_turbine_is_one_line_before_anything_starts(capsys, tmp_path, command):
    """hawt run once stopped with a traceback, and hawt launch's cpc node failed configure after the start."""
    other = copied_turbine(tmp_path / "other")
    definition = other / "turbine.yaml"
    definition.write_text(definition.read_text().replace("rated_rotor_speed: 1.26711", "rated_rotor_speed: 0.79168"))
    assert _refused(capsys, [command, "baseline", f"turbine:={other}"]).endswith(
        "baseline.yaml: node cpc: controller_file: rated generator speed 122.91 rad/s conflicts with plant/description "
        "76.793 rad/s (NREL 5MW onshore): a tuning for another turbine")
