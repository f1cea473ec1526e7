"""``hawt graph show`` lists what a graph declares without starting it: arguments with defaults, nodes, parameters."""
from pathlib import Path

from hawt_tools.graph_file import graph_summary

from hawt_tools.cli import main
from hawt_tools.graph_file import ArgumentSpec, declared_arguments


def test_the_ipc_graph_shows_its_arguments_with_defaults_and_its_nodes(capsys):
    assert main(["graph", "show", "ipc"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert ["turbine", "nrel_5mw"] in (line.split() for line in lines)
    assert ["namespace", "wt1"] in (line.split() for line in lines)
    for node in ("plant", "cpc", "mbc", "ipc_h1", "ipc_h2", "ipc_h3", "controller_manager"):
        assert any(line.split()[0] == f"/wt1/{node}" for line in lines if line.startswith("  /"))
    assert any(line.strip().startswith("from ") and line.endswith("ipc_nrel5mw.yaml") for line in lines)


def test_given_arguments_resolve_the_nodes_but_the_defaults_stay_listed(capsys):
    assert main(["graph", "show", "ipc", "namespace:=wt7"]) == 0
    out = capsys.readouterr().out
    assert "/wt7/plant" in out and "/wt1/plant" not in out
    assert ["namespace", "wt1"] in (line.split() for line in out.splitlines())


def test_an_unknown_graph_is_one_line_with_the_closest_name_and_exit_2(capsys):
    assert main(["graph", "show", "ipx"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "did you mean 'ipc'?" in err


def test_declared_arguments_keep_default_and_description_as_written(tmp_path: Path):
    graph = tmp_path / "graph.yaml"
    graph.write_text('launch:\n- arg: {name: gain, default: "2.5", description: loop gain}\n'
                     '- arg: {name: out}\n- node: {pkg: hawt_tools, exec: relay}\n')
    assert declared_arguments(graph) == (ArgumentSpec("gain", "2.5", "loop gain"), ArgumentSpec("out", None))


def test_graph_list_names_every_installed_graph_with_what_its_comment_says_offline(capsys):
    """hawt graph list starts and discovers nothing: each installed graph, one per line, with the first sentence of its
    file's comment; each name is one that hawt graph show takes."""
    assert main(["graph", "list"]) == 0
    rows = dict(line.split(None, 1) for line in capsys.readouterr().out.splitlines())
    assert {"baseline", "ipc", "lqg", "rosco", "validation"} <= rows.keys()
    assert rows["baseline"].startswith("the NREL 5 MW plant with its collective pitch and torque controller")
    assert all(summary and not summary.startswith("#") for summary in rows.values())
    assert all(main(["graph", "show", name]) == 0 for name in rows)


def test_graph_summary_is_the_first_sentence_of_the_leading_comment_after_its_title(tmp_path: Path):
    graph = tmp_path / "graph.yaml"
    graph.write_text("# Relay graph: two nodes passing loads. The second doubles them;\n# more text.\n"
                     "#   ./hawt launch graph.yaml\nlaunch: []\n")
    assert graph_summary(graph) == "two nodes passing loads"
    graph.write_text("# Tuned graph: the relay (gain 2, from its tuning; another turbine needs its own, e.g.\n"
                     "# gain:=3). More text.\nlaunch: []\n")
    assert graph_summary(graph) == "the relay (gain 2, from its tuning; another turbine needs its own, e.g. gain:=3)"
    graph.write_text("launch: []\n")
    assert graph_summary(graph) == ""


def test_an_inline_value_a_tuning_file_replaces_says_what_applies(tmp_path: Path, capsys, monkeypatch):
    """The ipc graph sets each harmonic's `active: true` before the turbine's tuning, which has the last word: where
    the tuning leaves a harmonic inactive (as `hawt design ipc` does past the rate budget), graph show says so."""
    from turbine_folders import copied_turbine

    turbine = copied_turbine(tmp_path / "turbine")
    tuning = turbine / "ipc.yaml"
    tuning.write_text(tuning.read_text().replace("/**/ipc_h3:\n  ros__parameters:\n",
                                                 "/**/ipc_h3:\n  ros__parameters:\n    active: false\n"))
    monkeypatch.chdir(tmp_path)
    assert main(["graph", "show", "ipc", "turbine:=turbine"]) == 0
    out = capsys.readouterr().out
    h2, h3 = (out.split(f"/wt1/ipc_h{n} ")[1].split("\n  /")[0] for n in (2, 3))
    assert "active: true\n" in h2 and "applies" not in h2
    assert f"active: true  (applies: false, from {tuning})" in h3
