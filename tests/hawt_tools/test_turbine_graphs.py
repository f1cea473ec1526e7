"""Every graph takes the turbine (issue 20 item 4): turbine:=nrel_5mw or an imported turbine's folder, whose
controller tunings the graph finds beside it ($(turbine-tuning TURBINE KIND)); a missing one stops the graph before
anything starts, naming the file and the command that writes it."""
import shutil
import subprocess
from pathlib import Path

import pytest

from hawt_controllers.design.tunings import FILE_NAMES, PACKAGED, TuningError, tuning_file
from hawt_tools.graph_file import find_graph
from hawt_tools.cli import main
from hawt_tools.graph_file import GraphError, ParameterFile, load_graph
from hawt_tools.graph_file import package_prefix
from turbine_folders import copied_turbine

GRAPHS = ("baseline", "controllers", "identification", "ipc", "lqg", "repetitive", "rosco", "rosco_ipc", "switching",
          "validation")


@pytest.mark.parametrize("name", GRAPHS)
def test_every_graph_takes_the_turbine_and_gives_the_nrel_5mw_its_packaged_tunings(name):
    text = find_graph(name).read_text()
    assert "- arg: {name: turbine, default: nrel_5mw}" in text
    assert "find-pkg-share hawt_controllers)/config" not in text  # no tuning named outside the turbine's
    load_graph(find_graph(name), {}, package_prefix)  # every substitution resolves


def test_the_packaged_tunings_are_the_files_the_controllers_default_to():
    from hawt_controllers.laws.collective import DEFAULT_BASELINE_FILE
    from hawt_controllers.design.ipc_design import DEFAULT_FILE, RETUNED_FILE
    from hawt_controllers.plugins.lqg_ipc import DEFAULT_MODELS

    assert tuning_file("nrel_5mw", "cpc") == DEFAULT_BASELINE_FILE and tuning_file("nrel_5mw", "ipc") == DEFAULT_FILE
    assert tuning_file("nrel_5mw", "ipc_retuned") == RETUNED_FILE
    assert tuning_file("nrel_5mw", "linear") == DEFAULT_MODELS
    assert all(path.is_file() for path in PACKAGED["nrel_5mw"].values())
    assert tuning_file("nrel_5mw", "discon").name == "DISCON.IN"


def test_a_turbine_folder_without_a_tuning_is_refused_with_the_command_that_writes_it(tmp_path):
    (tmp_path / "turbine.yaml").write_text("")
    with pytest.raises(TuningError, match=rf"no cpc tuning {tmp_path}/cpc.yaml; write it with: hawt design cpc "
                                          rf"--turbine {tmp_path}$"):
        tuning_file(str(tmp_path), "cpc")
    with pytest.raises(TuningError, match="unknown tuning kind 'ipx'"):
        tuning_file(str(tmp_path), "ipx")
    with pytest.raises(GraphError, match=r"baseline.yaml:\d+: turbine .*: no cpc tuning .*hawt design cpc"):
        load_graph(find_graph("baseline"), {"turbine": str(tmp_path)}, package_prefix)


def test_hawt_run_refuses_a_turbine_without_its_tuning_in_one_line(capsys, tmp_path):
    (tmp_path / "turbine.yaml").write_text("")
    assert main(["run", "baseline", f"turbine:={tmp_path}", "duration:=1"]) == 2
    out, err = capsys.readouterr()
    assert err.count("\n") == 1 and "no cpc tuning" in err and "hawt design cpc --turbine" in err


