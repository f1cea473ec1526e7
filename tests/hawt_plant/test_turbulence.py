"""Specification of hawt_plant.turbulence: IEC NTM and ETM fields from pyconturb, their cache and sampling."""

import numpy as np
import pytest
import scipy.signal
from scipy.interpolate import RegularGridInterpolator

from hawt_plant import turbulence
from hawt_plant.inflow import InflowSettings, make_wind
from hawt_plant.turbulence import (TurbulenceSpec, TurbulentWind, cached_turbulence, etm_standard_deviation,
                                   generate_turbulence, longitudinal_length_scale, ntm_standard_deviation,
                                   rotor_grid_size)

RATED_SPEED = 11.4  # NREL 5 MW rated wind speed [m/s]


def _small_spec(**changes) -> TurbulenceSpec:
    """A 3 x 3 grid (hub node at the centre, bottom row at 30 m), short enough for tests."""
    return TurbulenceSpec(**{"mean_speed": RATED_SPEED, "n_y": 3, "n_z": 3, "grid_width": 60.0,
                             "grid_height": 120.0, "duration": 60.0, **changes})


def _random_wind(n_t=6, n_z=4, n_y=5, periodic=True, x_offset=0.0, seed=0) -> TurbulentWind:
    """A field of random values on a small grid, for interpolation checks."""
    values = np.random.default_rng(seed).normal(10.0, 2.0, size=(n_t, n_z, n_y, 3))
    return TurbulentWind(values, time_step=0.5, grid_y=np.linspace(-20.0, 20.0, n_y),
                         grid_z=np.linspace(60.0, 120.0, n_z), mean_speed=10.0, hub_height=90.0,
                         periodic=periodic, x_offset=x_offset)


UNSCALED_RATE = 4.0
"""[Hz] The sample rate of the unscaled fields."""


@pytest.fixture(scope="module")
def unscaled_fields() -> list[np.ndarray]:
    """600 s, 3 x 3 fields for seeds 0..15, without hub sigma scaling (raw pyconturb), at 4 Hz (the spectrum is
    checked to 1 Hz): a fifth of the default 20 Hz field's cost."""
    return [generate_turbulence(_small_spec(seed=seed, duration=600.0, scale_to_hub_sigma=False,
                                            time_step=1.0 / UNSCALED_RATE)).velocity_grid for seed in range(16)]


@pytest.mark.parametrize("turbulence_class, sigma", [("A", 2.096), ("B", 1.834), ("C", 1.572)])
def test_ntm_sigma_is_iref_times_0_75_v_plus_5_6(turbulence_class, sigma):
    """sigma_1 = I_ref (0.75 V_hub + 5.6) with I_ref 0.16/0.14/0.12 (IEC 61400-1 NTM), at 10 m/s."""
    assert ntm_standard_deviation(10.0, turbulence_class) == pytest.approx(sigma)


@pytest.mark.parametrize("hub_speed, turbulence_class, i_ref, turbine_class, reference_speed", [
    (18.0, "B", 0.14, "I", 50.0), (11.4, "A", 0.16, "II", 42.5), (25.0, "C", 0.12, "III", 37.5)])
def test_etm_sigma_is_c_iref_times_0_072_v_ave_v_hub_term_plus_10(hub_speed, turbulence_class, i_ref, turbine_class,
                                                                   reference_speed):
    """sigma_1 = c I_ref (0.072 (V_ave / c + 3) (V_hub / c - 4) + 10), c = 2 m/s, V_ave = 0.2 V_ref (IEC 61400-1
    Ed. 3 eq. 19 and eq. 9); 3.606 m/s at 18 m/s in class IB, against the NTM's 2.674 m/s."""
    v_ave = 0.2 * reference_speed
    expected = 2.0 * i_ref * (0.072 * (v_ave / 2.0 + 3.0) * (hub_speed / 2.0 - 4.0) + 10.0)
    assert etm_standard_deviation(hub_speed, turbulence_class, turbine_class) == pytest.approx(expected, rel=1e-12)
    assert etm_standard_deviation(18.0, "B", "I") == pytest.approx(3.6064)


