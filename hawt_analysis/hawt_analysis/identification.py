"""A multi-input frequency response from recorded signals by cross-spectra (the H1 estimator).

For inputs u (n_inputs channels) and outputs y (n_outputs channels), sampled together, the
estimate at each frequency is

    P(jω) = S_yu(ω) S_uu(ω)⁻¹,

with S_yu[i, k] the cross-spectral density of y_i and u_k and S_uu[k, l] that of u_k and u_l
(Welch averages: scipy.signal.csd, Hann windows, half overlap). Noise on the outputs that is
uncorrelated with the inputs averages out; the coherence says where the estimate can be trusted.
This is how Disario (2018 §5-1) identified the tilt/yaw transfer matrix of the NREL 5 MW from
random-binary excitation of θ_tilt and θ_yaw.
"""
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.signal import csd

from ._checks import finite_array, same_length

__all__ = ["FrequencyResponse", "frequency_response", "ColemanIdentification", "identify_coleman_plant"]


@dataclass(frozen=True)
class FrequencyResponse:
    """An identified frequency response.

    Attributes
    ----------
    frequency : numpy.ndarray, shape (n_frequencies,)
        [Hz].
    response : numpy.ndarray, shape (n_frequencies, n_outputs, n_inputs), complex
        P(jω) [output unit / input unit].
    coherence : numpy.ndarray, shape (n_frequencies, n_outputs)
        Multiple coherence of each output with all inputs, in [0, 1].
    """

    frequency: np.ndarray
    response: np.ndarray
    coherence: np.ndarray


