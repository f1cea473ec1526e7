"""Specification of the hawt_analysis package as a whole."""
import os
import subprocess
import sys
from pathlib import Path

MODULES = ("comparison", "fatigue", "harmonics", "pitch_activity", "plots", "record", "spectra", "summary", "synthetic_run")


def test_importing_every_module_imports_neither_rclpy_nor_pyplot():
    """The analysis cores are pure numpy/scipy (STYLE: no rclpy), and plots avoid pyplot's global state."""
    source = Path(__file__).resolve().parents[2] / "hawt_analysis"
    code = (
        "import sys\n"
        + "".join(f"import hawt_analysis.{name}\n" for name in MODULES)
        + "print('rclpy' in sys.modules, 'matplotlib.pyplot' in sys.modules)"
    )
    environment = {**os.environ, "PYTHONPATH": str(source)}
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=environment, check=True)
    assert result.stdout.split() == ["False", "False"]


def test_summary_import_does_not_pull_in_matplotlib():
    """`hawt analyze --json` need not pay for matplotlib: summary imports only numpy, scipy and rainflow."""
    source = Path(__file__).resolve().parents[2] / "hawt_analysis"
    code = "import sys, hawt_analysis.summary, hawt_analysis.comparison; print('matplotlib' in sys.modules)"
    environment = {**os.environ, "PYTHONPATH": str(source)}
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=environment, check=True)
    assert result.stdout.strip() == "False"
