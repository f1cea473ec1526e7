"""Specification of hawt_plant.tower_shadow against Fratini (2019) eqs. 3.42-3.44 (notes AC-11)."""
import math

import numpy as np
import pytest

from hawt_plant.tower_shadow import TowerShadow, potential_flow_disturbance, wake_deficit
from hawt_plant.turbine import nrel_5mw


def test_deficit_straight_upwind_is_a2_over_x2():
    """At y = 0 the deficit is -a^2/x^2, whatever the distance along the blade."""
    du, dv = potential_flow_disturbance(np.array([-4.0, -8.0]), np.zeros(2), np.array([2.0, 2.0]))
    np.testing.assert_allclose(du, [-0.25, -0.0625])
    np.testing.assert_allclose(dv, 0.0, atol=1e-15)


def test_speed_up_beside_the_tower_is_one_eighth_of_the_deficit():
    """Maximum a^2/(8 x^2) at |y| = sqrt(3) |x|, ratio -1/8 as Fratini's 0.0444 / -0.36."""
    x, radius = -5.0, 2.0
    y = np.linspace(0.0, 40.0, 40001)
    du, _ = potential_flow_disturbance(np.full_like(y, x), y, np.full_like(y, radius))
    assert du.max() == pytest.approx(radius**2 / (8 * x**2), rel=1e-6)
    assert y[du.argmax()] == pytest.approx(math.sqrt(3) * abs(x), abs=2e-3)
    assert du.max() / du.min() == pytest.approx(-1 / 8, rel=1e-6)


def test_lateral_flow_diverges_upwind_of_the_tower():
    """Upwind of the tower the flow turns away from the centreline."""
    _, dv = potential_flow_disturbance(np.array([-5.0, -5.0]), np.array([2.0, -2.0]), np.array([2.0, 2.0]))
    assert dv[0] > 0.0 > dv[1]


def test_closer_or_wider_tower_gives_deeper_deficit():
    """Smaller x or larger a deepens the deficit (Fratini Figs. 3.10, 3.11)."""
    du_near, _ = potential_flow_disturbance(np.array([-3.0]), np.zeros(1), np.array([2.0]))
    du_far, _ = potential_flow_disturbance(np.array([-5.0]), np.zeros(1), np.array([2.0]))
    du_wide, _ = potential_flow_disturbance(np.array([-5.0]), np.zeros(1), np.array([3.0]))
    assert du_near[0] < du_far[0] and du_wide[0] < du_far[0]


def test_no_disturbance_above_the_tower_top_or_downwind():
    """The shadow zone is below the tower top and upwind of the centreline (errata AC-11)."""
    shadow = TowerShadow.from_tower(nrel_5mw().tower)
    x = np.array([-6.0, -6.0, 6.0])
    z = np.array([50.0, 100.0, 50.0])
    du, dv = shadow.disturbance(x, np.full(3, 0.5), z)
    assert du[0] < 0.0 and dv[0] != 0.0
    assert du[1] == dv[1] == du[2] == dv[2] == 0.0


def test_radius_follows_the_aerodyn_outline():
    """At the base the NREL 5 MW tower is 6 m wide: deficit (3/x)^2."""
    shadow = TowerShadow.from_tower(nrel_5mw().tower)
    du, _ = shadow.disturbance(np.array([-10.0]), np.zeros(1), np.zeros(1))
    assert du[0] == pytest.approx(-0.09)


@pytest.mark.parametrize("x, y, expected", [
    (9.0, 0.0, -1.0 / 3.0),                                 # centreline: -Cd / sqrt(x)
    (9.0, 1.5, -math.cos(0.5 * math.pi * 1.5 / math.hypot(9.0, 1.5) ** 0.5) ** 2 / math.hypot(9.0, 1.5) ** 0.5),
    (9.0, 3.2, 0.0),                                        # outside the wake, |y| > sqrt(r)
    (2.0, 0.0, -0.5),                                       # -1/sqrt(2) limited to -0.5
    (-9.0, 0.0, 0.0),                                       # upwind of the tower
])
def test_the_wake_deficit_is_powles_model_of_aerodyn(x, y, expected):
    """AeroDyn TwrShadow = 1: u = -Cd / sqrt(r) cos^2(pi/2 y / sqrt(r)), x, y in tower radii, behind the tower."""
    radius = 2.0
    assert wake_deficit(np.array(x * radius), np.array(y * radius), np.array(radius), 1.0) == pytest.approx(expected)
    assert wake_deficit(np.array(x * radius), np.array(y * radius), np.array(0.0), 1.0) == 0.0


def test_a_downwind_rotor_sees_the_wake_behind_the_tower_and_an_upwind_one_does_not():
    """Behind the tower a downwind rotor's shadow is the potential flow plus the wake; an upwind rotor's is nothing."""
    tower = nrel_5mw().tower
    upwind, downwind = TowerShadow.from_tower(tower), TowerShadow.from_tower(tower, downwind=True)
    x, y, z = np.array([8.0]), np.array([0.0]), np.array([60.0])
    radius = np.interp(60.0, tower.outline_elevation, tower.outline_diameter) / 2.0
    assert upwind.disturbance(x, y, z)[0] == 0.0
    du, _ = downwind.disturbance(x, y, z)
    assert du == pytest.approx(potential_flow_disturbance(x, y, radius)[0] + wake_deficit(x, y, radius, 1.0))
    assert du < -0.3
    assert downwind.disturbance(-x, y, z)[0] == pytest.approx(upwind.disturbance(-x, y, z)[0])
