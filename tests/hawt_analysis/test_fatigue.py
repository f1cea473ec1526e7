"""Specification of hawt_analysis.fatigue: rainflow counting and damage-equivalent loads."""
import numpy as np
import pytest
from scipy import signal as sps

from hawt_analysis.fatigue import WohlerExponents, damage_equivalent_load, rainflow_cycles


def _plain_astm_cycles(series):
    """Independent reference: ASTM E1049-85 §5.4.4 three-point rainflow, written plainly.

    Returns a list of (range, count), count 1.0 for a full cycle and 0.5 for a half.
    """
    reversals = [series[0]]
    for previous, current, following in zip(series, series[1:], series[2:]):
        if (current - previous) * (following - current) < 0.0:
            reversals.append(current)
        elif current == following:
            raise AssertionError("the reference expects no plateaus")
    reversals.append(series[-1])
    stack, cycles = [], []
    for point in reversals:
        stack.append(point)
        while len(stack) >= 3:
            x_range = abs(stack[-1] - stack[-2])
            y_range = abs(stack[-2] - stack[-3])
            if x_range < y_range:
                break
            if len(stack) == 3:
                cycles.append((y_range, 0.5))
                stack.pop(0)
            else:
                cycles.append((y_range, 1.0))
                del stack[-3:-1]
    cycles.extend((abs(b - a), 0.5) for a, b in zip(stack, stack[1:]))
    return cycles


def _realistic_load(seed=3, duration=600.0, sample_rate=100.0):
    """Filtered noise plus 1P and 3P sines at 12.1 rpm, sampled at 100 Hz [N·m]."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(duration * sample_rate)) / sample_rate
    one_p = 1.267 / (2.0 * np.pi)
    noise = sps.sosfilt(sps.butter(2, 1.5, fs=sample_rate, output="sos"), rng.standard_normal(t.size))
    return 8e6 + 2e6 * np.sin(2 * np.pi * one_p * t) + 5e5 * np.sin(6 * np.pi * one_p * t + 1.0) + 1e7 * noise


def test_astm_example_history_gives_the_standard_cycle_count():
    """The load history of ASTM E1049-85 Fig. 6 (-2, 1, -3, 5, -1, 3, -4, 4, -2) counts as in the standard."""
    cycles = rainflow_cycles([-2.0, 1.0, -3.0, 5.0, -1.0, 3.0, -4.0, 4.0, -2.0])
    assert cycles.ranges.tolist() == [3.0, 4.0, 6.0, 8.0, 9.0]
    assert cycles.counts.tolist() == [0.5, 1.5, 0.5, 1.0, 0.5]


@pytest.mark.parametrize("m", [4.0, 10.0])
def test_cosine_of_whole_periods_gives_twice_its_amplitude_scaled_by_cycles_per_second(m):
    """A cosine of amplitude A over N whole periods has DEL = 2A·(N/N_eq)^(1/m)."""
    amplitude, periods, per_period, duration = 3.0e6, 40, 100, 120.0
    k = np.arange(periods * per_period + 1)
    load = damage_equivalent_load(amplitude * np.cos(2 * np.pi * k / per_period), m, duration)
    assert load.value == pytest.approx(2 * amplitude * (periods / duration) ** (1 / m), rel=1e-12)
    assert load.n_cycles == pytest.approx(periods)
    assert (load.m, load.n_eq) == (m, duration)


def test_sine_from_zero_counts_its_end_ranges_as_half_cycles():
    """A sine from 0 over N periods counts N − ½ cycles of 2A and two half cycles of A (ASTM residue)."""
    amplitude, periods, per_period, duration, m = 2.0, 25, 100, 50.0, 4.0
    k = np.arange(periods * per_period + 1)
    load = damage_equivalent_load(amplitude * np.sin(2 * np.pi * k / per_period), m, duration)
    damage = (periods - 0.5) * (2 * amplitude) ** m + 1.0 * amplitude**m
    assert load.value == pytest.approx((damage / duration) ** (1 / m), rel=1e-12)
    assert load.n_cycles == pytest.approx(periods + 0.5)


def test_two_level_block_sequence_gives_the_miner_sum_of_both_levels():
    """K blocks of one large range 2L holding k small cycles of range d give Σ = K(2L)^m + Kk·d^m."""
    large, small, level, blocks, small_per_block, m, duration = 10.0, 1.5, 4.0, 7, 5, 4.0, 30.0
    block = [-large] + [level, level - small] * small_per_block + [large]
    history = np.array(block * blocks + [-large])
    load = damage_equivalent_load(history, m, duration)
    damage = blocks * (2 * large) ** m + blocks * small_per_block * small**m
    assert load.value == pytest.approx((damage / duration) ** (1 / m), rel=1e-12)
    cycles = rainflow_cycles(history)
    assert dict(zip(cycles.ranges.tolist(), cycles.counts.tolist())) == {small: 35.0, 2 * large: 7.0}


@pytest.mark.parametrize("m", [4.0, 10.0])
def test_independent_plain_astm_count_agrees_on_a_realistic_load(m):
    """A separately written three-point ASTM count gives the same DEL within 1 % on noise plus 1P/3P."""
    history = _realistic_load()
    duration = 600.0
    reference = _plain_astm_cycles(history.tolist())
    ranges = np.array([r for r, _ in reference])
    counts = np.array([n for _, n in reference])
    expected = (np.sum(counts * ranges**m) / duration) ** (1 / m)
    load = damage_equivalent_load(history, m, duration)
    assert load.value == pytest.approx(expected, rel=0.01)
    assert load.n_cycles == pytest.approx(counts.sum())


def test_binning_to_upper_edges_raises_the_del_by_at_most_one_bin():
    """Binned ranges sit at their bin's upper edge, so DEL ≤ DEL_binned ≤ DEL + width·(Σn/N_eq)^(1/m) (Minkowski)."""
    history, m, duration, nbins = _realistic_load(seed=5), 10.0, 600.0, 100
    exact = damage_equivalent_load(history, m, duration)
    binned = damage_equivalent_load(history, m, duration, nbins=nbins)
    width = (history.max() - history.min()) / nbins
    assert exact.value <= binned.value <= exact.value + width * (exact.n_cycles / duration) ** (1 / m)
    assert binned.n_cycles == pytest.approx(exact.n_cycles)
    assert "binned to 100 bins" in binned.convention


