"""Figures of ``hawt analyze --report`` and ``hawt compare --report`` (PNG files).

Only drawing lives here; the numbers come from `summary` and `comparison`.
Figures are built on ``matplotlib.figure.Figure`` and rendered by Agg, without
pyplot, so nothing changes matplotlib's global backend. Axes show display units
(MN·m, °, rpm, MW) with the unit in the label; the JSON stays SI.
"""
from collections.abc import Mapping
from pathlib import Path
from types import MappingProxyType

import numpy as np
from matplotlib.figure import Figure
from numpy.typing import ArrayLike

from .record import PER_BLADE_CHANNELS, Record, make_record
from .spectra import power_spectrum, rotor_harmonic_frequencies
from .summary import FATIGUE_CHANNELS, AnalysisOptions

__all__ = [
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


def _fields(record: Record, names: tuple[str, ...]) -> list[tuple[str, np.ndarray]]:
    """(field, values of shape (n_samples, n_columns)) for the fields of ``names`` the record has."""
    present = []
    for name in names:
        if name in record.per_blade:
            present.append((name, record.per_blade[name]))
        elif name in record.scalars:
            present.append((name, record.scalars[name][:, None]))
    return present


def _save(figure: Figure, path: Path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=110)
    return path


def plot_time_series(channels: Mapping[str, ArrayLike], path: Path) -> Path:
    """Time series of rotor speed, power, pitch and the load channels, one panel per field.

    Per-blade fields draw one line per blade. Returns the written PNG path.
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
            ax.legend(loc="upper right", fontsize="small", ncols=values.shape[1])
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    return _save(figure, path)


def _line_label(name: str, column: int) -> str:
    return f"blade {column + 1}" if name in PER_BLADE_CHANNELS else name


def plot_spectra(
    channels: Mapping[str, ArrayLike], path: Path, options: AnalysisOptions = AnalysisOptions()
) -> Path:
    """Welch PSDs of the load channels and pitch with the rotor harmonics nP marked.

    One panel per field (blades overlaid); dashed lines at n·Ω̄/(2π) for the
    harmonics of ``options``. Returns the written PNG path.
    """
    record = make_record(channels)
    fields = _fields(record, tuple(name for name, _ in FATIGUE_CHANNELS) + ("pitch",))
    mean_speed = float(record.scalars["rotor_speed"].mean())
    harmonic_frequencies = rotor_harmonic_frequencies(mean_speed, options.harmonics)
    highest = harmonic_frequencies.max()
    upper = 1.25 * highest if highest > 0.0 else 0.5 * record.sample_rate
    figure = Figure(figsize=(10, 2.0 * max(len(fields), 1) + 0.6), layout="constrained")
    axes = figure.subplots(max(len(fields), 1), 1, sharex=True, squeeze=False)[:, 0]
    for ax, (name, values) in zip(axes, fields):
        factor, quantity, unit = _DISPLAY[name]
        for column in range(values.shape[1]):
            spectrum = power_spectrum(
                factor * values[:, column], record.sample_rate, options.psd_segment_duration
            )
            ax.semilogy(spectrum.frequency, spectrum.density, lw=0.7, label=_line_label(name, column))
        for n, frequency in zip(options.harmonics, harmonic_frequencies):
            ax.axvline(frequency, color="grey", ls="--", lw=0.6)
            ax.annotate(
                f"{n}P", (frequency, 1.0), xycoords=("data", "axes fraction"), fontsize="small", va="bottom"
            )
        ax.set_ylabel(f"PSD {quantity}\n[{unit}²/Hz]")
        if values.shape[1] > 1:
            ax.legend(loc="upper right", fontsize="small", ncols=values.shape[1])
        ax.grid(alpha=0.3, which="both")
    axes[-1].set_xlim(0.0, upper)
    axes[-1].set_xlabel("frequency [Hz]")
    return _save(figure, path)


def plot_del_bars(summary: Mapping, path: Path) -> Path:
    """Horizontal bars of the DEL of each load channel [MN·m], labelled with m. Returns the PNG path."""
    names = list(summary["del"])
    values = [1e-6 * summary["del"][name]["value"] for name in names]
    labels = [f"{name} (m={summary['del'][name]['m']:g})" for name in names]
    figure = Figure(figsize=(8, 0.4 * len(names) + 1.2), layout="constrained")
    ax = figure.subplots()
    ax.barh(labels, values, color="tab:blue")
    ax.invert_yaxis()
    ax.set_xlabel("damage-equivalent load, 1 Hz [MN·m]")
    ax.grid(alpha=0.3, axis="x")
    return _save(figure, path)


def plot_comparison(comparison: Mapping, path: Path) -> Path:
    """Grouped bars of the change against the first run [%]: DELs and pitch activity.

    Returns the written PNG path.
    """
    rows = [(f"DEL {name}", entry["change_percent"]) for name, entry in comparison["del"].items()]
    if comparison["pitch"] is not None:
        rows += [
            (f"pitch {metric}", entry["change_percent"]) for metric, entry in comparison["pitch"].items()
        ]
    runs = comparison["labels"][1:]
    figure = Figure(figsize=(9, 0.35 * len(rows) * max(len(runs), 1) + 1.5), layout="constrained")
    ax = figure.subplots()
    height = 0.8 / max(len(runs), 1)
    positions = np.arange(len(rows))
    for k, label in enumerate(runs):
        changes = [np.nan if change[k + 1] is None else change[k + 1] for _, change in rows]
        bars = ax.barh(positions + k * height, changes, height=height, label=label)
        ax.bar_label(bars, fmt="%+.1f", fontsize="x-small", padding=2)
    ax.set_yticks(positions + 0.5 * height * (len(runs) - 1), [name for name, _ in rows])
    ax.invert_yaxis()
    ax.axvline(0.0, color="black", lw=0.8)
    low, high = ax.get_xlim()
    pad = 0.12 * (high - low)
    ax.set_xlim(low - pad, high + pad)
    ax.set_xlabel(f"change against {comparison['reference']} [%]")
    ax.grid(alpha=0.3, axis="x")
    if runs:
        ax.legend(fontsize="small")
    return _save(figure, path)


def write_report(
    channels: Mapping[str, ArrayLike],
    summary: Mapping,
    directory: Path,
    options: AnalysisOptions = AnalysisOptions(),
) -> list[Path]:
    """Write ``time_series.png``, ``spectra.png`` and ``del.png`` into ``directory``, and for a two-bladed rotor
    Zalkind & Pao's Fig. 8 (``main_bearing_fig8.png``, `hawt_analysis.two_bladed`); return their paths."""
    directory = Path(directory)
    images = [
        plot_time_series(channels, directory / "time_series.png"),
        plot_spectra(channels, directory / "spectra.png", options),
        plot_del_bars(summary, directory / "del.png"),
    ]
    if summary.get("n_blades") == 2 and {"hub_tilt_moment", "hub_yaw_moment"} <= set(channels):
        from .two_bladed import main_bearing_history, plot_fig8

        images.append(plot_fig8(main_bearing_history(channels), directory / "main_bearing_fig8.png"))
    return images


COMPARED_FIELDS = ("rotor_speed", "pitch", "root_moment_oop", "hub_tilt_moment", "hub_yaw_moment",
                   "tower_base_fa_moment")
"""What the overlays of several runs show (per-blade fields: blade 1)."""

MARKED_EVENTS = ("switch", "watchdog", "controller_failed", "contribution_lost", "contribution_returned",
                 "node_died", "node_respawn", "invalid_input")
"""Event kinds the time-series overlay marks."""


def _compared(runs: Mapping[str, Mapping[str, ArrayLike]], names: tuple[str, ...]):
    """(label, record, {field: blade-1 or scalar values}) per run, for the fields of ``names`` it has."""
    for label, channels in runs.items():
        record = make_record(channels)
        yield label, record, {name: values[:, 0] for name, values in _fields(record, names)}


def plot_compared_time_series(runs: Mapping[str, Mapping[str, ArrayLike]], events: Mapping[str, list],
                              path: Path) -> Path:
    """Rotor speed, pitch, blade-1 root moment, hub and tower loads of every run overlaid on one time axis, each
    run's events of MARKED_EVENTS as vertical lines in its colour. Returns the PNG path."""
    figure = Figure(figsize=(10, 1.7 * len(COMPARED_FIELDS) + 0.6), layout="constrained")
    axes = dict(zip(COMPARED_FIELDS, figure.subplots(len(COMPARED_FIELDS), 1, sharex=True, squeeze=False)[:, 0]))
    for k, (label, record, fields) in enumerate(_compared(runs, COMPARED_FIELDS)):
        colour = f"C{k}"
        for name, values in fields.items():
            axes[name].plot(record.time, _DISPLAY[name][0] * values, lw=0.6, color=colour, label=label)
        for event in events.get(label, ()):
            if event["kind"] in MARKED_EVENTS and event.get("time") is not None:
                for ax in axes.values():
                    ax.axvline(event["time"], color=colour, ls=":", lw=0.8)
                axes[COMPARED_FIELDS[0]].annotate(event["kind"], (event["time"], 1.0),
                                                  xycoords=("data", "axes fraction"), fontsize="x-small",
                                                  rotation=90, va="top", color=colour)
    for name, ax in axes.items():
        factor, quantity, unit = _DISPLAY[name]
        ax.set_ylabel(f"{quantity}{' 1' if name in PER_BLADE_CHANNELS else ''} [{unit}]")
        ax.grid(alpha=0.3)
    axes[COMPARED_FIELDS[-1]].set_xlabel("time [s]")
    axes[COMPARED_FIELDS[0]].legend(loc="lower right", fontsize="small", ncols=len(runs))
    return _save(figure, path)


def plot_compared_spectra(runs: Mapping[str, Mapping[str, ArrayLike]], path: Path,
                          options: AnalysisOptions = AnalysisOptions()) -> Path:
    """Welch PSDs of the blade-1 root moment, hub tilt/yaw and tower-base fore-aft moment of every run overlaid,
    the rotor harmonics nP of the first run's mean speed marked. Returns the PNG path."""
    names = COMPARED_FIELDS[2:]
    figure = Figure(figsize=(10, 2.0 * len(names) + 0.6), layout="constrained")
    axes = dict(zip(names, figure.subplots(len(names), 1, sharex=True, squeeze=False)[:, 0]))
    upper = None
    for label, record, fields in _compared(runs, names):
        if upper is None:
            frequencies = rotor_harmonic_frequencies(float(record.scalars["rotor_speed"].mean()), options.harmonics)
            upper = 1.25 * frequencies.max()
            for ax in axes.values():
                for n, frequency in zip(options.harmonics, frequencies):
                    ax.axvline(frequency, color="grey", ls="--", lw=0.6)
                    ax.annotate(f"{n}P", (frequency, 1.0), xycoords=("data", "axes fraction"), fontsize="small",
                                va="bottom")
        for name, values in fields.items():
            spectrum = power_spectrum(_DISPLAY[name][0] * values, record.sample_rate, options.psd_segment_duration)
            axes[name].semilogy(spectrum.frequency, spectrum.density, lw=0.7, label=label)
    for name, ax in axes.items():
        _, quantity, unit = _DISPLAY[name]
        ax.set_ylabel(f"PSD {quantity}{' 1' if name in PER_BLADE_CHANNELS else ''}\n[{unit}²/Hz]")
        ax.grid(alpha=0.3, which="both")
    axes[names[0]].legend(loc="upper right", fontsize="small")
    axes[names[-1]].set_xlim(0.0, upper)
    axes[names[-1]].set_xlabel("frequency [Hz]")
    return _save(figure, path)


def write_comparison_report(comparison: Mapping, directory: Path,
                            runs: Mapping[str, Mapping[str, ArrayLike]] = MappingProxyType({}),
                            events: Mapping[str, list] = MappingProxyType({})) -> list[Path]:
    """Write ``comparison.png`` (changes against the first run) into ``directory`` and, given the runs' channels
    by label (and their events), ``compared_time_series.png`` and ``compared_spectra.png``; return the paths."""
    directory = Path(directory)
    paths = [plot_comparison(comparison, directory / "comparison.png")]
    if runs:
        paths += [plot_compared_time_series(runs, events, directory / "compared_time_series.png"),
                  plot_compared_spectra(runs, directory / "compared_spectra.png")]
    return paths
