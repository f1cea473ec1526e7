"""The numbers of ``hawt compare``: several run summaries against the first."""
from collections.abc import Mapping, Sequence

__all__ = ["change_percent", "compare_summaries"]

_PITCH_METRICS = (
    ("travel_rad", "total"),
    ("max_rate_rad_s", "max"),
    ("max_acceleration_rad_s2", "max"),
    ("duty_cycle", "mean"),
)


def change_percent(values: Sequence[float]) -> list[float | None]:
    """100·(v − v_0)/|v_0| for each value against the first; None where v_0 = 0."""
    reference = values[0]
    return [None if reference == 0.0 else 100.0 * (value - reference) / abs(reference) for value in values]


def _series(values: list[float]) -> dict:
    return {"value": values, "change_percent": change_percent(values)}


def _common(summaries: Sequence[Mapping], section: str) -> list[str]:
    """Channels of ``section`` present in every summary, in the first summary's order."""
    return [name for name in summaries[0][section] if all(name in summary[section] for summary in summaries)]


def compare_summaries(summaries: Sequence[Mapping], labels: Sequence[str]) -> dict:
    """Compare run summaries (from `summarize`) with the first one.

    Parameters
    ----------
    summaries : sequence of dict
        Outputs of `hawt_analysis.summary.summarize`, the reference first.
    labels : sequence of str
        One unique label per summary (e.g. the bag file names).

    Returns
    -------
    dict
        JSON-serialisable: ``labels``, ``reference`` and, for the DELs and harmonic
        amplitudes of the channels every run has, the pitch activity, rotor speed
        and power, each number as ``{"value": [per run], "change_percent": [per run]}``
        (change against the first run, 0 for the first; None where the reference is 0);
        harmonic amplitudes and their changes are lists per run of lists per harmonic.
        ``pitch`` and ``power`` are None unless every run has them. ``warnings``: one line for runs
        of different length or sample rate (their DELs and spectra cover different records), else empty.

    Raises
    ------
    ValueError
        If the counts differ, labels repeat, or a channel's Wöhler exponent differs
        between runs (its DELs would not be comparable).
    """
    if len(summaries) != len(labels) or not summaries:
        raise ValueError(f"labels: expected one label per summary ({len(summaries)}), found {len(labels)}")
    if len(set(labels)) != len(labels):
        raise ValueError(f"labels: expected unique labels, found {list(labels)}")
    loads = {}
    for name in _common(summaries, "del"):
        exponents = {summary["del"][name]["m"] for summary in summaries}
        if len(exponents) > 1:
            raise ValueError(f"{name}: Wöhler exponent differs between runs ({sorted(exponents)})")
        values = [summary["del"][name]["value"] for summary in summaries]
        loads[name] = _series(values) | {"m": exponents.pop()}
    harmonics = {}
    for name in _common(summaries, "harmonics"):
        amplitudes = [summary["harmonics"][name]["amplitude"] for summary in summaries]
        changes_per_harmonic = [change_percent(per_run) for per_run in zip(*amplitudes)]
        harmonics[name] = {
            "n": summaries[0]["harmonics"][name]["n"],
            "amplitude": amplitudes,
            "change_percent": [list(per_harmonic) for per_harmonic in zip(*changes_per_harmonic)],
        }
    pitch = None
    if all(summary["pitch"] is not None for summary in summaries):
        pitch = {
            metric: _series([summary["pitch"][metric][overall] for summary in summaries])
            for metric, overall in _PITCH_METRICS
        }
    power = None
    if all(summary["power"] is not None for summary in summaries):
        power = {"mean": _series([summary["power"]["mean"] for summary in summaries])}
    return {
        "labels": list(labels),
        "reference": labels[0],
        "warnings": _differences(summaries, labels),
        "del": loads,
        "harmonics": harmonics,
        "pitch": pitch,
        "rotor_speed": {
            statistic: _series([summary["rotor_speed"][statistic] for summary in summaries])
            for statistic in ("mean", "std")
        },
        "power": power,
    }


def _differences(summaries: Sequence[Mapping], labels: Sequence[str]) -> list[str]:
    """Lines naming what makes the runs' figures cover different records: length and sample rate."""
    found = []
    for key, name, unit, tolerance in (("duration_s", "length", "s", lambda s: 1.0 / s["sample_rate_hz"]),
                                       ("sample_rate_hz", "sample rate", "Hz", lambda s: 1e-6 * s["sample_rate_hz"])):
        values = [summary[key] for summary in summaries]
        if max(values) - min(values) > tolerance(summaries[0]):
            listed = ", ".join(f"{label} {value:.6g} {unit}" for label, value in zip(labels, values))
            found.append(f"the runs differ in {name} ({listed}): their DELs and spectra cover different records")
    return found
