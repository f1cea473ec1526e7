"""ROSCO's files in the ``rosco`` wheel, and a private copy of a ROSCO ``DISCON.IN`` with hawt's settings.

The ``rosco`` wheel (requirements-nodeps.txt) holds the compiled controller ``rosco/lib/libdiscon.so`` and
the NREL 5 MW tuning ``Examples/Test_Cases/NREL-5MW/DISCON.IN`` with its rotor performance table
``Cp_Ct_Cq.NREL5MW.txt``; both are found through the installed distribution's file list, not a
site-packages path.

A ROSCO input file has one setting per line, ``value [value ...]  ! Name - description``. ROSCO reads
``PerfFileName`` and ``OL_Filename`` relative to the input file's folder (``ReadSetParameters.f90``,
``GetPath`` + ``PathIsRelative``), and writes its debug files next to the ``OUTNAME`` it is given.
:func:`write_private_input` writes a copy with those paths made absolute and chosen settings replaced,
so the copy can live in a private folder; it also checks the performance file exists, since ROSCO
opens it without a status check and a missing one would end the process.
"""
from __future__ import annotations

import importlib.metadata
import shutil
from pathlib import Path
from typing import Dict, Mapping, Tuple

__all__ = ["rosco_files", "is_rosco_input", "read_settings", "write_private_input", "copy_input",
           "RELATIVE_PATH_SETTINGS"]

RELATIVE_PATH_SETTINGS = ("PerfFileName", "OL_Filename")
"""Settings ROSCO resolves relative to the input file's folder."""


def rosco_files() -> Tuple[Path, Path]:
    """The ``rosco`` wheel's ``libdiscon.so`` and its NREL 5 MW ``DISCON.IN``.

    Raises
    ------
    FileNotFoundError
        The wheel is not installed (``scripts/setup.sh`` installs requirements-nodeps.txt).
    """
    try:
        distribution = importlib.metadata.distribution("rosco")
    except importlib.metadata.PackageNotFoundError:
        raise FileNotFoundError("the rosco wheel is not installed (requirements-nodeps.txt, scripts/setup.sh)") \
            from None
    return (Path(distribution.locate_file("rosco/lib/libdiscon.so")),
            Path(distribution.locate_file("Examples/Test_Cases/NREL-5MW/DISCON.IN")))


def _split(line: str) -> Tuple[str, str, str]:
    """(value, name, rest) of a setting line; name "" for other lines."""
    value, bang, comment = line.partition("!")
    words = comment.split()
    if not bang or not value.strip() or not words:
        return value, "", comment
    return value, words[0], comment


def read_settings(path: Path) -> Dict[str, str]:
    """The settings of a ROSCO input file: name -> value text (quotes kept)."""
    settings = {}
    for line in Path(path).read_text(errors="replace").splitlines():
        value, name, _ = _split(line)
        if name:
            settings.setdefault(name, value.strip())
    return settings


def is_rosco_input(path: Path) -> bool:
    """True if ``path`` reads as a ROSCO input file (it has a ``PerfFileName`` setting)."""
    return "PerfFileName" in read_settings(path)


def write_private_input(infile: Path, target: Path, settings: Mapping[str, str]) -> Path:
    """Write ``infile`` to ``target`` with relative paths made absolute and ``settings`` (name -> value text) set.

    Raises
    ------
    KeyError
        A name of ``settings`` the file does not have.
    FileNotFoundError
        The rotor performance file (``PerfFileName``) the estimator needs is not there.
    """
    infile = Path(infile).resolve()
    missing = [name for name in settings if name not in read_settings(infile)]
    if missing:
        raise KeyError(f"{infile}: no setting {', '.join(missing)}")
    _rewrite(infile, Path(target), lambda name, path: settings.get(name) if name in settings else
             (f'"{infile.parent / path}"' if path and path != "unused" and not Path(path).is_absolute() else None))
    written = read_settings(target)
    performance = Path(written["PerfFileName"].strip('"'))
    if written.get("WE_Mode", "0") != "0" and not performance.is_file():
        raise FileNotFoundError(f"{infile}: PerfFileName {performance}: no such file (ROSCO's wind speed estimator "
                                "needs it)")
    return Path(target)


def _rewrite(infile: Path, target: Path, replacement) -> None:
    """Write ``infile`` to ``target`` with each setting whose ``replacement(name, path)`` is not None replaced by
    it (``path``: the value of a RELATIVE_PATH_SETTINGS line without quotes, else None)."""
    lines = []
    for line in infile.read_text(errors="replace").splitlines():
        value, name, comment = _split(line)
        path = value.strip().strip('"') if name in RELATIVE_PATH_SETTINGS else None
        new = replacement(name, path) if name else None
        lines.append(f"{new:<20s} !{comment}" if new is not None else (f"{value}!{comment}" if name else line))
    target.write_text("\n".join(lines) + "\n")


def copy_input(infile: Path, target: Path) -> Path:
    """Copy the ROSCO input ``infile`` to ``target`` with the files it names (PerfFileName, OL_Filename) beside it,
    its paths rewritten to their names: a folder that can move. Returns ``target``.

    Raises
    ------
    FileNotFoundError
        A file the input names is not there.
    """
    infile, target = Path(infile).resolve(), Path(target)
    names = {}
    for name in RELATIVE_PATH_SETTINGS:
        path = read_settings(infile).get(name, "").strip('"')
        if path and path != "unused":
            source = infile.parent / path
            if not source.is_file():
                raise FileNotFoundError(f"{infile}: {name} {path}: no such file")
            shutil.copyfile(source, target.parent / source.name)
            names[name] = f'"{source.name}"'
    _rewrite(infile, target, lambda name, path: names.get(name))
    return target
