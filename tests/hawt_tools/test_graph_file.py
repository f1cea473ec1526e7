"""Graph and parameter files are checked before anything starts; each error names file, line and key."""
import shutil
from pathlib import Path

import pytest

from hawt_tools.graph_file import (GraphError, ParameterFile, ParameterValues, check_parameter_file, load_graph,
                                   yaml_value)

GOOD = """\
launch:
- arg: {name: gain, default: "2.5"}
- node:
    pkg: hawt_tools
    exec: relay
    name: relay
    namespace: wt1
    param:
    - {name: gain, value: $(var gain)}
    - {from: params.yaml}
    - {name: label, value: inline}
    remap:
    - {from: in, to: loads}
    respawn: true
    on_exit: shutdown
- node: {pkg: hawt_tools, exec: counter_sink, name: sink}
"""

PARAMS = """\
/**:
  ros__parameters:
    label: wildcard
relay:
  ros__parameters:
    gain: 3.0
    gains: {ki: [0.1, 0.2]}
"""


def _write(folder: Path, text: str, name: str = "graph.yaml") -> Path:
    path = folder / name
    path.write_text(text)
    return path


@pytest.fixture
def folder(tmp_path):
    _write(tmp_path, PARAMS, "params.yaml")
    return tmp_path


def test_a_good_graph_gives_its_nodes_in_order_with_parameters_and_remaps(folder):
    """Nodes keep file order; inline parameters around a file stay in order; substitutions are typed."""
    graph = load_graph(_write(folder, GOOD))
    relay, sink = graph.nodes
    assert (relay.label, sink.label) == ("/wt1/relay", "/sink")
    assert relay.parameters == (ParameterValues((("gain", 2.5),)), ParameterFile(folder / "params.yaml"),
                                ParameterValues((("label", "inline"),)))
    assert relay.remaps == (("in", "loads"),)
    assert relay.respawn and relay.shutdown_on_exit and not sink.respawn


def test_launch_arguments_override_defaults(folder):
    """gain:=4 on the command line replaces the arg's default."""
    relay = load_graph(_write(folder, GOOD), {"gain": "4"}).nodes[0]
    assert relay.parameters[0] == ParameterValues((("gain", 4),))


@pytest.mark.parametrize("text, message", [
    (GOOD.replace("    remap:", "    remaps:"), r"graph.yaml:12: unknown key 'remaps' in node \(did you mean 'remap'\?\)"),
    (GOOD.replace("exec: relay", "exe: relay"), r"graph.yaml:5: unknown key 'exe' in node \(did you mean 'exec'\?\)"),
    (GOOD.replace("- node: {pkg", "- nodes: {pkg"), r"graph.yaml:16: unsupported action 'nodes' \(did you mean 'node'\?\)"),
    (GOOD.replace("$(var gain)", "$(var gian)"), r"graph.yaml:9: \$\(var gian\): no launch argument of that name \(did you mean 'gain'\?\)"),
    (GOOD.replace("{from: params.yaml}", "{from: missing.yaml}"), r"graph.yaml:10: parameter file .*missing.yaml' does not exist"),
    (GOOD.replace("name: relay", "name: 9relay"), r"graph.yaml:6: node name '9relay' is not a valid ROS name"),
    (GOOD.replace("name: sink", "name: relay, namespace: wt1"), r"graph.yaml:16: a second node named '/wt1/relay' \(first at line 3\)"),
    (GOOD.replace("    param:\n", "    param:\n    - {name: bad, value: [1, two]}\n"), r"graph.yaml:9: parameter 'bad' has a value ROS 2 cannot hold"),
    (GOOD.replace("respawn: true", "respawn: maybe"), r"graph.yaml:14: 'respawn' must be true or false"),
    (GOOD.replace("on_exit: shutdown", "on_exit: restart"), r"graph.yaml:15: on_exit must be 'shutdown'"),
    (GOOD.replace("  name: relay\n", "  name: relay\n   namespace: x\n", 1), r"graph.yaml:\d+:\d+: YAML error"),
    ("nodes:\n- node: {pkg: a, exec: b}\n", r"graph.yaml:1: a graph file has exactly one root key 'launch', found \['nodes'\]"),
    ("launch: []\n", r"graph.yaml: the graph has no node"),
    (GOOD.replace('- arg: {name: gain, default: "2.5"}', "- arg: {name: gain}"), r"graph.yaml:2: launch argument 'gain' has no default and was not given \(pass gain:=VALUE\)"),
    (GOOD.replace("    pkg: hawt_tools\n", "", 1), r"graph.yaml:3: node is missing 'pkg'"),
    (GOOD.replace("exec: relay", "exec: /bin/sh"), r"graph.yaml:5: exec '/bin/sh' is not a package or executable name "
                                                  r"\(no path, no '..'\): a node runs an executable its package "
                                                  r"installs; another program needs an 'executable' action"),
    (GOOD.replace("exec: relay", "exec: ../../../../usr/bin/touch"), r"graph.yaml:5: exec '../../../../usr/bin/touch' "
                                                                   r"is not a package or executable name"),
    (GOOD.replace("pkg: hawt_tools\n", "pkg: ../hawt_tools\n", 1), r"graph.yaml:4: pkg '../hawt_tools' is not a "
                                                                   r"package or executable name"),
    (GOOD + "- executable: {cmd: 'sh -c id', shell: true}\n", r"graph.yaml:17: shell: true is not supported"),
    (GOOD + "- executable: {cmd: no_such_program_here --x}\n", r"graph.yaml:17: cmd: no program "
                                                                r"'no_such_program_here' \(not an executable file"),
    (GOOD + "- executable: {cmd: 'touch \"x'}\n", r"graph.yaml:17: cmd: No closing quotation"),
    (GOOD + "- executable: {cmd: 'true', cwd: /no/such/folder}\n", r"graph.yaml:17: cwd '/no/such/folder' is not a"),
    (GOOD + "- executable: {command: 'true'}\n", r"graph.yaml:17: unknown key 'command' in executable "
                                                r"\(did you mean 'cmd'\?\)"),
])
def test_a_broken_graph_is_refused_naming_file_line_and_key(folder, text, message):
    """Each typo or wrong value gives a one-line GraphError with the position and, where it can, a suggestion."""
    with pytest.raises(GraphError, match=message) as error:
        load_graph(_write(folder, text))
    assert "\n" not in str(error.value)


