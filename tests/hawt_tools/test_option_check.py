"""Options out of range and bag paths that cannot be written are refused before anything starts (issue 31 items 9 and
2): one line on stderr naming the option, exit 2, nothing started and nothing written."""
import subprocess
from pathlib import Path

import pytest

from hawt_tools import launcher
from hawt_tools.cli import main


@pytest.fixture(autouse=True)
def nothing_starts(monkeypatch):
    """Starting a graph (in processes, composed or in process), a recorder, a replay, a view or an analysis fails the
    test."""
    def refuse(*_args, **_kwargs):
        raise AssertionError("something was started although an option is bad")

    monkeypatch.setattr(launcher.ProcessGraph, "run", refuse)
    monkeypatch.setattr(launcher, "run_composed", refuse)
    monkeypatch.setattr("hawt_tools.recording.start_recorder", refuse)
    monkeypatch.setattr("hawt_tools.in_process.run_graph", refuse)
    monkeypatch.setattr("hawt_bag.recorder.record", refuse)
    monkeypatch.setattr("hawt_bag.replayer.replay", refuse)
    monkeypatch.setattr("hawt_analysis.run_analysis.compare_bags", refuse)
    monkeypatch.setattr(subprocess, "Popen", refuse)


def _refused(capsys, argv) -> str:
    """Run the command; it must exit 2 (returned, or argparse's exit) with one line on stderr and nothing on stdout."""
    try:
        code = main(argv)
    except SystemExit as stop:
        code = stop.code
    out, err = capsys.readouterr()
    assert (code, out) == (2, "")
    assert err.count("\n") == 1
    return err.rstrip("\n")


@pytest.mark.parametrize("argv, line", [
    (["launch", "baseline", "--duration", "-1"],
     "hawt launch: argument --duration: -1: expected a finite number above 0"),
    (["launch", "baseline", "--duration", "0"],
     "hawt launch: argument --duration: 0: expected a finite number above 0"),
    (["launch", "baseline", "--duration", "nan"],
     "hawt launch: argument --duration: nan: expected a finite number above 0"),
    (["launch", "baseline", "--duration", "inf"],
     "hawt launch: argument --duration: inf: expected a finite number above 0"),
    (["launch", "baseline", "--priority", "0"],
     "hawt launch: argument --priority: 0: expected a whole number from 1 to 99"),
    (["launch", "baseline", "--priority", "100"],
     "hawt launch: argument --priority: 100: expected a whole number from 1 to 99"),
    (["launch", "baseline", "--view", "--view-port", "65536"],
     "hawt launch: argument --view-port: 65536: expected a whole number from 0 to 65535"),
    (["launch", "baseline", "--view", "--view-port", "-1"],
     "hawt launch: argument --view-port: -1: expected a whole number from 0 to 65535"),
    (["run", "baseline", "--duration", "-1"], "hawt run: argument --duration: -1: expected a finite number above 0"),
    (["replay", "run.mcap", "--rate", "0"], "hawt replay: argument -r/--rate: 0: expected a finite number above 0"),
    (["replay", "run.mcap", "--rate", "inf"],
     "hawt replay: argument -r/--rate: inf: expected a finite number above 0"),
    (["replay", "run.mcap", "--start", "-2"],
     "hawt replay: argument --start: -2: expected a finite number of 0 or more"),
    (["replay", "run.mcap", "--clock", "-40"],
     "hawt replay: argument --clock: -40: expected a finite number of 0 or more"),
    (["replay", "run.mcap", "--wait-timeout", "0"],
     "hawt replay: argument --wait-timeout: 0: expected a finite number above 0"),
    (["replay", "run.mcap", "--step-timeout", "nan"],
     "hawt replay: argument --step-timeout: nan: expected a finite number above 0"),
    (["record", "--chunk-interval", "inf"],
     "hawt record: --chunk-interval: expected a positive number of seconds, found inf"),
    (["record", "--chunk-size", "0"], "hawt record: --chunk-size: expected a positive number of bytes, found 0"),
])
def test_an_option_out_of_range_is_refused_in_one_line_before_anything_starts(capsys, argv, line):
    """`hawt launch baseline --duration -1` once started every node and exited 0: now each out-of-range option of
    launch, run, replay and record is one line naming it and its value."""
    assert _refused(capsys, argv) == line


def test_a_report_folder_that_is_a_file_is_refused_before_the_analysis(capsys, tmp_path):
    """hawt compare --report FILE would have failed only after analysing every bag."""
    report = tmp_path / "report"
    report.write_text("")
    assert _refused(capsys, ["compare", "a.mcap", "b.mcap", "--report", str(report)]) == (
        f"hawt compare: --report {report}: is a file; expected a folder (or a name that does not exist yet)")


_WRITERS = [["launch", "baseline", "--record"], ["run", "baseline", "--record"], ["record", "-o"]]
"""Every command that records a bag, and its option naming the bag."""


@pytest.mark.parametrize("command", _WRITERS, ids=lambda command: command[0])
def test_a_bag_in_a_folder_that_is_a_file_is_refused_and_nothing_is_written(capsys, tmp_path, command):
    """A file where the bag's folder should be (or one of its parents) is named; no folder is made."""
    blocker = tmp_path / "bags"
    blocker.write_text("")
    bag = f"{blocker}/new/run.mcap"
    assert _refused(capsys, [*command, bag]) == (
        f"hawt {command[0]}: {command[-1]} {bag}: {blocker} is a file, not a folder")
    assert list(tmp_path.iterdir()) == [blocker]


@pytest.mark.parametrize("command", _WRITERS, ids=lambda command: command[0])
def test_a_bag_in_a_folder_that_cannot_be_written_is_refused(capsys, command):
    """/proc/1 is a folder no one may create files in, root included."""
    assert _refused(capsys, [*command, "/proc/1/run.mcap"]) == (
        f"hawt {command[0]}: {command[-1]} /proc/1/run.mcap: cannot write into the folder /proc/1")


@pytest.mark.parametrize("command", _WRITERS, ids=lambda command: command[0])
def test_an_existing_bag_is_refused_before_anything_starts(capsys, tmp_path, command):
    """A bag is never overwritten: the run that would have replaced it does not start."""
    bag = tmp_path / "run.mcap"
    bag.write_bytes(b"recorded")
    assert _refused(capsys, [*command, str(bag)]) == (
        f"hawt {command[0]}: {bag}: exists; refusing to overwrite a bag (choose another {command[-1]} name)")
    assert bag.read_bytes() == b"recorded"


def test_a_bag_in_folders_that_do_not_exist_yet_is_recorded_into_them(capsys, tmp_path, monkeypatch):
    """`--record bags/x.mcap` on a fresh clone, as the README's examples record: the folders are made before the run
    (once failed after the whole simulation with `cannot create (No such file or directory)`)."""
    monkeypatch.undo()  # this run starts
    monkeypatch.chdir(tmp_path)
    assert main(["run", "baseline", "duration:=1", "--record", "bags/deeper/x.mcap"]) == 0
    assert "recorded into bags/deeper/x.mcap" in capsys.readouterr().out
    assert (tmp_path / "bags" / "deeper" / "x.mcap").stat().st_size > 0
