"""The numbers of ``hawt analyze``: one JSON-ready dict per recorded run (DESIGN §8)."""
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from .fatigue import CONVENTION as FATIGUE_CONVENTION
from .fatigue import WohlerExponents, damage_equivalent_load
from .harmonics import harmonic_amplitudes, revolutions
from .pitch_activity import DEFAULT_RATE_THRESHOLD, pitch_activity, pitch_activity_convention
from .record import Record, make_record
from .spectra import power_spectrum, rotor_harmonic_frequencies, spectral_peaks

__all__ = ["FATIGUE_CHANNELS", "AnalysisOptions", "analysed_channels", "load_channels", "summarize",
           "segment_harmonics"]

FATIGUE_CHANNELS = (
    ("root_moment_oop", "blade_root"),
    ("root_moment_ip", "blade_root"),
    ("hub_tilt_moment", "steel"),
    ("hub_yaw_moment", "steel"),
    ("hub_rotating_y_moment", "steel"),
    ("hub_rotating_z_moment", "steel"),
    ("yaw_bearing_tilt_moment", "steel"),
    ("yaw_bearing_yaw_moment", "steel"),
    ("tower_base_fa_moment", "steel"),
    ("tower_base_ss_moment", "steel"),
)
"""Load channels that get a DEL, with their kind of material (see `WohlerExponents`)."""


@dataclass(frozen=True)
class AnalysisOptions:
    """How a run is analysed.

    Attributes
    ----------
    wohler : WohlerExponents
        m by kind of load path (10 blade root, 4 steel).
    equivalent_frequency : float
        f_eq of the DEL [Hz]; N_eq = f_eq·T.
    rainflow_bins : int or None
        Range bins of the rainflow count; None counts exact ranges.
    harmonics : tuple of int
        Harmonics nP whose amplitudes are reported.
    psd_segment_duration : float
        Welch segment length [s].
    psd_peaks : int
        Peaks reported per channel.
    pitch_rate_threshold : float
        Pitch rate above which the actuator counts as active [rad/s].
    pitch_lowpass_cutoff : float or None
        Zero-phase low-pass of the pitch before differencing [Hz]; None: none.
    """

    wohler: WohlerExponents = field(default_factory=WohlerExponents)
    equivalent_frequency: float = 1.0
    rainflow_bins: int | None = None
    harmonics: tuple[int, ...] = (1, 2, 3, 4, 5, 6)
    psd_segment_duration: float = 60.0
    psd_peaks: int = 8
    pitch_rate_threshold: float = DEFAULT_RATE_THRESHOLD
    pitch_lowpass_cutoff: float | None = None


def load_channels(record: Record) -> dict[str, tuple[np.ndarray, str]]:
    """Load channels of ``record`` that get a DEL: name → (signal, kind), per-blade fields expanded."""
    loads = {}
    for channel, kind in FATIGUE_CHANNELS:
        if channel in record.scalars:
            columns = {channel: record.scalars[channel]}
        else:
            columns = record.blade_columns(channel)
        loads.update({name: (values, kind) for name, values in columns.items()})
    return loads


def analysed_channels(record: Record) -> dict[str, np.ndarray]:
    """Channels that get harmonics and spectra: the load channels, then each blade's pitch."""
    channels = {name: values for name, (values, _) in load_channels(record).items()}
    channels.update(record.blade_columns("pitch"))
    return channels


