"""The turbulent load study of issue 4: CPC, +1P, +1P+2P and +1P+2P+3P IPC through the real node graph.

Run with ``./hawt bench ipc_study``. For each seed, four runs of the installed graphs in lockstep,
each recorded by ``hawt launch --record`` to ``<output>/seed<N>/<configuration>.mcap`` (its launch
output in ``.log`` beside it), on the same IEC class B turbulent field at 18 m/s mean hub speed:

- ``cpc``: the ``baseline`` graph (plant, cpc, mbc);
- ``ipc1``, ``ipc12``, ``ipc123``: the ``ipc`` graph with IPC-1P, 1P+2P, 1P+2P+3P active (its ``ipc_h1``,
  ``ipc_h2``, ``ipc_h3`` arguments; the others start inactive);
- ``rc``: the ``repetitive`` graph (repetitive IPC, Fratini 2019) on the same wind, shear and tower shadow.

Each node runs in its own process unless ``--composed``: a composed graph runs several times faster
than the recorder takes its messages, and the bag then misses steps. A bag that misses steps (in
the middle or at the end) or a failed launch is kept as ``<name>.failed<k>.mcap`` and the run
launched again, at most ``--attempts`` times.

Every bag is analysed by `hawt_analysis.run_analysis.analyze_bag`; per configuration the study gives the
mean over seeds (and min-max) of: blade-root M_oop DEL (m = 10, mean of the blades), hub tilt, hub yaw
and tower-base fore-aft DEL (m = 4), rotor-speed standard deviation, mean electrical power, pitch
travel per blade, max pitch rate and max pitch acceleration (measured pitch), each with its change
against CPC (`hawt_analysis.comparison.change_percent` of the means). Then the criteria of issue 4 for
+1P+2P against CPC, on the means over seeds (the change per seed is shown too):

- blade-root M_oop DEL at least 20 % lower;
- hub tilt and hub yaw DELs lower;
- rotor-speed standard deviation at most 10 % higher;

and the max pitch rate and acceleration beside van Engelen (2006) §4 (2, 7, 10, 12 °/s; 3, 18, 27,
50 °/s²). The table is printed and written to ``<output>/study.md`` and ``<output>/study.json``.

Usage: ./hawt bench ipc_study [--seeds N ...] [--duration S] [--output DIR] [--jobs J] [--composed | --in-process]
                             [--attempts A] [--reuse]
"""
from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor, as_completed
from pathlib import Path
from typing import Callable, Dict, List, NamedTuple, Optional, Sequence

import numpy as np
from domain_coordinator import domain_id
from hawt_analysis.comparison import change_percent
from hawt_bag.errors import BagError
from hawt_analysis.run_analysis import analyze_bag
from hawt_plant.turbine import nrel_5mw

WIND = {"wind_type": "turbulent", "wind_speed": "18.0"}
"""Graph arguments of every run besides seed and duration (turbulence class B is the plant's default)."""


class Configuration(NamedTuple):
    """One controller configuration: its bag name, label, installed graph and graph arguments."""

    name: str
    label: str
    graph: str
    arguments: Dict[str, str]


CONFIGURATIONS = (
    Configuration("cpc", "CPC", "baseline", {}),
    Configuration("ipc1", "+1P", "ipc", {"ipc_h1": "true", "ipc_h2": "false", "ipc_h3": "false"}),
    Configuration("ipc12", "+1P+2P", "ipc", {"ipc_h1": "true", "ipc_h2": "true", "ipc_h3": "false"}),
    Configuration("ipc123", "+1P+2P+3P", "ipc", {"ipc_h1": "true", "ipc_h2": "true", "ipc_h3": "true"}),
    Configuration("rc", "+repetitive", "repetitive", {"shear_exponent": "0.2", "tower_shadow": "true",
                                                       "learning_gain": "0.3", "proportional_gain": "0.1"}),
)
CRITERIA_CONFIGURATION = "ipc12"
"""The configuration the criteria of issue 4 judge against CPC (the first configuration)."""

