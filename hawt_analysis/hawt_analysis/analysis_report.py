"""What a person reads of ``hawt analyze`` / ``hawt compare``: text tables and a report folder.

Tables show display units (MN·m, °, °/s, rpm, MW); the JSON beside them stays SI. Text tables are fixed-width
columns two spaces apart (`text_table`). A change against the first run is a percentage only where the reference is
at least a tenth of the value (`change_text`), else the change in the row's unit.
A report folder holds ``index.html`` (the table, the blade-root moment's harmonics as an
HTML table, then the figures of `hawt_analysis.plots`, each under its heading), the PNGs and ``summary.json`` /
``comparison.json``.
"""
import html
import json
import math
import os
from pathlib import Path
from types import MappingProxyType
from typing import List, Mapping, Optional, Sequence, Tuple

import numpy as np

from hawt_bag.errors import BagError

from .comparison import change_percent, compare_summaries

__all__ = ["NEAR_ZERO", "PITCH_METRICS", "analysis_text", "change_text", "changes_table", "comparison_text",
           "harmonic_table", "headline_text", "text_table", "write_analysis_report", "write_comparison_report",
           "write_html_page"]

_MN = 1e-6
_DEG = 180.0 / math.pi
_RPM = 60.0 / (2.0 * math.pi)
PITCH_METRICS = MappingProxyType({
    "travel_rad": (_DEG, "°", "travel, sum of all blades"),
    "max_rate_rad_s": (_DEG, "°/s", "largest rate of any blade"),
    "max_acceleration_rad_s2": (_DEG, "°/s²", "largest acceleration of any blade"),
    "duty_cycle": (100.0, "%", "duty cycle, mean of the blades")})
"""The pitch activity `compare_summaries` compares → (factor from SI to the display unit, display unit, name)."""
NEAR_ZERO = 0.1
"""A reference under this fraction of the value it is compared with is near zero: the change is then given in the
row's unit, not as a percentage. Such a percentage (above +900 %) mostly says how small the reference is: an IPC's 1P
pitch against a baseline that has next to none read +10549 %, where +2.97° says what changed."""
_LEVELS = {10: "DEBUG", 20: "INFO", 30: "WARN", 40: "ERROR"}


def _unit(channel: str) -> tuple[float, str]:
    return (_DEG, "°") if channel.startswith("pitch") else (_MN, "MN·m")


def _fmt(value, factor: float = 1.0, digits: int = 4) -> str:
    return "-" if value is None else f"{factor * value:.{digits}g}"


def change_text(reference: Optional[float], value: Optional[float], factor: float, unit: str) -> str:
    """``value``'s change against ``reference`` as a person reads it: a percentage (``-42.0 %``), or, where the
    reference is near zero (`NEAR_ZERO`), the difference in ``unit`` after ``factor`` (``+2.969 °``; in percentage
    points, ``pp``, for a quantity in %); empty if either is missing."""
    if reference is None or value is None or not (math.isfinite(reference) and math.isfinite(value)):
        return ""
    if abs(reference) >= NEAR_ZERO * abs(value) and reference != 0.0:
        return f"{change_percent([reference, value])[1]:+.1f} %"
    return f"{factor * (value - reference):+.4g} {'pp' if unit == '%' else unit}"


def changes_table(corner: str, labels: Sequence[str],
                  rows: Sequence[Tuple[str, Sequence[Optional[float]], float, str]]) -> List[str]:
    """Quantities of several runs side by side as `text_table` lines: a column per run headed by its label, after
    each run but the first its change against the first (`change_text`). ``rows``: (name, SI value per run, factor
    to the display unit, display unit); ``corner`` heads the names."""
    header = [corner, labels[0], *(cell for label in labels[1:] for cell in (label, "change"))]
    return text_table([header, *([f"{name} [{unit}]", _fmt(values[0], factor),
                                  *(cell for value in values[1:]
                                    for cell in (_fmt(value, factor), change_text(values[0], value, factor, unit)))]
                                 for name, values, factor, unit in rows)])


def text_table(rows: Sequence[Sequence[str]]) -> List[str]:
    """``rows`` of cells (the first row the header) as lines of fixed-width columns, two spaces apart, each as wide
    as its widest cell: the first column left-aligned, the others right-aligned."""
    widths = [max(len(row[j]) for row in rows) for j in range(len(rows[0]))]
    return ["  ".join(cell.ljust(width) if j == 0 else cell.rjust(width)
                      for j, (cell, width) in enumerate(zip(row, widths))).rstrip() for row in rows]


