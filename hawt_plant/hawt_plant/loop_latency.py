"""Latency of the realtime control loop, as the plant sees it, in constant memory.

The latency of step k is the wall time from the plant sending step k's measurements to
the arrival of the command that answers step k. The plant keeps the send times of the
last ``window`` steps, and the latencies in an HDR histogram (HdrHistogram, the
maintained standard for latency percentiles: microsecond resolution, 3 significant
digits) so that a run of any length has the same memory: with a list of every latency
the plant grew by 23 MiB per hour in the 30-minute realtime soak at 100 Hz.
"""
import numpy as np
from hdrh.histogram import HdrHistogram

__all__ = ["LoopLatency"]

_LONGEST_US = 60_000_000
"""Largest latency the histogram resolves [µs]; longer ones are counted as this."""


class LoopLatency:
    """Send times of recent steps, and the histogram of answer latencies with the count of late answers."""

    def __init__(self, window: int = 256) -> None:
        self.window = window
        self._sent = np.full(window, np.nan)
        self.histogram = HdrHistogram(1, _LONGEST_US, 3)
        self.late_steps = 0

    def sent(self, step: int, now: float) -> None:
        """Step ``step`` was sent at wall time ``now`` [s]."""
        self._sent[step % self.window] = now

    def answered(self, step: int, plant_step: int, now: float) -> None:
        """The command of ``step`` arrived at ``now`` [s] while the plant was at ``plant_step`` (late if behind)."""
        if step < plant_step:
            self.late_steps += 1
        if plant_step - step < self.window:
            microseconds = int(round((now - self._sent[step % self.window]) * 1e6))
            self.histogram.record_value(min(max(microseconds, 1), _LONGEST_US))

    def summary(self) -> str:
        """``loop latency p50 … ms, p99 … ms, max … ms; late steps N`` (empty before the first answer)."""
        if self.histogram.get_total_count() == 0:
            return ""
        p50, p99 = (self.histogram.get_value_at_percentile(p) / 1e3 for p in (50.0, 99.0))
        return (f"loop latency p50 {p50:.2f} ms, p99 {p99:.2f} ms, max {self.histogram.get_max_value() / 1e3:.2f} ms; "
                f"late steps {self.late_steps}")
