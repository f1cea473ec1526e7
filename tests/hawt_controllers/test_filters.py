"""Specification of hawt_controllers.laws.filters: low-pass, notch, state handling, validation."""

import math

import numpy as np
import pytest

from hawt_core.exceptions import ConfigurationError
from hawt_controllers.laws.filters import (
    DiscreteFilter,
    ExponentialLowPass,
    cascade,
    first_order_lowpass,
    notch,
    second_order_lowpass,
)

DT = 0.00625  # ROSCO NREL-5MW time step [s]

DESIGNS = {
    "first_order": lambda ch=(): first_order_lowpass(1.5708, DT, ch),
    "second_order": lambda ch=(): second_order_lowpass(2.0, 0.7, DT, ch),
    "notch": lambda ch=(): notch(3.8, 0.0, 0.25, DT, ch),
}


@pytest.mark.parametrize("name", DESIGNS)
def test_dc_gain_is_one(name):
    """Low-passes and the notch pass a constant unchanged."""
    f = DESIGNS[name]()
    assert f.dc_gain == pytest.approx(1.0, abs=1e-12)
    assert abs(f.frequency_response(0.0)[0]) == pytest.approx(1.0, abs=1e-12)
    assert f.filter(np.ones(20000))[-1] == pytest.approx(1.0, abs=1e-9)


def test_first_order_low_pass_is_three_db_down_at_its_corner():
    """|H(jω_c)| = 1/√2 exactly, thanks to prewarping."""
    f = first_order_lowpass(1.5708, DT)
    assert abs(f.frequency_response(1.5708)[0]) == pytest.approx(1 / math.sqrt(2), abs=1e-12)


@pytest.mark.parametrize("damping", [0.3, 1 / math.sqrt(2), 1.0])
def test_second_order_low_pass_has_gain_one_over_two_zeta_at_its_corner(damping):
    """|H(jω)| = 1/(2ζ) at the natural frequency (−3 dB for ζ = 1/√2)."""
    f = second_order_lowpass(2.0, damping, DT)
    assert abs(f.frequency_response(2.0)[0]) == pytest.approx(1 / (2 * damping), rel=1e-10)


@pytest.mark.parametrize("beta_num, beta_den", [(0.0, 0.25), (0.05, 0.25), (0.1, 0.5)])
def test_notch_depth_at_its_frequency_is_beta_num_over_beta_den(beta_num, beta_den):
    """ROSCO's notch has gain β_num/β_den at ω (0 = full notch)."""
    f = notch(3.8, beta_num, beta_den, DT)
    assert abs(f.frequency_response(3.8)[0]) == pytest.approx(beta_num / beta_den, abs=1e-9)


def test_full_notch_removes_a_sinusoid_at_its_frequency():
    """After the transient, a sine at the notch frequency is gone."""
    t = np.arange(0, 60, DT)
    y = notch(3.8, 0.0, 0.25, DT).filter(np.sin(3.8 * t))
    assert np.max(np.abs(y[t > 40])) < 1e-3


def test_first_order_low_pass_matches_roscos_unwarped_recursion_closely():
    """ROSCO's y_k = [−(ωdt − 2)y_{k−1} + ωdt(u_k + u_{k−1})]/(2 + ωdt) differs by O((ωdt)²) only."""
    w, rng = 1.5708, np.random.default_rng(4)
    u = rng.normal(size=4000)
    rosco, y_prev, u_prev = np.zeros_like(u), 0.0, 0.0
    for k in range(u.size):
        rosco[k] = y_prev = (-(w * DT - 2) * y_prev + w * DT * (u[k] + u_prev)) / (2 + w * DT)
        u_prev = u[k]
    ours = first_order_lowpass(w, DT).filter(u)
    assert np.max(np.abs(ours - rosco)) < (w * DT) ** 2


@pytest.mark.parametrize("name", DESIGNS)
def test_filtering_in_chunks_equals_filtering_at_once(name):
    """The state carried between calls makes chunked output identical (two channels)."""
    x = np.random.default_rng(5).normal(size=(1000, 2))
    whole = DESIGNS[name]((2,)).filter(x)
    chunked_filter = DESIGNS[name]((2,))
    pieces = [chunked_filter.filter(x[a:b]) for a, b in [(0, 1), (1, 333), (333, 334), (334, 1000)]]
    np.testing.assert_allclose(np.vstack(pieces), whole, atol=1e-13)
    stepper = DESIGNS[name]((2,))
    np.testing.assert_allclose([stepper.step(sample) for sample in x], whole, atol=1e-13)
    on_floats = DESIGNS[name]((2,))  # the per-step path on plain floats is the same recursion, bit for bit
    assert [on_floats.step_values(sample.tolist()) for sample in x] == [s.tolist() for s in
                                                                      map(DESIGNS[name]((2,)).step, x)]


