"""LQG IPC with wind-estimate feedforward (Selvam 2009) against the baseline and the integrator IPC, in turbulence.

In process (``hawt run``), IEC class B turbulence at 18 m/s, each seed the same wind for every
controller: the baseline (cpc alone), the integrator IPC 1P and 1P+2P (the ipc graph's tuning) and
lqg_ipc (the lqg graph, default weights). Per controller, the mean over seeds of the blade-root
out-of-plane DEL (m = 10, mean of the blades), hub tilt and yaw DEL (m = 4), tower-base fore-aft and
side-side DEL (m = 4), the 3P of the hub tilt and yaw moments (rms over revolutions of the 3P fitted in
each), the individual pitch's travel
and the largest commanded pitch rate. Selvam gives no time-domain numbers: this table is the
project's own result. Also the lqg_ipc core's cost per step.

Selvam's own comparison (§4, Figs 6-7), the closed loop from the cos/sin blade-effective wind to the
1P cos/sin blade-root moments, from the runs by cross-spectra (the H1 estimate of
hawt_analysis.identification, the plant's true wind at 3/4 R as input, 100 s segments) beside the
linear model's (hawt_controllers.laws.lqg_ipc.closed_loop_response at 18 m/s): |T| (mean of the cos->cos and
sin->sin channels) at 0.02 Hz, 1P and 3P, and the runs' multiple coherence there. The model's input is
a wind change uniform along the blade, the runs' the wind at 3/4 R: the levels differ, the ordering of the
controllers is what compares.

Usage: ./hawt bench lqg [--seeds 1 2 3] [--duration 600]
"""
import argparse
import math
import os
import time
from typing import Dict, Mapping, Sequence

import numpy as np
import yaml

from hawt_analysis.fatigue import damage_equivalent_load
from hawt_analysis.harmonics import harmonic_amplitudes
from hawt_analysis.identification import frequency_response
from hawt_controllers.design.ipc_design import DEFAULT_FILE
from hawt_controllers.laws.coleman_models import load_models
from hawt_controllers.plugins.lqg_ipc import DEFAULT_MODELS
from hawt_controllers.laws.lqg_design import design_lqg
from hawt_controllers.laws.lqg_ipc import closed_loop_response
from hawt_core.rotor.mbc import mbc_forward
from hawt_tools.graph_file import find_graph
from hawt_tools.graph_file import load_graph
from hawt_tools.in_process import build_run
from hawt_tools.graph_file import package_prefix

CASES = {
    "cpc": ("lqg", {"lqg_ipc": "false"}),
    "ipc 1P": ("lqg", {"lqg_ipc": "false", "ipc_h1": "true"}),
    "ipc 1P+2P": ("ipc", {"ipc_h3": "false"}),
    "lqg_ipc": ("lqg", {}),
}
MODEL_CASES = {"cpc": "none", "ipc 1P": "integrator", "lqg_ipc": "lqg"}
"""The runs the linear model's closed loops stand for."""
WIND_SPEED = 18.0


def run_case(graph: str, arguments: Mapping[str, str], seed: int, duration: float) -> Dict[str, float]:
    run = build_run(load_graph(find_graph(graph), {"wind_type": "turbulent", "wind_speed": "18.0", "seed": str(seed),
                                                   "duration": str(duration), **arguments}, package_prefix))
    steps, dt = round(duration / run.description.dt), run.description.dt
    rows = {name: np.empty(steps) for name in ("tilt", "yaw", "fa", "ss", "azimuth", "speed", "u_cos", "u_sin")}
    oop, command = np.empty((steps, 3)), np.empty((steps, 3))
    for k in range(steps):
        run.step()
        out = run.output
        oop[k] = out.root_moment_oop
        command[k] = run.command[0]
        for name, value in (("tilt", out.hub_tilt_moment), ("yaw", out.hub_yaw_moment),
                            ("fa", out.tower_base_fa_moment), ("ss", out.tower_base_ss_moment),
                            ("azimuth", out.azimuth), ("speed", out.rotor_speed),
                            ("u_cos", out.effective_wind_cos), ("u_sin", out.effective_wind_sin)):
            rows[name][k] = value
    individual = command - command.mean(axis=1, keepdims=True)
    result = {"blade DEL [MN*m]": np.mean([damage_equivalent_load(oop[:, b], 10.0, duration).value
                                           for b in range(3)]) / 1e6}
    for name, label in (("tilt", "hub tilt"), ("yaw", "hub yaw"), ("fa", "tower fa"), ("ss", "tower ss")):
        result[f"{label} DEL [MN*m]"] = damage_equivalent_load(rows[name], 4.0, duration).value / 1e6
    for name, label in (("tilt", "hub tilt"), ("yaw", "hub yaw")):
        amplitudes = harmonic_amplitudes(rows[name], rows["azimuth"], (3,))
        result[f"{label} 3P [MN*m]"] = float(amplitudes.amplitude_per_revolution_rms[0]) / 1e6
    result["IPC pitch travel [deg]"] = math.degrees(float(np.abs(np.diff(individual, axis=0)).sum(axis=0).mean()))
    result["max pitch rate [deg/s]"] = math.degrees(float(np.abs(np.diff(command, axis=0)).max()) / dt)
    moments = mbc_forward(oop, rows["azimuth"], 1)
    measured = frequency_response(np.column_stack((rows["u_cos"], rows["u_sin"])),
                                  np.column_stack((moments.cos, moments.sin)) / 1e6, 1.0 / dt, 100.0)
    for label, hertz in response_frequencies(float(np.mean(rows["speed"]))).items():
        k = int(np.argmin(np.abs(measured.frequency - hertz)))
        result[f"|u->M| {label} (runs)"] = float(np.mean(np.abs(np.diagonal(measured.response[k]))))
        result[f"coherence {label} (runs)"] = float(np.mean(measured.coherence[k]))
    return result


