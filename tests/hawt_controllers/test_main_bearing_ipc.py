"""main_bearing_ipc, Zalkind & Pao's 2P main-bearing IPC: AC-16 in closed loop on the two-bladed plant, AC-10 on
the three-bladed one (literature/notes/seed001_zalkind.md §6), and the plug-in's behaviour."""
import math
from types import SimpleNamespace

import numpy as np
import pytest

from hawt_analysis.load_transfer import hub_to_main_bearing, main_bearing_to_hub
from hawt_core.rotor.harmonic_estimator import sliding_phasors
from hawt_controllers.plugins.main_bearing_ipc import MainBearingIpcController
from hawt_core.plant_description import PlantDescription
from hawt_tools.graph_file import find_graph
from hawt_tools.graph_file import load_graph
from hawt_tools.in_process import build_run
from hawt_tools.graph_file import package_prefix

PLANT = PlantDescription(turbine="test", dt=0.01, blades=2, rated_rotor_speed=1.55, rated_power=5e6,
                         rated_generator_torque=43093.55, gearbox_ratio=79.2, min_pitch=0.0, max_pitch=1.57,
                         max_pitch_rate=0.14)


def _closed_loop(seconds, **arguments):
    """The two_bladed graph in process (steady 15 m/s, α = 0.14): per step azimuth, main-bearing moments, blade-1
    pitch and main_bearing_ipc's contribution."""
    run = build_run(load_graph(find_graph("two_bladed"), {"duration": str(seconds), **arguments}, package_prefix))
    rows = []
    for _ in range(round(seconds / run.description.dt)):
        run.step()
        out = run.output
        rows.append((out.azimuth, out.hub_tilt_moment, out.hub_yaw_moment, out.pitch[0] - np.mean(out.pitch)))
    azimuth, tilt, yaw, cyclic = np.array(rows).T
    main = sliding_phasors(np.column_stack((tilt, yaw)), azimuth).phasors[:, :, 2]
    hub = sliding_phasors(np.column_stack(main_bearing_to_hub(tilt, yaw, azimuth)), azimuth).phasors[:, :, 1]
    return main, hub, sliding_phasors(cyclic, azimuth).phasors[:, 1], run


@pytest.fixture(scope="module")
def two_bladed_runs():
    """120 s with the controller, 30 s without it: in steady wind its main-bearing 2P has settled by then (within
    0.05 % of its value at 120 s)."""
    return _closed_loop(120.0), _closed_loop(30.0, main_bearing_ipc="false")


def test_ac16_closed_loop_at_15_m_s_meets_eq_20_and_removes_90_percent_of_the_main_bearing_2p(two_bladed_runs):
    """AC-16: B = 2, N_R = 2, steady 15 m/s: at the end |m_hy^{1P}| = |m_hz^{1P}| (2 %), ∠m_hy − ∠m_hz = +90° (1°),
    and the main-bearing 2P on both axes is ≥ 90 % below the run without IPC."""
    (main, hub, _, _), (main_off, _, _, _) = two_bladed_runs
    hy, hz = hub[-1]
    assert abs(hy) == pytest.approx(abs(hz), rel=0.02)
    assert math.degrees(np.angle(hy / hz)) == pytest.approx(90.0, abs=1.0)
    reduction = 1.0 - np.abs(main[-1]) / np.abs(main_off[-1])
    assert np.all(reduction >= 0.9), reduction


def test_the_two_blades_get_opposite_cyclic_pitch_of_about_a_degree(two_bladed_runs):
    """θ_2 = −θ_1 about the collective (eq. 19); the 1P of blade 1's cyclic pitch settles within the 3° limit."""
    (_, _, pitch_1p, run), _ = two_bladed_runs
    out = run.output
    assert out.pitch[1] - np.mean(out.pitch) == pytest.approx(-(out.pitch[0] - np.mean(out.pitch)), abs=1e-12)
    assert 0.2 < math.degrees(abs(pitch_1p[-1])) < 3.0