def test_an_etm_field_is_the_ntm_field_of_its_seed_with_the_etm_sigma():
    """Same seed and grid: the ETM field's fluctuations are the NTM field's times sigma_ETM / sigma_NTM (pyconturb's
    spectra take sigma_1 from the spec), the mean is the same, and the hub node has the ETM's sigma_1 (1, 0.8, 0.5)."""
    ntm = generate_turbulence(_small_spec(seed=5)).velocity_grid
    etm = generate_turbulence(_small_spec(seed=5, turbulence_model="ETM", turbine_class="II")).velocity_grid
    ratio = etm_standard_deviation(RATED_SPEED, "A", "II") / ntm_standard_deviation(RATED_SPEED, "A")
    np.testing.assert_allclose(etm.mean(axis=0), ntm.mean(axis=0), atol=1e-4)
    np.testing.assert_allclose(etm - etm.mean(axis=0), (ntm - ntm.mean(axis=0)) * ratio, atol=1e-4)
    np.testing.assert_allclose(etm[:, 1, 1].std(axis=0), ratio * ntm_standard_deviation(RATED_SPEED, "A") *
                               np.array([1.0, 0.8, 0.5]), rtol=1e-5)


def test_ntm_specs_keep_the_cache_keys_they_had_before_the_etm():
    """The hashes of NTM specs are those of the code before turbulence_model and turbine_class existed (commit
    be3b513; pyconturb 2.7.4 and cache format 2, whose change changes every key), so their cached fields are found
    again; an NTM spec's turbine class does not change its key, the ETM's does."""
    assert turbulence._cache_key(TurbulenceSpec(18.0, "B", seed=1)) == "cc0017dfe02ac3b8011435bbafdfd97b"
    assert turbulence._cache_key(TurbulenceSpec(RATED_SPEED, turbine_class="III")) == \
        "136b62c9f95b676df52b42ad144b75a1"
    etm = {turbulence._cache_key(TurbulenceSpec(18.0, "B", seed=1, turbulence_model="ETM", turbine_class=name))
           for name in ("I", "II")}
    assert len(etm) == 2 and "cc0017dfe02ac3b8011435bbafdfd97b" not in etm


def test_length_scale_is_0_7_z_up_to_60_m_and_42_m_above():
    """Lambda_1 = 0.7 z_hub for z_hub <= 60 m, 42 m above (IEC 61400-1 Ed. 3)."""
    assert longitudinal_length_scale(50.0) == pytest.approx(35.0)
    assert longitudinal_length_scale(90.0) == 42.0


@pytest.mark.parametrize("turbulence_class", ["A", "B", "C"])
def test_hub_mean_and_sigmas_match_ntm_over_600_s(turbulence_class):
    """Over 600 s the hub node has mean V_hub and sigmas (1, 0.8, 0.5) sigma_1, each within 5 %."""
    spec = _small_spec(turbulence_class=turbulence_class, duration=600.0)
    hub = generate_turbulence(spec).velocity_grid[:, 1, 1, :]
    sigma_1 = ntm_standard_deviation(RATED_SPEED, turbulence_class)
    assert hub[:, 0].mean() == pytest.approx(RATED_SPEED, rel=0.05)
    np.testing.assert_allclose(hub.std(axis=0), sigma_1 * np.array([1.0, 0.8, 0.5]), rtol=0.05)


def test_unscaled_hub_sigma_matches_ntm_on_average_over_seeds(unscaled_fields):
    """Without hub scaling, the 600 s hub sigma_u averaged over 16 seeds is sigma_1 within 5 %."""
    sigmas = [field[:, 1, 1, 0].std() for field in unscaled_fields]
    assert np.mean(sigmas) == pytest.approx(ntm_standard_deviation(RATED_SPEED, "A"), rel=0.05)


