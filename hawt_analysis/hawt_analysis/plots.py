"""Figures of ``hawt analyze --report`` and ``hawt compare --report`` (PNG files).

Only drawing lives here; the numbers come from `summary` and `comparison`.
Each ``plot_*`` function returns a ``matplotlib.figure.Figure``, built without
pyplot, so nothing changes matplotlib's global backend; `write_report` and
`write_comparison_report` render them by Agg into PNG files. Axes show display units
(MN·m, °, rpm, MW) with the unit in the label; the JSON stays SI. Legends of line plots sit right
of their panel, outside it, so that they cover no trace; a report page heads each figure with
its `FIGURE_HEADINGS`.
"""
from collections.abc import Mapping, Sequence
from pathlib import Path
from types import MappingProxyType

import numpy as np
from matplotlib.figure import Figure
from numpy.typing import ArrayLike

from .analysis_report import PITCH_METRICS
from .comparison import compare_summaries
from .record import PER_BLADE_CHANNELS, Record, make_record
from .spectra import power_spectrum, rotor_harmonic_frequencies
from .summary import FATIGUE_CHANNELS, AnalysisOptions

__all__ = [
    "FIGURE_HEADINGS",
    "plot_compared_spectra",
    "plot_compared_time_series",
    "plot_comparison",
    "plot_del_bars",
    "plot_spectra",
    "plot_time_series",
    "write_comparison_report",
    "write_report",
]

_DISPLAY = MappingProxyType(
    {
        "rotor_speed": (60.0 / (2.0 * np.pi), "rotor speed", "rpm"),
        "electrical_power": (1e-6, "electrical power", "MW"),
        "pitch": (180.0 / np.pi, "pitch", "°"),
        "root_moment_oop": (1e-6, "root M_oop", "MN·m"),
        "root_moment_ip": (1e-6, "root M_ip", "MN·m"),
        "hub_tilt_moment": (1e-6, "hub tilt", "MN·m"),
        "hub_yaw_moment": (1e-6, "hub yaw", "MN·m"),
        "hub_rotating_y_moment": (1e-6, "hub rotating y", "MN·m"),
        "hub_rotating_z_moment": (1e-6, "hub rotating z", "MN·m"),
        "yaw_bearing_tilt_moment": (1e-6, "yaw bearing tilt", "MN·m"),
        "yaw_bearing_yaw_moment": (1e-6, "yaw bearing yaw", "MN·m"),
        "tower_base_fa_moment": (1e-6, "tower base FA", "MN·m"),
        "tower_base_ss_moment": (1e-6, "tower base SS", "MN·m"),
    }
)
"""Field → (factor from SI to display unit, quantity, display unit)."""

FIGURE_HEADINGS = MappingProxyType({
    "time_series.png": "rotor speed, power, pitch and loads over time",
    "spectra.png": "power spectral densities of the loads and the pitch, rotor harmonics marked",
    "del.png": "damage-equivalent loads (1 Hz)",
    "main_bearing_fig8.png": "hub 1P, IPC 1P and main-bearing 2P over time (Zalkind & Pao, Fig. 8)",
    "comparison.png": "changes against the first run: damage-equivalent loads and pitch activity",
    "compared_time_series.png": "the runs over time: rotor speed, pitch, blade 1 root, hub and tower loads",
    "compared_spectra.png": "the runs' power spectral densities: blade 1 root, hub and tower moments",
})
"""The heading of each figure `write_report` and `write_comparison_report` write, by file name."""


def _fields(record: Record, names: tuple[str, ...]) -> list[tuple[str, np.ndarray]]:
    """(field, values of shape (n_samples, n_columns)) for the fields of ``names`` the record has."""
    present = []
    for name in names:
        if name in record.per_blade:
            present.append((name, record.per_blade[name]))
        elif name in record.scalars:
            present.append((name, record.scalars[name][:, None]))
    return present


def _legend_beside(ax) -> None:
    """The legend of ``ax``'s lines right of it, outside the panel (so that it covers no trace); the figure's
    constrained layout narrows the panels to make room."""
    ax.legend(loc="upper left", bbox_to_anchor=(1.005, 1.0), fontsize="small")


