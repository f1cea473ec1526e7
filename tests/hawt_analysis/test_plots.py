"""Specification of hawt_analysis.plots: the PNG reports."""
import matplotlib
import pytest

from hawt_analysis.comparison import compare_summaries
from hawt_analysis.plots import write_comparison_report, write_report
from hawt_analysis.summary import summarize
from hawt_analysis.synthetic_run import synthetic_channels

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def run():
    return synthetic_channels(duration=40.0, seed=5)


def test_report_writes_time_series_spectra_and_del_pngs(run, tmp_path):
    """write_report creates the three figures as PNG files in a new directory."""
    paths = write_report(run, summarize(run), tmp_path / "report")
    assert [path.name for path in paths] == ["time_series.png", "spectra.png", "del.png"]
    assert all(path.read_bytes().startswith(PNG_SIGNATURE) for path in paths)


def test_comparison_report_writes_one_png(run, tmp_path):
    """write_comparison_report draws the changes against the first run."""
    reduced = {**run, "hub_tilt_moment": 0.5 * run["hub_tilt_moment"]}
    comparison = compare_summaries([summarize(run), summarize(reduced)], ["a", "b"])
    (path,) = write_comparison_report(comparison, tmp_path)
    assert path.name == "comparison.png" and path.read_bytes().startswith(PNG_SIGNATURE)


def test_plotting_leaves_the_global_matplotlib_backend_alone(run, tmp_path):
    """Figures are rendered without pyplot, so the caller's backend setting is untouched."""
    backend = matplotlib.get_backend()
    write_report(run, summarize(run), tmp_path)
    assert matplotlib.get_backend() == backend


def test_comparison_report_with_the_runs_overlays_their_time_series_and_spectra(run, tmp_path):
    """Given each run's channels (and events), the report also overlays the runs in time (events marked) and
    frequency (nP marked)."""
    reduced = {**run, "hub_tilt_moment": 0.5 * run["hub_tilt_moment"]}
    comparison = compare_summaries([summarize(run), summarize(reduced)], ["a", "b"])
    events = {"b": [{"time": 10.0, "step": 1000, "kind": "switch", "source": "/wt1/ipc_h1", "level": 20,
                     "detail": "activated"}]}
    paths = write_comparison_report(comparison, tmp_path, {"a": run, "b": reduced}, events)
    assert [path.name for path in paths] == ["comparison.png", "compared_time_series.png", "compared_spectra.png"]
    assert all(path.read_bytes().startswith(PNG_SIGNATURE) for path in paths)
