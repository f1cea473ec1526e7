"""Every ``./hawt`` command the README prints works as printed, in a plain shell (issue 31 item 4).

The test reads each line of the README's code blocks that begins with ``./hawt`` (its ``# comment`` left out) and
finds it in one of three places:

- ``RUN``: the line runs, after the lines of its block that it needs, in a fresh folder (holding only a link to
  ``./hawt``) by ``bash`` in a plain login's environment: the system's PATH and HOME, none of ``scripts/env.sh``,
  which ``./hawt`` sources itself; only this run's ROS domain and a private turbulence cache are added. Where the
  line allows, the run is shortened (``duration:=2``; a 10 s turbulent field, whose generation is what a turbulent
  run's start costs) and a placeholder (``…/``, ``/path/…``) is filled; each entry says how.
- ``PARSED``: the line cannot run here, for the reason given; hawt's own parser takes its arguments, and a graph it
  starts loads with them (``hawt graph show``, which starts nothing).
- the command list under "Commands": usage forms, not commands. Each names a subcommand that exists and options
  that subcommand takes.

A README line in none of them fails the test, and so does an entry here that the README no longer prints.
"""
import argparse
import os
import re
import shlex
import subprocess
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, List, Tuple

import pytest

from hawt_tools import cli

pytestmark = pytest.mark.processes  # hawt commands in a shell: not in --quick

REPOSITORY = Path(__file__).resolve().parent.parent
README = REPOSITORY / "README.md"
HAWT = REPOSITORY / "hawt"

SHORT = "duration:=2"
"""A graph's simulated seconds, cut to what shows that the line runs."""
FIELD = "-p plant.field_duration:=10"
"""A turbulent run's field, 600 s by default, whose generation takes a turbulent run's start most of a minute."""

IEA15_DECK = ".venv/lib/python3*/site-packages/Examples/Test_Cases/IEA-15-240-RWT/IEA-15-240-RWT-Monopile"
"""Where the README finds the rosco wheel's IEA 15 MW deck (a glob the shell expands; the test uses rosco_case)."""


@dataclass(frozen=True)
class Line:
    """A README line as the test runs it: ``replace`` (README words -> the run's) and ``add`` (words appended)."""

    readme: str
    add: str = ""
    replace: Tuple[Tuple[str, str], ...] = ()

    def command(self, values: Dict[str, str]) -> str:
        """The line as run; ``{name}`` in a replacement is one of ``values``."""
        command = self.readme
        for old, new in self.replace:
            command = command.replace(old, new.format(**values))
        return f"{command} {self.add}".strip()


RUN: Dict[str, List[Line]] = {
    "the IEA 15 MW, end to end": [
        Line(f"./hawt turbine import {IEA15_DECK}/IEA-15-240-RWT-Monopile.fst -o iea15",
             replace=((IEA15_DECK, "{iea15_deck}"),)),
        Line("./hawt design cpc --turbine iea15 --natural-frequency 0.25 --damping 1.0"),
        # one operating point of the five, and the design's rate budget still leaves 2P and 3P inactive
        Line("./hawt design ipc --turbine iea15 --measured", add="--wind-speeds 18"),
        Line("./hawt run ipc turbine:=iea15 wind_type:=turbulent --record iea15-ipc1.mcap",
             add=f"{SHORT} {FIELD}"),
    ],
    "LQG IPC": [
        Line("./hawt design lqg --plot lqg.png"),
        Line("./hawt run lqg wind_type:=turbulent duration:=600 --record lqg.mcap", add=FIELD,
             replace=(("duration:=600", SHORT),)),
        Line("./hawt run lqg schedule:=\"['30000 +ipc_h1 -lqg_ipc']\"", add=SHORT),
    ],
    "two-bladed rotors": [  # 10 s: the comparison's harmonics need whole revolutions
        Line("./hawt run two_bladed duration:=200 --record 2b.mcap", replace=(("duration:=200", "duration:=10"),)),
        Line("./hawt run two_bladed main_bearing_ipc:=false duration:=200 --record 2b_off.mcap",
             replace=(("duration:=200", "duration:=10"),)),
        Line("./hawt compare 2b_off.mcap 2b.mcap"),
    ],
    "ROSCO in process": [
        Line("./hawt run rosco wind_type:=turbulent duration:=600 --record rosco.mcap", add=FIELD,
             replace=(("duration:=600", SHORT),)),
        Line("./hawt run rosco -p rosco.library:=/path/libctrl.so -p rosco.infile:=/path/ctrl.IN", add=SHORT,
             replace=(("/path/libctrl.so", "{rosco_library}"), ("/path/ctrl.IN", "{rosco_input}"))),
    ],
    "ROSCO's IPC graph": [Line("./hawt launch rosco_ipc", add=SHORT)],
}
"""Each block's lines that run, in the order they run in one folder."""