@pytest.mark.parametrize("row, height", [(1, 90.0), (0, 30.0)])
def test_u_spectrum_follows_kaimal_from_0_01_to_1_hz(unscaled_fields, row, height):
    """Welch PSD of u (16 seeds), in 6 log bands over 0.01-1 Hz, is the Kaimal shape within 15 %.

    IEC Kaimal: S(f) = 4 sigma_1^2 (L/V) / (1 + 6 f L/V)^(5/3), L = 8.1 Lambda_1(z_hub) = 340.2 m
    at every height (also at 30 m). A 600 s record has no variance below 1/600 Hz, so the
    generator scales the resolved spectrum to sigma_1^2: the reference is scaled the same way.
    """
    sigma, length = ntm_standard_deviation(RATED_SPEED, "A"), 8.1 * 42.0

    def kaimal(f):
        return 4.0 * sigma**2 * length / RATED_SPEED / (1.0 + 6.0 * f * length / RATED_SPEED) ** (5.0 / 3.0)

    resolved = np.arange(1, int(600 * UNSCALED_RATE / 2) + 1) / 600.0  # up to the Nyquist frequency
    level = sigma**2 / (kaimal(resolved).sum() / 600.0)
    freq, psd = scipy.signal.welch(np.stack([f[:, row, 1, 0] for f in unscaled_fields]).astype(float),
                                   fs=UNSCALED_RATE, nperseg=1024)
    edges = np.logspace(-2.0, 0.0, 7)
    for low, high in zip(edges[:-1], edges[1:]):
        band = (freq >= low) & (freq < high)
        ratio = psd[:, band].mean() / (level * kaimal(freq[band]).mean())
        assert ratio == pytest.approx(1.0, abs=0.15), f"band {low:.3f}-{high:.3f} Hz at z={height} m"


def test_mean_profile_follows_power_law():
    """The time-mean u at each height is V_hub (z / z_hub)^alpha (Fratini (2019) eq. 2.2)."""
    spec = _small_spec(shear_exponent=0.17)
    mean_u = generate_turbulence(spec).velocity_grid[..., 0].mean(axis=0)  # (n_z, n_y)
    expected = RATED_SPEED * (spec.grid_z / spec.hub_height) ** 0.17
    np.testing.assert_allclose(mean_u, np.repeat(expected[:, None], 3, axis=1), rtol=1e-4)


def test_near_lateral_neighbours_are_more_correlated_than_far_ones():
    """u at y = -30 m correlates more with y = 0 than with y = +30 m (IEC coherence decays with distance)."""
    u = generate_turbulence(_small_spec(duration=600.0)).velocity_grid[:, 1, :, 0]
    correlation = np.corrcoef(u.T)
    assert correlation[0, 1] > correlation[0, 2] + 0.05


def test_same_seed_gives_identical_field_and_different_seed_differs():
    """Generation is reproducible by seed."""
    first = generate_turbulence(_small_spec(seed=3)).velocity_grid
    np.testing.assert_array_equal(first, generate_turbulence(_small_spec(seed=3)).velocity_grid)
    assert not np.allclose(first, generate_turbulence(_small_spec(seed=4)).velocity_grid)


def test_generation_leaves_numpy_global_random_state_alone():
    """pyconturb seeds numpy's global generator; generate_turbulence restores it."""
    np.random.seed(1234)
    expected = np.random.rand()
    np.random.seed(1234)
    generate_turbulence(_small_spec())
    assert np.random.rand() == expected


def test_cache_hit_returns_same_data_without_regenerating(tmp_path, monkeypatch):
    """The second request for a spec loads the cached file instead of calling the generator."""
    spec = _small_spec(seed=7)
    generated = cached_turbulence(spec, cache_dir=tmp_path).velocity_grid

    def refuse(_spec):
        raise AssertionError("regenerated although cached")

    monkeypatch.setattr(turbulence, "generate_turbulence", refuse)
    np.testing.assert_array_equal(cached_turbulence(spec, cache_dir=tmp_path).velocity_grid, generated)