def _save(figure: Figure, path: Path) -> Path:
    """Render ``figure`` into the PNG file ``path`` (its folder made if missing); return the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=110)
    return path


def plot_time_series(channels: Mapping[str, ArrayLike], events: Sequence[Mapping] = ()) -> Figure:
    """Time series of rotor speed, power, pitch and the load channels, one panel per field.

    Per-blade fields draw one line per blade, labelled beside the panel; the ``events`` (``time``, ``kind``) of
    MARKED_EVENTS are vertical lines, labelled by kind.
    """
    record = make_record(channels)
    names = ("rotor_speed", "electrical_power", "pitch") + tuple(name for name, _ in FATIGUE_CHANNELS)
    fields = _fields(record, names)
    figure = Figure(figsize=(10, 1.7 * len(fields) + 0.6), layout="constrained")
    axes = figure.subplots(len(fields), 1, sharex=True, squeeze=False)[:, 0]
    for ax, (name, values) in zip(axes, fields):
        factor, quantity, unit = _DISPLAY[name]
        for column in range(values.shape[1]):
            ax.plot(record.time, factor * values[:, column], lw=0.6, label=_line_label(name, column))
        ax.set_ylabel(f"{quantity} [{unit}]")
        if values.shape[1] > 1:
            _legend_beside(ax)
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    _mark_events(axes, events, "black")
    return figure


def _line_label(name: str, column: int) -> str:
    return f"blade {column + 1}" if name in PER_BLADE_CHANNELS else name


def _plot_psd(ax, values: np.ndarray, sample_rate: float, options: AnalysisOptions, upper: float, label: str) -> None:
    """The Welch PSD of ``values`` on a log axis up to ``upper`` [Hz] (so that the axis scales to what is shown)."""
    spectrum = power_spectrum(values, sample_rate, options.psd_segment_duration)
    shown = spectrum.frequency <= upper
    ax.semilogy(spectrum.frequency[shown], spectrum.density[shown], lw=0.7, label=label)


def _mark_harmonics(axes: Sequence, harmonics: Sequence[int], frequencies: np.ndarray) -> None:
    """Dashed lines at the rotor harmonics' frequencies on every axis, labelled nP above it."""
    for ax in axes:
        for n, frequency in zip(harmonics, frequencies):
            ax.axvline(frequency, color="grey", ls="--", lw=0.6)
            ax.annotate(f"{n}P", (frequency, 1.0), xycoords=("data", "axes fraction"), fontsize="small", va="bottom")


def plot_spectra(channels: Mapping[str, ArrayLike], options: AnalysisOptions = AnalysisOptions()) -> Figure:
    """Welch PSDs of the load channels and pitch with the rotor harmonics nP marked.

    One panel per field (blades overlaid); dashed lines at n·Ω̄/(2π) for the
    harmonics of ``options``.
    """
    record = make_record(channels)
    fields = _fields(record, tuple(name for name, _ in FATIGUE_CHANNELS) + ("pitch",))
    mean_speed = float(record.scalars["rotor_speed"].mean())
    harmonic_frequencies = rotor_harmonic_frequencies(mean_speed, options.harmonics)
    highest = harmonic_frequencies.max()
    upper = 1.25 * highest if highest > 0.0 else 0.5 * record.sample_rate
    figure = Figure(figsize=(10, 2.0 * max(len(fields), 1) + 0.6), layout="constrained")
    axes = figure.subplots(max(len(fields), 1), 1, sharex=True, squeeze=False)[:, 0]
    _mark_harmonics(axes, options.harmonics, harmonic_frequencies)
    for ax, (name, values) in zip(axes, fields):
        factor, quantity, unit = _DISPLAY[name]
        for column in range(values.shape[1]):
            _plot_psd(ax, factor * values[:, column], record.sample_rate, options, upper, _line_label(name, column))
        ax.set_ylabel(f"PSD {quantity}\n[{unit}²/Hz]")
        if values.shape[1] > 1:
            _legend_beside(ax)
        ax.grid(alpha=0.3, which="both")
    axes[-1].set_xlim(0.0, upper)
    axes[-1].set_xlabel("frequency [Hz]")
    return figure


def _grouped_bars(ax, names: Sequence[str], values: Sequence[Sequence[float]], runs: Sequence[str],
                  fmt: str) -> None:
    """Horizontal bars on ``ax``: one group per name (top to bottom), one bar per run (``values[k]`` of run k, NaN
    for none), each labelled with its value by ``fmt``."""
    height = 0.8 / max(len(runs), 1)
    positions = np.arange(len(names))
    for k, label in enumerate(runs):
        bars = ax.barh(positions + k * height, values[k], height=height, label=label)
        ax.bar_label(bars, fmt=fmt, fontsize="x-small", padding=2)
    ax.set_yticks(positions + 0.5 * height * (len(runs) - 1), names)
    ax.invert_yaxis()
    low, high = ax.get_xlim()
    pad = 0.12 * (high - low)  # room for the value labels
    ax.set_xlim(low - pad if low < 0.0 else low, high + pad)
    ax.grid(alpha=0.3, axis="x")


