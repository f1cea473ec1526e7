"""Two-bladed rotors from recorded runs (Zalkind & Pao): the harmonic chain, its fitted transfer model, Fig. 8.

Works on the channels of a run (``hawt_bag.plant_run.load_plant_run(reader).channels``, or an
in-process run's): ``azimuth``, ``pitch`` (n, B), ``root_moment_oop`` (n, B), ``hub_tilt_moment``,
``hub_yaw_moment`` (the main-bearing moments), ``yaw_bearing_*`` and ``tower_base_*``. Phasors
are those of :mod:`hawt_core.rotor.harmonic_estimator` (true amplitudes, c + j s, a sliding
window of N_R revolutions in azimuth).

* :func:`chain_phasors`: the phasors of one steady run at its end, link by link (blade flap 1P,
  hub 1P, main-bearing, yaw-bearing and tower-base 0P and 2P) and its mean collective pitch.
* :func:`fit_chain`: Zalkind & Pao's transfer model over runs at several wind speeds (eqs. 8–11,
  region II and III apart by the collective pitch); hub → main bearing is the exact eq. 13.
  :func:`transfer_model_from_bags` does both for recorded steady runs, one bag per wind speed.
* :func:`main_bearing_history` and :func:`plot_fig8`: the paper's Fig. 8 redrawn from a run
  (AC-20): hub-y 1P and its reference j m_hz^{1P} (magnitude, phase), the 1P pitch of blade 1
  (magnitude, phase), the main-bearing 2P of both axes, over time.
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from hawt_bag.plant_run import load_plant_run
from hawt_bag.reader import BagReader
from hawt_core.rotor.harmonic_estimator import sliding_phasors
from hawt_core.rotor.hub_frame import main_bearing_to_hub

from .load_transfer import TransferFit, fit_transfer_by_region

__all__ = ["CHAIN_LINKS", "chain_phasors", "fit_chain", "main_bearing_history", "plot_fig8",
           "transfer_model_from_bags"]

CHAIN_LINKS = (
    ("flap_1p", "hub_y_1p"), ("flap_1p", "hub_z_1p"),
    ("main_y_0p", "yaw_y_0p"), ("main_z_0p", "yaw_z_0p"), ("main_y_2p", "yaw_y_2p"), ("main_z_2p", "yaw_z_2p"),
    ("yaw_y_0p", "tower_fa_0p"), ("yaw_y_2p", "tower_fa_2p"),
)
"""The fitted links (input, output) of :func:`fit_chain`: blade → hub (eq. 12), main → yaw bearing (Fig. 5),
yaw bearing → tower base (Fig. 6)."""

_FIXED = {"main_y": "hub_tilt_moment", "main_z": "hub_yaw_moment", "yaw_y": "yaw_bearing_tilt_moment",
          "yaw_z": "yaw_bearing_yaw_moment", "tower_fa": "tower_base_fa_moment"}


def chain_phasors(channels: Mapping[str, np.ndarray], revolutions: float = 2.0) -> dict[str, complex]:
    """The harmonic phasors along the chain over the last ``revolutions`` of a steady run, and its mean pitch.

    Keys: ``flap_1p`` (blade 1 root out-of-plane), ``hub_y_1p``, ``hub_z_1p`` (rotating hub), then
    ``<point>_0p`` and ``<point>_2p`` for main_y, main_z, yaw_y, yaw_z, tower_fa (those the run has), and
    ``collective_pitch`` [rad] (mean over the window, real).
    """
    psi = np.asarray(channels["azimuth"], dtype=float)
    tilt, yaw = channels["hub_tilt_moment"], channels["hub_yaw_moment"]
    rotating = np.column_stack((np.asarray(channels["root_moment_oop"])[:, 0], *main_bearing_to_hub(tilt, yaw, psi)))
    out = dict(zip(("flap_1p", "hub_y_1p", "hub_z_1p"), sliding_phasors(rotating, psi, revolutions).phasors[-1, :, 1]))
    fixed = {key: name for key, name in _FIXED.items() if name in channels}
    phasors = sliding_phasors(np.column_stack([channels[name] for name in fixed.values()]), psi, revolutions)
    for key, values in zip(fixed, phasors.phasors[-1]):
        out[f"{key}_0p"], out[f"{key}_2p"] = values[0], values[2]
    pitch = np.mean(np.asarray(channels["pitch"]), axis=1)
    window = np.unwrap(psi) >= np.unwrap(psi)[-1] - 2.0 * np.pi * revolutions
    out["collective_pitch"] = float(np.mean(pitch[window]))
    return {key: complex(value) for key, value in out.items()}


def fit_chain(points: Sequence[Mapping[str, complex]], fine_pitch: float = 0.0) -> dict[tuple[str, str], dict]:
    """Zalkind & Pao's transfer functions over operating points (:func:`chain_phasors` of runs at several winds).

    Returns ``{(input, output): {2: TransferFit, 3: TransferFit}}`` for each link of :data:`CHAIN_LINKS`
    whose points the runs have; a region with fewer than two points has no fit.
    """
    pitch = [p["collective_pitch"].real for p in points]
    fits: dict[tuple[str, str], dict[int, TransferFit]] = {}
    for source, target in CHAIN_LINKS:
        if all(source in p and target in p for p in points):
            fits[(source, target)] = dict(fit_transfer_by_region([p[source] for p in points],
                                                                 [p[target] for p in points], pitch, fine_pitch))
    return fits


def transfer_model_from_bags(paths: Sequence[Path], revolutions: float = 2.0,
                             fine_pitch: float = 0.0) -> tuple[list[dict[str, complex]], dict]:
    """:func:`chain_phasors` of each bag's plant run (a steady run per wind speed) and :func:`fit_chain` over them."""
    points = []
    for path in paths:
        with BagReader(path) as reader:
            points.append(chain_phasors(load_plant_run(reader).channels, revolutions))
    return points, fit_chain(points, fine_pitch)


