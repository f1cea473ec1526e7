"""The H1 estimate of a two-input, two-output response from random-binary excitation (hawt_analysis.identification)."""
import numpy as np
import pytest
from scipy.signal import lfilter

from hawt_analysis.identification import frequency_response

FS = 20.0


def _binary(rng, n, hold):
    return np.repeat(rng.choice([-1.0, 1.0], size=n // hold + 1), hold)[:n]


def test_a_known_coupled_system_is_recovered_with_its_cross_terms_and_coherence():
    """y1 = a·u1 − b·u2, y2 = b·u1 + a·u2 with a, b first-order discrete filters (a scaled rotation, as the
    Coleman-frame plant is), plus output noise: P within 5 % where the excitation has power."""
    rng = np.random.default_rng(3)
    n = int(2000 * FS)
    u = np.column_stack([_binary(rng, n, 5), _binary(rng, n, 5)])
    pole = np.exp(-1.0 / (0.3 * FS))
    a = lambda x: lfilter([0.9 * (1 - pole)], [1, -pole], x)  # noqa: E731
    b = lambda x: lfilter([0.4 * (1 - pole)], [1, -pole], x)  # noqa: E731
    y = np.column_stack([a(u[:, 0]) - b(u[:, 1]), b(u[:, 0]) + a(u[:, 1])]) + 0.05 * rng.standard_normal((n, 2))
    identified = frequency_response(u, y, FS, segment_duration=100.0)
    z = np.exp(-2j * np.pi * identified.frequency / FS)
    first_order = (1 - pole) / (1 - pole * z)
    expected = np.stack([np.stack([0.9 * first_order, -0.4 * first_order], -1),
                         np.stack([0.4 * first_order, 0.9 * first_order], -1)], -2)
    band = (identified.frequency > 0.01) & (identified.frequency < 1.0)
    error = np.abs(identified.response[band] - expected[band]) / np.abs(expected[band][..., :1, :1])
    assert error.max() < 0.05
    assert identified.coherence[band].min() > 0.9


def test_inputs_that_are_not_excited_or_do_not_match_are_refused_by_name():
    u = np.column_stack([np.ones(1000), np.zeros(1000)])
    with pytest.raises(ValueError, match="inputs: their spectral matrix is singular"):
        frequency_response(u, np.zeros((1000, 2)), FS)
    with pytest.raises(ValueError, match="outputs: expected 1000 samples like inputs"):
        frequency_response(u, np.zeros((999, 2)), FS)
    with pytest.raises(ValueError, match="inputs"):
        frequency_response(np.full((1000, 2), np.nan), np.zeros((1000, 2)), FS)