def frequency_response(inputs: ArrayLike, outputs: ArrayLike, sample_rate: float,
                       segment_duration: float = 200.0) -> FrequencyResponse:
    """H1 estimate of the response of ``outputs`` to ``inputs`` (module notes).

    Parameters
    ----------
    inputs : array_like, shape (n_samples, n_inputs)
    outputs : array_like, shape (n_samples, n_outputs)
    sample_rate : float
        [Hz].
    segment_duration : float
        Welch segment length [s] (shortened to the record): the frequency resolution is its inverse.

    Raises
    ------
    ValueError
        Naming the argument: NaN, shapes that do not match, a sample rate that is not positive, or inputs
        whose spectral matrix is singular (an input never excited).
    """
    u = finite_array("inputs", inputs, ndim=2)
    y = finite_array("outputs", outputs, ndim=2)
    same_length("outputs", y, u.shape[0], "inputs")
    if not sample_rate > 0.0:
        raise ValueError(f"sample_rate: expected a positive frequency in Hz, found {sample_rate}")
    segment = min(u.shape[0], max(8, int(round(segment_duration * sample_rate))))

    def spectrum(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """E[A B*] per frequency (scipy's csd(b, a) is E[conj(B) A])."""
        return csd(b, a, fs=sample_rate, nperseg=segment)[1]

    frequency = csd(u[:, 0], u[:, 0], fs=sample_rate, nperseg=segment)[0]
    s_uu = np.stack([np.stack([spectrum(u[:, k], u[:, m]) for m in range(u.shape[1])], axis=-1)
                     for k in range(u.shape[1])], axis=-2)
    s_yu = np.stack([np.stack([spectrum(y[:, i], u[:, m]) for m in range(u.shape[1])], axis=-1)
                     for i in range(y.shape[1])], axis=-2)
    s_yy = np.stack([spectrum(y[:, i], y[:, i]).real for i in range(y.shape[1])], axis=-1)
    try:
        response = np.swapaxes(np.linalg.solve(np.swapaxes(s_uu, -1, -2), np.swapaxes(s_yu, -1, -2)), -1, -2)
    except np.linalg.LinAlgError:
        raise ValueError("inputs: their spectral matrix is singular (an input is not excited)") from None
    explained = np.einsum("fik,fkl,fil->fi", response, s_uu, response.conj()).real
    coherence = np.clip(explained / np.where(s_yy > 0, s_yy, np.inf), 0.0, 1.0)
    return FrequencyResponse(frequency, response, coherence)


@dataclass(frozen=True)
class ColemanIdentification:
    """The tilt/yaw plant identified from a recorded run (:func:`identify_coleman_plant`).

    Attributes
    ----------
    response : FrequencyResponse
        Inputs (θ_tilt, θ_yaw) [rad], outputs (M_tilt, M_yaw) [N·m] of harmonic n, no offset.
    offset : float
        The phase offset φ_n [rad] that decouples tilt from yaw at low frequency: the rotation of the mean P
        below ``low_band`` (atan(P21/P11), Disario's check B10 on identified data).
    band_offset : float
        The offset in [0, 90°] that minimises the mean |P12| over ``band`` (Disario eq. 4-4), applying it as
        the input rotation P(ψ) = P(0) R(ψ) (Disario eq. 2-15).
    coherence : float
        The least multiple coherence over ``band``.
    """

    response: FrequencyResponse
    offset: float
    band_offset: float
    coherence: float


def identify_coleman_plant(path, harmonic: int = 1, namespace=None, segment_duration: float = 100.0,
                           low_band: float = 0.2, band: tuple = (0.1, 1.0)) -> ColemanIdentification:
    """Identify P(jω) from θ_tilt, θ_yaw to M_tilt, M_yaw of a recorded run with ``blade_pitch`` excitation.

    The inputs are the forward Coleman transform of the recorded ``control/blade_pitch`` increments (the
    ``coleman_excitation`` controller's random-binary tilt and yaw), the outputs that of the blade-root
    out-of-plane moments, both at each step's azimuth; ``low_band`` [rad/s] and ``band`` [rad/s] as in
    :class:`ColemanIdentification`.

    Raises
    ------
    hawt_bag.errors.BagError
        Naming the bag and topic if the run has no blade_pitch excitation or the plant topics are missing.
    """
    from hawt_bag.errors import BagError
    from hawt_bag.plant_run import load_plant_run, topic_in
    from hawt_bag.reader import BagReader
    from hawt_bag.topic_columns import read_topic_columns
    from hawt_core.rotor.mbc import mbc_forward
    from hawt_core.topics import blade_pitch_topic

    with BagReader(path) as reader:
        run = load_plant_run(reader, namespace)
        topic = topic_in(run.namespace, blade_pitch_topic())
        if topic not in reader.topic_names():
            raise BagError(f"{path}: missing topic {topic}: record a run with a blade_pitch excitation "
                           "(the identification graph's coleman_excitation)")
        increments = read_topic_columns(reader, topic, ("step", "increment"))
    steps = run.steps
    rows = {int(step): row for row, step in enumerate(increments.fields["step"])}
    missing = [int(step) for step in steps if int(step) not in rows]
    if missing:
        raise BagError(f"{path}: {topic} lacks step {missing[0]} ({len(missing)} steps in all)")
    pitch = increments.fields["increment"][[rows[int(step)] for step in steps]]
    azimuth = run.channels["azimuth"]
    inputs, outputs = (np.column_stack([c.cos, c.sin]) for c in (
        mbc_forward(pitch, azimuth, harmonic), mbc_forward(run.channels["root_moment_oop"], azimuth, harmonic)))
    sample_rate = 1.0 / float(np.median(np.diff(run.channels["time"])))
    response = frequency_response(inputs, outputs, sample_rate, segment_duration)
    omega = 2 * np.pi * response.frequency
    low = response.response[(omega > 0) & (omega <= low_band)].mean(axis=0).real
    in_band = (omega >= band[0]) & (omega <= band[1])
    psi = np.radians(np.arange(0.0, 90.05, 0.1))
    rotations = np.stack([np.stack([np.cos(psi), np.sin(psi)], -1), np.stack([-np.sin(psi), np.cos(psi)], -1)], -2)
    cross = np.abs((response.response[in_band][:, None] @ rotations[None])[..., 0, 1]).mean(axis=0)
    return ColemanIdentification(response, float(np.arctan(low[1, 0] / low[0, 0])), float(psi[np.argmin(cross)]),
                                 float(response.coherence[in_band].min()))