def main_bearing_history(channels: Mapping[str, np.ndarray], revolutions: float = 2.0) -> dict[str, np.ndarray]:
    """Time series of Fig. 8: ``time``, ``hub_y`` (m_hy^{1P}), ``reference`` (j m_hz^{1P}), ``pitch_1p`` (blade 1's
    cyclic pitch about the collective, phasor P; eq. 18's θ^{1P} is conj(P)), ``main_y_2p``, ``main_z_2p``
    (complex), and ``valid`` (the window full)."""
    psi = np.asarray(channels["azimuth"], dtype=float)
    tilt, yaw = channels["hub_tilt_moment"], channels["hub_yaw_moment"]
    pitch = np.asarray(channels["pitch"], dtype=float)
    signals = np.column_stack((*main_bearing_to_hub(tilt, yaw, psi), pitch[:, 0] - pitch.mean(axis=1), tilt, yaw))
    estimate = sliding_phasors(signals, psi, revolutions)
    p = estimate.phasors
    return {"time": np.asarray(channels["time"], dtype=float), "hub_y": p[:, 0, 1], "reference": 1j * p[:, 1, 1],
            "pitch_1p": p[:, 2, 1], "main_y_2p": p[:, 3, 2], "main_z_2p": p[:, 4, 2], "valid": estimate.valid}


def plot_fig8(history: Mapping[str, np.ndarray], path: Path) -> Path:
    """Zalkind & Pao Fig. 8 from :func:`main_bearing_history`: four panels over time; returns the PNG path."""
    keep = history["valid"]
    t = history["time"][keep]
    figure = Figure(figsize=(9, 9), layout="constrained")
    magnitude, phase, pitch, bearing = figure.subplots(4, 1, sharex=True)
    reference = history["reference"][keep]
    reference_phase = np.unwrap(np.angle(reference))
    for values, phase_values, label in ((history["hub_y"][keep], None, "m_hy 1P"),
                                        (reference, reference_phase, "reference j·m_hz 1P")):
        if phase_values is None:  # within ±180° of the reference, so that convergence shows as meeting
            phase_values = reference_phase + np.angle(values / reference)
        magnitude.plot(t, 1e-6 * np.abs(values), label=label)
        phase.plot(t, np.degrees(phase_values), label=label)
    magnitude.set_ylabel("hub 1P [MN·m]")
    phase.set_ylabel("hub 1P phase [°]")
    pitch_1p = history["pitch_1p"][keep]
    pitch.plot(t, np.degrees(np.abs(pitch_1p)), label="|θ^1P|")
    pitch.set_ylabel("IPC 1P magnitude [°]")
    pitch_phase = pitch.twinx()
    pitch_phase.plot(t, np.degrees(np.unwrap(np.angle(np.conj(pitch_1p)))), color="tab:orange", label="∠θ^1P (eq. 18)")
    pitch_phase.set_ylabel("IPC 1P phase [°]")
    pitch_phase.legend(loc="lower right", fontsize="small")
    for key, label in (("main_y_2p", "main bearing y 2P"), ("main_z_2p", "main bearing z 2P")):
        bearing.plot(t, 1e-6 * np.abs(history[key][keep]), label=label)
    bearing.set_ylabel("[MN·m]")
    bearing.set_xlabel("time [s]")
    for ax in (magnitude, phase, pitch, bearing):
        ax.legend(loc="upper right", fontsize="small")
        ax.grid(alpha=0.3)
    path = Path(path)
    figure.savefig(path, dpi=110)
    return path
