"""Specification of the hawt_analysis package as a whole."""
import subprocess
import sys

MODULES = ("comparison", "fatigue", "harmonics", "pitch_activity", "plots", "record", "spectra", "summary", "synthetic_run",
           "run_analysis", "analysis_report")


def test_importing_every_module_but_the_plots_leaves_pyplot_alone():
    """Plots avoid pyplot's global state: importing every analysis module loads no matplotlib.pyplot."""
    code = "import sys\n" + "".join(f"import hawt_analysis.{name}\n" for name in MODULES) \
        + "print('matplotlib.pyplot' in sys.modules)"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert result.stdout.strip() == "False"


def test_summary_import_does_not_pull_in_matplotlib():
    """`hawt analyze --json` need not pay for matplotlib: summary imports only numpy, scipy and rainflow."""
    code = "import sys, hawt_analysis.summary, hawt_analysis.comparison; print('matplotlib' in sys.modules)"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert result.stdout.strip() == "False"
