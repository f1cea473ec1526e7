"""Fixtures of the plant tests: the packaged NREL 5 MW definition and its BEM blade, loaded once."""
import pytest

from hawt_plant.bem import BemBlade
from hawt_plant.turbine import nrel_5mw


@pytest.fixture(scope="session")
def turbine():
    return nrel_5mw()


@pytest.fixture(scope="session")
def blade(turbine):
    return BemBlade.from_turbine(turbine)
