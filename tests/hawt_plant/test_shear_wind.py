"""Specification of hawt_plant.shear_wind against Fratini (2019) §3.2.2 (notes AC-9, AC-10)."""
import numpy as np
import pytest

from hawt_plant.shear_wind import PowerLawWind


def blade_tip_extremes(wind, radius=61.5):
    """Speed at the blade tip pointing up and down [m/s]."""
    z = wind.hub_height + np.array([radius, -radius])
    u = wind.velocity(0.0, np.zeros(2), np.zeros(2), z)[0]
    return u[0], u[1]


def test_shear_reproduces_fratini_variation_at_114_m_s():
    """alpha = 0.1 at 90 m: 12.00 m/s up, 10.18 m/s down (Fratini §3.2.2, corrected eq. 3.41)."""
    top, bottom = blade_tip_extremes(PowerLawWind(11.4, 90.0, 0.1))
    assert top == pytest.approx(12.00, abs=0.03)
    assert bottom == pytest.approx(10.18, abs=0.03)


@pytest.mark.parametrize(("speed", "height", "variation"), [(14.0, 90.0, 2.24), (11.4, 120.0, 1.26)])
def test_shear_reproduces_fratini_variations(speed, height, variation):
    """The other two variations of Fratini §3.2.2 (the 80 m one is an erratum, not tested)."""
    top, bottom = blade_tip_extremes(PowerLawWind(speed, height, 0.1))
    assert top - bottom == pytest.approx(variation, abs=0.04)


def test_alpha_017_spans_about_9_to_12_m_s():
    """Fratini §5.1 shear case (AC-10): the power law gives 9.38 to 12.46 m/s at the tip."""
    top, bottom = blade_tip_extremes(PowerLawWind(11.4, 90.0, 0.17))
    assert (bottom, top) == (pytest.approx(9.38, abs=0.01), pytest.approx(12.46, abs=0.01))


def test_velocity_has_the_shape_of_the_points_and_only_u():
    """Shape (3,) + x.shape; lateral and vertical components are zero."""
    z = np.linspace(10.0, 150.0, 12).reshape(3, 4)
    velocity = PowerLawWind(8.0, shear_exponent=0.2).velocity(3.0, np.zeros_like(z), np.zeros_like(z), z)
    assert velocity.shape == (3, 3, 4)
    assert np.all(velocity[1:] == 0.0) and np.all(np.diff(velocity[0].ravel()) > 0.0)


def test_uniform_wind_without_exponent():
    """alpha = 0 gives the mean speed everywhere, the ground included."""
    z = np.array([0.0, 1.0, 90.0, 200.0])
    u = PowerLawWind(9.0).velocity(0.0, z, z, z)[0]
    assert np.all(u == 9.0)


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"mean_speed": 0.0}, "mean_speed"),
    ({"mean_speed": 8.0, "hub_height": float("nan")}, "hub_height"),
    ({"mean_speed": 8.0, "shear_exponent": 1.5}, "shear_exponent"),
])
def test_invalid_parameters_are_named(kwargs, message):
    """Construction checks its arguments and names the one at fault."""
    with pytest.raises(ValueError, match=message):
        PowerLawWind(**kwargs)
