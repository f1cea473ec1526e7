"""Speed of the plant core: step time percentiles and real-time factor.

Runs the NREL 5 MW model for 600 s of simulated time at 100 Hz (default) in an IEC class B
turbulent field (pyconturb, cached; ``--steady`` for steady sheared wind) with tower shadow,
commands held at the initial operating point, and prints the step
time p50/p99 and the real-time factor (simulated time / wall time of the steps). The machine's
load average is printed too: on a shared machine the wall-clock mean and p99 include
preemption, which the thread CPU time leaves out.

In the same run a second model with unsteady airfoil aerodynamics (``ModelConfig.unsteady_airfoil``,
the HGM dynamic stall model) steps alternately with the first, in the same wind, so that both see the
same machine load; its step time is printed as a ratio to the step without it (target: at most 1.3).
``--no-unsteady`` leaves it out (half the run time).

Usage: ./hawt bench plant_core [--duration S] [--dt S] [--wind M/S] [--shear A] [--steady] [--no-unsteady]
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "hawt_plant"))

from hawt_plant.inflow import InflowSettings, make_wind
from hawt_plant.model import ModelConfig, TurbineModel
from hawt_plant.turbine import nrel_5mw


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=600.0, help="simulated time [s]")
    parser.add_argument("--dt", type=float, default=0.01, help="plant step [s]")
    parser.add_argument("--wind", type=float, default=11.4, help="hub wind speed [m/s]")
    parser.add_argument("--shear", type=float, default=0.2, help="power-law exponent [-]")
    parser.add_argument("--steady", action="store_true", help="steady sheared wind instead of turbulence")
    parser.add_argument("--no-unsteady", action="store_true",
                        help="leave out the model with unsteady airfoil aerodynamics and the cost ratio")
    args = parser.parse_args()

    turbine = nrel_5mw()
    started = time.perf_counter()
    wind = make_wind(InflowSettings(kind="steady" if args.steady else "turbulent", wind_speed=args.wind,
                                    shear_exponent=args.shear, hub_height=turbine.hub_height,
                                    field_duration=args.duration))
    print(f"wind: {'steady' if args.steady else 'IEC class B turbulence, seed 0'} at {args.wind} m/s "
          f"(ready in {time.perf_counter() - started:.1f} s, cached after the first run)")
    started = time.perf_counter()
    model = TurbineModel(turbine, wind, ModelConfig(dt=args.dt))
    setup = time.perf_counter() - started
    pitch, torque = model.output.pitch.copy(), model.output.generator_torque
    unsteady = None if args.no_unsteady else TurbineModel(turbine, wind, ModelConfig(dt=args.dt, unsteady_airfoil=True))
    steps = round(args.duration / args.dt)
    durations, cpu_durations = np.empty((2, steps)), np.empty((2, steps))
    clock, cpu_clock = time.perf_counter_ns, time.thread_time_ns
    for k in range(steps):
        begin, cpu_begin = clock(), cpu_clock()
        model.step(pitch, torque)
        durations[0, k], cpu_durations[0, k] = clock() - begin, cpu_clock() - cpu_begin
        if unsteady is not None:
            begin, cpu_begin = clock(), cpu_clock()
            unsteady.step(pitch, torque)
            durations[1, k], cpu_durations[1, k] = clock() - begin, cpu_clock() - cpu_begin
    durations *= 1e-9
    cpu_durations *= 1e-9
    (durations, unsteady_durations), (cpu_durations, unsteady_cpu_durations) = durations, cpu_durations
    wall = float(durations.sum())
    print(f"plant core, NREL 5 MW, {args.wind} m/s, shear {args.shear}, tower shadow, dt {args.dt} s")
    print(f"model construction and operating point: {setup * 1e3:.1f} ms")
    print(f"steps: {steps}  simulated: {steps * args.dt:.1f} s  wall: {wall:.2f} s")
    print(f"step time p50: {np.percentile(durations, 50) * 1e6:.1f} us  "
          f"p99: {np.percentile(durations, 99) * 1e6:.1f} us  mean: {durations.mean() * 1e6:.1f} us")
    print(f"step CPU time p50: {np.percentile(cpu_durations, 50) * 1e6:.1f} us  "
          f"p99: {np.percentile(cpu_durations, 99) * 1e6:.1f} us  mean: {cpu_durations.mean() * 1e6:.1f} us")
    print(f"real-time factor: {steps * args.dt / wall:.1f}x (wall), "
          f"{steps * args.dt / cpu_durations.sum():.1f}x (CPU time), "
          f"{args.dt / np.percentile(durations, 50):.1f}x (at the median wall step)")
    if unsteady is not None:
        p50, cpu_mean = np.percentile(unsteady_durations, 50), unsteady_cpu_durations.mean()
        print(f"with unsteady airfoil aerodynamics (HGM dynamic stall): step time p50: {p50 * 1e6:.1f} us  "
              f"p99: {np.percentile(unsteady_durations, 99) * 1e6:.1f} us  CPU mean: {cpu_mean * 1e6:.1f} us")
        print(f"unsteady airfoil cost per step, ratio to the step without it: "
              f"{p50 / np.percentile(durations, 50):.2f}x (p50 wall), {cpu_mean / cpu_durations.mean():.2f}x "
              f"(mean CPU time); target <= 1.3x")
    print("load average (1, 5, 15 min): {:.2f} {:.2f} {:.2f} on {} CPUs".format(*os.getloadavg(), os.cpu_count()))


if __name__ == "__main__":
    main()