def analysis_text(summary: Mapping) -> str:
    """The ``hawt analyze`` table: operating point, DELs, 1P–3P harmonics, pitch activity and the commands the plant
    refused, events."""
    bag = summary.get("bag", {})
    lines = [f"hawt analyze: {bag.get('file', '')} (namespace {bag.get('namespace', '/')}), "
             f"steps {bag.get('first_step', '?')}..{bag.get('last_step', '?')}",
             f"duration {summary['duration_s']:.2f} s at {summary['sample_rate_hz']:.4g} Hz, "
             f"B = {summary['n_blades']}",
             f"rotor speed {_RPM * summary['rotor_speed']['mean']:.4g} rpm mean, "
             f"{_RPM * summary['rotor_speed']['std']:.3g} rpm std"]
    if summary.get("power"):
        lines.append(f"electrical power {_MN * summary['power']['mean']:.4g} MW mean")
    table = [["channel", "m", "DEL", "1P", "2P", "3P", "unit"]]
    for name in dict.fromkeys([*summary["del"], *summary["harmonics"]]):
        factor, unit = _unit(name)
        entry = summary["del"].get(name)
        amplitudes = dict(zip(summary["harmonics"].get(name, {}).get("n", []),
                              summary["harmonics"].get(name, {}).get("amplitude", [])))
        table.append([name, _fmt(entry and entry["m"]), _fmt(entry and entry["value"], factor),
                      *(_fmt(amplitudes.get(n), factor) for n in (1, 2, 3)), unit])
    fit = ("harmonic amplitudes (azimuth-domain fit)" if summary["harmonics"] else
           f"no harmonics (the rotor turned {summary.get('revolutions', 0.0):.2f} revolutions, less than one)")
    lines += ["", f"damage-equivalent loads (1 Hz) and {fit}:", *text_table(table), ""]
    for label, pitch in (("pitch (measured)", summary.get("pitch")), ("pitch (command)", summary.get("pitch_command"))):
        if pitch:
            lines.append(f"{label:<18} travel {_DEG * pitch['travel_rad']['total']:.4g}° (sum of all blades), "
                         f"max rate {_DEG * pitch['max_rate_rad_s']['max']:.3g}°/s (any blade), "
                         f"duty cycle {100 * pitch['duty_cycle']['mean']:.3g} % (mean of the blades)")
    command = summary.get("pitch_command")
    if command and command.get("flag_steps"):
        lines.append("command flags      " + ", ".join(f"{name} {count} steps"
                                                       for name, count in command["flag_steps"].items()))
    refused = summary.get("refused_commands")
    if refused:
        lines.append("refused commands   " + "; ".join(
            f"{r['messages']} from {r['publisher']} (steps {r['first_step']}..{r['last_step']})" for r in refused)
            + ", not in the pitch command above")
    lines += _segment_lines(summary.get("segments") or [], summary.get("n_blades") or 3)
    for name, by_axis in (summary.get("wind_estimate") or {}).items():
        lines.append(f"wind estimate of {name} against the plant's blade-effective wind (means removed): " + "; ".join(
            f"{axis} correlation {q['correlation']:.3f}, error RMS {q['error_rms']:.3g} of {q['truth_rms']:.3g} m/s"
            for axis, q in by_axis.items()))
    events = summary.get("events") or []
    lines += ["", f"events ({len(events)}):" if events else "events: none recorded"]
    lines += [f"  t={e['time']:10.3f} s  step {e['step']:>8}  {_LEVELS.get(e['level'], e['level'])!s:<5} "
              f"{e['source']}: {e['kind']}" + (f" — {e['detail']}" if e['detail'] else "") for e in events]
    return "\n".join(lines)


def _segment_lines(segments: list, n_blades: int) -> list:
    """Loads between controller switches: M_oop 1P-3P (mean of the blades) and hub tilt/yaw B·P per segment (the
    fixed frame's blade-passing harmonic: 3P for three blades, 2P for two), a `text_table`; a segment under one
    revolution has no harmonics ("-")."""
    if not segments:
        return []
    table = [["steps", "from [s]", "M_oop 1P", "2P", "3P", f"tilt {n_blades}P", f"yaw {n_blades}P"]]
    for segment in segments:
        values = [None] * 5
        if segment["harmonics"] is not None:
            amplitude = {name: dict(zip(h["n"], h["amplitude"])) for name, h in segment["harmonics"].items()}
            blades = [a for name, a in amplitude.items() if name.startswith("root_moment_oop")]
            values = [sum(a[n] for a in blades) / len(blades) if blades else None for n in (1, 2, 3)]
            values += [amplitude.get(name, {}).get(n_blades) for name in ("hub_tilt_moment", "hub_yaw_moment")]
        table.append([f"{segment['first_step']}..{segment['last_step']}", f"{segment['start_s']:.1f}",
                      *(_fmt(value, _MN) for value in values)])
    return ["", "loads between controller switches (harmonic amplitudes in MN·m; M_oop: mean of the blades; - under "
                "one revolution):", *text_table(table)]


