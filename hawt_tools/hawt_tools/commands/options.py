"""What the command groups share: argument types that check their range while argparse reads the command line, the
parser's one-line refusal of bad usage, output paths checked before the work, stage lines and warnings on stderr,
and the plant's NAME:=VALUE parameters."""
import argparse
import difflib
import math
import re
import sys
from pathlib import Path
from typing import Callable, Dict, List, NoReturn, Optional

from hawt_tools.graph_file import GraphError, launch_arguments, yaml_value


def within(low: float, high: float = math.inf, above: bool = False, kind: type = float) -> Callable[[str], float]:
    """argparse's ``type=`` of an option that takes a finite number of ``kind`` from ``low`` (or above it) to ``high``.

    Declared with the option, the range holds in every command that has it, and argparse checks it while it reads the
    command line, before any command starts; anything else is its one-line refusal (`Parser`), exit 2.
    """
    lower = f"above {low:g}" if above else f"from {low:g}"
    span = f"{lower} to {high:g}" if high < math.inf else lower if above else f"of {low:g} or more"
    expected = f"expected a {'whole' if kind is int else 'finite'} number {span}"

    def number(text: str) -> float:
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text}: {expected}") from None
        if not (math.isfinite(value) and (value > low if above else value >= low) and value <= high):
            raise argparse.ArgumentTypeError(f"{text}: {expected}")
        return value

    return number


POSITIVE = within(0.0, above=True)
"""Seconds, speed factors, timeouts: above 0 (and finite)."""
NOT_NEGATIVE = within(0.0)
PORT = within(0, 65535, kind=int)
"""A TCP port as `hawt view` takes it (0: any free one, which the view prints)."""
PRIORITY = within(1, 99, kind=int)
"""A SCHED_FIFO priority."""


class Parser(argparse.ArgumentParser):
    """argparse with hawt's one-line refusal of bad usage (exit 2), the usage left to ``--help``."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: {message}\n")


def output_path(path: str | Path, option: str, folder: bool = False) -> Path:
    """``path`` as the file (or, with ``folder``, the folder) a command writes once its work is done, checked before
    the work: nothing of the other kind is there, and the folder it goes into exists (GraphError, one line)."""
    target = Path(path)
    if target.exists() and target.is_dir() != folder:
        raise GraphError(f"{option} {path}: " + ("is a file; expected a folder (or a name that does not exist yet)"
                                                 if folder else "is a folder; expected a file name"))
    if not target.resolve().parent.is_dir():
        raise GraphError(f"{option} {path}: the folder {target.resolve().parent} does not exist")
    return target


SCHEDULER_ADDRESS = re.compile(r"(tcp|tls)://[A-Za-z0-9_.\-\[\]:]+:(\d{1,5})")
"""A Dask scheduler's address as ``--scheduler`` takes it: ``tcp://HOST:PORT`` (or ``tls://``)."""


def scheduler_address(address: Optional[str]) -> Optional[str]:
    """``--scheduler``'s address, checked before anything starts (GraphError, one line)."""
    if address is None:
        return None
    found = SCHEDULER_ADDRESS.fullmatch(address)
    if found is None or not 0 < int(found.group(2)) < 65536:
        raise GraphError(f"--scheduler {address}: expected tcp://HOST:PORT with a port of 1 to 65535 (the address "
                         "dask-scheduler prints)")
    return address


def progress(line: str) -> None:
    """Stage lines of long work, on an interactive terminal only (stderr stays one error line otherwise)."""
    if sys.stderr.isatty():
        print(f"hawt: {line}", file=sys.stderr, flush=True)


def warn(command: str, warnings: List[str]) -> None:
    """Each warning of an analysis as one line on stderr."""
    for warning in warnings:
        print(f"hawt {command}: warning: {warning}", file=sys.stderr)


def report_folder(report: Optional[str]) -> None:
    """``--report DIR`` checked before the analysis: not a file (its missing folders are made when it is written)."""
    if report and Path(report).exists():
        output_path(report, "--report", folder=True)


def plant_overrides(words: List[str]) -> Dict[str, object]:
    """NAME:=VALUE words as the plant's parameters, each checked against the plant node's table."""
    from hawt_core.parameter_table import ParameterError
    from hawt_plant.plant_setup import PARAMETERS

    table = {spec.name: spec for spec in PARAMETERS}
    values = {}
    for name, text in launch_arguments(words).items():
        if name not in table:
            close = difflib.get_close_matches(name, table, n=1)
            raise GraphError(f"plant parameter {name!r} does not exist" + (f" (did you mean {close[0]!r}?)"
                                                                            if close else ""))
        try:
            values[name] = table[name].typed(yaml_value(text))  # 8e-11 a float, as everywhere else
        except ParameterError as error:
            raise GraphError(f"plant parameter {error}") from None
    return values