def summarize(channels: Mapping[str, ArrayLike], options: AnalysisOptions = AnalysisOptions()) -> dict:
    """Analyse one run: DELs, harmonics, spectra, pitch activity and operating statistics.

    Parameters
    ----------
    channels : Mapping[str, array_like]
        Named channel arrays as described in `hawt_analysis.record` (``time``,
        ``azimuth``, ``rotor_speed`` required; ``root_moment_oop`` etc. of shape
        (n_samples, n_blades); SI units).
    options : AnalysisOptions

    Returns
    -------
    dict
        JSON-serialisable (plain floats, ints, strings, lists; None where a channel
        is absent) with the keys of DESIGN §8: ``duration_s``, ``sample_rate_hz``,
        ``n_blades``, ``del``, ``harmonics``, ``psd``, ``pitch``, ``rotor_speed``,
        ``power``, ``conventions``.

    Raises
    ------
    ValueError
        Naming the channel at fault (see `make_record`). A record of less than one
        rotor revolution (``revolutions``: a short one, or a parked or idling rotor's)
        has no ``harmonics`` ({}).
    """
    record = make_record(channels)
    loads = load_channels(record)
    analysed = analysed_channels(record)
    rotor_speed = record.scalars["rotor_speed"]
    return {
        "duration_s": record.duration,
        "sample_rate_hz": record.sample_rate,
        "n_blades": record.n_blades,
        "del": _damage_equivalent_loads(loads, record.duration, options),
        "revolutions": revolutions(record.scalars["azimuth"]),
        "harmonics": _harmonics(analysed, record.scalars["azimuth"], options.harmonics),
        "psd": _spectra(analysed, record.sample_rate, float(rotor_speed.mean()), options),
        "pitch": _pitch(record, options),
        "rotor_speed": {"mean": float(rotor_speed.mean()), "std": float(rotor_speed.std())},
        "power": (
            {"mean": float(record.scalars["electrical_power"].mean())}
            if "electrical_power" in record.scalars
            else None
        ),
        "conventions": _conventions(options),
    }


def segment_harmonics(channels: Mapping[str, ArrayLike], boundaries: ArrayLike,
                      options: AnalysisOptions = AnalysisOptions(), min_revolutions: int = 1) -> list[dict]:
    """Harmonic amplitudes of every analysed channel between boundaries (e.g. the steps of controller switches).

    Parameters
    ----------
    channels : Mapping[str, array_like]
        As for :func:`summarize`.
    boundaries : array_like of int
        Sample indices where a segment starts (0 and the end are added).
    min_revolutions : int
        A segment with fewer whole rotor revolutions is reported without harmonics.

    Returns
    -------
    list of dict
        Per segment: ``first``, ``last`` (sample indices), ``start_s``, ``duration_s``,
        ``harmonics`` (as in :func:`summarize`, or None if the segment is too short).
    """
    record = make_record(channels)
    n = record.time.size
    edges = sorted({0, n, *(int(b) for b in np.asarray(boundaries).ravel() if 0 < b < n)})
    segments = []
    for first, end in zip(edges[:-1], edges[1:]):
        part = {name: np.asarray(values)[first:end] for name, values in channels.items()}
        turns = abs(float(np.unwrap(part["azimuth"])[-1] - np.unwrap(part["azimuth"])[0])) / (2 * np.pi) \
            if end - first > 2 else 0.0
        harmonics = None
        if turns >= min_revolutions:
            piece = make_record(part)
            harmonics = _harmonics(analysed_channels(piece), piece.scalars["azimuth"], options.harmonics)
        segments.append({"first": first, "last": end - 1, "start_s": float(record.time[first]),
                         "duration_s": float(record.time[end - 1] - record.time[first]), "harmonics": harmonics})
    return segments


def _damage_equivalent_loads(
    loads: dict[str, tuple[np.ndarray, str]], duration: float, options: AnalysisOptions
) -> dict:
    result = {}
    for name, (values, kind) in loads.items():
        load = damage_equivalent_load(
            values,
            options.wohler.for_kind(kind),
            duration,
            equivalent_frequency=options.equivalent_frequency,
            nbins=options.rainflow_bins,
            name=name,
        )
        result[name] = {"value": load.value, "m": load.m, "n_eq": load.n_eq, "n_cycles": load.n_cycles}
    return result


def _harmonics(analysed: dict[str, np.ndarray], azimuth: np.ndarray, harmonics: tuple[int, ...]) -> dict:
    if not analysed or revolutions(azimuth) < 1.0:  # a short record's, or a standing or idling rotor's
        return {}
    names = list(analysed)
    fit = harmonic_amplitudes(np.column_stack(list(analysed.values())), azimuth, harmonics, name=names[0])
    return {
        name: {
            "n": list(fit.harmonics),
            "amplitude": fit.amplitude[i].tolist(),
            "amplitude_per_revolution_rms": fit.amplitude_per_revolution_rms[i].tolist(),
            "revolutions": fit.revolutions,
        }
        for i, name in enumerate(names)
    }