def comparison_text(comparison: Mapping) -> str:
    """The ``hawt compare`` table: each run's DELs, harmonics 1P–3P, pitch, rotor speed and power, with the change
    against the first run."""
    labels = comparison["labels"]
    rows = [(f"DEL {name}", entry["value"], *_unit(name)) for name, entry in comparison["del"].items()]
    rows += [(f"{n}P {name}", [a[j] for a in entry["amplitude"]], *_unit(name))
             for name, entry in comparison["harmonics"].items() for j, n in enumerate(entry["n"][:3])]
    rows += [(f"pitch {PITCH_METRICS[metric][2]}", entry["value"], *PITCH_METRICS[metric][:2])
             for metric, entry in (comparison.get("pitch") or {}).items()]
    rows += [(f"rotor speed {statistic}", entry["value"], _RPM, "rpm")
             for statistic, entry in comparison["rotor_speed"].items()]
    if comparison.get("power"):
        rows.append(("electrical power mean", comparison["power"]["mean"]["value"], _MN, "MW"))
    return "\n".join([f"hawt compare: {len(labels)} runs, changes against {comparison['reference']} (in %, or in the "
                      f"row's unit where the reference is under {NEAR_ZERO:g}× the run's value)",
                      *changes_table("quantity", labels, rows)])


def headline_text(comparison: Mapping) -> str:
    """A few lines a load engineer reads first: the second run against the first in blade-root, hub tilt/yaw and
    tower-base DEL, pitch activity, and the rotor speed and power it held."""
    loads, second = comparison["del"], 1

    def change(names: Sequence[str]) -> str:
        found = [loads[name] for name in names if name in loads]
        if not found:
            return "n/a"
        return f"{np.mean([entry['change_percent'][second] for entry in found]):+.1f} %"

    pitch, speed, power = comparison["pitch"], comparison["rotor_speed"]["mean"], comparison["power"]
    travel = pitch["travel_rad"]["value"] if pitch else [math.nan, math.nan]
    rows = [("blade-root out-of-plane DEL",
             change([n for n in loads if n.startswith("root_moment_oop_")]) + " (mean of the blades)"),
            ("hub tilt / yaw DEL", f"{change(['hub_tilt_moment'])} / {change(['hub_yaw_moment'])}"),
            ("tower-base fore-aft / side-side DEL",
             f"{change(['tower_base_fa_moment'])} / {change(['tower_base_ss_moment'])}"),
            ("pitch travel (sum of all blades)",
             f"{math.degrees(travel[0]):.0f} -> {math.degrees(travel[second]):.0f} deg"),
            ("rotor speed held (mean)", f"{speed['value'][0] * 30 / math.pi:.2f} -> "
                                        f"{speed['value'][second] * 30 / math.pi:.2f} rpm")]
    if power:
        rows.append(("power (mean)", f"{power['mean']['value'][0] / 1e6:.2f} -> "
                                     f"{power['mean']['value'][second] / 1e6:.2f} MW"))
    lines = [f"{comparison['labels'][second]} against {comparison['labels'][0]}:"]
    lines += [f"  {label:37s} {value}" for label, value in rows]
    return "\n".join(lines)


def harmonic_table(comparison: Mapping) -> str:
    """The harmonic amplitudes of the blade-root out-of-plane moment as an HTML table under its heading [MN·m, as the
    text tables]: one row per harmonic nP, one column per run of ``comparison`` (`compare_summaries`; a comparison of
    one summary has one column), each cell the mean of the blades' amplitudes and, after the first run, its change
    against the first (`change_text`); empty without that channel."""
    blades = {name: entry for name, entry in comparison["harmonics"].items() if name.startswith("root_moment_oop_")}
    if not blades:
        return ""
    amplitude = np.mean([entry["amplitude"] for entry in blades.values()], axis=0)  # (runs, harmonics)
    head = "".join(f"<th>{html.escape(label)}</th>" for label in comparison["labels"])
    rows = []
    for n, per_run in zip(next(iter(blades.values()))["n"], amplitude.T.tolist()):
        cells = "".join(f"<td>{_fmt(value, _MN)}" + (f" ({change_text(per_run[0], value, _MN, 'MN·m')})" if k else "")
                        + "</td>" for k, value in enumerate(per_run))
        rows.append(f"<tr><th>{n}P</th>{cells}</tr>")
    return (f"<h2>harmonics of the blade-root out-of-plane moment</h2>\n<table>\n<caption>amplitude of the periodic "
            f"part, mean of the {len(blades)} blades [MN·m]</caption>\n<tr><th>harmonic</th>{head}</tr>\n"
            + "\n".join(rows) + "\n</table>")


