"""``hawt validate``: the same cases in OpenFAST and in hawt, with the same controller and wind, side by side.

For each :class:`ValidationCase` the turbine's ``validation`` graph (plant, ROSCO, mbc) runs in process (``hawt run``, recorded to MCAP) and
OpenFAST runs the turbine's own deck (:mod:`hawt_tools.openfast_case`) with the same ROSCO library and DISCON.IN,
the same wind (steady power law; turbulent: the plant's own field written as a TurbSim ``.bts`` that both read) and
the same initial state (hawt's operating point at step 0: rotor speed, pitch, azimuth, tower-top displacement).
Both are analysed by the same code (:func:`hawt_analysis.summary.summarize`; OpenFAST's ``.outb`` through
:func:`hawt_analysis.openfast_output.read_openfast_output`) over the same window, the last ``analysed`` seconds,
after the start has settled. :data:`STEADY_CHECKS` and :data:`TURBULENT_CHECKS` are the figures compared, each with
its tolerance (issue 29); :func:`write_report` writes ``validation.md``, ``index.html`` with plots, and
``validation.json``.
"""
from __future__ import annotations

import json
import math
import re
import threading
import time
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple

import numpy as np

from hawt_analysis.summary import summarize
from hawt_tools.openfast_case import CaseInputs, WrittenCase, deck_hub_height, output_of, run_openfast, write_case

if TYPE_CHECKING:
    from hawt_plant.turbine import Turbine
    from hawt_tools.in_process import InProcessRun

__all__ = ["Check", "Figure", "DEFAULT_CASES", "FIGURES", "LOAD_PATHS", "STEADY_CHECKS", "TURBULENT_CHECKS", "ValidationCase", "CaseResult",
           "case_figures", "compare_figures", "not_like_for_like", "parse_case", "run_case", "write_report"]


@dataclass(frozen=True)
class ValidationCase:
    """One case run on both sides.

    Attributes
    ----------
    name : str
        ``steady-V`` or ``turbulent-V`` (V the hub wind speed in m/s).
    wind_speed : float
        Mean hub-height wind speed [m/s].
    turbulent : bool
        IEC Kaimal turbulence of ``turbulence_class`` with ``seed`` (the plant's generator), else steady.
    shear_exponent : float
        Power-law shear α.
    duration, analysed : float
        Simulated time [s], and the last part of it that is analysed [s] (the start rings: ElastoDyn's tower starts
        where the case puts it, and both controllers settle).
    """

    name: str
    wind_speed: float
    turbulent: bool = False
    shear_exponent: float = 0.2
    turbulence_class: str = "B"
    seed: int = 1
    duration: float = 160.0
    analysed: float = 60.0


DEFAULT_CASES = (
    ValidationCase("steady-8", 8.0),
    ValidationCase("steady-11.4", 11.4),
    ValidationCase("steady-18", 18.0),
    ValidationCase("turbulent-18", 18.0, turbulent=True, duration=600.0, analysed=540.0),
)
"""The default set (issue 29): steady 8, 11.4 and 18 m/s with shear 0.2, and 600 s of class-B turbulence at 18 m/s."""

_CASE_NAME = re.compile(r"^(steady|turbulent)-([0-9]+(?:\.[0-9]+)?)$")


def parse_case(text: str, duration: Optional[float] = None) -> ValidationCase:
    """A case from its name (``steady-13``, ``turbulent-18``), a default case's settings for its kind; ``duration``
    [s] replaces the simulated time (the analysed part keeps its share). ValueError naming the text if malformed."""
    match = _CASE_NAME.match(text)
    if not match:
        raise ValueError(f"--case {text!r}: expected steady-V or turbulent-V (V the wind speed in m/s), e.g. "
                         f"{', '.join(c.name for c in DEFAULT_CASES)}")
    speed = float(match.group(2))
    if not 3.0 <= speed <= 30.0:
        raise ValueError(f"--case {text}: {speed:g} m/s is outside the plant's 3..30 m/s")
    template = next(c for c in DEFAULT_CASES if c.turbulent == (match.group(1) == "turbulent"))
    case = replace(template, name=text, wind_speed=speed)
    return with_duration(case, duration) if duration is not None else case


