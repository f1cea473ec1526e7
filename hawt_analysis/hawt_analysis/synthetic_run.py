"""A synthetic recorded run with every channel, for tests, examples and benchmarks.

Not a turbine model: loads are rotor harmonics plus low-pass filtered noise, of
roughly NREL 5 MW size, on a rotor whose speed varies slowly. Deterministic for a
given seed.
"""
import numpy as np
from scipy import signal as sps

__all__ = ["synthetic_channels"]


def synthetic_channels(
    duration: float = 600.0, sample_rate: float = 100.0, n_blades: int = 3, seed: int = 0
) -> dict[str, np.ndarray]:
    """Channels named as `hawt_analysis.record` expects, SI units.

    Parameters
    ----------
    duration : float
        Record length [s].
    sample_rate : float
        [Hz].
    n_blades : int
        B.
    seed : int
        Seed of the noise.

    Returns
    -------
    dict
        ``time``, ``azimuth``, ``rotor_speed``, every other measured scalar channel of
        `hawt_analysis.record.SCALAR_CHANNELS`, and ``root_moment_oop``,
        ``root_moment_ip``, ``pitch`` of shape (n_samples, n_blades).

    Notes
    -----
    Ω(t) = 1.267 rad/s (12.1 rpm)·(1 + 0.03 sin(2πt/97 s)); ψ = ∫Ω dt wrapped to
    [0, 2π); blade i sees ψ_i = ψ + 2π(i−1)/B. M_oop,i = 8 MN·m + 2 MN·m cos ψ_i
    + 0.4 MN·m cos 3ψ_i + turbulence; M_ip,i = 1 MN·m + 5 MN·m sin ψ_i (gravity)
    + turbulence; θ_i = 0.1 rad + 0.02 rad cos(ψ_i + 0.3) + turbulence; hub tilt
    and yaw are Σ M_oop,i cos ψ_i and Σ M_oop,i sin ψ_i; the yaw bearing's add 2.4 m × thrust
    and −0.087 × aero torque; the blade-effective wind is 14.7 m/s (mean) and 1.1 m/s (cos) with
    turbulence. The derived ``hub_rotating_*`` channels are left to the record. Turbulence is white
    noise through a 2nd-order Butterworth low-pass at 1 Hz, scaled to unit
    standard deviation.
    """
    rng = np.random.default_rng(seed)
    time = np.arange(int(round(duration * sample_rate)) + 1) / sample_rate
    mean_speed, period = 1.267, 97.0
    speed = mean_speed * (1.0 + 0.03 * np.sin(2.0 * np.pi * time / period))
    psi = mean_speed * (time + 0.03 * period / (2.0 * np.pi) * (1.0 - np.cos(2.0 * np.pi * time / period)))
    blade_psi = psi[:, None] + 2.0 * np.pi * np.arange(n_blades) / n_blades
    sos = sps.butter(2, 1.0, fs=sample_rate, output="sos")

    def turbulence(*shape: int) -> np.ndarray:
        filtered = sps.sosfilt(sos, rng.standard_normal((time.size, *shape)), axis=0)
        return filtered / filtered.std(axis=0)

    oop = 8e6 + 2e6 * np.cos(blade_psi) + 0.4e6 * np.cos(3.0 * blade_psi) + 1.0e6 * turbulence(n_blades)
    ip = 1e6 + 5e6 * np.sin(blade_psi) + 0.3e6 * turbulence(n_blades)
    pitch = 0.1 + 0.02 * np.cos(blade_psi + 0.3) + 0.01 * turbulence(n_blades)
    thrust = 7e5 + 1e5 * turbulence()
    power = 5e6 + 1e5 * turbulence()
    gearbox = 97.0
    return {
        "time": time,
        "azimuth": np.mod(psi, 2.0 * np.pi),
        "rotor_speed": speed,
        "generator_speed": gearbox * speed,
        "generator_torque": power / (gearbox * speed),
        "electrical_power": power,
        "aero_torque": power / speed,
        "rotor_thrust": thrust,
        "hub_wind_speed": 15.0 + 1.5 * turbulence(),
        "tower_top_fa_accel": 0.1 * turbulence(),
        "tower_top_ss_accel": 0.05 * turbulence(),
        "tower_top_fa_disp": 0.3 + 0.05 * turbulence(),
        "tower_top_ss_disp": 0.02 * turbulence(),
        "hub_tilt_moment": np.sum(oop * np.cos(blade_psi), axis=1),
        "hub_yaw_moment": np.sum(oop * np.sin(blade_psi), axis=1),
        "yaw_bearing_tilt_moment": np.sum(oop * np.cos(blade_psi), axis=1) + 2.4 * thrust,
        "yaw_bearing_yaw_moment": np.sum(oop * np.sin(blade_psi), axis=1) - 0.087 * power / speed,
        "tower_base_fa_moment": 87.6 * thrust + 2e6 * turbulence(),
        "tower_base_ss_moment": 3e6 * turbulence(),
        "root_moment_oop": oop,
        "root_moment_ip": ip,
        "pitch": pitch,
        "effective_wind_mean": 14.7 + 1.4 * turbulence(),
        "effective_wind_cos": 1.1 + 0.5 * turbulence(),
        "effective_wind_sin": 0.5 * turbulence(),
    }