def test_ac10_on_three_blades_the_controller_does_next_to_nothing():
    """AC-10: on the NREL 5 MW (B = 3) in the same wind, eq. 20 holds by itself: after 60 s the controller's 1P pitch
    is under 0.05° and the main-bearing 2P stays under 1 % of the two-bladed rotor's without IPC."""
    main, _, _, run = _closed_loop(60.0, turbine="nrel_5mw")
    ipc = next(c for c in run.controllers if c.name.endswith("main_bearing_ipc")).core
    assert math.degrees(abs(ipc.phasor)) < 0.05
    assert np.all(np.abs(main[-1]) < 0.01 * 1.2e6)


def _step(controller, psi, hub_y, hub_z):
    tilt, yaw = hub_to_main_bearing(hub_y, hub_z, psi)
    return controller.update(0, SimpleNamespace(azimuth=psi),
                             SimpleNamespace(hub_tilt_moment=float(tilt), hub_yaw_moment=float(yaw)))[0]


def test_it_waits_for_a_full_window_and_for_activation_and_claims_harmonic_1():
    """Soft start: no output while inactive or before the window holds N_R revolutions; then it acts on harmonic/1
    with phase offset 0, and its output never exceeds max_amplitude."""
    controller = MainBearingIpcController({"ramp_time": 0.0, "integral_gain": 5.0}, PLANT)
    assert controller.claims() == ("harmonic/1",)
    omega = 1.5
    for k in range(500):
        out = _step(controller, omega * 0.01 * k % (2 * math.pi), 2e6 * math.cos(omega * 0.01 * k), 0.0)
    assert (out.cos, out.sin) == (0.0, 0.0)  # inactive
    controller.on_activate(None, (), None)
    outputs = []
    for k in range(500, 3000):
        psi = omega * 0.01 * k
        outputs.append(_step(controller, psi % (2 * math.pi), 2e6 * math.cos(psi), 0.0))
    assert outputs[0].phase_offset == 0.0 and outputs[0].harmonic == 1
    first = next(i for i, o in enumerate(outputs) if o.cos or o.sin) + 500
    assert omega * 0.01 * first == pytest.approx(2 * 2 * math.pi, abs=0.05)  # two revolutions after the start
    assert max(math.hypot(o.cos, o.sin) for o in outputs) <= math.radians(3.0) + 1e-15


def test_without_finite_hub_moments_the_demand_fades_out_over_the_ramp_time_and_back_in():
    """A NaN hub moment is refused input (update_or_hold): the demand falls linearly from its last value to 0 over
    ramp_time, and once the moments are finite again it comes back as fast, from where the law stood."""
    from hawt_controllers.plugins.controller import update_or_hold

    controller = MainBearingIpcController({"ramp_time": 1.0, "integral_gain": 5.0}, PLANT)
    controller.on_activate(0.0, (), None)
    omega, held = 1.5, ()

    def step(k, tilt_scale=1.0):
        psi = omega * 0.01 * k
        tilt, yaw = hub_to_main_bearing(2e6 * math.cos(psi), 0.0, psi)
        state = SimpleNamespace(hub_tilt_moment=float(tilt) * tilt_scale, hub_yaw_moment=float(yaw))
        return update_or_hold(controller, k, SimpleNamespace(azimuth=psi % (2 * math.pi)), state, held)

    for k in range(1500):
        held, refusal = step(k)
    assert refusal is None and math.hypot(held[0].cos, held[0].sin) > 0.0
    last = math.hypot(held[0].cos, held[0].sin)
    demands = []
    for k in range(1500, 1650):
        held, refusal = step(k, math.nan)
        demands.append(math.hypot(held[0].cos, held[0].sin))
    assert "not finite" in refusal and controller.WITHOUT_INPUT == "output fading out over its ramp time"
    np.testing.assert_allclose(demands[:100], last * (1.0 - np.arange(1, 101) * 0.01), rtol=1e-9, atol=1e-15)
    assert max(demands[100:]) == 0.0
    back = [math.hypot(out[0].cos, out[0].sin) for out, _ in (step(k) for k in range(1650, 1760))]
    assert back[0] > 0.0 and back[-1] > 0.5 * last