VAN_ENGELEN = {"ipc": ("CPC", "+1P", "+2P", "+3P"), "max_rate_deg_s": (2.0, 7.0, 10.0, 12.0),
               "max_acceleration_deg_s2": (3.0, 18.0, 27.0, 50.0)}
"""Van Engelen (2006) §4, per configuration in the order of CONFIGURATIONS (seed003 notes)."""


class Metric(NamedTuple):
    """A figure of one run: key, label, unit, and how it is read from an `analyze_bag` summary."""

    key: str
    label: str
    unit: str
    value: Callable[[dict], float]


def _del(summary: dict, channel: str, m: float) -> float:
    """DEL of ``channel`` [N·m], checked to use Wöhler exponent ``m``."""
    load = summary["del"][channel]
    if load["m"] != m:
        raise BagError(f"{summary['bag']['file']}: {channel} DEL has m = {load['m']}, the study needs m = {m:g}")
    return load["value"]


def _blade_mean_del(summary: dict, field: str, m: float) -> float:
    """Mean over the blades of the DELs of ``field`` [N·m]."""
    return float(np.mean([_del(summary, f"{field}_{blade}", m) for blade in range(1, summary["n_blades"] + 1)]))


METRICS = (
    Metric("del_root_oop", "blade-root M_oop DEL m=10 (mean of blades)", "MN·m",
           lambda s: 1e-6 * _blade_mean_del(s, "root_moment_oop", 10.0)),
    Metric("del_hub_tilt", "hub tilt DEL m=4", "MN·m", lambda s: 1e-6 * _del(s, "hub_tilt_moment", 4.0)),
    Metric("del_hub_yaw", "hub yaw DEL m=4", "MN·m", lambda s: 1e-6 * _del(s, "hub_yaw_moment", 4.0)),
    Metric("del_tower_fa", "tower-base FA DEL m=4", "MN·m", lambda s: 1e-6 * _del(s, "tower_base_fa_moment", 4.0)),
    Metric("rotor_speed_std", "rotor-speed std", "rpm", lambda s: s["rotor_speed"]["std"] * 30.0 / np.pi),
    Metric("power_mean", "electrical power mean", "MW", lambda s: 1e-6 * s["power"]["mean"]),
    Metric("pitch_travel", "pitch travel per blade", "deg",
           lambda s: float(np.rad2deg(s["pitch"]["travel_rad"]["total"] / s["n_blades"]))),
    Metric("pitch_max_rate", "max pitch rate", "deg/s",
           lambda s: float(np.rad2deg(s["pitch"]["max_rate_rad_s"]["max"]))),
    Metric("pitch_max_acceleration", "max pitch acceleration", "deg/s²",
           lambda s: float(np.rad2deg(s["pitch"]["max_acceleration_rad_s2"]["max"]))),
)


def bag_path(output: Path, seed: int, configuration: Configuration) -> Path:
    """Where the run of ``configuration`` on ``seed`` is recorded."""
    return output / f"seed{seed}" / f"{configuration.name}.mcap"


def launch_command(configuration: Configuration, seed: int, duration: float, bag: Path, engine: str) -> List[str]:
    """The command line that records one run: ``engine`` 'processes' or 'composed' is ``hawt launch`` in lockstep,
    'in_process' is ``hawt run`` (the same numbers, tests/hawt_tools/test_in_process.py)."""
    arguments = {**WIND, "seed": str(seed), "duration": f"{duration:g}", **configuration.arguments}
    verb = ["run"] if engine == "in_process" else ["launch", *(["--composed"] * (engine == "composed"))]
    return [sys.executable, "-m", "hawt_tools.cli", verb[0], configuration.graph, *verb[1:],
            "--record", str(bag), *(f"{name}:={value}" for name, value in arguments.items())]


