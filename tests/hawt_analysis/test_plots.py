"""Specification of hawt_analysis.plots: the figures of the reports and their PNG files."""
import matplotlib
import numpy as np
import pytest

from hawt_analysis.comparison import compare_summaries
from hawt_analysis.plots import (plot_compared_spectra, plot_compared_time_series, plot_comparison, plot_del_bars,
                                 plot_spectra, plot_time_series, write_comparison_report, write_report)
from hawt_analysis.spectra import rotor_harmonic_frequencies
from hawt_analysis.summary import summarize
from hawt_analysis.synthetic_run import synthetic_channels

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def run():
    return synthetic_channels(duration=40.0, seed=5)


@pytest.fixture(scope="module")
def runs(run):
    """Run "a" and run "b": half a's hub tilt moment and three times its pitch excursion (+200 % travel)."""
    return {"a": run, "b": {**run, "hub_tilt_moment": 0.5 * run["hub_tilt_moment"],
                            "pitch": run["pitch"].mean() + 3.0 * (run["pitch"] - run["pitch"].mean())}}


@pytest.fixture(scope="module")
def comparison(runs):
    return compare_summaries([summarize(channels) for channels in runs.values()], list(runs))


def _bar_widths(ax) -> list[list[float]]:
    """The lengths of the horizontal bars of ``ax``, one list per bar series (run)."""
    return [[bar.get_width() for bar in container] for container in ax.containers]


def _event_lines(ax) -> list[tuple[float, str]]:
    """(time, colour) of the dotted vertical lines of ``ax``: the marked events."""
    return [(line.get_xdata()[0], line.get_color()) for line in ax.lines if line.get_linestyle() == ":"]


def test_report_writes_time_series_spectra_and_del_pngs(run, tmp_path):
    """write_report creates the three figures as PNG files in a new directory."""
    paths = write_report(run, summarize(run), tmp_path / "report")
    assert [path.name for path in paths] == ["time_series.png", "spectra.png", "del.png"]
    assert all(path.read_bytes().startswith(PNG_SIGNATURE) for path in paths)


def test_comparison_report_writes_the_dels_and_their_changes(comparison, tmp_path):
    """write_comparison_report draws each run's DELs and the changes against the first run."""
    paths = write_comparison_report(comparison, tmp_path)
    assert [path.name for path in paths] == ["del.png", "comparison.png"]
    assert all(path.read_bytes().startswith(PNG_SIGNATURE) for path in paths)


def test_plotting_leaves_the_global_matplotlib_backend_alone(run, tmp_path):
    """Figures are rendered without pyplot, so the caller's backend setting is untouched."""
    backend = matplotlib.get_backend()
    write_report(run, summarize(run), tmp_path)
    assert matplotlib.get_backend() == backend


def test_comparison_report_with_the_runs_overlays_their_time_series_and_spectra(comparison, runs, tmp_path):
    """Given each run's channels (and events), the report also overlays the runs in time (events marked) and
    frequency (nP marked)."""
    events = {"b": [{"time": 10.0, "step": 1000, "kind": "switch", "source": "/wt1/ipc_h1", "level": 20,
                     "detail": "activated"}]}
    paths = write_comparison_report(comparison, tmp_path, runs, events)
    assert [path.name for path in paths] == ["del.png", "comparison.png", "compared_time_series.png",
                                             "compared_spectra.png"]
    assert all(path.read_bytes().startswith(PNG_SIGNATURE) for path in paths)


def test_del_bars_are_grouped_by_channel_with_one_bar_per_run_in_mn_m(comparison):
    """One group per load channel (labelled with m), one bar series per run, each bar the run's DEL in MN·m."""
    ax = plot_del_bars(comparison).axes[0]
    names = list(comparison["del"])
    assert [label.get_text() for label in ax.get_yticklabels()] == [
        f"{name} (m={comparison['del'][name]['m']:g})" for name in names]
    assert np.allclose(_bar_widths(ax), [[1e-6 * comparison["del"][name]["value"][k] for name in names]
                                         for k in range(2)])
    assert [text.get_text() for text in ax.get_legend().get_texts()] == ["a", "b"]
    assert "[MN·m]" in ax.get_xlabel()


def test_del_bars_of_one_run_have_one_bar_per_channel_and_no_legend(run):
    """A comparison of one summary (what hawt analyze draws) gives one bar per channel."""
    summary = summarize(run)
    ax = plot_del_bars(compare_summaries([summary], ["run"])).axes[0]
    assert np.allclose(_bar_widths(ax), [[1e-6 * entry["value"] for entry in summary["del"].values()]])
    assert ax.get_legend() is None