_STYLE = ("table{border-collapse:collapse;margin:1em 0}caption{text-align:left;font-size:small}"
          "th,td{border:1px solid #bbb;padding:2px 10px}td{text-align:right;font-family:monospace}")


def write_html_page(path: Path, title: str, text: str, images: Sequence[Path], data_files: Sequence[str],
                    tables: Sequence[str] = (), headings: Mapping[str, str] = MappingProxyType({})) -> Path:
    """One report page: the title, ``text`` as preformatted text, links to the data files beside it, the HTML
    ``tables`` and the images (PNGs in the same folder), each under its heading in ``headings`` (by file name, e.g.
    `hawt_analysis.plots.FIGURE_HEADINGS`), else its file name's words; returns ``path``."""
    figures = "\n".join(f'<h2>{html.escape(headings.get(p.name, p.stem.replace("_", " ")))}</h2>\n'
                        f'<img src="{html.escape(p.name)}" alt="{html.escape(p.stem)}" style="max-width:100%">'
                        for p in images)
    links = ", ".join(f'<a href="{html.escape(name)}">{html.escape(name)}</a>' for name in data_files)
    page = (f"<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>{html.escape(title)}</title>"
            f"<style>{_STYLE}</style></head>\n<body>\n<h1>{html.escape(title)}</h1>\n<pre>{html.escape(text)}</pre>\n"
            f"<p>All numbers in SI units: {links}</p>\n{''.join(tables)}\n{figures}\n</body></html>\n")
    path.write_text(page, encoding="utf-8")
    return path


def _folder(directory: os.PathLike) -> Path:
    directory = Path(directory)
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise BagError(f"{directory}: cannot create the report folder ({error.strerror})") from None
    return directory


def write_analysis_report(analysis, directory: os.PathLike) -> Path:
    """Write ``index.html`` (with the harmonic table), the PNGs of `hawt_analysis.plots.write_report` and
    ``summary.json``; return the index."""
    from .plots import FIGURE_HEADINGS, _save, write_report
    from .run_analysis import wind_estimate_qualities
    from .wind_estimation import AXES, plot_wind_estimate

    directory = _folder(directory)
    images = write_report(analysis.run.channels, analysis.summary, directory)
    headings = dict(FIGURE_HEADINGS)
    run = analysis.run
    for name, quality in wind_estimate_qualities(run).items():
        rows = run.wind_estimates[name]["rows"]
        heading = f"{name}: multi-blade wind estimate against the plant's truth"
        figure = plot_wind_estimate(run.channels["time"][rows],
                                    {axis: run.channels[f"effective_wind_{axis}"][rows] for axis in AXES},
                                    {axis: run.wind_estimates[name][f"wind_{axis}"] for axis in AXES}, quality,
                                    heading)
        images.append(_save(figure, directory / f"wind_estimate_{name}.png"))
        headings[images[-1].name] = heading
    (directory / "summary.json").write_text(json.dumps(analysis.summary, indent=1))
    return write_html_page(directory / "index.html", f"hawt analyze: {analysis.path.name}",
                           analysis_text(analysis.summary), images, ["summary.json"],
                           [harmonic_table(compare_summaries([analysis.summary], [analysis.path.name]))], headings)


def write_comparison_report(comparison: Mapping, directory: os.PathLike, analyses: Sequence = ()) -> Path:
    """Write ``index.html`` (with the harmonic table), ``del.png``, ``comparison.png`` and ``comparison.json`` and,
    given the runs' analyses (in the comparison's order), their time series and spectra overlaid; return the
    index."""
    from .plots import FIGURE_HEADINGS, write_comparison_report as plot

    directory = _folder(directory)
    labels = comparison["labels"]
    images = plot(comparison, directory, {label: a.run.channels for label, a in zip(labels, analyses)},
                  {label: a.run.events for label, a in zip(labels, analyses)})
    (directory / "comparison.json").write_text(json.dumps(comparison, indent=1))
    return write_html_page(directory / "index.html", f"hawt compare: {', '.join(comparison['labels'])}",
                           comparison_text(comparison), images, ["comparison.json"], [harmonic_table(comparison)],
                           FIGURE_HEADINGS)
