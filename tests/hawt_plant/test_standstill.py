"""Specification of a shut-down turbine (IEC 61400-1 DLC 6.x) and of a yawed inflow: the plant's ``rotor`` idling or
parked, its ``yaw_misalignment``, and a grid loss that takes the generator's torque at once."""
import math

import numpy as np
import pytest

from hawt_core.parameter_table import ParameterError, resolve_values
from hawt_plant.gusts import extreme_wind_speed
from hawt_plant.model import ModelConfig, TurbineModel
from hawt_plant.plant_setup import PARAMETERS, check_parameters, make_plant
from hawt_plant.shear_wind import PowerLawWind
from hawt_plant.turbine import nrel_5mw
from hawt_plant.turbulence import TurbulenceSpec, cached_turbulence
from hawt_plant.wind_field import YawedWind

FEATHER = nrel_5mw().pitch_actuator.max_angle


def _plant(**given):
    """The plant of these parameters (the rest the defaults) and its output at time 0."""
    _, model, output = make_plant(resolve_values(PARAMETERS, given))
    return model, output


def _run(model, output, seconds: float, pitch: float = 0.0, torque: float = 4e4):
    """Step ``seconds`` under one command; the outputs."""
    outputs = [output]
    for _ in range(round(seconds / model.config.dt)):
        outputs.append(model.step(np.full(model.number_of_blades, pitch), torque))
    return outputs


@pytest.mark.parametrize("rotor", ["idling", "parked"])
def test_a_shut_down_rotor_holds_its_blades_at_feather_with_the_generator_off_whatever_is_commanded(rotor):
    """Idling or parked in the 50-year extreme wind of class I (70 m/s at the hub, 15 deg of yaw misalignment), the
    commands (fine pitch, full torque) are checked but not applied: the blades stay at feather, the generator torque
    and the power are 0 at every step; parked, the brake keeps the generator at rest and the rotor moves only by
    the shaft's torsion."""
    model, output = _plant(rotor=rotor, wind_type="ewm50", yaw_misalignment=math.radians(15.0))
    assert output.hub_wind_speed == pytest.approx(extreme_wind_speed("I", 50) * math.cos(math.radians(15.0)), rel=1e-3)
    outputs = _run(model, output, 10.0, pitch=0.0, torque=4e4)
    assert all(np.all(out.pitch == FEATHER) for out in outputs)
    assert all(out.generator_torque == 0.0 and out.electrical_power == 0.0 for out in outputs)
    speeds = np.array([out.rotor_speed for out in outputs])
    if rotor == "parked":
        assert all(out.generator_speed == 0.0 for out in outputs)
        assert np.abs(speeds).max() < 0.05  # rad/s: the rotor swinging on the shaft's torsion
        azimuths = np.array([out.azimuth for out in outputs])
        assert np.abs((azimuths + math.pi) % (2 * math.pi) - math.pi).max() < math.radians(1.0)
    with pytest.raises(ValueError, match="pitch_command"):
        model.step(np.full(3, math.nan), 0.0)  # a bad command is still refused


def test_an_idling_rotor_starts_at_the_speed_where_its_mean_torque_vanishes():
    """With the generator off, an idling rotor in steady wind starts at its equilibrium: over 20 s its speed stays
    within 0.02 rad/s of where it started (a feathered NREL 5 MW idles slowly backwards at 70 m/s, the twist's
    doing) and below a tenth of the rated speed."""
    model, output = _plant(rotor="idling", wind_type="ewm50")
    speeds = np.array([out.rotor_speed for out in _run(model, output, 20.0)])
    assert np.abs(speeds - speeds[0]).max() < 0.02
    assert np.abs(speeds).max() < 0.1 * nrel_5mw().schedule.rated_rotor_speed


@pytest.mark.parametrize("yaw_degrees", [0.0, 30.0, -30.0, 90.0, 180.0])
def test_a_parked_rotor_stays_stable_at_any_yaw_misalignment(yaw_degrees):
    """Parked in the 50-year wind at yaw misalignments up to the wind from behind (DLC 6.1-6.2), the loads settle: the
    blade-root moments' peak-to-peak over the last 10 of 30 s is no larger than over the first 10 s (the flexible
    flap mode of a feathered blade gave a growing stall flutter here, model notes), and every load is finite."""
    model, output = _plant(rotor="parked", wind_type="ewm50", yaw_misalignment=math.radians(yaw_degrees))
    outputs = _run(model, output, 30.0)
    moments = np.array([out.root_moment_oop for out in outputs])
    first, last = np.ptp(moments[:1000], axis=0), np.ptp(moments[-1000:], axis=0)
    assert np.all(last <= first + 1e4)
    assert all(np.isfinite([out.tower_base_fa_moment, out.tower_base_ss_moment]).all() for out in outputs)


