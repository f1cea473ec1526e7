"""The report of a load campaign: one HTML page with its tables and plots (``hawt campaign`` writes it).

Plots: the DEL of the main load channels against wind speed per controller (mean over seeds, each
seed a dot), the lifetime DEL of each channel relative to the first controller (one axis, bars), and
pitch activity against wind speed. Rows are the per-case dicts of ``hawt_tools.campaign``; the
lifetime table is ``hawt_tools.campaign.lifetime_table``'s.
"""
import math
from pathlib import Path
from typing import Any, Dict, List, Mapping, Sequence, Tuple

import numpy as np

from .analysis_report import write_html_page

__all__ = ["MAIN_CHANNELS", "lifetime_text", "write_campaign_report"]

MAIN_CHANNELS = {"root_moment_oop_1": "blade 1 root out-of-plane", "hub_tilt_moment": "hub tilt",
                 "hub_yaw_moment": "hub yaw", "tower_base_fa_moment": "tower base fore-aft",
                 "tower_base_ss_moment": "tower base side-side"}
"""The channels the report plots and the summary prints, with their names for people."""


def _controllers(rows: Sequence[Mapping[str, Any]]) -> List[str]:
    return list(dict.fromkeys(row["controller"] for row in rows))


def _by_speed(rows: Sequence[Mapping[str, Any]], controller: str, column: str):
    speeds = sorted({row["wind_speed"] for row in rows if row["controller"] == controller})
    values = [[row[column] for row in rows if row["controller"] == controller and row["wind_speed"] == speed]
              for speed in speeds]
    return np.array(speeds), values


def _incomplete(lifetime: Sequence[Mapping[str, Any]]) -> Dict[Tuple[str, str], List[str]]:
    """The controllers of each incomplete campaign in the entries, by its (``cases``, ``missing``); entries read back
    from a ``lifetime.csv`` written before campaigns said so have neither."""
    found: Dict[Tuple[str, str], List[str]] = {}
    for entry in lifetime:
        cases = entry.get("cases")
        if isinstance(cases, str) and cases.startswith("incomplete"):
            names = found.setdefault((cases, str(entry.get("missing"))), [])
            if entry["controller"] not in names:
                names.append(entry["controller"])
    return found


def lifetime_text(lifetime: Sequence[Mapping[str, Any]]) -> str:
    """The lifetime DEL of the main channels and the AEP per controller, changes against the first, as text; first a
    line ``incomplete: N of M cases (missing: …)`` per incomplete campaign (naming its controllers when the entries
    hold more than its own, as ``hawt compare`` of campaign folders does)."""
    controllers = list(dict.fromkeys(entry["controller"] for entry in lifetime))
    value = {(e["controller"], e["quantity"]): e["value"] for e in lifetime}
    quantities = [(f"lifetime DEL {c}", f"{name} DEL [MN*m]", 1e-6) for c, name in MAIN_CHANNELS.items()]
    quantities.append(("AEP [J]", "AEP [GWh]", 1 / 3.6e12))
    lines = [("" if names == controllers else f"{', '.join(names)}: ") + f"{cases} (missing: {missing})"
             for (cases, missing), names in _incomplete(lifetime).items()]
    lines.append(f"{'':38s}" + "".join(f"{name:>24s}" for name in controllers))
    for quantity, label, factor in quantities:
        base = value.get((controllers[0], quantity), math.nan)
        cells = []
        for name in controllers:
            number = value.get((name, quantity), math.nan)
            change = f" ({100 * (number / base - 1):+6.1f}%)" if name != controllers[0] and base else " " * 10
            cells.append(f"{number * factor:10.4g}{change}")
        lines.append(f"{label:38s}" + "".join(f"{cell:>24s}" for cell in cells))
    return "\n".join(lines)


