"""Load transfer along the chain blade → hub → main bearing → yaw bearing → tower base (Zalkind & Pao).

Zalkind & Pao, "A Harmonic Model for Loads Analysis and Control Design of a 2-bladed Wind
Turbine" (notes: ``literature/notes/seed001_zalkind.md`` §2.4–2.6, Appendix A). Loads are
harmonic phasors m^{iP} = m_c^{iP} + j m_s^{iP} in true amplitudes
(:mod:`hawt_core.rotor.harmonic_estimator`).

* Hub (rotating) → main bearing (fixed): the exact azimuth rotation, eq. 13
  (:mod:`hawt_core.rotor.hub_frame`, re-exported here), and its closed forms for the hub 1P,
  eqs. 14–17 with eq. 16 corrected (:func:`main_bearing_from_hub_1p`).
* Every other link: the complex affine map m_2 = a_1 m_1 + a_0 fitted by least squares over
  N >= 2 operating points, eqs. 8–11 (:func:`fit_transfer`), separately for region II and
  region III, the region read from the collective pitch (:func:`operating_region`,
  :func:`fit_transfer_by_region`). The paper writes a^*[m_1; 1] and fits with conjugated
  data; the coefficients returned here are conj(a), so that m_2 = gain·m_1 + offset.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np
from numpy.typing import ArrayLike

from hawt_core.rotor.hub_frame import hub_to_main_bearing, main_bearing_to_hub

from ._checks import finite_array, same_length

__all__ = [
    "MainBearingHarmonics",
    "TransferFit",
    "fit_transfer",
    "fit_transfer_by_region",
    "hub_to_main_bearing",
    "main_bearing_from_hub_1p",
    "main_bearing_to_hub",
    "operating_region",
]


@dataclass(frozen=True)
class MainBearingHarmonics:
    """Main-bearing 0P (real) and 2P (complex) components caused by the hub 1P, both axes."""

    y0: np.ndarray
    y2: np.ndarray
    z0: np.ndarray
    z2: np.ndarray


def main_bearing_from_hub_1p(hub_y_1p: ArrayLike, hub_z_1p: ArrayLike) -> MainBearingHarmonics:
    """Main-bearing 0P and 2P from the hub 1P phasors, Zalkind & Pao eqs. 14–17, eq. 16 corrected.

    ::

        m_my^{0P} = ½ Re{m_hy^{1P} + j m_hz^{1P}}     (14)
        m_my^{2P} = ½ (m_hy^{1P} − j m_hz^{1P})       (15)
        m_mz^{0P} = ½ Re{m_hz^{1P} − j m_hy^{1P}}     (16, corrected: the paper prints + j)
        m_mz^{2P} = ½ (m_hz^{1P} + j m_hy^{1P})       (17)

    Exact under eq. 13 with true-amplitude phasors (notes §2.5, Appendix A). The hub 0P, 2P,
    3P … add further main-bearing harmonics (0P → 1P, 2P → 1P and 3P, 3P → 2P and 4P) that
    these relations leave out. Both 2P terms vanish if and only if m_hy^{1P} = j m_hz^{1P} (eq. 20).
    """
    y = np.asarray(hub_y_1p, dtype=complex)
    z = np.asarray(hub_z_1p, dtype=complex)
    return MainBearingHarmonics(
        y0=0.5 * (y + 1j * z).real,
        y2=0.5 * (y - 1j * z),
        z0=0.5 * (z - 1j * y).real,
        z2=0.5 * (z + 1j * y),
    )


@dataclass(frozen=True)
class TransferFit:
    """A fitted complex affine load transfer m_2 ≈ gain·m_1 + offset (Zalkind & Pao eq. 8).

    ``gain`` and ``offset`` are conj(a_1) and conj(a_2) of the paper's a; ``residual_rms`` is the
    RMS magnitude of m_2 − (gain·m_1 + offset) over the points; ``points`` their number.
    """

    gain: complex
    offset: complex
    residual_rms: float
    points: int

    def predict(self, m1: ArrayLike) -> np.ndarray:
        """gain·m_1 + offset."""
        return self.gain * np.asarray(m1, dtype=complex) + self.offset


def fit_transfer(m1: ArrayLike, m2: ArrayLike) -> TransferFit:
    """Least-squares complex affine fit of m_2 on m_1 across operating points, eqs. 9–11.

    Parameters
    ----------
    m1, m2 : array_like of complex, shape (N,)
        The harmonic phasors of the input and output load at N operating points (wind speeds).

    Raises
    ------
    ValueError
        With fewer than 2 points, or when m_1 takes one value at every point: M_1^* M_1 is
        singular (eq. 11) and the gain is not determined.
    """
    x = np.asarray(m1, dtype=complex).ravel()
    y = np.asarray(m2, dtype=complex).ravel()
    finite_array("m1", np.concatenate((x.real, x.imag)), ndim=1)
    finite_array("m2", np.concatenate((y.real, y.imag)), ndim=1)
    same_length("m2", y, x.size, "m1")
    if x.size < 2:
        raise ValueError(f"m1: the fit needs N >= 2 operating points (M_1^* M_1 is singular for N = 1), found {x.size}")
    design = np.column_stack((x, np.ones_like(x)))
    coefficients, _, rank, _ = np.linalg.lstsq(design, y, rcond=None)
    if rank < 2:
        raise ValueError("m1: takes the same value at every point; M_1^* M_1 is singular and the gain undetermined")
    residual = y - design @ coefficients
    return TransferFit(gain=complex(coefficients[0]), offset=complex(coefficients[1]),
                       residual_rms=float(np.sqrt(np.mean(np.abs(residual) ** 2))), points=int(x.size))


def operating_region(collective_pitch: ArrayLike, fine_pitch: float = 0.0,
                     margin: float = np.deg2rad(0.5)) -> np.ndarray:
    """Region 2 (below rated) or 3 (collective pitch active) of each operating point, an int array.

    Region III where the collective pitch exceeds ``fine_pitch`` + ``margin`` [rad]: the
    paper's split, "once collective pitch control is used" (notes §2.4). The default fine pitch
    is the NREL 5 MW's 0 rad.
    """
    pitch = finite_array("collective_pitch", np.atleast_1d(collective_pitch), ndim=1)
    return np.where(pitch > fine_pitch + margin, 3, 2)


def fit_transfer_by_region(m1: ArrayLike, m2: ArrayLike, collective_pitch: ArrayLike,
                           fine_pitch: float = 0.0, margin: float = np.deg2rad(0.5)) -> Mapping[int, TransferFit]:
    """:func:`fit_transfer` separately for region II and region III points (Zalkind & Pao §II.C).

    Returns ``{2: fit, 3: fit}`` for each region with at least two points; a region with one
    point is left out (it cannot be fitted), and so is one without points.
    """
    x = np.asarray(m1, dtype=complex).ravel()
    y = np.asarray(m2, dtype=complex).ravel()
    region = operating_region(collective_pitch, fine_pitch, margin)
    same_length("collective_pitch", region, x.size, "m1")
    return {int(r): fit_transfer(x[region == r], y[region == r])
            for r in (2, 3) if np.count_nonzero(region == r) >= 2}