def plot_del_bars(comparison: Mapping) -> Figure:
    """Grouped bars of the DELs [MN·m]: one group per load channel (labelled with its Wöhler exponent m), one bar
    per run of ``comparison`` (`compare_summaries`; a comparison of one summary draws one bar per channel)."""
    names, runs = list(comparison["del"]), comparison["labels"]
    values = [[1e-6 * comparison["del"][name]["value"][k] for name in names] for k in range(len(runs))]
    figure = Figure(figsize=(9, 0.3 * len(names) * len(runs) + 1.2), layout="constrained")
    ax = figure.subplots()
    _grouped_bars(ax, [f"{name} (m={comparison['del'][name]['m']:g})" for name in names], values, runs, "%.3g")
    ax.set_xlabel("damage-equivalent load, 1 Hz [MN·m]")
    if len(runs) > 1:
        ax.legend(fontsize="small")
    return figure


def _pitch_label(metric: str, values: Sequence[float]) -> str:
    """A pitch-activity bar's label: its name and display unit as the text tables give them, then each run's value
    (``travel, sum of all blades [°]`` over ``23.02 → 246.5``)."""
    factor, unit, name = PITCH_METRICS[metric]
    return f"{name} [{unit}]\n" + " → ".join(f"{factor * value:.4g}" for value in values)


def plot_comparison(comparison: Mapping) -> Figure:
    """Grouped bars of the change against the first run [%], the DELs on one axis and the pitch activity on
    another (each axis scaled to its own changes), each pitch quantity labelled with its unit and the runs' values."""
    runs = comparison["labels"][1:]
    panels = [("DEL", comparison["del"], list(comparison["del"]))]
    if comparison["pitch"] is not None:
        panels.append(("pitch activity", comparison["pitch"],
                       [_pitch_label(metric, entry["value"]) for metric, entry in comparison["pitch"].items()]))
    sizes = [len(entries) for _, entries, _ in panels]
    figure = Figure(figsize=(9, 0.35 * sum(sizes) * max(len(runs), 1) + 1.3 * len(panels)), layout="constrained")
    axes = figure.subplots(len(panels), 1, squeeze=False, height_ratios=sizes)[:, 0]
    for ax, (quantity, entries, names) in zip(axes, panels):
        changes = [[np.nan if entry["change_percent"][k] is None else entry["change_percent"][k]
                    for entry in entries.values()] for k in range(1, len(runs) + 1)]
        ax.axvline(0.0, color="black", lw=0.8)
        _grouped_bars(ax, names, changes, runs, "%+.1f")
        ax.set_xlabel(f"{quantity}: change against {comparison['reference']} [%]")
    if runs:
        axes[0].legend(fontsize="small")
    return figure


def write_report(
    channels: Mapping[str, ArrayLike],
    summary: Mapping,
    directory: Path,
    options: AnalysisOptions = AnalysisOptions(),
) -> list[Path]:
    """Write ``time_series.png`` (the summary's ``events`` marked, if it has them), ``spectra.png`` and ``del.png``
    into ``directory``, and for a two-bladed rotor Zalkind & Pao's Fig. 8 (``main_bearing_fig8.png``,
    `hawt_analysis.two_bladed`); return their paths."""
    directory = Path(directory)
    figures = {"time_series.png": plot_time_series(channels, summary.get("events") or ()),
               "spectra.png": plot_spectra(channels, options),
               "del.png": plot_del_bars(compare_summaries([summary], ["run"]))}
    images = [_save(figure, directory / name) for name, figure in figures.items()]
    if summary.get("n_blades") == 2 and {"hub_tilt_moment", "hub_yaw_moment"} <= set(channels):
        from .two_bladed import main_bearing_history, plot_fig8

        images.append(plot_fig8(main_bearing_history(channels), directory / "main_bearing_fig8.png"))
    return images


COMPARED_FIELDS = ("rotor_speed", "pitch", "root_moment_oop", "hub_tilt_moment", "hub_yaw_moment",
                   "tower_base_fa_moment")
"""What the overlays of several runs show (per-blade fields: blade 1)."""

MARKED_EVENTS = ("switch", "watchdog", "intruder", "controller_failed", "contribution_lost", "contribution_returned",
                 "node_died", "node_respawn", "invalid_input", "protection_warning", "protection_trip")
"""Event kinds the time series mark."""