def _spectra(
    analysed: dict[str, np.ndarray], sample_rate: float, mean_rotor_speed: float, options: AnalysisOptions
) -> dict:
    rotor_frequency = float(rotor_harmonic_frequencies(mean_rotor_speed, (1,))[0])
    peaks = {}
    resolution = None
    for name, values in analysed.items():
        spectrum = power_spectrum(values, sample_rate, options.psd_segment_duration, name=name)
        resolution = spectrum.resolution
        peaks[name] = [
            {"frequency_hz": peak.frequency, "density": peak.density, "harmonic": peak.harmonic}
            for peak in spectral_peaks(spectrum, options.psd_peaks, rotor_frequency)
        ]
    return {
        "segment_duration_s": None if resolution is None else 1.0 / resolution,
        "frequency_resolution_hz": resolution,
        "rotor_frequency_hz": rotor_frequency,
        "harmonic_frequencies_hz": rotor_harmonic_frequencies(mean_rotor_speed, options.harmonics).tolist(),
        "peaks": peaks,
    }


def _pitch(record: Record, options: AnalysisOptions) -> dict | None:
    if "pitch" not in record.per_blade:
        return None
    activity = pitch_activity(
        record.time,
        record.per_blade["pitch"],
        rate_threshold=options.pitch_rate_threshold,
        lowpass_cutoff=options.pitch_lowpass_cutoff,
    )
    return {
        "travel_rad": {"per_blade": activity.travel.tolist(), "total": activity.total_travel},
        "max_rate_rad_s": {"per_blade": activity.max_rate.tolist(), "max": activity.overall_max_rate},
        "max_acceleration_rad_s2": {
            "per_blade": activity.max_acceleration.tolist(),
            "max": activity.overall_max_acceleration,
        },
        "duty_cycle": {"per_blade": activity.duty_cycle.tolist(), "mean": activity.mean_duty_cycle},
        "rate_threshold_rad_s": activity.rate_threshold,
    }


def _conventions(options: AnalysisOptions) -> dict:
    binning = "none"
    if options.rainflow_bins is not None:
        binning = f"{options.rainflow_bins} bins, ranges at upper bin edges"
    return {
        "units": "SI: moments N*m, angles rad, rates rad/s and rad/s^2, power W, time s, frequency Hz; "
        "PSD in (channel unit)^2/Hz",
        "channels": "per-blade fields are reported per blade as <field>_<blade>, blades numbered from 1",
        "cycle_counting": "rainflow, ASTM E1049-85 (rainflow 3.2.0); residual half cycles count 0.5",
        "binning": binning,
        "mean_correction": "none",
        "equivalent_frequency_hz": options.equivalent_frequency,
        "del": FATIGUE_CONVENTION,
        "wohler_m": {"blade_root": options.wohler.blade_root, "steel": options.wohler.steel},
        "harmonics": "least-squares fit of mean, linear trend, cos(n psi) and sin(n psi) per whole "
        "revolution of the azimuth psi; amplitude = |mean over revolutions of (a_n - i b_n)| (periodic part), "
        "amplitude_per_revolution_rms = sqrt(mean of a_n^2 + b_n^2)",
        "psd": "Welch, Hann window, 50% overlap, segment means removed, one-sided density; peaks = local "
        "maxima of log10(PSD) whose prominence within +-10 bins is >= max(0.3 decade, 7 robust standard "
        "deviations of the log-PSD scatter), strongest first; labelled n (nP) within 1.5 bins of n * 1P",
        "pitch": pitch_activity_convention(options.pitch_rate_threshold, options.pitch_lowpass_cutoff),
        "rotor_speed": "mean and population standard deviation over the record",
    }