ROS_GRAPHS = {"ROSCO's IPC graph"}
"""The blocks that start a ROS graph, one process per node (marker ``ros``)."""

BESIDE_SWITCHING = "acts on the switching graph that the block's first line runs, from another shell while it runs"
"""The switching graph's lines: tests/hawt_controllers/test_switching_realtime.py runs the graph in real time with
--record, switches it as most of them do (not ipc_h4, blade_sine, the lifecycle line) and analyses its bag."""
PARSED = {
    "./hawt demo": "two graphs of 60 s (baseline and ipc), one process per node: over a minute on two cores",
    "./hawt test": "the whole suite, which this test is part of",
    "./hawt launch ipc duration:=600 --view": "serves the graph to Foxglove on port 8765 of this shared machine "
                                              "(tests/hawt_tools/test_view.py serves one on a free port)",
    "./hawt switch --activate cpc ipc_h1 ipc_h2 --deactivate rosco": "acts on the rosco_ipc graph of the line "
                                                                      "before, from another shell while it runs",
    "./hawt campaign campaigns/dlc12.yaml -o dlc12": "a design-load-case campaign of 600 s cases on Dask "
                                                      "(tests/hawt_tools/test_campaign.py runs small ones)",
    "./hawt campaign campaigns/dlc12.yaml -o dlc12 --scheduler tcp://HOST:8786": "needs Dask workers at HOST",
    "./hawt launch switching --mode realtime --record bags/switching.mcap":
        "ten processes in real time, a third of this file's time on two cores for what "
        "tests/hawt_controllers/test_switching_realtime.py runs already",
    "./hawt analyze bags/switching.mcap": "needs the bag of the switching graph's run, the block's first line",
    "./hawt switch --activate ipc_h1": BESIDE_SWITCHING,
    "./hawt switch --activate ipc_h2": BESIDE_SWITCHING,
    "./hawt switch --activate ipc_h1_retuned --deactivate ipc_h1": BESIDE_SWITCHING,
    "./hawt switch --deactivate ipc_h1_retuned ipc_h2 --ramp 1": BESIDE_SWITCHING,
    "./hawt switch --activate ipc_h4 blade_sine": BESIDE_SWITCHING,
    "./hawt bridge --file case.bridge --record run.mcap": "serves a simulator's DISCON calls: waits for OpenFAST "
                                                          "(tests/hawt_tools/test_discon_bridge.py drives a bridge "
                                                          "with hawt's own DISCON host)",
    "./hawt bridge switching namespace:=of --file case.bridge --record run.mcap":
        "serves a simulator's DISCON calls on the ROS graph: waits for OpenFAST (tests/hawt_tools/test_bridge_node.py "
        "drives one with hawt's own DISCON host and switches it live)",
    "./hawt switch --activate ipc_h1 --namespace of": "acts on the bridged switching graph of the line before, during "
                                                      "the simulator's run",
    "./hawt lifecycle ipc_h4 deactivate": BESIDE_SWITCHING,
    "./hawt list": BESIDE_SWITCHING,
}
"""README lines that cannot run here, with the reason."""

SCRIPT_COMMANDS = ("test", "bench")
"""Words the ``./hawt`` script itself handles before hawt's parser (pytest, a benchmark)."""


def _readme_lines() -> List[Tuple[str, str]]:
    """(section, line) of each README code-block line that begins with ``./hawt``, its comment left out; a line
    holding two commands (``./hawt bag info …  ./hawt bag recover …``) gives both."""
    found, section, in_block = [], "", False
    for text in README.read_text().splitlines():
        if text.startswith("```"):
            in_block = not in_block
        elif text.startswith("## "):
            section = text[3:]
        elif in_block and text.startswith("./hawt"):
            command = re.sub(r"\s+#\s.*$", "", text)
            found += [(section, f"./hawt{part}".strip()) for part in command.split("./hawt")[1:]]
    return found


