"""The controller tunings shipped with this package, by turbine and kind (hawt_controllers.design.tunings says
what each kind is and where a turbine folder keeps its own)."""
from pathlib import Path

__all__ = ["PACKAGED"]

_CONFIG = Path(__file__).resolve().parent.parent / "config"
PACKAGED = {
    "nrel_5mw": {"cpc": Path(__file__).resolve().parent / "data" / "nrel5mw_baseline.yaml",
                 "ipc": _CONFIG / "ipc_nrel5mw.yaml", "ipc_retuned": _CONFIG / "ipc_nrel5mw_retuned.yaml",
                 "linear": _CONFIG / "linear_nrel5mw.npz"},
}
"""The packaged turbines' tunings (and the NREL 5 MW's ``discon``: the rosco wheel's DISCON.IN)."""
