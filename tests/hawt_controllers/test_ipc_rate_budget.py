"""The IPC design's rate budget: what cancelling a harmonic's moment of steady sheared wind asks of the pitch
actuator. On the NREL 5 MW (8 °/s) 1P takes about a quarter of it; on the IEA 15 MW (2 °/s) most of it, which is why
its 2P IPC, designed for 0.1 Hz like the NREL 5 MW's, was rate-limited in turbulence and raised the loads."""
import math

import pytest

from hawt_controllers.ipc_design import measure_harmonic_response, rate_budget
from hawt_plant.turbine import nrel_5mw, turbine_from

IEA_15MW = "IEA-15-240-RWT/IEA-15-240-RWT-Monopile/IEA-15-240-RWT-Monopile.fst"


def test_the_budget_is_the_pitch_that_cancels_the_steady_shear_moment_at_its_harmonic_s_rate():
    turbine = nrel_5mw()
    response = measure_harmonic_response(turbine, 18.0, 1)
    budget = rate_budget(turbine, response)
    assert budget.rate == pytest.approx(response.rotor_speed * budget.amplitude, rel=0.01)
    assert budget.max_rate == turbine.pitch_actuator.max_rate
    assert 1.0 < math.degrees(budget.amplitude) < 2.5  # the 1P of shear 0.2 over dM/dθ of −54 MN·m/rad
    assert 0.2 < budget.share < 0.35
    uniform = rate_budget(turbine, response, shear=0.0)
    assert uniform.amplitude < 0.2 * budget.amplitude  # without shear only tilt and gravity are left


def test_on_the_iea_15mw_1p_alone_takes_most_of_the_2_deg_per_second(imported_deck):
    turbine = turbine_from(str(imported_deck(IEA_15MW)))
    budget = rate_budget(turbine, measure_harmonic_response(turbine, 18.0, 1))
    assert math.degrees(budget.max_rate) == pytest.approx(2.0, rel=1e-3)
    assert budget.share > 0.5
