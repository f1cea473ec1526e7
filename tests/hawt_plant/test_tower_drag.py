"""Tower drag (AeroDyn's TwrAero): the drag of the outline in the relative wind, its modal and base loads."""
import numpy as np
import pytest

from hawt_plant.tower_drag import TowerDrag
from hawt_plant.turbine import nrel_5mw


@pytest.fixture(scope="module")
def drag() -> TowerDrag:
    return TowerDrag.from_turbine(nrel_5mw())


def test_still_tower_in_uniform_wind_carries_the_integrated_cylinder_drag(drag):
    turbine = nrel_5mw()
    tower = turbine.tower
    u = 18.0
    loads = drag.loads(np.full(drag.elevation.shape, u), np.zeros(drag.elevation.shape), 0.0, 0.0)
    per_length = 0.5 * turbine.environment.air_density * tower.drag_coefficient * tower.outline_diameter * u**2
    assert loads.base_fa_moment == pytest.approx(np.trapezoid(per_length * tower.outline_elevation,
                                                              tower.outline_elevation), rel=1e-12)
    # Between the moments of uniform cylinders of the top's and the base's diameter: 3.0 and 4.6 MN m.
    bounds = [0.5 * 1.225 * diameter * u**2 * tower.height**2 / 2.0 for diameter in (3.87, 6.0)]
    assert bounds[0] < loads.base_fa_moment < bounds[1]
    assert loads.base_ss_moment == 0.0 and loads.ss_force == 0.0
    assert 0.0 < loads.fa_force < np.trapezoid(per_length, tower.outline_elevation)  # weighted by phi <= 1


def test_lateral_wind_bends_the_tower_sideways_with_the_side_side_sign_of_the_plant(drag):
    zero = np.zeros(drag.elevation.shape)
    loads = drag.loads(zero, np.full(drag.elevation.shape, 5.0), 0.0, 0.0)
    assert loads.ss_force > 0.0 and loads.base_ss_moment < 0.0  # drag to +y: a negative moment about x
    assert loads.fa_force == 0.0 and loads.base_fa_moment == 0.0


def test_the_moving_tower_is_damped_by_the_relative_wind(drag):
    u = np.full(drag.elevation.shape, 12.0)
    zero = np.zeros(drag.elevation.shape)
    step = 1e-3
    slope = (drag.loads(u, zero, step, 0.0).fa_force - drag.loads(u, zero, -step, 0.0).fa_force) / (2 * step)
    # d/dx' of sum k (u - phi x')^2 phi at x' = 0: -2 u sum k phi^2
    assert slope == pytest.approx(-2.0 * 12.0 * np.dot(drag.coefficient, drag.fa_shape**2), rel=1e-6)
    assert slope < 0.0
    # Side-side motion in still air is damped too, by the quadratic drag of its own speed.
    assert drag.loads(zero, zero, 0.0, 0.5).ss_force < 0.0


def test_mode_shapes_are_zero_at_the_base_and_one_at_the_top(drag):
    assert drag.fa_shape[0] == 0.0 and drag.ss_shape[0] == 0.0
    assert drag.fa_shape[-1] == pytest.approx(1.0, abs=1e-3) and drag.ss_shape[-1] == pytest.approx(1.0, abs=1e-3)


def test_the_plant_adds_the_drag_to_the_tower_base_and_damps_the_tower_with_it():
    from hawt_plant.inflow import InflowSettings, make_wind
    from hawt_plant.model import ModelConfig, TurbineModel

    turbine = nrel_5mw()
    wind = make_wind(InflowSettings(kind="steady", wind_speed=18.0, shear_exponent=0.2))
    drag = TowerDrag.from_turbine(turbine)
    runs = {}
    for on in (False, True):
        model = TurbineModel(turbine, wind, ModelConfig(tower_drag=on))
        start = model.reset_to_operating_point(tower_offset=(0.2, 0.0))  # released from a fore-aft deflection
        pitch, torque = start.pitch.copy(), start.generator_torque
        runs[on] = np.array([model.step(pitch, torque).tower_top_fa_disp for _ in range(1000)]), model.output
    # The mean base moment grows by the drag of the sheared wind on the still tower (the motion is small).
    sheared = 18.0 * (drag.elevation / turbine.hub_height) ** 0.2
    expected = drag.loads(sheared, np.zeros_like(sheared), 0.0, 0.0).base_fa_moment
    change = runs[True][1].tower_base_fa_moment - runs[False][1].tower_base_fa_moment
    assert change == pytest.approx(expected, rel=0.1)
    # Released from 0.2 m, the tower's oscillation decays faster with the drag's damping.
    def decay(displacement):
        swing = displacement - displacement[-300:].mean()
        return np.abs(swing[-300:]).max() / np.abs(swing[:300]).max()
    assert decay(runs[True][0]) < decay(runs[False][0])