def response_frequencies(rotor_speed: float) -> Dict[str, float]:
    """Where the wind -> moment responses are compared [Hz]."""
    return {"0.02 Hz": 0.02, "1P": rotor_speed / (2 * math.pi), "3P": 3 * rotor_speed / (2 * math.pi)}


def model_responses(dt: float = 0.01) -> Dict[str, Dict[str, float]]:
    """|u -> M| of the linear model at 18 m/s closed with no IPC, the integrator IPC (ipc_h1's gain and offset)
    and FB-FF (the default weights), as the runs' table gives it."""
    model = next(m for m in load_models(DEFAULT_MODELS) if m.wind_speed == WIND_SPEED)
    design = design_lqg(model.model, dt)
    ipc_h1 = yaml.safe_load(DEFAULT_FILE.read_text())["/**/ipc_h1"]["ros__parameters"]
    frequencies = response_frequencies(model.rotor_speed)
    omega = [2 * math.pi * f for f in frequencies.values()]
    responses = {}
    for case, kind in MODEL_CASES.items():
        response = closed_loop_response(design, omega, kind, ipc_h1["integral_gain"], ipc_h1["phase_offset"])
        responses[case] = {f"|u->M| {label} (model)": float(np.mean(np.abs(np.diagonal(response[k]))))
                           for k, label in enumerate(frequencies)}
    return responses


def step_cost(steps: int = 2000) -> float:
    """Wall time [us] of one lqg_ipc core update (every scheduled law) on the plant's output."""
    run = build_run(load_graph(find_graph("lqg"), {"duration": "60"}, package_prefix))
    core = next(c.core for c in run.controllers if c.core.TYPE == "lqg_ipc")
    out = run.output
    start = time.perf_counter()
    for k in range(steps):
        core.update(k, out, out)
    return (time.perf_counter() - start) / steps * 1e6


def main(argv: Sequence[str] = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    parser.add_argument("--duration", type=float, default=600.0, help="simulated seconds per run")
    args = parser.parse_args(argv)
    print(f"IEC class B turbulence at 18 m/s, {args.duration:g} s, seeds {args.seeds}; means over seeds")
    results = {}
    for name, (graph, arguments) in CASES.items():
        per_seed = [run_case(graph, arguments, seed, args.duration) for seed in args.seeds]
        results[name] = {key: float(np.mean([r[key] for r in per_seed])) for key in per_seed[0]}
        print(f"  {name} done", flush=True)
    for case, responses in model_responses().items():
        results[case].update(responses)
    keys = list(dict.fromkeys(key for values in results.values() for key in values))
    print(f"{'':26s}" + "".join(f"{name:>22s}" for name in results))
    for key in keys:
        base = results["cpc"][key]
        relative = ("DEL" in key or "3P" in key or "|u->M|" in key) and "coherence" not in key
        cells = [(f"{results[name][key]:10.4g}" + (f" ({100 * (results[name][key] / base - 1):+6.1f}%)"
                                                   if name != "cpc" and relative else " " * 10))
                 if key in results[name] else "-" for name in results]
        print(f"{key:26s}" + "".join(f"{cell:>22s}" for cell in cells))
    print(f"lqg_ipc core: {step_cost():.0f} us per step (every scheduled law; the step is 10000 us)")
    print("load average (1, 5, 15 min): {:.2f} {:.2f} {:.2f} on {} CPUs".format(*os.getloadavg(), os.cpu_count()))


if __name__ == "__main__":
    main()
