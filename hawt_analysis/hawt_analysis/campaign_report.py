"""The report of a load campaign: one HTML page with its tables and plots (``hawt campaign`` writes it).

Plots: the DEL of the main load channels (`main_channels`: every blade's root, hub and tower base)
against wind speed per controller (mean over seeds, each seed a dot), the lifetime DEL of each channel
relative to the first controller (one axis, bars), and pitch activity against wind speed. Rows are the
per-case dicts of ``hawt_tools.campaign``; the lifetime table is ``hawt_tools.campaign.lifetime_table``'s.
"""
import math
import re
import textwrap
from pathlib import Path
from typing import Any, Dict, Iterable, List, Mapping, Sequence, Tuple

import numpy as np

from .analysis_report import changes_table, write_html_page

__all__ = ["lifetime_text", "ultimate_text", "main_channels", "write_campaign_report"]

_BLADE_ROOT = re.compile(r"root_moment_oop_(\d+)")
_ROTOR_CHANNELS = {"hub_tilt_moment": "hub tilt", "hub_yaw_moment": "hub yaw",
                   "tower_base_fa_moment": "tower base fore-aft", "tower_base_ss_moment": "tower base side-side"}


def main_channels(channels: Iterable[str]) -> Dict[str, str]:
    """The channels among ``channels`` the report plots and the summary prints, with their names for people: every
    blade's root out-of-plane moment (a blade may differ from the others: a campaign once cut blade 1's lifetime DEL
    by 19.3 % and blade 3's by 0.3 %), then the hub's tilt and yaw and the tower base's fore-aft and side-side."""
    present = set(channels)
    blades = sorted(int(found.group(1)) for found in map(_BLADE_ROOT.fullmatch, present) if found)
    return {**{f"root_moment_oop_{blade}": f"blade {blade} root out-of-plane" for blade in blades},
            **{channel: name for channel, name in _ROTOR_CHANNELS.items() if channel in present}}


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
    quantities = [(f"lifetime DEL {c}", f"{name} DEL", 1e-6, "MN·m") for c, name in _lifetime_channels(value).items()]
    quantities.append(("AEP [J]", "AEP", 1 / 3.6e12, "GWh"))
    lines = [("" if names == controllers else f"{', '.join(names)}: ") + f"{cases} (missing: {missing})"
             for (cases, missing), names in _incomplete(lifetime).items()]
    rows = [(label, [value.get((name, quantity), math.nan) for name in controllers], factor, unit)
            for quantity, label, factor, unit in quantities]
    return "\n".join(lines + changes_table("", controllers, rows))


def ultimate_text(ultimate: Sequence[Mapping[str, Any]], over: Sequence[str] = ()) -> str:
    """The design loads γ_f·F_k (magnitudes) of the main channels per controller, changes against the first, then
    what governs each: the case, or the extrapolation with its interval (``hawt_tools.campaign.ultimate_table``);
    ``over`` names the DLCs a table of :func:`hawt_analysis.ultimate.governing_loads` was taken over, and each
    governing case then its DLC."""
    if not ultimate:
        return ""
    controllers = list(dict.fromkeys(entry["controller"] for entry in ultimate))
    entry_of = {(entry["controller"], entry["channel"]): entry for entry in ultimate}
    channels = main_channels(entry["channel"] for entry in ultimate)
    rows = [(f"{name} design", [abs(entry_of[(c, channel)]["design"]) if (c, channel) in entry_of else math.nan
                                for c in controllers], 1e-6, "MN·m") for channel, name in channels.items()]
    dlcs = list(over) or sorted({str(entry["dlc"]) for entry in ultimate}, key=float)
    first = ultimate[0]
    several = len(dlcs) > 1
    lines = [f"ultimate loads over DLC {', '.join(dlcs)}: design load = the largest γ_f × characteristic load"
             if several else
             f"ultimate loads, DLC {first['dlc']}: design load = γ_f {first['factor']:g} × characteristic load"]
    lines += changes_table("", controllers, rows) + ["governed by:"]
    lines += [f"  {c}, {name}: " + (f"DLC {e['dlc']} (γ_f {e['factor']:g}), " if several else "")
              + f"{e['case']} ({e['basis']})"
              for c in controllers for channel, name in channels.items() if (e := entry_of.get((c, channel)))]
    return "\n".join(lines)


