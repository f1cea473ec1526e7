"""Fratini 2019's repetitive-control scenarios on the NREL 5 MW: R3, R4 (repetitive-PD) and R8 (repetitive IPC).

Every run is ``hawt run repetitive`` (the graph's cores in process, 100 Hz):

- R3 / AC-18: wind step 11.4 -> 15 m/s at 20 s, no shear; time until the rotor speed stays within
  1 % of rated, for the baseline PI (``cpc``) and the repetitive-PD (``repetitive_cpc``); thesis ~20 s.
- R4 / AC-19: steady 13 m/s, no shear, an unmeasured 4 kN*m 1P disturbance on the generator torque;
  1P amplitude and mean of the rotor speed over the last 50 s of 150 s, PI against repetitive-PD.
- R8 / AC-21: steady wind, shear 0.17, no tower shadow; blade 1's flap-moment oscillation (peak to
  peak), its 1P, 2P and 3P over the last ``--window`` s, for (a) the baseline alone, (b) plus an
  individual PI on each blade's flap moment (``repetitive_ipc`` with learning_gain 0), (c) plus the
  repetitive IPC, (d) (c) with each increment limited to the collective's headroom above the pitch
  floor; thesis: (b) −22 %, (c) −94 %, 1P −92 %, 2P −63 %. Then (c)'s learning curve.

Writes the three scenarios as a figure (``--plot``, default bags/repetitive.png).

Usage: ./hawt bench repetitive [--wind-speed 11.4] [--duration 300] [--window 100] [--plot FILE]
"""
import argparse
import math
import os
from pathlib import Path
from typing import Dict, Mapping

import numpy as np
from matplotlib.figure import Figure

from hawt_analysis.harmonics import harmonic_amplitudes
from hawt_tools.graph_file import find_graph
from hawt_tools.graph_file import load_graph
from hawt_tools.in_process import build_run
from hawt_tools.graph_file import package_prefix

RATED_RPM = 12.1
REPETITIVE_PD = {"cpc": "false", "repetitive_cpc": "true"}
R8_CASES = {
    "(a) CPC alone": {"repetitive_ipc": "false"},
    "(b) CPC + individual PI": {"learning_gain": "0.0", "proportional_gain": "0.1", "integral_gain": "0.2"},
    "(c) CPC + repetitive IPC": {"learning_gain": "0.3", "proportional_gain": "0.1"},
    "(d) (c) within the headroom": {"learning_gain": "0.3", "proportional_gain": "0.1",
                                    "limit_to_headroom": "true"},
}
THESIS = {"(b) CPC + individual PI": "-22 %", "(c) CPC + repetitive IPC": "-94 % (1P -92 %, 2P -63 %)"}


def run_rows(arguments: Mapping[str, str], duration: float, overrides: Mapping = ()) -> np.ndarray:
    """Rows of time, azimuth, rotor speed [rpm], blade 1's flap moment of ``hawt run repetitive``; ``overrides``
    as -p gives them (full node name -> [(parameter, value)]), not checked (build_run checks nothing)."""
    run = build_run(load_graph(find_graph("repetitive"), {"duration": str(duration), **arguments}, package_prefix),
                    overrides)
    rows = np.empty((round(duration / run.description.dt), 4))
    for k in range(len(rows)):
        run.step()
        out = run.output
        rows[k] = out.time, out.azimuth, out.rotor_speed * 30 / math.pi, out.root_moment_oop[0]
    return rows


def speed_recovery(collective: Mapping[str, str]) -> Dict[str, object]:
    """R3: seconds after the 11.4 -> 15 m/s step at 20 s until the rotor speed stays within 1 % of rated."""
    rows = run_rows({**collective, "repetitive_ipc": "false", "shear_exponent": "0.0", "wind_type": "step",
                 "step_speed": "15.0", "step_time": "20.0"}, 90.0)
    outside = rows[(rows[:, 0] > 20.0) & (np.abs(rows[:, 2] / RATED_RPM - 1.0) > 0.01), 0]
    return {"seconds": float(outside.max() - 20.0) if outside.size else 0.0, "rows": rows}


def speed_ripple(collective: Mapping[str, str], duration: float = 150.0) -> Dict[str, float]:
    """R4: 1P amplitude and mean of the rotor speed [rpm], last 50 s of ``duration`` [s], 4 kN*m 1P torque
    disturbance."""
    rows = run_rows({**collective, "repetitive_ipc": "false", "shear_exponent": "0.0", "wind_speed": "13.0",
                 "torque_disturbance": "4000.0"}, duration)
    last = rows[rows[:, 0] > duration - 50.0]
    return {"1P": float(harmonic_amplitudes(last[:, 2], last[:, 1], harmonics=(1,)).amplitude[0]),
            "mean": float(np.mean(last[:, 2])), "rows": last}


