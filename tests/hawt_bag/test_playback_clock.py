"""Player time of a replay: rate, pause, resume and jumps map bag time to wall time like rosbag2's PlayerClock."""
import pytest

from hawt_bag.playback_clock import PlaybackClock


class FakeWall:
    """A wall clock the test moves by hand [ns]."""

    def __init__(self) -> None:
        self.now = 1_000

    def __call__(self) -> int:
        return self.now


def test_bag_time_runs_rate_times_as_fast_as_wall_time():
    """At rate 2, one wall second is two bag seconds, and a message 4 s into the bag is due after 2 s."""
    wall = FakeWall()
    clock = PlaybackClock(bag_start=50_000_000_000, rate=2.0, now=wall)
    wall.now += 1_000_000_000
    assert clock.bag_now() == 52_000_000_000
    assert clock.wall_time_of(54_000_000_000) == 1_000 + 2_000_000_000


def test_pause_freezes_bag_time_and_resume_continues_without_a_jump():
    """Paused: bag time stands still and nothing is due; resumed: it continues from where it stopped."""
    wall = FakeWall()
    clock = PlaybackClock(bag_start=0, now=wall)
    wall.now += 300
    clock.pause()
    wall.now += 10_000
    assert clock.bag_now() == 300 and clock.wall_time_of(400) is None
    clock.resume()
    wall.now += 50
    assert clock.bag_now() == 350
    assert clock.wall_time_of(400) == wall.now + 50


def test_rate_change_keeps_the_current_bag_time():
    """Changing the rate re-anchors: the bag time at the change is kept, later times scale with the new rate."""
    wall = FakeWall()
    clock = PlaybackClock(bag_start=0, now=wall)
    wall.now += 1_000
    clock.set_rate(0.5)
    wall.now += 1_000
    assert clock.bag_now() == 1_500


def test_jump_sets_bag_time_for_a_step_while_paused():
    """play_next while paused moves bag time to the released message and stays paused."""
    wall = FakeWall()
    clock = PlaybackClock(bag_start=0, now=wall, paused=True)
    clock.jump(7_000)
    assert clock.paused and clock.bag_now() == 7_000


@pytest.mark.parametrize("rate", [0.0, -1.0, float("nan")])
def test_rate_must_be_positive(rate):
    """A rate that is not > 0 is refused, naming the argument."""
    with pytest.raises(ValueError, match="rate: expected a positive playback rate"):
        PlaybackClock(bag_start=0, rate=rate)