def with_duration(case: ValidationCase, duration: float) -> ValidationCase:
    """``case`` over ``duration`` [s] simulated, the analysed part the same share of it."""
    if not (math.isfinite(duration) and duration >= 20.0):
        raise ValueError(f"--duration {duration:g}: expected at least 20 s simulated")
    return replace(case, duration=duration, analysed=duration * case.analysed / case.duration)


@dataclass(frozen=True)
class Figure:
    """One figure a case reports (:func:`case_figures` computes it in SI): its key, name and display unit, and
    ``scale``, the factor from SI to that unit."""

    key: str
    label: str
    unit: str
    scale: float


@dataclass(frozen=True)
class Check:
    """A figure compared between hawt and OpenFAST with its tolerance: relative (a fraction of OpenFAST's
    magnitude), or absolute in the figure's display unit when ``absolute``."""

    key: str
    tolerance: float
    absolute: bool = False


LOAD_PATHS = (("hub_tilt", "hub_tilt_moment", "hub tilt (LSSTipMys)"),
              ("hub_yaw", "hub_yaw_moment", "hub yaw (LSSTipMzs)"),
              ("tower_fa", "tower_base_fa_moment", "tower-base fore-aft"),
              ("tower_ss", "tower_base_ss_moment", "tower-base side-side"))
"""The hub and tower-base channels each reported as mean, 3P and DEL (m = 4): figure key prefix, channel, label."""

FIGURES = {f.key: f for f in (
    Figure("power_mean", "electrical power, mean", "MW", 1e-6),
    Figure("pitch_mean", "pitch, mean of the blades", "deg", 180.0 / math.pi),
    Figure("rotor_speed_mean", "rotor speed, mean", "rpm", 30.0 / math.pi),
    Figure("thrust_mean", "rotor thrust, mean", "kN", 1e-3),
    Figure("root_oop_mean", "blade-root out-of-plane, mean", "MN·m", 1e-6),
    Figure("root_oop_1p", "blade-root out-of-plane, 1P", "MN·m", 1e-6),
    Figure("root_oop_2p", "blade-root out-of-plane, 2P", "MN·m", 1e-6),
    Figure("root_oop_del", "blade-root out-of-plane, DEL m=10", "MN·m", 1e-6),
    *(Figure(f"{prefix}_{kind}", f"{label}, {text}", "MN·m", 1e-6) for prefix, _, label in LOAD_PATHS
      for kind, text in (("mean", "mean"), ("3p", "3P"), ("del", "DEL m=4"))),
)}
"""Every figure a case reports, in SI; ``scale`` converts to the display unit."""

_OPERATION = (Check("power_mean", 0.02), Check("pitch_mean", 0.3, absolute=True), Check("rotor_speed_mean", 0.02),
              Check("thrust_mean", 0.02))
STEADY_CHECKS = _OPERATION + (
    Check("root_oop_mean", 0.10), Check("root_oop_1p", 0.10), Check("root_oop_2p", 0.10), Check("root_oop_del", 0.10),
    Check("hub_tilt_mean", 0.15), Check("hub_yaw_mean", 0.15), Check("hub_tilt_3p", 0.15), Check("hub_yaw_3p", 0.15),
    Check("tower_fa_mean", 0.05), Check("tower_ss_mean", 0.05), Check("tower_fa_3p", 0.25), Check("tower_ss_3p", 0.25))
"""Steady cases: issue 29's tolerances (operation 2 %, pitch 0.3°; blade root 10 %; hub 15 %; tower means 5 %,
3P 25 %)."""
TURBULENT_CHECKS = _OPERATION + (
    Check("root_oop_del", 0.10), Check("hub_tilt_del", 0.10), Check("hub_yaw_del", 0.10), Check("tower_fa_del", 0.10),
    Check("tower_ss_del", 0.10))
"""Turbulent cases: the operation as steady, and the DELs of blade root (m = 10), hub and tower base (m = 4): 10 %."""


def analysed_window(channels: Mapping[str, np.ndarray], seconds: float) -> Dict[str, np.ndarray]:
    """The channels over their last ``seconds`` of time."""
    time_ = np.asarray(channels["time"])
    keep = time_ >= time_[-1] - seconds - 1e-9
    return {name: np.asarray(values)[keep] for name, values in channels.items()}