def flap_loads(arguments: Mapping[str, str], duration: float, window: float) -> Dict[str, object]:
    """R8: blade 1's flap-moment oscillation and harmonics over the last ``window`` s; p-p per revolution."""
    rows = run_rows(arguments, duration)
    last = rows[rows[:, 0] > duration - window]
    amplitudes = harmonic_amplitudes(last[:, 3], last[:, 1], harmonics=(1, 2, 3)).amplitude
    starts = np.flatnonzero(np.diff(rows[:, 1]) < 0) + 1
    return {"oscillation": float(np.ptp(last[:, 3])), "1P": float(amplitudes[0]), "2P": float(amplitudes[1]),
            "3P": float(amplitudes[2]), "rotor_speed": float(np.mean(last[:, 2])),
            "learning": [float(np.ptp(rows[a:b, 3])) for a, b in zip(starts[:-1], starts[1:])],
            "rows": rows[starts[-2]:starts[-1]]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--wind-speed", type=float, default=11.4, help="R8: hub-height wind speed [m/s]")
    parser.add_argument("--duration", type=float, default=300.0, help="R8: simulated time of each run [s]")
    parser.add_argument("--window", type=float, default=100.0, help="R8: the last seconds analysed [s]")
    parser.add_argument("--plot", type=Path, default=Path("bags/repetitive.png"), help="figure of the three scenarios")
    args = parser.parse_args()
    recovery = {"PI": speed_recovery({}), "repetitive-PD": speed_recovery(REPETITIVE_PD)}
    print("R3, wind step 11.4 -> 15 m/s: back within 1 % of rated after "
          f"{recovery['PI']['seconds']:.1f} s (PI), {recovery['repetitive-PD']['seconds']:.1f} s (repetitive-PD); "
          "thesis ~20 s")
    pi, repetitive = speed_ripple({}), speed_ripple(REPETITIVE_PD)
    print(f"R4, 4 kN*m 1P torque disturbance at 13 m/s: rotor-speed 1P {pi['1P']:.4f} rpm (PI), "
          f"{repetitive['1P']:.4f} rpm (repetitive-PD), {100 * (repetitive['1P'] / pi['1P'] - 1):+.0f} %; means "
          f"{pi['mean']:.3f} and {repetitive['mean']:.3f} rpm; thesis: only the repetitive removes the ripple")
    print(f"R8: steady {args.wind_speed:g} m/s at hub height, shear 0.17, no tower shadow, {args.duration:g} s, "
          f"last {args.window:g} s; blade 1 flap (out-of-plane) root moment [MN*m]")
    results = {name: flap_loads({"wind_speed": str(args.wind_speed), **case}, args.duration, args.window)
               for name, case in R8_CASES.items()}
    base = results["(a) CPC alone"]
    print(f"{'case':28s} {'p-p':>7s} {'1P':>7s} {'2P':>7s} {'3P':>7s} {'rpm':>6s}   change p-p / 1P / 2P      thesis")
    for name, r in results.items():
        change = " / ".join(f"{100 * (r[key] / base[key] - 1):+.0f} %" for key in ("oscillation", "1P", "2P"))
        print(f"{name:28s} {r['oscillation'] / 1e6:7.3f} {r['1P'] / 1e6:7.3f} {r['2P'] / 1e6:7.3f} "
              f"{r['3P'] / 1e6:7.3f} {r['rotor_speed']:6.2f}   {change:22s} {THESIS.get(name, '')}")
    learning = results["(c) CPC + repetitive IPC"]["learning"]
    print("(c) blade 1 flap p-p per revolution [MN*m]: " + " ".join(f"{v / 1e6:.2f}" for v in learning[:12]) + " ...")
    print(f"figure: {plot(recovery, {'PI': pi, 'repetitive-PD': repetitive}, results, args.plot)}")
    print("load average (1, 5, 15 min): {:.2f} {:.2f} {:.2f} on {} CPUs".format(*os.getloadavg(), os.cpu_count()))


def plot(recovery: Mapping[str, dict], ripple: Mapping[str, dict], flap: Mapping[str, dict], path: Path) -> Path:
    """R3: speed after the step; R4: speed over the last 20 s; R8: blade 1's flap moment over its last revolution."""
    figure = Figure(figsize=(13, 4), layout="constrained")
    r3, r4, r8 = figure.subplots(1, 3)
    for name, result in recovery.items():
        r3.plot(result["rows"][:, 0], result["rows"][:, 2], label=f"{name}: {result['seconds']:.1f} s")
    r3.axhspan(0.99 * RATED_RPM, 1.01 * RATED_RPM, color="0.9")
    r3.set(title="R3: wind step 11.4 -> 15 m/s at 20 s", xlabel="time [s]", ylabel="rotor speed [rpm]")
    for name, result in ripple.items():
        rows = result["rows"][-2000:]
        r4.plot(rows[:, 0], rows[:, 2], label=f"{name}: 1P {result['1P']:.4f} rpm")
    r4.set(title="R4: 4 kN*m 1P torque disturbance, 13 m/s", xlabel="time [s]", ylabel="rotor speed [rpm]")
    for name, result in flap.items():
        rows = result["rows"]
        r8.plot(np.degrees(rows[:, 1]), rows[:, 3] / 1e6, label=name)
    r8.set(title="R8: shear 0.17, last revolution", xlabel="azimuth of blade 1 [deg]",
           ylabel="blade 1 flap root moment [MN*m]")
    for axes in (r3, r4, r8):
        axes.grid(True, alpha=0.3)
        axes.legend(fontsize=8)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=110)
    return path


if __name__ == "__main__":
    main()
