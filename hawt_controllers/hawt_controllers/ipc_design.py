"""IPC tuning from the plant itself: measured harmonic response, integral gains, phase offsets, schedule.

For each operating point (wind speed) and harmonic n, the turbine model
(:mod:`hawt_plant.model`) runs open loop at its steady operating point in uniform
wind with a constant demand ``(c_n, s_n) = (A, 0)`` remodulated on the blades
(DESIGN.md §3). After the transient, the change of the MBC components of the
out-of-plane root moments against a run without demand is the plant's response
in the non-rotating frame: a gain ``k = dM/dθ`` [N·m/rad] (negative: pitching to
feather unloads the blade) and a rotation ``φ`` of the (cos, sin) plane that the
remodulation's phase offset ``φ_n`` undoes (Disario: azimuth offset measured on the
plant). The integral gain follows van Engelen's recipe
(:func:`hawt_controllers.ipc_tuning.design_integral_gain`: ~0.1 Hz crossover with
the loop delay and the pre-filter), and the gain schedule over collective pitch
keeps the loop gain ``k_i k`` constant across the operating points.

Run ``python -m hawt_controllers.ipc_design`` to print the design and write the
parameter file the ``ipc`` graph uses.
"""
import argparse
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, List, Sequence

import numpy as np
import yaml

from hawt_controllers.ipc import HarmonicIpcConfig, design_prefilter
from hawt_controllers.ipc_tuning import design_integral_gain
from hawt_controllers.mbc import mbc_forward, mbc_inverse
from hawt_plant.model import ModelConfig, TurbineModel
from hawt_plant.shear_wind import PowerLawWind
from hawt_plant.turbine import Turbine, nrel_5mw

__all__ = ["HarmonicResponse", "measure_harmonic_response", "design", "main"]

DEFAULT_FILE = Path(__file__).resolve().parent.parent / "config" / "ipc_nrel5mw.yaml"


@dataclass(frozen=True)
class HarmonicResponse:
    """The plant's non-rotating response of harmonic n at one operating point."""

    wind_speed: float
    harmonic: int
    collective_pitch: float
    rotor_speed: float
    sensitivity: float
    phase: float


def _mean_components(turbine: Turbine, wind_speed: float, harmonic: int, demand: float, dt: float,
                     settle: float, average: float):
    model = TurbineModel(turbine, PowerLawWind(wind_speed, hub_height=turbine.hub_height),
                         ModelConfig(dt=dt, tower_shadow=False))
    out = model.reset_to_operating_point()
    collective, torque = float(np.mean(out.pitch)), float(out.generator_torque)
    blades = model.number_of_blades
    samples = []
    for step in range(int((settle + average) / dt)):
        pitch = collective + mbc_inverse(demand, 0.0, out.azimuth, harmonic, blades)
        out = model.step(np.asarray(pitch), torque)
        if step * dt >= settle:
            c = mbc_forward(out.root_moment_oop, out.azimuth, harmonic)
            samples.append((c.cos, c.sin))
    return np.mean(samples, axis=0), collective, out.rotor_speed


def measure_harmonic_response(turbine: Turbine, wind_speed: float, harmonic: int, amplitude: float = 0.01,
                              dt: float = 0.01, settle: float = 15.0, average: float = 10.0) -> HarmonicResponse:
    """dM/dθ and the phase rotation of harmonic n at the operating point of ``wind_speed`` (uniform wind).

    The rotor speed is held by holding the generator torque of the operating point; runs
    with and without the demand are differenced, so the residual of the operating point cancels.
    """
    loaded, collective, rotor_speed = _mean_components(turbine, wind_speed, harmonic, amplitude, dt, settle,
                                                       average)
    reference, _, _ = _mean_components(turbine, wind_speed, harmonic, 0.0, dt, settle, average)
    response = (loaded - reference) / amplitude
    gain = -float(np.hypot(*response))
    phase = math.atan2(-response[1], -response[0])
    return HarmonicResponse(wind_speed, harmonic, collective, rotor_speed, gain, phase)


def design(turbine: Turbine, harmonics: Sequence[int], wind_speeds: Sequence[float], reference_speed: float,
           bandwidth: float, loop_delay: float, dt: float) -> Dict[str, dict]:
    """Parameters of each ipc_h{n} node: gain at ``reference_speed``, phase offset, schedule over pitch."""
    nodes = {}
    for n in harmonics:
        responses: List[HarmonicResponse] = [measure_harmonic_response(turbine, v, n, dt=dt) for v in wind_speeds]
        reference = min(responses, key=lambda r: abs(r.wind_speed - reference_speed))
        prefilter = design_prefilter(HarmonicIpcConfig(harmonic=n), dt)
        gain = design_integral_gain(reference.sensitivity, bandwidth, loop_delay, prefilter)
        ordered = sorted(responses, key=lambda r: r.collective_pitch)
        nodes[f"/**/ipc_h{n}"] = {"ros__parameters": {
            "harmonic": n,
            "integral_gain": float(gain.integral_gain),
            "phase_offset": float(reference.phase),
            "schedule_breakpoints": [float(r.collective_pitch) for r in ordered],
            "schedule_factors": [float(reference.sensitivity / r.sensitivity) for r in ordered],
        }}
        print(f"h{n}: " + "; ".join(f"{r.wind_speed:g} m/s pitch {math.degrees(r.collective_pitch):.1f} deg: "
                                     f"dM/dtheta {r.sensitivity / 1e6:.2f} MN*m/rad, phase "
                                     f"{math.degrees(r.phase):.1f} deg" for r in ordered))
        print(f"h{n}: k_i {gain.integral_gain:.3e} rad/(N*m*s) at {reference_speed:g} m/s, crossover "
              f"{gain.crossover_frequency / (2 * math.pi):.3f} Hz, phase margin {math.degrees(gain.phase_margin):.1f} deg")
    return nodes


def main(argv: Sequence[str] = None) -> None:
    parser = argparse.ArgumentParser(description="Tune the IPC harmonics from the turbine model's measured response "
                                                 "and write the ipc graph's parameter file.")
    parser.add_argument("--harmonics", type=int, nargs="+", default=[1, 2, 3])
    parser.add_argument("--wind-speeds", type=float, nargs="+", default=[13.0, 16.0, 18.0, 20.0, 24.0],
                        help="operating points above rated [m/s]")
    parser.add_argument("--reference-speed", type=float, default=18.0, help="where the gain is designed [m/s]")
    parser.add_argument("--bandwidth-hz", type=float, default=0.1, help="loop crossover (van Engelen: 0.1 Hz)")
    parser.add_argument("--loop-delay", type=float, default=0.1,
                        help="delay from measurement to pitch [s]: one plant step plus the pitch actuator's lag")
    parser.add_argument("--dt", type=float, default=0.01)
    parser.add_argument("-o", "--output", type=Path, default=DEFAULT_FILE)
    args = parser.parse_args(argv)
    nodes = design(nrel_5mw(), args.harmonics, args.wind_speeds, args.reference_speed,
                   2 * math.pi * args.bandwidth_hz, args.loop_delay, args.dt)
    header = ("# IPC parameters of the NREL 5 MW, written by `python -m hawt_controllers.ipc_design "
              f"{' '.join(argv or [])}`.\n# Gains, phase offsets and schedules come from the turbine model's "
              "measured response (see that module).\n")
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(header + yaml.safe_dump(nodes, sort_keys=False))
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
