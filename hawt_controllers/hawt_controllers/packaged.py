"""The controller tunings shipped with this package (its ``data`` folder), by turbine and kind (hawt_controllers.design.tunings says
what each kind is and where a turbine folder keeps its own)."""
from pathlib import Path

__all__ = ["PACKAGED"]

_DATA = Path(__file__).resolve().parent / "data"
PACKAGED = {
    "nrel_5mw": {"cpc": _DATA / "nrel5mw_baseline.yaml", "ipc": _DATA / "ipc_nrel5mw.yaml",
                 "ipc_retuned": _DATA / "ipc_nrel5mw_retuned.yaml", "linear": _DATA / "linear_nrel5mw.npz"},
}
"""The packaged turbines' tunings (and the NREL 5 MW's ``discon``: the rosco wheel's DISCON.IN)."""