def case_figures(channels: Mapping[str, np.ndarray]) -> Dict[str, float]:
    """Every figure of :data:`FIGURES` for one run's analysed channels (SI units), by key; a blade figure is the
    mean over the blades. Harmonic amplitudes are fitted on the azimuth, revolution by revolution."""
    summary = summarize(channels)
    harmonics = summary["harmonics"]

    def amplitude(channel: str, n: int) -> float:
        entry = harmonics[channel]
        return float(entry["amplitude"][entry["n"].index(n)])

    def blades(field: str) -> List[str]:
        return [name for name in harmonics if re.fullmatch(f"{field}_[0-9]+", name)]

    oop = blades("root_moment_oop")
    delta = summary["del"]
    figures = {
        "power_mean": summary["power"]["mean"],
        "pitch_mean": float(np.mean(channels["pitch"])),
        "rotor_speed_mean": summary["rotor_speed"]["mean"],
        "thrust_mean": float(np.mean(channels["rotor_thrust"])),
        "root_oop_mean": float(np.mean(channels["root_moment_oop"])),
        "root_oop_1p": float(np.mean([amplitude(name, 1) for name in oop])),
        "root_oop_2p": float(np.mean([amplitude(name, 2) for name in oop])),
        "root_oop_del": float(np.mean([delta[name]["value"] for name in oop])),
    }
    for prefix, channel, _ in LOAD_PATHS:
        figures |= {f"{prefix}_mean": float(np.mean(channels[channel])), f"{prefix}_3p": amplitude(channel, 3),
                    f"{prefix}_del": delta[channel]["value"]}
    return figures


def compare_figures(hawt: Mapping[str, float], openfast: Mapping[str, float], checks: Sequence[Check]) -> List[dict]:
    """One row per check: both values in the display unit, the difference (relative to OpenFAST's magnitude, or
    absolute in the display unit), the tolerance and whether the difference is within it."""
    rows = []
    for check in checks:
        figure = FIGURES[check.key]
        ours, theirs = hawt[check.key] * figure.scale, openfast[check.key] * figure.scale
        if check.absolute:
            difference = ours - theirs
        else:
            difference = (ours - theirs) / abs(theirs) if theirs != 0.0 else math.copysign(math.inf, ours - theirs)
        rows.append({"key": check.key, "label": figure.label, "unit": figure.unit, "hawt": ours, "openfast": theirs,
                     "difference": difference, "absolute": check.absolute, "tolerance": check.tolerance,
                     "within": bool(abs(difference) <= check.tolerance)})
    return rows


@dataclass
class CaseResult:
    """One case run on both sides: the rows of its checks, the analysed channels, and how it was run."""

    case: ValidationCase
    rows: List[dict]
    hawt_channels: Dict[str, np.ndarray]
    openfast_channels: Dict[str, np.ndarray]
    bag: Path
    openfast_output: Path
    deck_changes: Tuple[str, ...]
    hawt_wall: float
    openfast_wall: float
    settings: Dict[str, Any]


def _hawt_overrides(case: ValidationCase, turbine: str, bts: Optional[Path]) -> Tuple[Dict[str, str], List[str]]:
    """The ``validation`` graph's launch arguments and ``-p`` overrides for ``case``."""
    arguments = {"turbine": turbine, "wind_speed": str(case.wind_speed), "shear_exponent": str(case.shear_exponent),
                 "duration": str(case.duration), "wind_type": "bts" if bts is not None else "steady"}
    return arguments, ([f"plant.bts_file:={bts}"] if bts is not None else [])


