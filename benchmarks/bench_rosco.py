"""ROSCO (NREL's reference controller, hosted by the discon node) against hawt's cpc and IPC, in turbulence.

In process (``hawt run``), IEC class B turbulence at 18 m/s, each seed the same wind for every controller:
ROSCO with its shipped NREL 5 MW DISCON.IN (the rosco graph) against the NREL 5 MW baseline (cpc, the
baseline graph); ROSCO with its 1P IPC on (the rosco_ipc graph: IPC_KI 1e-8, IPC_aziOffset 0.5236 rad, ROSCO's
NREL 5 MW example) against hawt's integrator IPC 1P and 1P+2P (the ipc graph's tuning). Per controller,
the mean over seeds of: the blade-root out-of-plane DEL (m = 10, mean of the blades), hub tilt and yaw DEL and
tower-base fore-aft and side-side DEL (m = 4); rotor speed mean, standard deviation and maximum; electrical
power mean and standard deviation; the measured pitch's travel per blade and largest rate
(hawt_analysis.pitch_activity), and the travel of the individual part of the command (each blade's command
less the mean of the blades).

Usage: ./hawt bench rosco [--seeds 1 2 3] [--duration 600]
"""
import argparse
import math
import os
import time
from typing import Dict, Mapping, Sequence

import numpy as np

from hawt_analysis.fatigue import damage_equivalent_load
from hawt_analysis.pitch_activity import pitch_activity
from hawt_tools.graph_file import find_graph
from hawt_tools.graph_file import load_graph
from hawt_tools.in_process import build_run
from hawt_tools.graph_file import package_prefix

CASES = {
    "cpc": ("baseline", {}),
    "rosco": ("rosco", {}),
    "ipc 1P": ("ipc", {"ipc_h2": "false", "ipc_h3": "false"}),
    "ipc 1P+2P": ("ipc", {"ipc_h3": "false"}),
    "rosco ipc 1P": ("rosco_ipc", {}),
}
RELATIVE_TO = {"rosco": "cpc", "ipc 1P": "cpc", "ipc 1P+2P": "cpc", "rosco ipc 1P": "cpc"}
_LOADS = (("tilt", "hub_tilt_moment", "hub tilt"), ("yaw", "hub_yaw_moment", "hub yaw"),
          ("fa", "tower_base_fa_moment", "tower fa"), ("ss", "tower_base_ss_moment", "tower ss"))


def run_case(graph: str, arguments: Mapping[str, str], seed: int, duration: float) -> Dict[str, float]:
    """One controller on one seed: the figures of the module notes."""
    run = build_run(load_graph(find_graph(graph), {"wind_type": "turbulent", "wind_speed": "18.0", "seed": str(seed),
                                                   "duration": str(duration), **arguments}, package_prefix))
    steps, dt = round(duration / run.description.dt), run.description.dt
    rows = {name: np.empty(steps) for name in ("tilt", "yaw", "fa", "ss", "speed", "power")}
    oop, pitch, command = np.empty((steps, 3)), np.empty((steps, 3)), np.empty((steps, 3))
    for k in range(steps):
        run.step()
        out = run.output
        oop[k], pitch[k], command[k] = out.root_moment_oop, out.pitch, run.command[0]
        for name, field, _ in _LOADS:
            rows[name][k] = getattr(out, field)
        rows["speed"][k], rows["power"][k] = out.rotor_speed, out.electrical_power
    result = {"blade DEL [MN*m]": np.mean([damage_equivalent_load(oop[:, b], 10.0, duration).value
                                           for b in range(3)]) / 1e6}
    for name, _, label in _LOADS:
        result[f"{label} DEL [MN*m]"] = damage_equivalent_load(rows[name], 4.0, duration).value / 1e6
    rpm = rows["speed"] * 30.0 / math.pi
    result.update({"rotor speed mean [rpm]": rpm.mean(), "rotor speed std [rpm]": rpm.std(),
                   "rotor speed max [rpm]": rpm.max(), "power mean [MW]": rows["power"].mean() / 1e6,
                   "power std [MW]": rows["power"].std() / 1e6})
    activity = pitch_activity(np.arange(steps) * dt, pitch)
    individual = command - command.mean(axis=1, keepdims=True)
    individual_travel = np.abs(np.diff(individual, axis=0)).sum(axis=0).mean()
    result.update({"pitch travel [deg/blade]": math.degrees(float(activity.travel.mean())),
                   "max pitch rate [deg/s]": math.degrees(activity.overall_max_rate),
                   "IPC travel [deg/blade]": math.degrees(float(individual_travel))})
    return result


def main(argv: Sequence[str] = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    parser.add_argument("--duration", type=float, default=600.0, help="simulated seconds per run")
    args = parser.parse_args(argv)
    start = time.monotonic()
    results = {}
    for name, (graph, arguments) in CASES.items():
        per_seed = [run_case(graph, arguments, seed, args.duration) for seed in args.seeds]
        results[name] = {key: float(np.mean([r[key] for r in per_seed])) for key in per_seed[0]}
        print(f"  {name} done ({time.monotonic() - start:.0f} s)", flush=True)
    print(f"IEC class B turbulence at 18 m/s, {args.duration:g} s, seeds {args.seeds}; means over seeds "
          "(in brackets: change against cpc)")
    print(f"{'':26s}" + "".join(f"{name:>20s}" for name in results))
    for key in results["cpc"]:
        cells = []
        for name in results:
            value, base = results[name][key], results[RELATIVE_TO.get(name, name)][key]
            change = f" ({100 * (value / base - 1):+5.1f}%)" if name in RELATIVE_TO and "DEL" in key else ""
            cells.append(f"{value:.4g}{change}")
        print(f"{key:26s}" + "".join(f"{cell:>20s}" for cell in cells))
    print(f"wall time {time.monotonic() - start:.0f} s; load average (1, 5, 15 min): "
          "{:.2f} {:.2f} {:.2f} on {} CPUs".format(*os.getloadavg(), os.cpu_count()))


if __name__ == "__main__":
    main()