def _lifetime_channels(value: Mapping[Tuple[str, str], float]) -> Dict[str, str]:
    """`main_channels` of lifetime entries by (controller, quantity)."""
    return main_channels(quantity.removeprefix("lifetime DEL ") for _, quantity in value)


def _figure_del_against_speed(rows, path: Path) -> Path:
    from matplotlib.figure import Figure

    channels = main_channels(rows[0]["wohler"])
    figure = Figure(figsize=(11, 2.6 * math.ceil(len(channels) / 2)), layout="constrained")
    axes = figure.subplots(math.ceil(len(channels) / 2), 2).ravel()
    for ax, (channel, name) in zip(axes, channels.items()):
        for controller in _controllers(rows):
            speeds, values = _by_speed(rows, controller, f"del.{channel}")
            line, = ax.plot(speeds, [np.mean(v) / 1e6 for v in values], "o-", label=controller)
            for speed, seeds in zip(speeds, values):
                ax.plot([speed] * len(seeds), np.array(seeds) / 1e6, ".", color=line.get_color(), alpha=0.4)
        ax.set(title=f"{name} DEL", xlabel="wind speed [m/s]", ylabel="DEL [MN·m]")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    for ax in axes[len(channels):]:
        ax.set_visible(False)
    figure.savefig(path, dpi=90)
    return path


def _figure_lifetime(lifetime, path: Path) -> Path:
    from matplotlib.figure import Figure

    controllers = list(dict.fromkeys(entry["controller"] for entry in lifetime))
    value = {(e["controller"], e["quantity"]): e["value"] for e in lifetime}
    channels = _lifetime_channels(value)
    figure = Figure(figsize=(11, 3.6), layout="constrained")
    ax = figure.subplots()
    width = 0.8 / max(1, len(controllers) - 1)
    for i, controller in enumerate(controllers[1:]):
        changes = [100 * (value[(controller, f"lifetime DEL {c}")] / value[(controllers[0], f"lifetime DEL {c}")] - 1)
                   for c in channels]
        ax.bar(np.arange(len(channels)) + (i - (len(controllers) - 2) / 2) * width, changes, width,
               label=controller)
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_xticks(np.arange(len(channels)), list(channels.values()), fontsize=8)
    ax.set(ylabel=f"lifetime DEL change against {controllers[0]} [%]")
    if len(controllers) > 1:  # one controller has no change against itself, no bar to name
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
    travel.set(title="pitch travel (sum of all blades, analysed time)", xlabel="wind speed [m/s]", ylabel="[deg]")
    rate.set(title="largest commanded pitch rate", xlabel="wind speed [m/s]", ylabel="[deg/s]")
    for ax in (travel, rate):
        ax.grid(alpha=0.3)
    travel.legend(fontsize=8)
    figure.savefig(path, dpi=90)
    return path


def _figure_governing(series, path: Path) -> Path:
    """Each main channel's time series in the case that governs its design load, per controller, the extreme
    marked."""
    from matplotlib.figure import Figure

    by_channel: Dict[str, list] = {}
    for entry in series:
        by_channel.setdefault(entry["channel"], []).append(entry)
    channels = main_channels(by_channel)
    figure = Figure(figsize=(11, 2.6 * math.ceil(len(channels) / 2)), layout="constrained")
    axes = figure.subplots(math.ceil(len(channels) / 2), 2, squeeze=False).ravel()
    for ax, (channel, name) in zip(axes, channels.items()):
        for entry in by_channel[channel]:
            time, values = np.asarray(entry["time"]), np.asarray(entry["values"]) / 1e6
            line, = ax.plot(time, values, lw=0.8, label=f"{entry['controller']}: {entry['case']}")
            extreme = int(np.argmax(np.abs(values)))
            ax.plot(time[extreme], values[extreme], "o", color=line.get_color())
        ax.set(title=name, xlabel="time [s]", ylabel="[MN·m]")
        ax.legend(fontsize=6, loc="best")
        ax.grid(alpha=0.3)
    for ax in axes[len(channels):]:
        ax.set_visible(False)
    figure.savefig(path, dpi=90)
    return path


