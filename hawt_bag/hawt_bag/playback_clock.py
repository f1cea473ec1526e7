"""Player time of a replay: bag time mapped to wall time at a rate, with pause and resume.

As rosbag2's PlayerClock (``docs/design/rosbag2_playback_time.md``): the clock holds
an anchor pair (bag time, wall time); while playing, bag time advances ``rate`` times
as fast as wall time from the anchor; pausing freezes bag time; resuming and changing
the rate re-anchor at the current bag time, so no message is skipped or bunched.
All times are integer nanoseconds; wall time comes from ``now`` (monotonic by default).
"""
import time
from typing import Callable, Optional

__all__ = ["PlaybackClock"]


class PlaybackClock:
    """Bag time ↔ wall time for a replay.

    Parameters
    ----------
    bag_start : int
        Bag time at which playback starts [ns].
    rate : float
        Playback speed (> 0): 2 plays twice as fast as recorded.
    now : callable
        Wall clock [ns].
    paused : bool
        Start paused.
    """

    def __init__(self, bag_start: int, rate: float = 1.0, now: Callable[[], int] = time.monotonic_ns,
                 paused: bool = False) -> None:
        if not rate > 0.0:
            raise ValueError(f"rate: expected a positive playback rate, found {rate}")
        self._now = now
        self._bag_anchor = int(bag_start)
        self._wall_anchor = now()
        self._rate = float(rate)
        self._paused = paused

    @property
    def rate(self) -> float:
        return self._rate

    @property
    def paused(self) -> bool:
        return self._paused

    def bag_now(self) -> int:
        """The current bag time [ns]."""
        if self._paused:
            return self._bag_anchor
        return self._bag_anchor + round((self._now() - self._wall_anchor) * self._rate)

    def wall_time_of(self, bag_time: int) -> Optional[int]:
        """Wall time at which bag time ``bag_time`` is reached [ns]; None while paused."""
        if self._paused:
            return None
        return self._wall_anchor + round((bag_time - self._bag_anchor) / self._rate)

    def _anchor(self, bag_time: int) -> None:
        self._bag_anchor, self._wall_anchor = bag_time, self._now()

    def pause(self) -> None:
        """Freeze bag time."""
        if not self._paused:
            self._anchor(self.bag_now())
            self._paused = True

    def resume(self) -> None:
        """Let bag time run again from where it stopped."""
        if self._paused:
            self._anchor(self._bag_anchor)
            self._paused = False

    def set_rate(self, rate: float) -> None:
        """Change the speed from now on."""
        if not rate > 0.0:
            raise ValueError(f"rate: expected a positive playback rate, found {rate}")
        self._anchor(self.bag_now())
        self._rate = float(rate)

    def jump(self, bag_time: int) -> None:
        """Set the current bag time (a step while paused, or the start of a loop)."""
        self._anchor(int(bag_time))
