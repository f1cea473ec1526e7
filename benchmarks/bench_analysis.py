"""Time the numbers of `hawt analyze` on a 600 s, 100 Hz, 3-bladed synthetic run with every channel.

Run from the repository root:  .venv/bin/python benchmarks/bench_analysis.py
Target: the whole `hawt analyze` under 2 s, so summarize() well under 1 s.
"""
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "hawt_analysis"))

from hawt_analysis.fatigue import damage_equivalent_load  # noqa: E402
from hawt_analysis.harmonics import harmonic_amplitudes  # noqa: E402
from hawt_analysis.pitch_activity import pitch_activity  # noqa: E402
from hawt_analysis.record import make_record  # noqa: E402
from hawt_analysis.spectra import power_spectrum, spectral_peaks  # noqa: E402
from hawt_analysis.summary import analysed_channels, load_channels, summarize  # noqa: E402
from hawt_analysis.synthetic_run import synthetic_channels  # noqa: E402

REPEATS = 5


def _best(function) -> float:
    """Best wall time of REPEATS calls [s]."""
    times = []
    for _ in range(REPEATS):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    channels = synthetic_channels(duration=600.0, sample_rate=100.0, n_blades=3, seed=0)
    record = make_record(channels)
    loads = load_channels(record)
    analysed = analysed_channels(record)
    print(f"record: {record.time.size} samples, {len(channels)} channels, "
          f"{len(loads)} DEL channels, {len(analysed)} harmonic/PSD channels")
    parts = {
        "make_record (checks)": lambda: make_record(channels),
        "DELs (rainflow)": lambda: [damage_equivalent_load(v, 10.0, record.duration) for v, _ in loads.values()],
        "harmonics 1P-6P": lambda: harmonic_amplitudes(
            np.column_stack(list(analysed.values())), record.scalars["azimuth"]
        ),
        "PSD + peaks": lambda: [spectral_peaks(power_spectrum(v, 100.0), 8, 0.2) for v in analysed.values()],
        "pitch activity": lambda: pitch_activity(record.time, record.per_blade["pitch"]),
        "summarize (all)": lambda: summarize(channels),
    }
    for name, function in parts.items():
        print(f"{name:22s} {1e3 * _best(function):8.1f} ms (best of {REPEATS})")
    summary = summarize(channels)
    print(f"JSON size: {len(json.dumps(summary))} bytes")
    from hawt_analysis.plots import write_report  # noqa: E402  (matplotlib import counted separately)

    with tempfile.TemporaryDirectory() as directory:
        start = time.perf_counter()
        write_report(channels, summary, Path(directory))
        print(f"{'write_report (3 PNG)':22s} {1e3 * (time.perf_counter() - start):8.1f} ms (once)")


if __name__ == "__main__":
    main()