def launch(command: List[str], log: Path, timeout: float) -> str | None:
    """Run ``command`` on a ROS domain of its own, its output appended to ``log``; why it failed, or None.

    After ``timeout`` wall seconds the launch gets SIGINT (it stops its graph and recorder), then
    SIGKILL if it has not ended 60 s later.
    """
    with domain_id() as domain, open(log, "a") as output:
        output.write(f"$ {' '.join(command)}\n")
        output.flush()
        with subprocess.Popen(command, stdout=output, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                              env={**os.environ, "ROS_DOMAIN_ID": str(domain)}) as process:
            try:
                code = process.wait(timeout)
            except subprocess.TimeoutExpired:
                process.send_signal(signal.SIGINT)
                try:
                    process.wait(60.0)
                except subprocess.TimeoutExpired:
                    process.kill()
                return f"no end within {timeout:g} s"
    return None if code == 0 else f"exit {code}: {log.read_text().splitlines()[-1]}"


def run_figures(bag: Path, duration: float) -> Dict[str, float]:
    """The METRICS of one recorded run, checked to cover ``duration`` simulated seconds.

    Raises
    ------
    BagError
        If the bag cannot be analysed, misses steps in the middle (from `analyze_bag`) or ends early.
    """
    summary = analyze_bag(bag).summary
    covered = summary["duration_s"] + 1.0 / summary["sample_rate_hz"]
    if covered < duration - 1e-6:
        raise BagError(f"{bag}: the recorded steps cover {covered:g} s of the {duration:g} s run")
    return {metric.key: metric.value(summary) for metric in METRICS}


def recorded_figures(configuration: Configuration, seed: int, bag: Path, duration: float, engine: str,
                     attempts: int, report: Callable[[str], None]) -> Dict[str, float]:
    """Record one run into ``bag`` (its launch output in ``<bag>.log``) and return its `run_figures`.

    A launch that fails or a bag that misses steps is reported and renamed
    ``<bag>.failed<attempt>.mcap``, and the run launched again (lockstep runs are deterministic,
    so a repeat records the same run), at most ``attempts`` times in all.

    Raises
    ------
    RuntimeError
        If the last attempt fails.
    """
    bag.parent.mkdir(parents=True, exist_ok=True)
    command = launch_command(configuration, seed, duration, bag, engine)
    log = bag.with_suffix(".log")
    log.unlink(missing_ok=True)
    attempt = 1
    while True:
        failure = launch(command, log, timeout=30.0 * duration + 600.0)
        if failure is None:
            try:
                return run_figures(bag, duration)
            except BagError as error:
                failure = str(error)
        if attempt == attempts:
            raise RuntimeError(f"{bag}: attempt {attempt} of {attempts} failed ({failure}; log {log})")
        if bag.exists():
            bag.rename(bag.with_suffix(f".failed{attempt}.mcap"))
        report(f"attempt {attempt} failed ({failure}); launching again")
        attempt += 1


def study_figures(runs: Sequence[tuple[Configuration, int, Path]], duration: float, engine: str, jobs: int,
                  attempts: int) -> Dict[str, Dict[int, Dict[str, float]]]:
    """Figures of every run (configuration, seed, bag), ``jobs`` at a time; a bag that exists is only analysed.

    Returns
    -------
    dict
        configuration name -> seed -> metric key -> value.
    """
    start = time.monotonic()
    lock = threading.Lock()

    def report(line: str) -> None:
        with lock:
            print(line, flush=True)

    def figures_of(number: int, configuration: Configuration, seed: int, bag: Path) -> Dict[str, float]:
        name = f"[{number}/{len(runs)}] seed {seed} {configuration.label}"
        began = time.monotonic()
        if bag.exists():
            report(f"{name}: analysing {bag}")
            return run_figures(bag, duration)
        report(f"{name}: recording {bag} (at {began - start:.0f} s)")
        figures = recorded_figures(configuration, seed, bag, duration, engine, attempts,
                                   lambda line: report(f"{name}: {line}"))
        report(f"{name}: recorded and analysed in {time.monotonic() - began:.0f} s (elapsed "
               f"{time.monotonic() - start:.0f} s, load {os.getloadavg()[0]:.1f})")
        return figures

    figures: Dict[str, Dict[int, Dict[str, float]]] = {c.name: {} for c in CONFIGURATIONS}
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        futures = {pool.submit(figures_of, number, *run): run for number, run in enumerate(runs, 1)}
        try:
            for future in as_completed(futures):
                configuration, seed, _ = futures[future]
                figures[configuration.name][seed] = future.result()
        except BaseException:
            for future in futures:
                future.cancel()
            raise
    return figures


