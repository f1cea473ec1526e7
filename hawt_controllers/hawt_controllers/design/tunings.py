"""A turbine's controller tunings: the file of each kind that its graphs give the controllers (issue 20).

A turbine is what the plant's ``turbine_file`` takes: a packaged turbine's name, whose tunings ship with
this package, or the path of a turbine's folder or of its ``turbine.yaml`` (``hawt turbine import``), whose
tunings are files beside it, written by the design tools:

=============== =================== ==========================================================
kind            file in the folder  written by
=============== =================== ==========================================================
``cpc``         ``cpc.yaml``        ``hawt design cpc --turbine DIR``
``ipc``         ``ipc.yaml``        ``hawt design ipc --turbine DIR``
``ipc_retuned`` ``ipc_retuned.yaml`` the same
``linear``      ``linear.npz``      ``hawt linearize turbine_file:=DIR --output DIR/linear.npz``
``discon``      ``DISCON.IN``       ``hawt turbine import``: the deck's ROSCO input, with its Cp/Ct/Cq file
=============== =================== ==========================================================

Graph files ask for them with ``$(turbine-tuning TURBINE KIND)``. The ``ipc`` file holds every designed
harmonic; those past the pitch actuator's rate budget carry ``active: false``
(:func:`hawt_controllers.design.ipc_design.within_budget`), which a graph's own ``active`` parameter, given after the
file, overrides (the ``ipc`` graph's ``ipc_hN`` arguments).
"""
from __future__ import annotations

from pathlib import Path
from typing import Optional

from hawt_plant.turbine import PACKAGED_TURBINES

from hawt_controllers.discon.rosco_input import rosco_files
from hawt_controllers.packaged import PACKAGED

__all__ = ["FILE_NAMES", "PACKAGED", "TuningError", "tuning_file", "tuning_path", "turbine_folder"]

FILE_NAMES = {"cpc": "cpc.yaml", "ipc": "ipc.yaml", "ipc_retuned": "ipc_retuned.yaml", "linear": "linear.npz",
              "discon": "DISCON.IN"}
"""Each kind's file name in a turbine's folder."""


_WRITERS = {"cpc": "hawt design cpc --turbine {t}", "ipc": "hawt design ipc --turbine {t}",
            "ipc_retuned": "hawt design ipc --turbine {t}",
            "linear": "hawt linearize turbine_file:={t} --output {f}",
            "discon": "hawt turbine import DECK.fst -o {t} (it copies the deck's DISCON.IN and the Cp/Ct/Cq file "
                      "it names)"}


class TuningError(ValueError):
    """A turbine without the tuning asked for, or an unknown kind; the message says how to write it."""


def turbine_folder(turbine: str) -> Optional[Path]:
    """The folder of a turbine given by path (a folder or its ``turbine.yaml``); None for a packaged name."""
    if turbine in PACKAGED_TURBINES:
        return None
    path = Path(turbine)
    return path if path.is_dir() else path.parent


def tuning_path(turbine: str, kind: str) -> Path:
    """Where the ``kind`` tuning of ``turbine`` is (or is to be written): the packaged file, or the file of that
    kind in the turbine's folder; not checked to exist (:func:`tuning_file` checks)."""
    folder = turbine_folder(turbine)
    return PACKAGED[turbine][kind] if folder is None else folder / FILE_NAMES[kind]


def tuning_file(turbine: str, kind: str) -> Path:
    """The ``kind`` tuning of ``turbine`` (see the module notes), checked to exist.

    Raises
    ------
    TuningError
        Naming the kind or the missing file and how to write it.
    """
    if kind not in FILE_NAMES:
        raise TuningError(f"unknown tuning kind {kind!r} (expected one of: {', '.join(FILE_NAMES)})")
    folder = turbine_folder(turbine)
    if folder is None:
        if turbine == "nrel_5mw" and kind == "discon":
            return rosco_files()[1]
        if kind not in PACKAGED.get(turbine, {}):
            raise TuningError(f"turbine {turbine}: no packaged {kind} tuning (packaged: "
                              + ", ".join(f"{name} {'/'.join(kinds)}" for name, kinds in PACKAGED.items()) + ")")
        return PACKAGED[turbine][kind]
    path = tuning_path(turbine, kind)
    if not path.is_file():
        raise TuningError(f"turbine {turbine}: no {kind} tuning {path}; write it with: "
                          + _WRITERS[kind].format(t=folder, f=path))
    return path
