"""The realtime loop's latency: from sending a step to the arrival of its command, in constant memory."""
import pytest

from hawt_plant.loop_latency import LoopLatency


def test_latency_runs_from_the_send_of_the_answered_step():
    latency = LoopLatency()
    latency.sent(5, 100.000)
    latency.answered(5, 5, 100.002)
    assert latency.histogram.get_value_at_percentile(50.0) == pytest.approx(2000, rel=1e-3)
    assert latency.late_steps == 0


def test_a_command_that_arrives_after_the_next_step_is_late_and_its_whole_latency_counts():
    """Step 5 answered 12 ms after it was sent, 2 ms after step 6 went out: late, latency 12 ms (not 2, not -8)."""
    latency = LoopLatency()
    latency.sent(5, 100.000)
    latency.sent(6, 100.010)
    latency.answered(5, 6, 100.012)
    assert latency.late_steps == 1
    assert latency.histogram.get_max_value() == pytest.approx(12000, rel=1e-3)
    assert latency.summary().endswith("max 12.01 ms; late steps 1")  # 3 significant digits: 12 000 -> 12 007 µs


def test_an_answer_older_than_the_window_is_late_without_a_latency():
    latency = LoopLatency(window=4)
    latency.sent(0, 1.0)
    for step in range(1, 10):
        latency.sent(step, 1.0 + step * 0.01)
    latency.answered(0, 9, 1.1)
    assert (latency.late_steps, latency.histogram.get_total_count()) == (1, 0)


def test_memory_does_not_grow_with_the_length_of_the_run():
    latency = LoopLatency()
    size = len(latency.histogram.counts)
    for step in range(200_000):
        latency.sent(step, step * 0.01)
        latency.answered(step, step, step * 0.01 + 0.002 + (step % 7) * 1e-4)
    assert len(latency.histogram.counts) == size
    assert latency.histogram.get_total_count() == 200_000
    assert latency.summary().startswith("loop latency p50 2.30 ms, p99 2.60 ms, max 2.60 ms")


def test_no_summary_before_the_first_answer():
    assert LoopLatency().summary() == ""
