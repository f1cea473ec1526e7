"""Specification of hawt_plant.airfoil_table: fast per-element polar lookup."""
import math

import numpy as np

from hawt_plant.airfoil_table import ElementPolars


def test_lookup_matches_interpolating_the_source_polars(turbine):
    """On every element the uniform-grid lookup agrees with np.interp of the source table."""
    names = turbine.blade_aerodynamics.airfoil
    polars = ElementPolars(turbine.airfoils, names)
    alpha = np.linspace(-math.pi, math.pi - 1e-9, 5001)
    grid = np.broadcast_to(alpha[:, None], (alpha.size, len(names)))
    cl, cd = polars.coefficients(grid)
    for k, name in enumerate(names):
        source = turbine.airfoils[name]
        assert np.max(np.abs(cl[:, k] - np.interp(alpha, source.alpha, source.cl))) < 2e-3
        assert np.max(np.abs(cd[:, k] - np.interp(alpha, source.alpha, source.cd))) < 2e-3


def test_angles_outside_the_circle_wrap(turbine):
    """alpha and alpha + 2 pi give the same coefficients."""
    polars = ElementPolars(turbine.airfoils, turbine.blade_aerodynamics.airfoil)
    alpha = np.linspace(-0.5, 0.5, len(turbine.blade_aerodynamics.airfoil))[None, :]
    cl, cd = polars.coefficients(alpha)
    cl_wrapped, cd_wrapped = polars.coefficients(alpha + 2 * math.pi)
    np.testing.assert_allclose(cl_wrapped, cl, atol=1e-9)
    np.testing.assert_allclose(cd_wrapped, cd, atol=1e-9)