def test_plateaus_and_constant_offsets_do_not_change_the_count():
    """Repeated samples and a constant offset leave the rainflow ranges unchanged."""
    history = _realistic_load(seed=7, duration=60.0)
    held = np.repeat(history, 3)
    assert damage_equivalent_load(held + 5e6, 10.0, 60.0).value == pytest.approx(
        damage_equivalent_load(history, 10.0, 60.0).value, rel=1e-12
    )


def test_constant_signal_has_zero_del():
    """A load that never changes does no fatigue damage."""
    assert damage_equivalent_load(np.full(100, 3.0), 4.0, 1.0).value == 0.0


def test_del_states_its_convention():
    """The result names ASTM counting, half cycles, no mean correction and the 1 Hz equivalent."""
    convention = damage_equivalent_load(_realistic_load(duration=10.0), 4.0, 10.0).convention
    for phrase in ("ASTM E1049-85", "half cycles count 0.5", "unbinned", "no mean-stress correction", "1 Hz"):
        assert phrase in convention


def test_wohler_exponents_default_to_ten_for_blades_and_four_for_steel():
    """m = 10 for composite blade roots and m = 4 for steel (WEIS defaults, van Engelen 2006 §4)."""
    exponents = WohlerExponents()
    assert (exponents.for_kind("blade_root"), exponents.for_kind("steel")) == (10.0, 4.0)
    with pytest.raises(ValueError, match="kind: expected 'blade_root' or 'steel', found 'wood'"):
        exponents.for_kind("wood")


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (([1.0, np.nan, 2.0], 4.0, 1.0), "root_moment_oop: NaN at sample 1"),
        (([[1.0, 2.0]], 4.0, 1.0), r"root_moment_oop: expected 1-D array \(samples,\), found shape \(1, 2\)"),
        (([1.0, 2.0], 0.0, 1.0), "m: Wöhler exponent must be positive"),
        (([1.0, 2.0], 4.0, 0.0), "duration: expected a positive record length"),
    ],
)
def test_bad_input_raises_value_error_naming_it(arguments, message):
    """NaN, a wrong shape, a non-positive m or duration are refused with the argument's name."""
    with pytest.raises(ValueError, match=message):
        damage_equivalent_load(*arguments, name="root_moment_oop")