def _synopsis() -> List[str]:
    return [line for section, line in _readme_lines() if section == "Commands"]


def _commands() -> List[str]:
    return [line for section, line in _readme_lines() if section != "Commands"]


def test_every_readme_command_is_run_or_parsed_here():
    """A line the README gains is classified here; an entry whose line the README lost is removed."""
    here = {line.readme for lines in RUN.values() for line in lines} | set(PARSED)
    printed = set(_commands())
    assert sorted(printed - here) == [], "README lines neither run nor parsed here"
    assert sorted(here - printed) == [], "lines here that the README no longer prints"


@pytest.fixture(scope="module")
def plain_shell(tmp_path_factory):
    """The environment of a plain login shell, with this run's ROS domain and a private turbulence cache."""
    kept = {name: os.environ[name] for name in ("HOME", "USER", "LANG", "TERM", "ROS_DOMAIN_ID",
                                                "ROS_AUTOMATIC_DISCOVERY_RANGE") if name in os.environ}
    return {**kept, "PATH": "/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin",
            "HAWT_CACHE_DIR": str(tmp_path_factory.mktemp("cache"))}


@pytest.fixture(scope="module")
def placeholders(rosco_case):
    """What the README's placeholders stand for on this machine."""
    from hawt_controllers.discon.rosco_input import rosco_files

    library, rosco_input = rosco_files()
    return {"iea15_deck": str(rosco_case("IEA-15-240-RWT/IEA-15-240-RWT-Monopile")), "rosco_library": str(library),
            "rosco_input": str(rosco_input)}


@pytest.mark.parametrize("block", [pytest.param(name, marks=[pytest.mark.ros] if name in ROS_GRAPHS else [])
                                   for name in RUN])
def test_the_readme_lines_run_as_printed_in_a_plain_shell(block, plain_shell, placeholders, tmp_path):
    (tmp_path / "hawt").symlink_to(HAWT)
    for line in RUN[block]:
        command = line.command(placeholders)
        result = subprocess.run(["bash", "-c", command], cwd=tmp_path, env=plain_shell, capture_output=True,
                                text=True)
        assert result.returncode == 0, f"{command}\n{result.stdout[-3000:]}\n{result.stderr[-3000:]}"


@pytest.mark.parametrize("line", sorted(PARSED))
def test_the_readme_lines_that_cannot_run_here_parse(line, capsys):
    """hawt's parser takes the line, and the graph it would start loads with its arguments."""
    words = shlex.split(line)[1:]
    if words[0] in SCRIPT_COMMANDS:
        assert f'"${{1:-}}" = "{words[0]}"' in HAWT.read_text()
        return
    args = cli.parse_command_line(words)
    if args.command in ("launch", "run"):
        assert cli.main(["graph", "show", args.graph, *args.arguments]) == 0, capsys.readouterr().err


def _subcommands(parser: argparse.ArgumentParser) -> Dict[str, argparse.ArgumentParser]:
    return next((action.choices for action in parser._actions if isinstance(action, argparse._SubParsersAction)),
                {})


@pytest.mark.parametrize("usage", _synopsis())
def test_each_usage_in_the_command_list_names_a_subcommand_and_options_it_takes(usage):
    words = [word.strip("[]") for word in usage.split()[1:]]
    if words[0] in SCRIPT_COMMANDS:
        assert f'"${{1:-}}" = "{words[0]}"' in HAWT.read_text()
        assert words[0] != "bench" or list((REPOSITORY / "benchmarks").glob("bench_*.py"))
        return
    parser, path = cli._parser(), []
    while words and words[0] in _subcommands(parser):
        parser = _subcommands(parser)[words[0]]
        path.append(words.pop(0))
    assert path or words[0].startswith("-"), f"{usage}: no such command"
    options = [word for word in words if word.startswith("-")]
    unknown = [option for option in options if option not in parser._option_string_actions]
    assert unknown == [], f"hawt {' '.join(path)} takes no {', '.join(unknown)}"
