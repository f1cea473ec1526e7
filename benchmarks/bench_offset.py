"""IPC-1P with and without Disario's azimuth offset on the NREL 5 MW, closed loop (issue 15 item 4).

The models: the first-order blade K/(τs + 1) whose DC-decoupling offset equals the offset measured
on the plant at 18 m/s (``hawt coupling``), in the Coleman frame (hawt_controllers.laws.coleman_coupling):
RGA11 at the 1P loop's crossover without and with the offset (Disario: 0.9052 -> 0.9997 at 0.47 rad/s);
and the plant's linear model at 18 m/s (``hawt linearize``, data/linear_nrel5mw.npz) closed with the
two loops below (hawt_controllers.design.ipc_design.loop_analysis, Disario §5-3-2): the crossover and phase
margin, RGA11 at the crossover, the sensitivity's largest singular value (its peak, and at 1P) and where
its singular values reach -3 dB (Disario: a region [0.38, 0.65] rad/s without the offset, 0.47 with it).

The runs: ``hawt run ipc`` with only ipc_h1 active, as designed with the offset and with its
integral gain divided by cos ψ without it (Disario's gain compensation: the same crossover, his
1e-8 at 0° and 0.95e-8 at 19°), IEC class B turbulence at 18 m/s,
600 s, seeds 1-3: blade-root M_oop DEL (m = 10, mean of the blades), hub tilt and yaw DEL (m = 4),
and the pitch activity above 1P (the standard deviation of each blade's individual pitch above
1.5P, from its Welch PSD), each as the mean over seeds.

Usage: ./hawt bench offset [--seeds 1 2 3] [--duration 600]
"""
import argparse
import math
import os
from typing import Dict, Sequence

import numpy as np
import yaml

from hawt_analysis.fatigue import damage_equivalent_load
from hawt_analysis.spectra import power_spectrum
from hawt_controllers.laws.coleman_coupling import coleman_plant, first_order, relative_gain_array
from hawt_controllers.design.ipc_design import DEFAULT_FILE, coupling_survey, loop_analysis
from hawt_controllers.laws.coleman_models import load_models
from hawt_controllers.plugins.lqg_ipc import DEFAULT_MODELS
from hawt_plant.turbine import nrel_5mw
from hawt_tools.graph_file import find_graph
from hawt_tools.graph_file import load_graph
from hawt_tools.in_process import build_run
from hawt_tools.graph_file import package_prefix

CROSSOVER = 2 * math.pi * 0.1
"""The IPC design's crossover (van Engelen's 0.1 Hz, hawt_controllers.design.ipc_design) [rad/s]."""


def model_rga(offset: float, rotor_speed: float) -> Dict[str, float]:
    """RGA11 of the first-order Coleman plant with the measured offset's τ, at the crossover, without/with it."""
    blade = first_order(1.0, math.tan(offset) / rotor_speed)
    return {name: float(abs(relative_gain_array(coleman_plant(blade, 1j * CROSSOVER, rotor_speed, psi))[0, 0]))
            for name, psi in (("without", 0.0), ("with", offset))}


def closed_loop(phase_offset: float, integral_gain: float, seed: int, duration: float) -> Dict[str, float]:
    """DELs and pitch activity above 1P of ``hawt run ipc`` with ipc_h1 alone at this offset and gain."""
    overrides = {"/wt1/ipc_h1": [("phase_offset", phase_offset), ("integral_gain", integral_gain)]}
    run = build_run(load_graph(find_graph("ipc"), {"wind_type": "turbulent", "wind_speed": "18.0", "seed": str(seed),
                                                   "duration": str(duration), "ipc_h2": "false", "ipc_h3": "false"},
                               package_prefix), overrides)
    steps, dt = round(duration / run.description.dt), run.description.dt
    oop, tilt, yaw, individual, speed = (np.empty((steps, 3)), np.empty(steps), np.empty(steps),
                                         np.empty((steps, 3)), np.empty(steps))
    for k in range(steps):
        run.step()
        out = run.output
        oop[k], tilt[k], yaw[k], speed[k] = out.root_moment_oop, out.hub_tilt_moment, out.hub_yaw_moment, \
            out.rotor_speed
        individual[k] = out.pitch - np.mean(out.pitch)
    one_p = float(np.mean(speed)) / (2 * math.pi)
    activity = []
    for blade in range(3):
        psd = power_spectrum(individual[:, blade], 1.0 / dt)
        above = psd.frequency > 1.5 * one_p
        activity.append(math.sqrt(float(np.sum(psd.density[above]) * (psd.frequency[1] - psd.frequency[0]))))
    return {"blade DEL m=10 [MN*m]": np.mean([damage_equivalent_load(oop[:, b], 10.0, duration).value
                                             for b in range(3)]) / 1e6,
            "hub tilt DEL m=4 [MN*m]": damage_equivalent_load(tilt, 4.0, duration).value / 1e6,
            "hub yaw DEL m=4 [MN*m]": damage_equivalent_load(yaw, 4.0, duration).value / 1e6,
            "pitch std above 1.5P [deg]": math.degrees(float(np.mean(activity)))}


def main(argv: Sequence[str] = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    parser.add_argument("--duration", type=float, default=600.0, help="simulated seconds per run")
    args = parser.parse_args(argv)
    point, = coupling_survey(nrel_5mw(), [18.0], [1])
    offset, rotor_speed = point.offset, point.response.rotor_speed
    rga = model_rga(offset, rotor_speed)
    print(f"measured 1P offset at 18 m/s: {math.degrees(offset):.1f} deg (first-order tau "
          f"{point.time_constant:.3f} s); first-order model RGA11 at the {CROSSOVER:.2f} rad/s crossover: "
          f"{rga['without']:.4f} without, {rga['with']:.4f} with (Disario: 0.9052 -> 0.9997 at 0.47 rad/s)")
    designed = yaml.safe_load(DEFAULT_FILE.read_text())["/**/ipc_h1"]["ros__parameters"]
    cases = {"without offset": (0.0, designed["integral_gain"] / math.cos(offset)),
             "with offset": (designed["phase_offset"], designed["integral_gain"])}
    model = next(m for m in load_models(DEFAULT_MODELS) if m.wind_speed == 18.0)
    for name, (phase, gain) in cases.items():
        a = loop_analysis(model, 1, gain, phase, 0.01)
        print(f"linear model at 18 m/s, {name}: crossover {a.crossover:.3f} rad/s, phase margin "
              f"{math.degrees(a.phase_margin):.1f} deg, RGA11 there {a.rga:.4f}; sensitivity: largest singular value "
              f"{a.peak:.2f} at {a.peak_frequency:.2f} rad/s, {a.at_1p:.2f} at 1P ({model.rotor_speed:.3f} rad/s), "
              f"-3 dB at {a.bandwidth[0]:.3f}-{a.bandwidth[1]:.3f} rad/s")
    results = {}
    for name, (phase, gain) in cases.items():
        per_seed = [closed_loop(phase, gain, seed, args.duration) for seed in args.seeds]
        results[name] = {key: float(np.mean([r[key] for r in per_seed])) for key in per_seed[0]}
        print(f"{name}: " + ", ".join(f"{key} {value:.4g}" for key, value in results[name].items()), flush=True)
    print("change with the offset: " + ", ".join(
        f"{key} {100 * (results['with offset'][key] / results['without offset'][key] - 1):+.1f} %"
        for key in results["with offset"]))
    print("load average (1, 5, 15 min): {:.2f} {:.2f} {:.2f} on {} CPUs".format(*os.getloadavg(), os.cpu_count()))


if __name__ == "__main__":
    main()
