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
parameter file the ``ipc`` graph uses, and the retuned 1P controller of the ``switching``
graph derived from it (:func:`retuned`); ``--retuned-only`` derives that one again from the
existing file.
"""
import argparse
import math
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, List, Sequence

import numpy as np
import yaml

from hawt_controllers.coleman_coupling import offset_from_dc_response, relative_gain_array
from hawt_controllers.controller import HarmonicContribution
from hawt_controllers.ipc import HarmonicIpcConfig, design_prefilter
from hawt_controllers.ipc_tuning import design_integral_gain
from hawt_controllers.limits import PitchLimits
from hawt_controllers.loop_assembly import LoopAssembler
from hawt_controllers.mbc import mbc_forward
from hawt_plant.model import ModelConfig, TurbineModel
from hawt_plant.shear_wind import PowerLawWind
from hawt_plant.turbine import Turbine, nrel_5mw

__all__ = ["HarmonicResponse", "CouplingPoint", "measure_harmonic_response", "coupling_survey", "design", "retuned",
           "main"]

DEFAULT_FILE = Path(__file__).resolve().parent.parent / "config" / "ipc_nrel5mw.yaml"
RETUNED_FILE = DEFAULT_FILE.with_name("ipc_nrel5mw_retuned.yaml")


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
    actuator = turbine.pitch_actuator
    assembler = LoopAssembler(model.number_of_blades, PitchLimits(actuator.min_angle, actuator.max_angle,
                                                                  actuator.max_rate), dt)
    samples = []
    for step in range(int((settle + average) / dt)):
        pitch = collective + assembler.individual([(HarmonicContribution(harmonic, demand, 0.0), 1.0)],
                                                  out.azimuth)
        out = model.step(pitch, torque)
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


@dataclass(frozen=True)
class CouplingPoint:
    """Disario's analysis of one measured response (hawt_controllers.coleman_coupling, the notes' check B10).

    ``offset`` is the phase offset φ_n = nψ_n [rad] that decouples tilt from yaw at DC (atan2(P21(0), P11(0))
    of the response measured without offset); ``cross_gain`` |P21/P11| and ``rga`` RGA11 at DC without it
    (with it: 0 and 1); ``time_constant`` the first-order blade K/(τs + 1) with the same offset,
    τ = tan(φ_n)/(nω0) (Disario eq. 3-7).
    """

    response: HarmonicResponse
    offset: float
    cross_gain: float
    rga: float
    time_constant: float


def coupling_survey(turbine: Turbine, wind_speeds: Sequence[float], harmonics: Sequence[int], dt: float = 0.01,
                    progress=lambda line: None) -> List[CouplingPoint]:
    """The decoupling offset and the coupling without it, per wind speed and harmonic, from the plant's response."""
    points = []
    for v in wind_speeds:
        for n in harmonics:
            r = measure_harmonic_response(turbine, v, n, dt=dt)
            p11, p21 = math.cos(r.phase), math.sin(r.phase)  # the response rotated by φ, its sign taken out
            dc = np.array([[p11, -p21], [p21, p11]])
            rga = float(relative_gain_array(dc)[0, 0])
            points.append(CouplingPoint(r, offset_from_dc_response(p11, p21), abs(p21 / p11), rga,
                                        math.tan(r.phase) / (n * r.rotor_speed)))
            progress(f"{v:g} m/s, harmonic {n}: offset {math.degrees(r.phase):.1f} deg")
    return points


def retuned(nodes: Dict[str, dict], harmonic: int = 1, gain_factor: float = 1.3) -> Dict[str, dict]:
    """The ``ipc_h{n}_retuned`` controller of the switching graph: harmonic n's design with ``gain_factor`` times
    its integral gain and no gain schedule."""
    design_n = nodes[f"/**/ipc_h{harmonic}"]["ros__parameters"]
    return {f"/**/ipc_h{harmonic}_retuned": {"ros__parameters": {
        "harmonic": harmonic, "integral_gain": gain_factor * design_n["integral_gain"],
        "phase_offset": design_n["phase_offset"]}}}


def _write(path: Path, nodes: Dict[str, dict], what: str, argv: Sequence[str]) -> None:
    header = (f"# {what}, written by `python -m hawt_controllers.ipc_design {' '.join(argv or [])}`.\n"
              "# Gains, phase offsets and schedules come from the turbine model's measured response (see that "
              "module).\n")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(header + yaml.safe_dump(nodes, sort_keys=False))
    print(f"wrote {path}")


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
    parser.add_argument("--retuned-output", type=Path, default=RETUNED_FILE)
    parser.add_argument("--retuned-only", action="store_true",
                        help="only derive the retuned 1P controller from the existing --output file")
    argv = sys.argv[1:] if argv is None else argv
    args = parser.parse_args(argv)
    if args.retuned_only:
        nodes = yaml.safe_load(args.output.read_text())
    else:
        nodes = design(nrel_5mw(), args.harmonics, args.wind_speeds, args.reference_speed,
                       2 * math.pi * args.bandwidth_hz, args.loop_delay, args.dt)
        _write(args.output, nodes, "IPC parameters of the NREL 5 MW", argv)
    _write(args.retuned_output, retuned(nodes), f"The retuned 1P controller, derived from {args.output.name}", argv)


if __name__ == "__main__":
    main()
