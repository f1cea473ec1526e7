"""Hub moments between the rotating hub frame and the fixed shaft frame, Zalkind & Pao eq. 13.

Axes: the rotating hub axes y, z coincide with the fixed shaft axes y_s, z_s at ψ = 0 (blade 1 up,
DESIGN §3); the rotor turns right-handedly about the downwind shaft axis, so the fixed components
are the rotating ones turned by ψ. The fixed-frame moments are the plant's ``hub_tilt_moment`` and
``hub_yaw_moment``, which are Zalkind & Pao's main-bearing moments m_my, m_mz (hub and main bearing
at one point); the rotating ones are their hub moments m_hy, m_hz (OpenFAST LSSTipMya, LSSTipMza).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["hub_to_main_bearing", "main_bearing_to_hub"]


def hub_to_main_bearing(hub_y: ArrayLike, hub_z: ArrayLike, azimuth: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Fixed-frame main-bearing moments from rotating hub moments, eq. 13.

    m_my = cos ψ m_hy − sin ψ m_hz,  m_mz = sin ψ m_hy + cos ψ m_hz (ψ of blade 1, rad).
    """
    y, z, psi = (np.asarray(v, dtype=float) for v in (hub_y, hub_z, azimuth))
    c, s = np.cos(psi), np.sin(psi)
    return c * y - s * z, s * y + c * z


def main_bearing_to_hub(main_y: ArrayLike, main_z: ArrayLike, azimuth: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Rotating hub moments from fixed-frame main-bearing moments: the inverse (transpose) of eq. 13."""
    y, z, psi = (np.asarray(v, dtype=float) for v in (main_y, main_z, azimuth))
    c, s = np.cos(psi), np.sin(psi)
    return c * y + s * z, -s * y + c * z