def _turbulent_fields(case: ValidationCase, turbine, folder: Path, deck_hub_height: float) -> Tuple[Path, Path]:
    """The plant's own turbulent field for ``case`` (the disk cache's, generated if new) as ``.bts`` files: the
    plant's, and OpenFAST's, the same field raised to centre on ``deck_hub_height`` for a deck whose hub is higher
    than the plant's (a turbine whose substructure the import lowered; the same file if the hubs agree)."""
    from hawt_plant.bts import write_bts
    from hawt_plant.inflow import InflowSettings, make_wind
    from hawt_plant.turbulence import TurbulentWind

    wind = make_wind(InflowSettings(kind="turbulent", wind_speed=case.wind_speed, shear_exponent=case.shear_exponent,
                                    hub_height=turbine.hub_height, rotor_radius=turbine.rotor.tip_radius,
                                    turbulence_class=case.turbulence_class,
                                    seed=case.seed, field_duration=max(600.0, case.duration)))
    path = folder / f"{case.name}.bts"
    write_bts(path, wind, f"hawt validate {case.name}: IEC Kaimal class {case.turbulence_class}, seed {case.seed}",
              tower=True)
    if abs(deck_hub_height - wind.hub_height) < 1e-3:
        return path, path
    raised = TurbulentWind(wind.velocity_grid, time_step=wind.time_step, grid_y=wind.grid_y,
                           grid_z=wind.grid_z + (deck_hub_height - wind.hub_height), mean_speed=wind.mean_speed,
                           hub_height=deck_hub_height, periodic=wind.periodic, x_offset=wind.x_offset)
    raised_path = path.with_name(f"{path.stem}-hub{deck_hub_height:.1f}.bts")
    write_bts(raised_path, raised, f"{path.stem} raised to a hub at {deck_hub_height:.2f} m", tower=True)
    return path, raised_path


def prepare_case(case: ValidationCase, turbine: str, graph_path: Path, deck: Path, folder: Path,
                 parameters: Sequence[str] = ()) -> Tuple[InProcessRun, WrittenCase]:
    """Both sides of ``case``, ready to run: hawt's ``validation`` graph (``graph_path``) built in process at step 0,
    and OpenFAST's inputs written into ``folder`` from the turbine's ``deck``, started at that same operating point,
    with the same ROSCO library and DISCON.IN and the same wind (a turbulent case's field as ``.bts`` files in
    ``folder``). ``parameters`` are more ``-p NODE.PARAM:=VALUE`` for hawt's side."""
    from hawt_analysis.openfast_output import openfast_channel_names
    from hawt_controllers.discon.rosco_input import rosco_files, write_private_input
    from hawt_controllers.design.tunings import tuning_file
    from hawt_tools.graph_file import load_graph
    from hawt_tools.in_process import build_run
    from hawt_tools.graph_file import package_prefix
    from hawt_tools.node_parameters import parse_overrides
    from hawt_tools.parameter_check import check_graph_parameters

    from hawt_plant.turbine import turbine_from

    folder.mkdir(parents=True, exist_ok=True)
    bts, openfast_bts = _turbulent_fields(case, turbine_from(turbine), folder, deck_hub_height(deck)) \
        if case.turbulent else (None, None)
    arguments, overrides = _hawt_overrides(case, turbine, bts)
    graph = load_graph(graph_path, arguments, package_prefix)
    plan = parse_overrides(graph, list(overrides) + list(parameters))
    run = build_run(graph, plan)  # at step 0, the operating point both sides start from
    check_graph_parameters(graph, plan)
    output = run.output
    discon = write_private_input(tuning_file(turbine, "discon"), folder / "DISCON.IN", {})
    inputs = CaseInputs(
        duration=case.duration, wind_speed=case.wind_speed, shear_exponent=case.shear_exponent,
        rotor_speed=float(output.rotor_speed), pitch=tuple(float(p) for p in output.pitch),
        azimuth=float(output.azimuth), tower_top=(float(output.tower_top_fa_disp), float(output.tower_top_ss_disp)),
        discon_library=rosco_files()[0], discon_input=discon,
        channels=openfast_channel_names(run.description.blades),
        bts_file=openfast_bts)
    return run, write_case(deck, folder, case.name, inputs)