def test_changes_of_loads_and_of_pitch_activity_are_on_separate_axes(comparison):
    """DEL changes on one axis, pitch-activity changes on another, each scaled to its own bars: the +200 % pitch
    travel does not set the scale of the -50 % hub tilt DEL. Each pitch bar is labelled as the text table names it,
    with its unit (degrees) and the runs' values in that unit."""
    loads, pitch = plot_comparison(comparison).axes
    assert np.allclose(_bar_widths(loads), [[entry["change_percent"][1] for entry in comparison["del"].values()]])
    assert np.allclose(_bar_widths(pitch), [[entry["change_percent"][1] for entry in comparison["pitch"].values()]])
    assert comparison["pitch"]["travel_rad"]["change_percent"][1] == pytest.approx(200.0, abs=1.0)
    assert max(abs(limit) for limit in loads.get_xlim()) < 100.0 < pitch.get_xlim()[1]
    travel = np.degrees(comparison["pitch"]["travel_rad"]["value"])
    assert [label.get_text().split("\n") for label in pitch.get_yticklabels()][0] == [
        "travel, sum of all blades [°]", f"{travel[0]:.4g} → {travel[1]:.4g}"]
    assert [label.get_text().split("\n")[0] for label in pitch.get_yticklabels()][1:] == [
        "largest rate of any blade [°/s]", "largest acceleration of any blade [°/s²]",
        "duty cycle, mean of the blades [%]"]


EVENTS = [{"time": 10.0, "kind": "switch"}, {"time": 10.0, "kind": "switch"}, {"time": 10.0, "kind": "watchdog"},
          {"time": 15.0, "kind": "parameter_change"}, {"time": 20.0, "kind": "intruder"},
          {"time": 25.0, "kind": "contribution_lost"}, {"time": 30.0, "kind": "controller_failed"}]
"""Marked kinds at 10 s (three events), 20, 25 and 30 s; a parameter change (not marked) at 15 s."""
MARKED = [(10.0, "switch, watchdog"), (20.0, "intruder"), (25.0, "contribution_lost"), (30.0, "controller_failed")]


@pytest.mark.parametrize("draw, colour", [
    (lambda runs: plot_compared_time_series(runs, {"b": EVENTS}), "C1"),
    (lambda runs: plot_time_series(runs["b"], EVENTS), "black"),
], ids=["compared runs: in the run's colour", "one run: black"])
def test_switch_and_fault_events_are_vertical_lines_on_every_panel_labelled_by_kind(runs, draw, colour):
    """Each time with marked events is one dotted vertical line on every panel, labelled on the top panel with
    its kinds, each once; other kinds are not marked."""
    axes = draw(runs).axes
    lines = [(time, matplotlib.colors.to_hex(colour)) for time, _ in MARKED]
    for ax in axes:
        assert [(time, matplotlib.colors.to_hex(c)) for time, c in _event_lines(ax)] == lines
    assert [(text.xy[0], text.get_text()) for text in axes[0].texts] == MARKED
    assert all(not ax.texts for ax in axes[1:])


def test_compared_spectra_mark_the_rotor_harmonics_and_scale_to_the_band_shown(runs):
    """Blade-root, hub tilt/yaw and tower-base PSDs of both runs with 1P-6P (of the first run's mean speed) marked;
    the curves stop at 1.25 × 6P, where the frequency axis ends, so the density axis spans only what is seen."""
    frequencies = rotor_harmonic_frequencies(float(runs["a"]["rotor_speed"].mean()), (1, 2, 3, 4, 5, 6))
    axes = plot_compared_spectra(runs).axes
    assert [ax.get_ylabel().split("\n")[0] for ax in axes] == ["PSD root M_oop 1", "PSD hub tilt", "PSD hub yaw",
                                                               "PSD tower base FA"]
    for ax in axes:
        marks = [line for line in ax.lines if line.get_linestyle() == "--"]
        assert np.allclose([line.get_xdata()[0] for line in marks], frequencies)
        assert [text.get_text() for text in ax.texts] == [f"{n}P" for n in range(1, 7)]
        curves = [line for line in ax.lines if line.get_linestyle() == "-"]
        assert [line.get_label() for line in curves] == ["a", "b"]
        assert max(line.get_xdata().max() for line in curves) <= 1.25 * frequencies[-1] == ax.get_xlim()[1]


@pytest.mark.parametrize("draw", [
    lambda runs: plot_compared_time_series(runs, {}),
    lambda runs: plot_time_series(runs["a"]),
    lambda runs: plot_compared_spectra(runs),
    lambda runs: plot_spectra(runs["a"]),
], ids=["compared time series", "time series", "compared spectra", "spectra"])
def test_a_legend_covers_no_trace(runs, draw):
    """Every legend (the runs', the blades') sits outside every panel: the compared time series once had the runs'
    legend over the end of the rotor-speed trace."""
    figure = draw(runs)
    figure.draw_without_rendering()  # lays the figure out
    legends = [ax.get_legend() for ax in figure.axes if ax.get_legend() is not None]
    assert legends
    for legend in legends:
        assert not any(legend.get_window_extent().overlaps(ax.get_window_extent()) for ax in figure.axes)
