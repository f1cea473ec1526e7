"""Speed of the inflow models: sampling per plant step, turbulence generation and cache load.

Run from the repository root::

    .venv/bin/python benchmarks/bench_wind.py            # includes a cold 600 s 11 x 11 generation (~30 s)
    .venv/bin/python benchmarks/bench_wind.py --skip-generation   # sampling only, on a random field

Sampling is timed like the plant calls it: 51 points (3 blades x 17 nodes) on the
NREL 5 MW rotor (R = 63 m, hub 90 m, x = -5 m), rotating at 12.1 rpm, at 100 Hz.
"""
import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "hawt_plant"))

from hawt_plant.gusts import ExtremeOperatingGust, WindStep  # noqa: E402
from hawt_plant.turbulence import TurbulenceSpec, TurbulentWind, cached_turbulence  # noqa: E402

STEP = 0.01  # plant step [s]
ROTOR_SPEED = 12.1 * 2.0 * np.pi / 60.0  # [rad/s]
RADII = np.linspace(2.0, 63.0, 17)  # [m]


def rotor_points(t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """x, y, z [m] of 3 x 17 blade nodes at time t, shape (3, 17)."""
    azimuth = ROTOR_SPEED * t + np.array([0.0, 2.0, 4.0])[:, None] * np.pi / 3.0
    return (np.full((3, RADII.size), -5.0), -RADII * np.sin(azimuth), 90.0 + RADII * np.cos(azimuth))


def time_sampling(wind, calls: int) -> tuple[float, float]:
    """p50 and p99 of one velocity() call [us] over ``calls`` plant steps."""
    points = [rotor_points(i * STEP) for i in range(calls)]
    durations = np.empty(calls)
    for i, (x, y, z) in enumerate(points):
        start = time.perf_counter()
        wind.velocity(i * STEP, x, y, z)
        durations[i] = time.perf_counter() - start
    return tuple(np.percentile(durations[calls // 10:], [50, 99]) * 1e6)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--skip-generation", action="store_true", help="time sampling on a random field")
    parser.add_argument("--calls", type=int, default=20000, help="velocity() calls per model")
    args = parser.parse_args()
    spec = TurbulenceSpec(mean_speed=11.4)
    if args.skip_generation:
        rng = np.random.default_rng(0)
        turbulent = TurbulentWind(rng.normal(11.4, 2.0, size=(spec.n_t, spec.n_z, spec.n_y, 3)),
                                  time_step=spec.time_step, grid_y=spec.grid_y, grid_z=spec.grid_z,
                                  mean_speed=11.4, hub_height=90.0)
    else:
        with tempfile.TemporaryDirectory() as cache:
            start = time.perf_counter()
            cached_turbulence(spec, cache_dir=cache)
            cold = time.perf_counter() - start
            start = time.perf_counter()
            turbulent = cached_turbulence(spec, cache_dir=cache)
            hit = time.perf_counter() - start
        print(f"generation, 600 s 11x11 at 0.05 s (cold, pyconturb): {cold:8.2f} s")
        print(f"cache hit load of the same field:                    {hit * 1e3:8.1f} ms")
    models = {"TurbulentWind (600 s, 11x11)": turbulent,
              "ExtremeOperatingGust": ExtremeOperatingGust(11.4, start_time=10.0),
              "WindStep (ramped)": WindStep(11.4, 15.0, step_time=10.0, ramp_duration=1.0)}
    for name, wind in models.items():
        p50, p99 = time_sampling(wind, args.calls)
        print(f"velocity() for 51 points, {name:30s} p50 {p50:6.1f} us   p99 {p99:6.1f} us")


if __name__ == "__main__":
    main()