def test_cache_keys_differ_per_parameter_and_leave_no_temporary_files(tmp_path):
    """Each distinct spec gets its own cache file; writes are rename-complete."""
    for spec in (_small_spec(), _small_spec(seed=1), _small_spec(turbulence_class="B")):
        cached_turbulence(spec, cache_dir=tmp_path)
    assert sorted(p.suffix for p in tmp_path.iterdir()) == [".npy"] * 3


def test_cache_dir_comes_from_hawt_cache_dir(tmp_path, monkeypatch):
    """Without cache_dir, fields are cached under $HAWT_CACHE_DIR/turbulence."""
    monkeypatch.setenv("HAWT_CACHE_DIR", str(tmp_path))
    cached_turbulence(_small_spec())
    assert len(list((tmp_path / "turbulence").glob("*.npy"))) == 1


def test_a_generated_field_is_announced_with_its_cache_file_and_a_cached_one_silently(tmp_path, monkeypatch):
    """Generating says what, where it is cached, each component as it is done, then how long it took; the field from
    the cache says nothing."""
    monkeypatch.setenv("HAWT_CACHE_DIR", str(tmp_path))
    first: list[str] = []
    cached_turbulence(_small_spec(seed=3), progress=first.append)
    assert len(first) == 4
    assert first[0].startswith(f"generating a turbulent wind field (class A, 11.4 m/s, seed 3, 60 s) into "
                               f"{tmp_path / 'turbulence'}/")
    assert first[0].endswith(".npy; cached for the next run")
    assert first[1:3] == ["turbulence component u done (1 of 3)", "turbulence component v done (2 of 3)"]
    assert first[3].startswith("turbulent wind field generated in ") and first[3].endswith(" s")
    second: list[str] = []
    cached_turbulence(_small_spec(seed=3), progress=second.append)
    assert second == []


@pytest.mark.parametrize("tip_radius, hub_height", [(63.0, 90.0), (120.97, 150.0), (120.97, 135.0), (40.0, 42.0)])
def test_the_grid_for_a_rotor_covers_it_with_a_margin_above_ground(tip_radius, hub_height):
    """The grid a turbine's plant gets (make_wind) covers its rotor with 10 % margin (less above a hub lower than
    that), the bottom row 1 m above ground:
    the NREL 5 MW's is the 140 m square of the defaults, the IEA 15 MW's 268 m."""
    width, height = rotor_grid_size(tip_radius, hub_height)
    spec = TurbulenceSpec(mean_speed=RATED_SPEED, hub_height=hub_height, grid_width=width, grid_height=height)
    assert spec.grid_y[0] <= -1.1 * tip_radius and spec.grid_y[-1] >= 1.1 * tip_radius
    assert spec.grid_z[0] >= 1.0 and spec.grid_z[-1] >= hub_height + tip_radius  # a low hub: less margin above
    assert spec.grid_z[0] <= max(1.0, hub_height - 1.1 * tip_radius)
    if tip_radius == 63.0:
        assert (width, height) == (TurbulenceSpec.grid_width, TurbulenceSpec.grid_height) == (140.0, 140.0)


def test_a_turbines_turbulent_wind_is_generated_on_its_rotors_grid(tmp_path, monkeypatch):
    """make_wind's field for a 121 m rotor spans it (the grid is not the NREL 5 MW's 140 m)."""
    monkeypatch.setenv("HAWT_CACHE_DIR", str(tmp_path))
    wind = make_wind(InflowSettings(kind="turbulent", wind_speed=11.0, hub_height=150.0, rotor_radius=120.97,
                                    field_duration=20.0))
    assert wind.grid_y[-1] - wind.grid_y[0] == 268.0 and wind.grid_z[-1] - wind.grid_z[0] == 268.0