def test_a_lateral_wind_on_the_parked_rotor_loads_the_tower_sideways_its_way():
    """The wind turned towards +y pushes the tower towards +y: its base side-side moment (about x, positive for a
    load towards -y) turns negative, and the other way for -y; head-on, the side-side moment is the smaller."""
    base = {}
    for yaw in (-90.0, 0.0, 90.0):
        model, output = _plant(rotor="parked", wind_type="ewm50", yaw_misalignment=math.radians(yaw))
        base[yaw] = np.mean([out.tower_base_ss_moment for out in _run(model, output, 5.0)])
    assert base[90.0] < -5e7 and base[-90.0] > 5e7
    assert abs(base[0.0]) < 0.2 * min(abs(base[90.0]), abs(base[-90.0]))


def test_a_yawed_field_is_the_field_turned_about_the_tower_axis():
    """YawedWind(field, gamma) at a point p is R(gamma) field(R(-gamma) p): a steady wind blows along (cos gamma,
    sin gamma, 0) at every height, and a turbulent field's frozen turbulence is convected along its own mean wind."""
    gamma = math.radians(25.0)
    steady = YawedWind(PowerLawWind(12.0, shear_exponent=0.2), gamma)
    hub = steady.velocity(0.0, np.zeros(1), np.zeros(1), np.full(1, 90.0))[:, 0]
    np.testing.assert_allclose(hub, [12.0 * math.cos(gamma), 12.0 * math.sin(gamma), 0.0], atol=1e-12)
    field = cached_turbulence(TurbulenceSpec(mean_speed=12.0, duration=20.0, grid_width=40.0, grid_height=40.0,
                                             n_y=9, n_z=9, seed=3))
    yawed = YawedWind(field, gamma)
    rng = np.random.default_rng(1)
    x, y, z = rng.uniform(-10, 10, 5), rng.uniform(-15, 15, 5), rng.uniform(75, 105, 5)
    c, s = math.cos(gamma), math.sin(gamma)
    u, v, w = field.velocity(4.0, x, y, z)
    turned = yawed.velocity(4.0, c * x - s * y, s * x + c * y, z)
    np.testing.assert_allclose(turned, [c * u - s * v, s * u + c * v, w], atol=1e-12)
    with pytest.raises(ValueError, match="yaw_misalignment"):
        YawedWind(field, 4.0)


@pytest.mark.parametrize("given, message", [
    ({"yaw_misalignment": math.radians(50.0)}, "^yaw_misalignment: 0.872665 rad \\(50.0 deg\\) is beyond the 45 deg"),
    ({"wind_type": "ewm1"}, "^wind_type: ewm1 is the extreme wind of a shut-down turbine"),
    ({"rotor": "stopped"}, "^rotor: "),
    ({"yaw_misalignment": 3.2, "rotor": "parked"}, "^yaw_misalignment: "),
])
def test_the_plant_refuses_what_an_operating_rotor_cannot_run_in_one_line(given, message):
    """An operating rotor takes up to 45 deg of yaw misalignment and no extreme wind model; a shut-down one any yaw
    in [-pi, pi]; the rotor is operating, idling or parked."""
    with pytest.raises(ParameterError, match=message):
        check_parameters(resolve_values(PARAMETERS, given))


def test_a_shut_down_rotor_takes_any_yaw_misalignment_and_the_extreme_wind():
    check_parameters(resolve_values(PARAMETERS, {"yaw_misalignment": -math.pi, "rotor": "idling",
                                                 "wind_type": "ewm1"}))


def test_a_grid_loss_takes_the_generator_torque_at_once():
    """At rated wind, the generator off the grid has no torque from the next step on, whatever is commanded (it
    used to fall at the torque rate limit, 15 kN*m/s, for 2.9 s), and the rotor speeds up."""
    model = TurbineModel(nrel_5mw(), PowerLawWind(11.4, shear_exponent=0.2), ModelConfig())
    output = model.output
    assert model.grid_connected and output.generator_torque > 4e4
    model.disconnect_grid()
    outputs = _run(model, output, 1.0, pitch=float(output.pitch[0]), torque=output.generator_torque)
    assert all(out.generator_torque == 0.0 for out in outputs[1:])
    assert outputs[-1].rotor_speed > output.rotor_speed + 0.01