def _figure_del_against_speed(rows, path: Path) -> Path:
    from matplotlib.figure import Figure

    figure = Figure(figsize=(11, 2.6 * math.ceil(len(MAIN_CHANNELS) / 2)), layout="constrained")
    axes = figure.subplots(math.ceil(len(MAIN_CHANNELS) / 2), 2).ravel()
    for ax, (channel, name) in zip(axes, MAIN_CHANNELS.items()):
        for controller in _controllers(rows):
            speeds, values = _by_speed(rows, controller, f"del.{channel}")
            line, = ax.plot(speeds, [np.mean(v) / 1e6 for v in values], "o-", label=controller)
            for speed, seeds in zip(speeds, values):
                ax.plot([speed] * len(seeds), np.array(seeds) / 1e6, ".", color=line.get_color(), alpha=0.4)
        ax.set(title=f"{name} DEL", xlabel="wind speed [m/s]", ylabel="DEL [MN·m]")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    for ax in axes[len(MAIN_CHANNELS):]:
        ax.set_visible(False)
    figure.savefig(path, dpi=90)
    return path


def _figure_lifetime(lifetime, path: Path) -> Path:
    from matplotlib.figure import Figure

    controllers = list(dict.fromkeys(entry["controller"] for entry in lifetime))
    value = {(e["controller"], e["quantity"]): e["value"] for e in lifetime}
    figure = Figure(figsize=(11, 3.6), layout="constrained")
    ax = figure.subplots()
    width = 0.8 / max(1, len(controllers) - 1)
    for i, controller in enumerate(controllers[1:]):
        changes = [100 * (value[(controller, f"lifetime DEL {c}")] / value[(controllers[0], f"lifetime DEL {c}")] - 1)
                   for c in MAIN_CHANNELS]
        ax.bar(np.arange(len(MAIN_CHANNELS)) + (i - (len(controllers) - 2) / 2) * width, changes, width,
               label=controller)
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_xticks(np.arange(len(MAIN_CHANNELS)), list(MAIN_CHANNELS.values()), fontsize=8)
    ax.set(ylabel=f"lifetime DEL change against {controllers[0]} [%]")
    ax.legend(fontsize=8)
    ax.grid(axis="y", alpha=0.3)
    figure.savefig(path, dpi=90)
    return path


def _figure_pitch(rows, path: Path) -> Path:
    from matplotlib.figure import Figure

    figure = Figure(figsize=(11, 3.2), layout="constrained")
    travel, rate = figure.subplots(1, 2)
    for controller in _controllers(rows):
        speeds, values = _by_speed(rows, controller, "pitch.travel")
        travel.plot(speeds, [np.degrees(np.mean(v)) for v in values], "o-", label=controller)
        speeds, values = _by_speed(rows, controller, "pitch.max_command_rate")
        rate.plot(speeds, [np.degrees(np.max(v)) for v in values], "o-", label=controller)
    travel.set(title="pitch travel (all blades, analysed time)", xlabel="wind speed [m/s]", ylabel="[deg]")
    rate.set(title="largest commanded pitch rate", xlabel="wind speed [m/s]", ylabel="[deg/s]")
    for ax in (travel, rate):
        ax.grid(alpha=0.3)
    travel.legend(fontsize=8)
    figure.savefig(path, dpi=90)
    return path


def write_campaign_report(title: str, rows: Sequence[Mapping[str, Any]], lifetime: Sequence[Mapping[str, Any]],
                          directory: Path, tables: Mapping[str, Path]) -> Path:
    """Write ``report.html`` and its PNGs into ``directory``; return the page. The title of an incomplete campaign
    ends with ``incomplete: N of M cases``, and the missing cases head the text."""
    title = " — ".join([title, *dict.fromkeys(cases for cases, _ in _incomplete(lifetime))])
    images = [_figure_del_against_speed(rows, directory / "DEL_against_wind_speed.png"),
              _figure_lifetime(lifetime, directory / "lifetime_DEL_change.png"),
              _figure_pitch(rows, directory / "pitch_activity.png")]
    return write_html_page(directory / "report.html", title, lifetime_text(lifetime), images,
                           [path.name for path in tables.values()])