def test_default_grid_covers_the_nrel_5mw_rotor():
    """Default 11 x 11 grid spans the 63 m rotor radius around the 90 m hub, above ground."""
    spec = TurbulenceSpec(mean_speed=RATED_SPEED)
    assert spec.grid_y[0] <= -63.0 and spec.grid_y[-1] >= 63.0
    assert 0.0 < spec.grid_z[0] <= 90.0 - 63.0 and spec.grid_z[-1] >= 90.0 + 63.0
    assert (spec.n_t, spec.n_y, spec.n_z) == (12000, 11, 11)


@pytest.mark.parametrize("changes, message", [
    ({"turbulence_class": "D"}, "turbulence_class"),
    ({"seed": -1}, "seed"),
    ({"time_step": 0.07}, "whole multiple"),
    ({"grid_height": 200.0}, "grid_height"),
    ({"n_y": 4}, "odd"),
    ({"mean_speed": 0.0}, "hub_speed"),
    ({"turbulence_model": "EWM"}, "turbulence_model"),
    ({"turbulence_model": "ETM", "turbine_class": "IV"}, "turbine_class"),
])
def test_invalid_spec_is_rejected_naming_the_argument(changes, message):
    """Bad parameters raise a ValueError that says which one."""
    with pytest.raises(ValueError, match=message):
        _small_spec(**changes)


def test_sampling_at_grid_nodes_returns_the_node_values():
    """At node positions and sample times the sampled velocity is the stored value."""
    wind = _random_wind()
    zz, yy = np.meshgrid(wind.grid_z, wind.grid_y, indexing="ij")
    for step in range(6):
        sampled = wind.velocity(step * wind.time_step, np.zeros_like(zz), yy, zz)
        np.testing.assert_allclose(np.moveaxis(sampled, 0, -1), wind.velocity_grid[step], rtol=1e-6)


def test_sampling_is_trilinear_between_nodes():
    """Between nodes, sampling equals scipy's linear RegularGridInterpolator on (t, z, y)."""
    wind = _random_wind()
    reference = RegularGridInterpolator((np.arange(6) * wind.time_step, wind.grid_z, wind.grid_y),
                                        wind.velocity_grid.astype(float))
    rng = np.random.default_rng(1)
    for t in rng.uniform(0.0, 2.5, size=5):
        y, z = rng.uniform(-20.0, 20.0, size=(4, 7)), rng.uniform(60.0, 120.0, size=(4, 7))
        expected = reference(np.stack(np.broadcast_arrays(t, z, y), axis=-1))
        np.testing.assert_allclose(np.moveaxis(wind.velocity(t, np.zeros_like(y), y, z), 0, -1),
                                   expected, rtol=1e-6)


def test_points_outside_the_grid_take_the_nearest_edge_value():
    """Sampling clamps to the grid: beyond a corner it returns the corner node."""
    wind = _random_wind()
    outside = wind.velocity(0.0, np.zeros(2), np.array([-500.0, 500.0]), np.array([0.0, 1000.0]))
    np.testing.assert_allclose(outside[:, 0], wind.velocity_grid[0, 0, 0], rtol=1e-6)
    np.testing.assert_allclose(outside[:, 1], wind.velocity_grid[0, -1, -1], rtol=1e-6)


def test_periodic_field_wraps_and_interpolates_last_sample_towards_first():
    """A periodic field repeats every n_t dt; half a step after the last sample it is their average."""
    wind = _random_wind(periodic=True)
    point = (np.zeros(1), np.array([-20.0]), np.array([60.0]))
    assert wind.period == pytest.approx(6 * 0.5)
    np.testing.assert_allclose(wind.velocity(0.7 + 4 * wind.period, *point), wind.velocity(0.7, *point))
    halfway = wind.velocity(5.5 * wind.time_step, *point)[:, 0]
    np.testing.assert_allclose(halfway, 0.5 * (wind.velocity_grid[-1, 0, 0] + wind.velocity_grid[0, 0, 0]),
                               rtol=1e-6)