@pytest.mark.parametrize("name", DESIGNS)
def test_reset_to_steady_state_gives_no_transient(name):
    """reset(initial) makes a constant input of that value pass through from the first sample."""
    f = DESIGNS[name]((2,))
    f.reset([3.0, -1.5])
    np.testing.assert_allclose(f.filter(np.tile([3.0, -1.5], (50, 1))), np.tile([3.0, -1.5], (50, 1)), atol=1e-12)


PROTOTYPES = {  # each design's continuous prototype b(s)/a(s), prewarped at its frequency w
    "first_order": (lambda w: ([w], [1.0, w]), 1.5708),
    "second_order": (lambda w: ([w * w], [1.0, 1.4 * w, w * w]), 2.0),
    "notch": (lambda w: ([1.0, 0.0, w * w], [1.0, 0.5 * w, w * w]), 3.8),
}


@pytest.mark.parametrize("name", DESIGNS)
def test_the_sections_and_their_steady_state_are_scipys_bilinear_tf2sos_and_sosfilt_zi(name):
    """The Tustin substitution and the steady state written out give scipy.signal's coefficients and zi."""
    signal = pytest.importorskip("scipy.signal")
    prototype, frequency = PROTOTYPES[name]
    warped = 2.0 / DT * math.tan(frequency * DT / 2.0)
    expected = signal.tf2sos(*signal.bilinear(*prototype(warped), fs=1.0 / DT))
    f = DESIGNS[name]()
    np.testing.assert_allclose(f.sos, expected, rtol=1e-12, atol=1e-15)
    chain = cascade(f, DESIGNS["second_order"]())
    f.reset(1.0)
    chain.reset(1.0)
    np.testing.assert_allclose(f.state, signal.sosfilt_zi(f.sos), rtol=1e-10, atol=1e-15)
    np.testing.assert_allclose(chain.state, signal.sosfilt_zi(chain.sos), rtol=1e-10, atol=1e-15)


def test_cascade_multiplies_the_responses():
    """A series connection has the product of the frequency responses."""
    a, b = first_order_lowpass(1.0, DT), notch(3.8, 0.0, 0.25, DT)
    w = np.array([0.5, 2.0, 5.0])
    np.testing.assert_allclose(cascade(a, b).frequency_response(w), a.frequency_response(w) * b.frequency_response(w))


@pytest.mark.parametrize(
    "make, field",
    [
        (lambda: first_order_lowpass(math.nan, DT), "corner_frequency: must be finite"),
        (lambda: first_order_lowpass(-1.0, DT), "corner_frequency: must be > 0"),
        (lambda: first_order_lowpass(600.0, DT), "corner_frequency: .*Nyquist"),
        (lambda: second_order_lowpass(2.0, 0.0, DT), "damping: must be > 0"),
        (lambda: second_order_lowpass(2.0, math.nan, DT), "damping: must be finite"),
        (lambda: notch(3.8, 0.0, -0.1, DT), "beta_den: must be > 0"),
        (lambda: notch(3.8, -0.1, 0.25, DT), "beta_num: must be >= 0"),
        (lambda: first_order_lowpass(1.0, 0.0), "dt: must be > 0"),
        (lambda: DiscreteFilter([[1, 0, 0, 1, -2.5, 1.5]], DT), "sos: unstable design"),
        (lambda: DiscreteFilter([[1, 0, 0, 1, math.nan, 0]], DT), "sos: NaN"),
    ],
)
def test_invalid_designs_are_refused_naming_the_parameter(make, field):
    """NaN, negative bandwidth, above Nyquist, unstable: refused with the parameter named."""
    with pytest.raises(ConfigurationError, match=field):
        make()


def test_exponential_low_pass_is_jonkmans_recursion_and_starts_at_its_first_input():
    """y = (1 − α)u + α y_prev with α = exp(−ω dt); the first output equals the first input."""
    f = ExponentialLowPass(1.570796)
    assert f.step(100.0, 0.01) == 100.0
    alpha = math.exp(-1.570796 * 0.02)
    assert f.step(110.0, 0.02) == pytest.approx((1 - alpha) * 110.0 + alpha * 100.0)


def test_exponential_low_pass_reaches_one_minus_one_over_e_after_one_time_constant():
    """The step response is 1 − exp(−ωt) at the sample times, whatever the step size."""
    f = ExponentialLowPass(2.0)
    f.reset(0.0)
    for dt in [0.1, 0.05, 0.2, 0.15]:
        y = f.step(1.0, dt)
    assert y == pytest.approx(1 - math.exp(-1.0), rel=1e-12)
