"""Turbine folders for tests, as ``hawt turbine import`` and the design tools leave them, made without importing a
deck."""
import shutil
from pathlib import Path

from hawt_controllers.design.tunings import FILE_NAMES, tuning_file

PACKAGED_NREL_5MW = Path(__file__).resolve().parent.parent / "hawt_plant" / "hawt_plant" / "turbines" / "nrel_5mw"


def copied_turbine(folder: Path) -> Path:
    """``folder`` made a turbine folder: the packaged NREL 5 MW's definition and airfoils, with its packaged tunings of
    every kind beside them (the DISCON.IN with its Cp/Ct/Cq file)."""
    shutil.copytree(PACKAGED_NREL_5MW, folder)
    for kind, name in FILE_NAMES.items():
        shutil.copy(tuning_file("nrel_5mw", kind), folder / name)
    shutil.copy(tuning_file("nrel_5mw", "discon").parent / "Cp_Ct_Cq.NREL5MW.txt", folder)
    return folder
