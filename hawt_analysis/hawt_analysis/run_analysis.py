"""The numbers of ``hawt analyze`` and ``hawt compare`` for bags: `hawt_analysis` on the recorded topics.

`analyze_bag` reads one turbine's run (`plant_run.load_plant_run`) and returns the
dict of `hawt_analysis.summary.summarize` (DESIGN §8) with seven more keys:
``bag`` (file, namespace, messages per topic), ``pitch_command`` (activity of the
commanded pitch the plant obeyed and the steps each PitchCommand flag was set; None
without that topic), ``refused_commands`` (per publisher whose pitch commands the plant
refused, an intruder: ``publisher``, ``messages``, ``first_step``, ``last_step``; empty
without), ``events`` (the ``control/events`` timeline), ``segments`` (harmonic
amplitudes between the steps of controller switches; empty without switches),
``wind_estimate`` (per controller that publishes one and per axis, its estimate against
the plant's true blade-effective wind, `hawt_analysis.wind_estimation`; empty without) and
``warnings`` (one line each, e.g. steps missing in the plant topics; empty if none).
"""
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Dict, Optional, Sequence

import numpy as np

from hawt_bag.errors import BagError
from hawt_bag.plant_run import PlantRun, load_plant_run
from hawt_bag.reader import BagReader

from .comparison import compare_summaries
from .pitch_activity import pitch_activity
from .summary import AnalysisOptions, segment_harmonics, summarize
from .wind_estimation import AXES, EstimateQuality, estimate_quality

__all__ = ["BagAnalysis", "analyze_bag", "compare_bags", "wind_estimate_qualities"]


@dataclass(frozen=True)
class BagAnalysis:
    """One analysed bag: the run's arrays and the JSON-ready summary."""

    path: Path
    run: PlantRun
    summary: dict


def _command_summary(run: PlantRun, options: AnalysisOptions) -> Optional[dict]:
    command = run.pitch_command
    if command is None or command["time"].size < 3 or command["pitch"].ndim != 2:
        return None
    activity = pitch_activity(command["time"], command["pitch"], rate_threshold=options.pitch_rate_threshold,
                              lowpass_cutoff=options.pitch_lowpass_cutoff)
    # The commanded rate is what was commanded from one step to the next, not a central difference: a command
    # held to 8 deg/s per step reads 8 deg/s, where a difference of second order reads more at a reversal.
    max_rate = np.max(np.abs(np.diff(command["pitch"], axis=0)) / np.diff(command["time"])[:, None], axis=0)
    flags = command["flags"].astype(np.int64)
    return {
        "steps": int(command["time"].size),
        "travel_rad": {"per_blade": activity.travel.tolist(), "total": activity.total_travel},
        "max_rate_rad_s": {"per_blade": max_rate.tolist(), "max": float(max_rate.max())},
        "duty_cycle": {"per_blade": activity.duty_cycle.tolist(), "mean": activity.mean_duty_cycle},
        "individual_rms_rad": np.sqrt(np.mean(command["individual"] ** 2, axis=0)).tolist()
        if command["individual"].ndim == 2 and command["individual"].shape[1] else None,
        "flag_steps": {name: int(np.count_nonzero(flags & bit)) for bit, name in sorted(run.flag_names.items())},
    }


def analyze_bag(path: os.PathLike, namespace: Optional[str] = None, options: AnalysisOptions = AnalysisOptions(),
                progress: Callable[[str], None] = lambda _: None) -> BagAnalysis:
    """Analyse one turbine's run in a bag.

    Parameters
    ----------
    path : path-like
    namespace : str, optional
        The turbine's namespace (``/wt1``); found automatically when the bag holds one.
    options : hawt_analysis.summary.AnalysisOptions
    progress : callable
        Called with a short line at each stage (reading a topic, analysing).

    Returns
    -------
    BagAnalysis

    Raises
    ------
    BagError
        Naming the file and the topic or channel at fault.
    """
    with BagReader(path) as reader:
        run = load_plant_run(reader, namespace, progress)
    progress(f"analysing {run.steps.size} steps")
    try:
        summary = summarize(run.channels, options)
    except ValueError as error:
        raise BagError(f"{path}: {error}") from None
    summary["bag"] = {"file": str(path), "namespace": run.namespace or "/", "messages": run.counts,
                      "first_step": int(run.steps[0]), "last_step": int(run.steps[-1])}
    summary["pitch_command"] = _command_summary(run, options)
    summary["refused_commands"] = run.refused_commands
    summary["events"] = run.events
    summary["segments"] = _switch_segments(run, options)
    summary["wind_estimate"] = {name: {axis: quality.summary() for axis, quality in by_axis.items()}
                                for name, by_axis in wind_estimate_qualities(run, options).items()}
    summary["warnings"] = list(run.warnings)
    return BagAnalysis(Path(path), run, summary)


def wind_estimate_qualities(run: PlantRun, options: AnalysisOptions = AnalysisOptions()
                            ) -> Dict[str, Dict[str, EstimateQuality]]:
    """Per controller that published a wind estimate, per axis (cos, sin): the estimate against the plant's
    truth at the steps both have (none if the bag's plant/state lacks the truth, recorded before it had it)."""
    if not {f"effective_wind_{axis}" for axis in AXES} <= set(run.channels):
        return {}
    rate = 1.0 / float(np.median(np.diff(run.channels["time"])))
    return {name: {axis: estimate_quality(run.channels[f"effective_wind_{axis}"][estimate["rows"]],
                                          estimate[f"wind_{axis}"], rate, options.psd_segment_duration)
                   for axis in AXES}
            for name, estimate in run.wind_estimates.items() if estimate["rows"].size >= 3}


def _switch_segments(run: PlantRun, options: AnalysisOptions) -> list:
    """Harmonics between the steps at which controller switches took effect (none without switches)."""
    steps = sorted({e["step"] for e in run.events if e["kind"] == "switch"})
    if not steps:
        return []
    segments = segment_harmonics(run.channels, np.searchsorted(run.steps, steps), options)
    for segment in segments:
        segment["first_step"], segment["last_step"] = int(run.steps[segment["first"]]), int(run.steps[segment["last"]])
    return segments


def compare_bags(paths: Sequence[os.PathLike], namespace: Optional[str] = None,
                 options: AnalysisOptions = AnalysisOptions(),
                 progress: Callable[[str], None] = lambda _: None) -> tuple[list[BagAnalysis], dict]:
    """Analyse several bags and compare each with the first (`hawt_analysis.comparison.compare_summaries`).

    Labels are the file names (their paths if names repeat).

    Returns
    -------
    (list of BagAnalysis, dict)
        The analyses, and the comparison dict.
    """
    if len(paths) < 2:
        raise BagError(f"expected at least two bags, found {len(paths)}")
    analyses = []
    for number, path in enumerate(paths, 1):
        progress(f"[{number}/{len(paths)}] {path}")
        analyses.append(analyze_bag(path, namespace, options, progress))
    labels = [Path(p).name for p in paths]
    if len(set(labels)) != len(labels):
        labels = [str(p) for p in paths]
    try:
        comparison = compare_summaries([a.summary for a in analyses], labels)
    except ValueError as error:
        raise BagError(f"compare: {error}") from None
    return analyses, comparison