def _mark_events(axes: Sequence, events: Sequence[Mapping], colour: str) -> None:
    """Dotted vertical lines in ``colour`` on every axis at the times of the ``events`` of MARKED_EVENTS, labelled
    on the first axis with their kinds (events at one time: one line, its label each kind once)."""
    kinds: dict[float, dict[str, None]] = {}
    for event in events:
        if event["kind"] in MARKED_EVENTS and event.get("time") is not None:
            kinds.setdefault(event["time"], {})[event["kind"]] = None
    for time, names in kinds.items():
        for ax in axes:
            ax.axvline(time, color=colour, ls=":", lw=0.8)
        axes[0].annotate(", ".join(names), (time, 1.0), xycoords=("data", "axes fraction"), fontsize="x-small",
                         rotation=90, ha="right", va="top", color=colour)


def _compared(runs: Mapping[str, Mapping[str, ArrayLike]], names: tuple[str, ...]):
    """(label, record, {field: blade-1 or scalar values}) per run, for the fields of ``names`` it has."""
    for label, channels in runs.items():
        record = make_record(channels)
        yield label, record, {name: values[:, 0] for name, values in _fields(record, names)}


def plot_compared_time_series(runs: Mapping[str, Mapping[str, ArrayLike]], events: Mapping[str, list]) -> Figure:
    """Rotor speed, pitch, blade-1 root moment, hub and tower loads of every run overlaid on one time axis, each
    run's events of MARKED_EVENTS as vertical lines in its colour, labelled by kind."""
    figure = Figure(figsize=(10, 1.7 * len(COMPARED_FIELDS) + 0.6), layout="constrained")
    axes = dict(zip(COMPARED_FIELDS, figure.subplots(len(COMPARED_FIELDS), 1, sharex=True, squeeze=False)[:, 0]))
    for k, (label, record, fields) in enumerate(_compared(runs, COMPARED_FIELDS)):
        colour = f"C{k}"
        for name, values in fields.items():
            axes[name].plot(record.time, _DISPLAY[name][0] * values, lw=0.6, color=colour, label=label)
        _mark_events(list(axes.values()), events.get(label, ()), colour)
    for name, ax in axes.items():
        factor, quantity, unit = _DISPLAY[name]
        ax.set_ylabel(f"{quantity}{' 1' if name in PER_BLADE_CHANNELS else ''} [{unit}]")
        ax.grid(alpha=0.3)
    axes[COMPARED_FIELDS[-1]].set_xlabel("time [s]")
    _legend_beside(axes[COMPARED_FIELDS[0]])
    return figure


def plot_compared_spectra(runs: Mapping[str, Mapping[str, ArrayLike]],
                          options: AnalysisOptions = AnalysisOptions()) -> Figure:
    """Welch PSDs of the blade-1 root moment, hub tilt/yaw and tower-base fore-aft moment of every run overlaid,
    the rotor harmonics nP of the first run's mean speed marked."""
    names = COMPARED_FIELDS[2:]
    figure = Figure(figsize=(10, 2.0 * len(names) + 0.6), layout="constrained")
    axes = dict(zip(names, figure.subplots(len(names), 1, sharex=True, squeeze=False)[:, 0]))
    upper = None
    for label, record, fields in _compared(runs, names):
        if upper is None:
            frequencies = rotor_harmonic_frequencies(float(record.scalars["rotor_speed"].mean()), options.harmonics)
            upper = 1.25 * frequencies.max()
            _mark_harmonics(list(axes.values()), options.harmonics, frequencies)
        for name, values in fields.items():
            _plot_psd(axes[name], _DISPLAY[name][0] * values, record.sample_rate, options, upper, label)
    for name, ax in axes.items():
        _, quantity, unit = _DISPLAY[name]
        ax.set_ylabel(f"PSD {quantity}{' 1' if name in PER_BLADE_CHANNELS else ''}\n[{unit}²/Hz]")
        ax.grid(alpha=0.3, which="both")
    _legend_beside(axes[names[0]])
    axes[names[-1]].set_xlim(0.0, upper)
    axes[names[-1]].set_xlabel("frequency [Hz]")
    return figure


def write_comparison_report(comparison: Mapping, directory: Path,
                            runs: Mapping[str, Mapping[str, ArrayLike]] = MappingProxyType({}),
                            events: Mapping[str, list] = MappingProxyType({})) -> list[Path]:
    """Write ``del.png`` (each run's DELs) and ``comparison.png`` (changes against the first run) into ``directory``
    and, given the runs' channels by label (and their events), ``compared_time_series.png`` and
    ``compared_spectra.png``; return the paths."""
    figures = {"del.png": plot_del_bars(comparison), "comparison.png": plot_comparison(comparison)}
    if runs:
        figures |= {"compared_time_series.png": plot_compared_time_series(runs, events),
                    "compared_spectra.png": plot_compared_spectra(runs)}
    return [_save(figure, Path(directory) / name) for name, figure in figures.items()]