def aggregate(figures: Dict[str, Dict[int, Dict[str, float]]], seeds: Sequence[int]) -> dict:
    """Per metric and configuration: values per seed, mean, min, max, and changes against the first configuration.

    Parameters
    ----------
    figures : dict
        configuration name -> seed -> metric key -> value, as `run_figures` gives.
    seeds : sequence of int

    Returns
    -------
    dict
        metric key -> {label, unit, configurations: name -> {per_seed, mean, min, max,
        change_percent (of the means), change_percent_per_seed}}.
    """
    names = [c.name for c in CONFIGURATIONS]
    table = {}
    for metric in METRICS:
        values = np.array([[figures[name][seed][metric.key] for seed in seeds] for name in names])
        change_of_mean = change_percent(values.mean(axis=1).tolist())
        change_per_seed = np.array([change_percent(column.tolist()) for column in values.T], dtype=float).T
        table[metric.key] = {"label": metric.label, "unit": metric.unit, "configurations": {
            name: {"per_seed": row.tolist(), "mean": float(row.mean()), "min": float(row.min()),
                   "max": float(row.max()), "change_percent": change, "change_percent_per_seed": per_seed.tolist()}
            for name, row, change, per_seed in zip(names, values, change_of_mean, change_per_seed)}}
    return table


def criteria(table: dict) -> List[dict]:
    """The pass/fail criteria of issue 4 for CRITERIA_CONFIGURATION against CPC, on the means over seeds."""
    # metric, limit of the change [%], whether the limit itself fails, wording
    checks = (("del_root_oop", -20.0, False, "at least 20 % lower"), ("del_hub_tilt", 0.0, True, "lower"),
              ("del_hub_yaw", 0.0, True, "lower"), ("rotor_speed_std", 10.0, False, "at most 10 % higher"))
    result = []
    for key, limit, strict, wanted in checks:
        row = table[key]["configurations"][CRITERIA_CONFIGURATION]
        change = row["change_percent"]
        result.append({"metric": key, "label": table[key]["label"], "wanted": wanted, "limit_percent": limit,
                       "change_percent": change, "change_percent_per_seed": row["change_percent_per_seed"],
                       "passed": bool(change < limit if strict else change <= limit)})
    return result