def test_a_graph_on_an_imported_turbine_runs_its_plant_and_its_designed_controllers(imported_deck, tmp_path):
    """The NREL 5 MW imported from ROSCO's deck, its cpc designed and the packaged IPC tuning copied beside it: the
    ipc graph with turbine:=that folder gives the plant that turbine and each controller that folder's files."""
    from hawt_controllers.design.cpc_design import design_collective, write_design
    from hawt_plant.turbine import turbine_from
    from hawt_tools.in_process import build_run

    folder = tmp_path / "nrel5mw"
    shutil.copytree(imported_deck("NREL-5MW/NREL-5MW.fst"), folder)
    write_design(design_collective(turbine_from(str(folder))), folder / "cpc.yaml")
    shutil.copy(tuning_file("nrel_5mw", "ipc"), folder / "ipc.yaml")
    graph = load_graph(find_graph("ipc"), {"turbine": str(folder), "duration": "2"}, package_prefix)
    plant, = [n for n in graph.nodes if n.name == "plant"]
    cpc, = [n for n in graph.nodes if n.name == "cpc"]
    assert str(folder) in repr(plant.parameters) and str(folder / "cpc.yaml") in repr(cpc.parameters)
    run = build_run(graph)
    for _ in range(200):
        run.step(None)
    assert run.step_index == 200 and run.turbine.name == turbine_from(str(folder)).name


@pytest.mark.parametrize("name", GRAPHS)
def test_a_relative_turbine_folder_is_the_working_directorys_in_every_graph(name, tmp_path, monkeypatch):
    """turbine:=FOLDER from a working directory that is not the repository: every tuning a node gets, inline or as a
    parameter file, is the file in that folder, whatever folder the graph file is in (issue 31)."""
    folder = copied_turbine(tmp_path / "my_turbine")
    monkeypatch.chdir(tmp_path)
    graph = load_graph(find_graph(name), {"turbine": "my_turbine"}, package_prefix)
    tunings = [str(source.path) for node in graph.nodes for source in node.parameters
               if isinstance(source, ParameterFile) and source.path.name in FILE_NAMES.values()]
    tunings += [value for node in graph.nodes for source in node.parameters if not isinstance(source, ParameterFile)
                for key, value in source.values if key in ("controller_file", "linear_models", "infile")]
    assert tunings and all(Path(path).parent == folder for path in tunings), tunings


def test_hawt_run_takes_the_readmes_relative_turbine_folder_from_another_directory(tmp_path, monkeypatch, capsys):
    """``hawt run ipc turbine:=DIR`` (the README's command) from the folder holding DIR runs, where it once looked for
    the IPC tuning in the graph file's folder."""
    copied_turbine(tmp_path / "iea15")
    monkeypatch.chdir(tmp_path)
    assert main(["run", "ipc", "turbine:=iea15", "duration:=0.2"]) == 0, capsys.readouterr().err


@pytest.mark.ros
def test_hawt_launch_takes_a_relative_turbine_folder_from_another_directory(tmp_path, hawt_cli):
    """The same on the ROS graph: every node process, the plant's included, finds the folder from the launcher's
    working directory."""
    copied_turbine(tmp_path / "iea15")
    result = subprocess.run([*hawt_cli, "launch", "ipc", "turbine:=iea15", "duration:=0.5"], cwd=tmp_path,
                            capture_output=True, text=True, timeout=180)
    assert result.returncode == 0 and "finished 50 steps" in result.stdout + result.stderr, result.stderr[-3000:]


@pytest.mark.parametrize("turbine, message", [
    ("iea15", "turbine 'iea15': no packaged turbine of that name (packaged: nrel_5mw, "),
    ("empty", "turbine 'empty': the folder {tmp_path}/empty has no turbine.yaml (hawt turbine import writes one)"),
], ids=["no such folder", "folder without a definition"])
def test_a_turbine_that_is_neither_packaged_nor_a_definition_is_one_line(turbine, message, tmp_path, monkeypatch):
    (tmp_path / "empty").mkdir()
    monkeypatch.chdir(tmp_path)
    with pytest.raises(GraphError, match=r"baseline.yaml:\d+: ") as raised:
        load_graph(find_graph("baseline"), {"turbine": turbine}, package_prefix)
    assert message.format(tmp_path=tmp_path) in str(raised.value) and "\n" not in str(raised.value)