def test_an_executable_action_runs_a_program_by_its_words_without_a_shell(folder):
    """cmd is split as a shell would split it, its program found on PATH now; no shell interprets it."""
    graph = load_graph(_write(folder, GOOD + "- executable: {cmd: \"touch '$(var gain) x' ;\", name: marker, "
                                             "on_exit: shutdown}\n"))
    (program,) = graph.programs
    assert program.command == (shutil.which("touch"), "2.5 x", ";")
    assert (program.name, program.label, program.shutdown_on_exit) == ("marker", "program marker", True)
    assert [node.label for node in graph.nodes] == ["/wt1/relay", "/sink"]


def test_an_undeclared_launch_argument_is_refused(folder):
    """gian:=3 is a typo, not silently ignored."""
    with pytest.raises(GraphError, match=r"launch argument 'gian' is not declared by the graph \(did you mean 'gain'\?\)"):
        load_graph(_write(folder, GOOD), {"gian": "3"})


@pytest.mark.parametrize("text, message", [
    ("relay:\n  ros_parameters:\n    gain: 1.0\n", r"params.yaml:3: 'gain' must hold 'ros__parameters'"),
    ("ros__parameters:\n  gain: 1.0\n", r"params.yaml:1: 'ros__parameters' needs a node name above it"),
    ("relay:\n  ros__parameters:\n    gain: null\n", r"params.yaml:3: parameter 'gain' has a value ROS 2 cannot hold"),
    ("relay:\n  ros__parameters:\n    g: {ki: [[1]]}\n", r"params.yaml:3: parameter 'g.ki' has a value ROS 2 cannot hold"),
    ("- just a list\n", r"params.yaml: a parameter file must be a mapping of node names"),
    ("relay:\n  ros__parameters:\n    gain: 1.0\n    gain: 2.0\n", r"params.yaml:4: duplicate key 'gain'"),
])
def test_a_broken_parameter_file_is_refused_naming_file_and_line(tmp_path, text, message):
    """Parameter files are checked with the structure rcl expects, wildcards allowed."""
    with pytest.raises(GraphError, match=message):
        check_parameter_file(_write(tmp_path, text, "params.yaml"))


def test_wildcard_and_namespaced_parameter_files_are_accepted(tmp_path):
    """'/**', '/ns/*' and nested namespace levels are valid parameter-file keys."""
    check_parameter_file(_write(tmp_path, PARAMS + "/wt1/*:\n  ros__parameters:\n    x: 1\nwt2:\n  relay:\n"
                                          "    ros__parameters:\n      y: [true, false]\n", "params.yaml"))


@pytest.mark.parametrize("text, value", [("8e-11", 8e-11), ("-1E5", -1e5), ("[8e-11, 0.0]", [8e-11, 0.0]),
                                         ("2.5e-3", 2.5e-3), ("12", 12), ("true", True), ("e5", "e5"),
                                         ("1e", "1e"), ("nrel_5mw", "nrel_5mw")])
def test_a_parameter_text_has_rcls_type_an_exponent_without_a_dot_included(text, value):
    """A launch argument or -p value typed as YAML types it, except that 8e-11 is a float as rcl reads it (PyYAML's
    YAML 1.1 keeps it text, which a float parameter then refused: a new user's ipc_integral_gain:=[8e-11, 0.0])."""
    typed = yaml_value(text)
    assert typed == value and type(typed) is type(value)
