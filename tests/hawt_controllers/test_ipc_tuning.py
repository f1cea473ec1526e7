"""Specification of hawt_controllers.laws.ipc_tuning: van Engelen's I-gain recipe and delay offsets."""

import math

import numpy as np
import pytest

from hawt_core.exceptions import ConfigurationError
from hawt_controllers.laws.filters import second_order_lowpass
from hawt_controllers.laws.ipc_tuning import design_integral_gain, phase_offset_for_delay
from hawt_core.rotor.mbc import mbc_forward, mbc_inverse


def test_integral_gain_for_a_tenth_of_a_hertz_matches_van_engelens_recipe():
    """k_i = 2π·0.1/|k| and 82.8° phase margin with a 0.2 s delay (seed003 notes §3.6)."""
    design = design_integral_gain(-3.0e7, 2 * math.pi * 0.1, loop_delay=0.2)
    assert design.integral_gain == pytest.approx(2 * math.pi * 0.1 / 3.0e7)
    assert math.degrees(design.phase_margin) == pytest.approx(82.8, abs=0.05)


def test_gain_sign_gives_negative_feedback_for_either_plant_sign():
    """k_i·k < 0 whatever the sign of dM/dθ."""
    assert design_integral_gain(-1.0e7, 0.5).integral_gain > 0
    assert design_integral_gain(1.0e7, 0.5).integral_gain < 0


def test_loop_gain_is_one_at_the_bandwidth_with_the_prefilter_included():
    """|k_i k F(jω_c)/(jω_c)| = 1, and the phase margin includes the filter's lag."""
    prefilter, k, wc = second_order_lowpass(2.0, 0.7071, 0.0125), -5.0e7, 0.6
    design = design_integral_gain(k, wc, loop_delay=0.1, prefilter=prefilter)
    response = prefilter.frequency_response(wc)[0]
    loop = -design.integral_gain * k * response * np.exp(-1j * wc * 0.1) / (1j * wc)
    assert abs(loop) == pytest.approx(1.0)
    assert design.phase_margin == pytest.approx(math.pi + np.angle(loop))


def test_bandwidth_without_phase_margin_is_refused():
    """A crossover beyond what the delay allows is refused, naming the bandwidth."""
    with pytest.raises(ConfigurationError, match="bandwidth: .*no phase margin"):
        design_integral_gain(-1.0e7, 10.0, loop_delay=0.2)
    with pytest.raises(ConfigurationError, match="sensitivity: must be non-zero"):
        design_integral_gain(0.0, 0.6)


def test_delay_offset_is_n_omega_tau():
    """At 15 rpm a 0.2 s delay turns the 1P/2P/3P planes by 18°/36°/54° (seed003 notes §2.5)."""
    omega = 15 * 2 * math.pi / 60
    assert [round(math.degrees(phase_offset_for_delay(n, omega, 0.2)), 9) for n in (1, 2, 3)] == [18, 36, 54]


@pytest.mark.parametrize("harmonic", [1, 2])
def test_delay_offset_undoes_a_pure_delay_between_command_and_blade(harmonic):
    """A command applied τ late, remodulated with φ_n = nΩτ, demodulates to the demand."""
    omega, tau, c, s = 1.26711, 0.2, 0.03, -0.01
    psi = np.linspace(0, 2 * np.pi, 17)
    phi = phase_offset_for_delay(harmonic, omega, tau)
    applied = mbc_inverse(c, s, psi - omega * tau, harmonic, 3, phase_offset=phi)
    out = mbc_forward(applied, psi, harmonic)
    np.testing.assert_allclose([out.cos, out.sin], [[c] * 17, [s] * 17], atol=1e-12)