def test_non_periodic_field_wraps_after_its_last_sample():
    """A non-periodic field has period (n_t - 1) dt: the last sample is reached, then it restarts."""
    wind = _random_wind(periodic=False)
    point = (np.zeros(1), np.array([-20.0]), np.array([60.0]))
    assert wind.period == pytest.approx(5 * 0.5)
    np.testing.assert_allclose(wind.velocity(wind.period - 1e-9, *point)[:, 0], wind.velocity_grid[-1, 0, 0],
                               rtol=1e-6)
    np.testing.assert_allclose(wind.velocity(wind.period + 0.2, *point), wind.velocity(0.2, *point))


@pytest.mark.parametrize("x_offset", [0.0, 20.0])
def test_frozen_turbulence_reaches_downwind_points_later(x_offset):
    """A point at x sees at t what x = 0 saw at t - x / U; x_offset shifts field time by x_offset / U."""
    wind = _random_wind(x_offset=x_offset)
    y, z = np.array([3.0]), np.array([77.0])
    np.testing.assert_allclose(wind.velocity(1.7, np.array([5.0]), y, z),
                               wind.velocity(1.7 - 5.0 / 10.0, np.zeros(1), y, z), rtol=1e-9)
    np.testing.assert_allclose(wind.velocity(0.4, np.array([x_offset]), y, z),
                               _random_wind().velocity(0.4, np.zeros(1), y, z), rtol=1e-9)


def test_single_node_axes_are_constant_along_that_axis():
    """A 1 x 1 grid (one point) gives the same time history everywhere."""
    values = np.random.default_rng(2).normal(size=(4, 1, 1, 3))
    wind = TurbulentWind(values, time_step=1.0, grid_y=[0.0], grid_z=[90.0], mean_speed=8.0, hub_height=90.0)
    sampled = wind.velocity(2.0, np.zeros(3), np.array([-50.0, 0.0, 40.0]), np.array([20.0, 90.0, 150.0]))
    np.testing.assert_allclose(sampled, np.repeat(values[2, 0, 0][:, None], 3, axis=1), rtol=1e-6)


def test_velocity_has_shape_3_plus_point_shape_and_grid_is_read_only():
    """velocity returns (3,) + x.shape; the stored grid cannot be modified."""
    wind = _random_wind()
    assert wind.velocity(0.3, np.zeros((3, 17)), np.zeros((3, 17)), np.full((3, 17), 90.0)).shape == (3, 3, 17)
    with pytest.raises(ValueError):
        wind.velocity_grid[0, 0, 0, 0] = 1.0


@pytest.mark.parametrize("build, message", [
    (lambda: _random_wind().velocity(0.0, np.zeros(2), np.zeros(3), np.zeros(2)), "equal shapes"),
    (lambda: TurbulentWind(np.zeros((4, 2, 2, 3)), time_step=1.0, grid_y=[0.0, 1.0], grid_z=[1.0, 2.0, 3.0],
                           mean_speed=8.0, hub_height=90.0), "velocity: expected shape"),
    (lambda: TurbulentWind(np.zeros((4, 3, 1, 3)), time_step=1.0, grid_y=[0.0], grid_z=[1.0, 2.0, 4.0],
                           mean_speed=8.0, hub_height=90.0), "evenly spaced"),
    (lambda: TurbulentWind(np.full((4, 1, 1, 3), np.nan), time_step=1.0, grid_y=[0.0], grid_z=[90.0],
                           mean_speed=8.0, hub_height=90.0), "NaN"),
])
def test_invalid_field_or_points_are_rejected(build, message):
    """Malformed fields and mismatched point arrays raise a ValueError saying what is wrong."""
    with pytest.raises(ValueError, match=message):
        build()