def run_case(case: ValidationCase, turbine: str, graph_path: Path, deck: Path, openfast: Path, out: Path,
             parameters: Sequence[str] = (), progress: Callable[[str], None] = print) -> CaseResult:
    """Run ``case`` (:func:`prepare_case`) in OpenFAST (in a thread) and in hawt (here) at once, then analyse both
    over the same window.

    ``graph_path`` is the ``validation`` graph; ``parameters`` are more ``-p NODE.PARAM:=VALUE`` for hawt's side.
    """
    from hawt_analysis.openfast_output import read_openfast_output
    from hawt_bag.plant_run import load_plant_run
    from hawt_bag.reader import BagReader
    from hawt_tools.in_process import step_run

    from hawt_plant.plant_setup import aerodynamics_line

    (out / "hawt").mkdir(parents=True, exist_ok=True)
    run, written = prepare_case(case, turbine, graph_path, deck, out / "openfast" / case.name, parameters)
    output = run.output

    failure: List[BaseException] = []
    walls: Dict[str, float] = {}
    tenth = {"next": 0.1}

    def openfast_progress(t: float, total: float) -> None:
        if total > 0 and t / total >= tenth["next"] - 1e-9:
            tenth["next"] = math.floor(t / total * 10 + 1e-9) / 10 + 0.1
            progress(f"  {case.name}: OpenFAST t={t:g} of {total:g} s")

    def openfast_run() -> None:
        try:
            walls["openfast"] = run_openfast(openfast, written.fst, openfast_progress)
        except BaseException as error:  # handed to the main thread, which raises it
            failure.append(error)

    thread = threading.Thread(target=openfast_run, name=f"openfast-{case.name}", daemon=True)
    thread.start()
    bag = out / "hawt" / f"{case.name}.mcap"
    if bag.exists():
        bag.unlink()

    def hawt_progress(line: str) -> None:
        if failure:  # OpenFAST has failed: no use in finishing hawt's side
            raise failure[0]
        progress(f"  {case.name}: hawt {line}")

    began = time.monotonic()
    step_run(run, case.duration, bag, hawt_progress)
    walls["hawt"] = time.monotonic() - began
    thread.join()
    if failure:
        raise failure[0]
    with BagReader(bag) as reader:
        hawt_channels = analysed_window(load_plant_run(reader).channels, case.analysed)
    openfast_channels = analysed_window(read_openfast_output(output_of(written.fst), run.description.blades),
                                        case.analysed)
    checks = TURBULENT_CHECKS if case.turbulent else STEADY_CHECKS
    rows = compare_figures(case_figures(hawt_channels), case_figures(openfast_channels), checks)
    settings = {"plant": f"{aerodynamics_line(run.turbine, run.plant_values)}, dt {run.plant_values['dt']} s",
                "hub_height_openfast": written.hub_height, "hub_height_hawt": run.turbine.hub_height,
                "not_like_for_like": not_like_for_like(run.turbine),
                "initial": {"rotor_speed_rpm": float(output.rotor_speed) * 30 / math.pi,
                            "pitch_deg": [math.degrees(p) for p in output.pitch],
                            "tower_top_m": (float(output.tower_top_fa_disp), float(output.tower_top_ss_disp))}}
    return CaseResult(case, rows, hawt_channels, openfast_channels, bag, output_of(written.fst), written.changed,
                      walls["hawt"], walls["openfast"], settings)


def _difference_text(row: Mapping) -> str:
    if row["absolute"]:
        return f"{row['difference']:+.3g} {row['unit']}"
    return f"{100 * row['difference']:+.1f} %" if math.isfinite(row["difference"]) else "—"


def _tolerance_text(row: Mapping) -> str:
    return f"{row['tolerance']:g} {row['unit']}" if row["absolute"] else f"{100 * row['tolerance']:g} %"


def case_table(result: CaseResult) -> List[str]:
    """The Markdown table of one case's checks."""
    lines = ["| figure | hawt | OpenFAST | difference | tolerance | |", "|---|---:|---:|---:|---:|---|"]
    for row in result.rows:
        lines.append(f"| {row['label']} [{row['unit']}] | {row['hawt']:.4g} | {row['openfast']:.4g} | "
                     f"{_difference_text(row)} | {_tolerance_text(row)} | {'within' if row['within'] else '**outside**'} |")
    return lines


def not_like_for_like(turbine: Turbine) -> List[str]:
    """What the two sides model differently by construction, as sentences for the report: a tower on a flexible base
    (its substructure's sections in the plant's tower mode) against OpenFAST's deck, which a case runs on a rigid base
    (:data:`hawt_tools.openfast_case.FIXED_BOTTOM`)."""
    tower = turbine.tower
    if tower.base_kind != "flexible":
        return []
    return [f"The plant's tower stands on its flexible substructure (the beam clamped at {tower.clamp_height:g} m, "
            f"the tower's base at {tower.base_height:g} m); OpenFAST runs the deck on a rigid base (no substructure, "
            "waves or soil), so the tower's mode, and with it the tower's figures (its 3P above all), are not like "
            "for like."]