def write_campaign_report(title: str, rows: Sequence[Mapping[str, Any]], lifetime: Sequence[Mapping[str, Any]],
                          directory: Path, tables: Mapping[str, Path], ultimate: Sequence[Mapping[str, Any]] = (),
                          governing: Sequence[Mapping[str, Any]] = ()) -> Path:
    """Write ``report.html`` and its PNGs into ``directory``; return the page. The title of an incomplete campaign
    ends with ``incomplete: N of M cases``, and the missing cases head the text; an ultimate-load campaign's design
    loads (`ultimate_text`) follow the lifetime table, and the time series of the cases that govern them
    (``hawt_tools.campaign.governing_series``) are a figure."""
    title = " — ".join([title, *dict.fromkeys(cases for cases, _ in _incomplete(lifetime))])
    figures = {"DEL_against_wind_speed.png": (_figure_del_against_speed, rows, "DEL of the main channels against wind "
                                              "speed (mean over the seeds, each seed a dot)"),
               "lifetime_DEL_change.png": (_figure_lifetime, lifetime, f"lifetime DEL change against "
                                           f"{lifetime[0]['controller']}"),
               "pitch_activity.png": (_figure_pitch, rows, "pitch activity against wind speed")}
    if governing:
        figures["governing_cases.png"] = (_figure_governing, governing, "the cases that govern the design loads: "
                                          "each channel's time series in the analysed time, its extreme marked")
    images = [draw(data, directory / name) for name, (draw, data, _) in figures.items()]
    text = "\n\n".join(part for part in (lifetime_text(lifetime), ultimate_text(ultimate)) if part)
    return write_html_page(directory / "report.html", title, text, images,
                           [path.name for path in tables.values()],
                           headings={name: heading for name, (_, _, heading) in figures.items()})


def _figure_design_loads(governing, path: Path) -> Path:
    """The design load of each main channel per controller, each bar labelled with the DLC that governs it."""
    from matplotlib.figure import Figure

    controllers = list(dict.fromkeys(entry["controller"] for entry in governing))
    entry_of = {(entry["controller"], entry["channel"]): entry for entry in governing}
    channels = main_channels(entry["channel"] for entry in governing)
    figure = Figure(figsize=(11, 3.8), layout="constrained")
    ax = figure.subplots()
    width = 0.8 / len(controllers)
    for i, controller in enumerate(controllers):
        entries = [entry_of.get((controller, channel)) for channel in channels]
        heights = [abs(e["design"]) / 1e6 if e else math.nan for e in entries]
        bars = ax.bar(np.arange(len(channels)) + (i - (len(controllers) - 1) / 2) * width, heights, width,
                      label=controller)
        ax.bar_label(bars, [f"DLC {e['dlc']}" if e else "" for e in entries], fontsize=6, rotation=90,
                     padding=2)
    names = [textwrap.fill(name, 16, break_on_hyphens=False) for name in channels.values()]
    ax.set_xticks(np.arange(len(channels)), names, fontsize=8)
    ax.set(ylabel="design load [MN·m]")
    ax.margins(y=0.25)
    ax.legend(fontsize=8)
    ax.grid(axis="y", alpha=0.3)
    figure.savefig(path, dpi=90)
    return path


def write_design_load_report(title: str, governing: Sequence[Mapping[str, Any]], over: Sequence[str],
                             directory: Path, dlc_reports: Sequence[str]) -> Path:
    """Write ``report.html`` of a campaign of several DLCs into ``directory``: the design loads over them
    (:func:`ultimate_text` of ``hawt_analysis.ultimate.governing_loads``), a figure of them with the DLC that governs
    each, and links to ``ultimate.csv`` and to each DLC's own report (``dlc_reports``, relative paths)."""
    image = _figure_design_loads(governing, directory / "design_loads.png")
    return write_html_page(directory / "report.html", title, ultimate_text(governing, over), [image],
                           ["ultimate.csv", *dlc_reports],
                           headings={image.name: "design loads over the DLCs, each bar labelled with the DLC that "
                                                 "governs it (each DLC's report: the links above)"})