def study_markdown(study: dict) -> str:
    """The study as markdown: conditions, table, criteria, van Engelen comparison."""
    labels = [c["label"] for c in study["configurations"]]
    wind = study["wind"]
    lines = [f"# IPC load study (issue 4): {wind['wind_type']} {wind['wind_speed']} m/s, IEC class B, "
             f"{study['duration_s']:g} s, seeds {', '.join(map(str, study['seeds']))}", "",
             f"Command: `{study['command']}`", "",
             "Mean over seeds (min–max over seeds) [change of the mean against CPC].", "",
             "| metric | unit | " + " | ".join(labels) + " |", "|---|---|" + "---|" * len(labels)]
    for row in study["table"].values():
        cells = []
        for name, cell in row["configurations"].items():
            change = "" if name == study["configurations"][0]["name"] else f" [{cell['change_percent']:+.1f} %]"
            cells.append(f"{cell['mean']:.4g} ({cell['min']:.4g}–{cell['max']:.4g}){change}")
        lines.append(f"| {row['label']} | {row['unit']} | " + " | ".join(cells) + " |")
    criteria_label = next(c["label"] for c in study["configurations"] if c["name"] == CRITERIA_CONFIGURATION)
    lines += ["", f"## Criteria of issue 4 ({criteria_label} against CPC, means over seeds)", ""]
    for check in study["criteria"]:
        per_seed = ", ".join(f"{change:+.1f}" for change in check["change_percent_per_seed"])
        lines.append(f"- {'PASS' if check['passed'] else 'FAIL'}: {check['label']} {check['wanted']}: "
                     f"{check['change_percent']:+.1f} % (per seed: {per_seed} %)")
    lines += ["", f"## Pitch activity against van Engelen (2006) §4 (actuator rate limit "
                  f"{study['actuator_rate_limit_deg_s']:.1f} °/s)", "",
              "| configuration | van Engelen | max rate °/s | van Engelen °/s | max acceleration °/s² | "
              "van Engelen °/s² |", "|---|---|---|---|---|---|"]
    rates = study["table"]["pitch_max_rate"]["configurations"]
    accelerations = study["table"]["pitch_max_acceleration"]["configurations"]
    for configuration, ipc, rate, acceleration in zip(study["configurations"], *VAN_ENGELEN.values()):
        ours_rate, ours_acceleration = rates[configuration["name"]], accelerations[configuration["name"]]
        lines.append(f"| {configuration['label']} | {ipc} | {ours_rate['mean']:.2f} ({ours_rate['min']:.2f}–"
                     f"{ours_rate['max']:.2f}) | {rate:g} | {ours_acceleration['mean']:.1f} "
                     f"({ours_acceleration['min']:.1f}–{ours_acceleration['max']:.1f}) | {acceleration:g} |")
    return "\n".join(lines) + "\n"


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3], help="turbulence seeds (default 1 2 3)")
    parser.add_argument("--duration", type=float, default=600.0, help="simulated seconds per run (default 600)")
    parser.add_argument("--output", type=Path, default=Path("bags/study"), help="folder of bags and tables")
    parser.add_argument("--jobs", type=int, default=2, help="runs at a time, each on its own ROS domain")
    parser.add_argument("--composed", action="store_true",
                        help="run each graph in one process (faster, but the recorder may then fall behind and "
                             "lose steps, which fails the run)")
    parser.add_argument("--in-process", action="store_true",
                        help="hawt run instead of hawt launch: the same numbers, several times faster")
    parser.add_argument("--attempts", type=int, default=3, help="launches of a run before giving up (default 3)")
    parser.add_argument("--reuse", action="store_true",
                        help="analyse the bags already in --output instead of recording them again (records "
                             "only the missing ones)")
    args = parser.parse_args(argv)
    engine = "in_process" if args.in_process else "composed" if args.composed else "processes"
    runs = [(configuration, seed, bag_path(args.output, seed, configuration))
            for seed in args.seeds for configuration in CONFIGURATIONS]
    try:
        existing = [bag for _, _, bag in runs if bag.exists()]
        if existing and not args.reuse:
            raise BagError(f"{existing[0]}: exists; pass --reuse to analyse it, or choose another --output")
        print(f"ipc study: {len(runs)} runs of {args.duration:g} s simulated, {len(runs) - len(existing)} to record "
              f"({engine}, {args.jobs} at a time) into {args.output}", flush=True)
        figures = study_figures(runs, args.duration, engine, args.jobs, args.attempts)
    except (BagError, RuntimeError) as error:
        print(f"bench ipc_study: {error}", file=sys.stderr)
        return 1
    table = aggregate(figures, args.seeds)
    study = {
        "command": " ".join(["./hawt bench ipc_study", *(sys.argv[1:] if argv is None else argv)]),
        "wind": WIND, "turbulence_class": "B", "duration_s": args.duration, "seeds": args.seeds,
        "configurations": [{"name": c.name, "label": c.label, "graph": c.graph, "arguments": c.arguments}
                           for c in CONFIGURATIONS],
        "bags": {c.name: {seed: str(bag_path(args.output, seed, c)) for seed in args.seeds} for c in CONFIGURATIONS},
        "table": table,
        "criteria": criteria(table),
        "actuator_rate_limit_deg_s": float(np.rad2deg(nrel_5mw().pitch_actuator.max_rate)),
        "van_engelen": VAN_ENGELEN,
    }
    text = study_markdown(study)
    (args.output / "study.md").write_text(text)
    (args.output / "study.json").write_text(json.dumps(study, indent=1))
    print(f"\n{text}\nwritten: {args.output / 'study.md'}, {args.output / 'study.json'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