def report_text(turbine: str, openfast: Path, results: Sequence[CaseResult]) -> str:
    """``validation.md``: what was run and every case's table."""
    within = sum(row["within"] for r in results for row in r.rows)
    total = sum(len(r.rows) for r in results)
    lines = [f"# hawt validate: {turbine} against OpenFAST", "",
             f"OpenFAST: `{openfast}`. Controller on both sides: ROSCO (the rosco wheel's libdiscon.so) with the "
             "turbine's DISCON.IN. Both sides start at hawt's operating point of the case's mean wind (rotor speed, "
             "pitch, azimuth, tower-top displacements); each figure is computed by hawt's analysis over the last part "
             "of the run, the same window on both sides.", "",
             f"**{within} of {total} figures within tolerance.**", ""]
    notes = results[0].settings.get("not_like_for_like", []) if results else []
    if notes:
        lines += [" ".join(notes), ""]
    for result in results:
        case = result.case
        wind = (f"IEC class {case.turbulence_class} turbulence, seed {case.seed}, the plant's field as a TurbSim .bts"
                if case.turbulent else "steady")
        plant = result.settings["plant"]
        lines += [f"## {case.name}", "",
                  f"{case.wind_speed:g} m/s at the hub, shear {case.shear_exponent:g}, {wind}; {case.duration:g} s "
                  f"simulated, the last {case.analysed:g} s analysed. Wall: hawt {result.hawt_wall:.1f} s, OpenFAST "
                  f"{result.openfast_wall:.1f} s (run at once, one core each).", "",
                  f"hawt plant: {plant}; hub height {result.settings['hub_height_hawt']:.2f} m "
                  f"(OpenFAST {result.settings['hub_height_openfast']:.2f} m).", "",
                  *case_table(result), "",
                  "The deck as run differs from the turbine's deck in: "
                  + ("; ".join(result.deck_changes) or "nothing") + ".", "",
                  f"![{case.name} time series]({case.name}_time_series.png)",
                  f"![{case.name} spectra]({case.name}_spectra.png)", ""]
    return "\n".join(lines)


def write_report(turbine: str, openfast: Path, results: Sequence[CaseResult], out: Path) -> Path:
    """Write ``validation.md``, ``validation.json``, ``index.html`` and each case's overlaid time series and spectra
    into ``out``; return the HTML page."""
    import html

    from hawt_analysis.analysis_report import write_html_page
    from hawt_analysis.plots import _save, plot_compared_spectra, plot_compared_time_series

    images = []
    for result in results:
        runs = {"hawt": result.hawt_channels, "OpenFAST": result.openfast_channels}
        images.append(_save(plot_compared_time_series(runs, {}), out / f"{result.case.name}_time_series.png"))
        images.append(_save(plot_compared_spectra(runs), out / f"{result.case.name}_spectra.png"))
    text = report_text(turbine, openfast, results)
    (out / "validation.md").write_text(text + "\n")
    data = [{"case": asdict(r.case), "rows": r.rows, "bag": str(r.bag), "openfast_output": str(r.openfast_output),
             "deck_changes": list(r.deck_changes), "wall_s": {"hawt": r.hawt_wall, "openfast": r.openfast_wall},
             "settings": r.settings} for r in results]
    (out / "validation.json").write_text(json.dumps({"turbine": turbine, "openfast": str(openfast), "cases": data},
                                                    indent=1, default=str))
    tables = []
    for result in results:
        body = "".join(
            f"<tr><td>{html.escape(row['label'])} [{html.escape(row['unit'])}]</td><td>{row['hawt']:.4g}</td>"
            f"<td>{row['openfast']:.4g}</td><td>{html.escape(_difference_text(row))}</td>"
            f"<td>{html.escape(_tolerance_text(row))}</td>"
            f"<td style=\"color:{'#070' if row['within'] else '#b00'}\">{'within' if row['within'] else 'outside'}</td>"
            "</tr>" for row in result.rows)
        tables.append(f"<h2>{html.escape(result.case.name)}</h2><table><tr><th>figure</th><th>hawt</th>"
                      f"<th>OpenFAST</th><th>difference</th><th>tolerance</th><th></th></tr>{body}</table>")
    return write_html_page(out / "index.html", f"hawt validate: {turbine} against OpenFAST", text.split("\n## ")[0],
                           images, ["validation.md", "validation.json"], tables)
