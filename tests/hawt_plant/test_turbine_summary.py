"""turbine_summary: rated values, the BEM's peak power coefficient and the first modes of a definition."""
import math
from dataclasses import replace

import numpy as np
import pytest

from hawt_plant.bem import rotor_performance
from hawt_plant.modal import blade_edge_mode, blade_edgewise_frequency, blade_modal_properties
from hawt_plant.turbine import nrel_5mw
from hawt_plant.turbine_summary import format_summary, peak_power_coefficient, turbine_summary


@pytest.fixture(scope="module")
def summary():
    return turbine_summary(nrel_5mw())


def test_the_peak_power_coefficient_is_the_best_of_a_fine_grid():
    """No point of a fine grid (tip-speed ratio 0.05, pitch 0.25 deg, from the lower pitch limit up) beats the
    peak found, and the peak is the BEM's value at the point it names."""
    turbine = nrel_5mw()
    cp, tsr, pitch = peak_power_coefficient(turbine)
    radius = turbine.rotor.tip_radius
    grid = max(rotor_performance(turbine, 10.0, l * 10.0 / radius, math.radians(b)).power_coefficient
               for l in np.arange(6.5, 9.0, 0.05) for b in np.arange(0.0, 3.0, 0.25))
    assert grid <= cp + 1e-6
    assert cp == pytest.approx(rotor_performance(turbine, 10.0, tsr * 10.0 / radius, pitch).power_coefficient)
    assert pitch >= turbine.pitch_actuator.min_angle


def test_the_bem_rated_wind_speed_gives_rated_power_on_the_schedule(summary):
    """At the summary's BEM rated wind speed the schedule (rated rotor speed there, lowest pitch) gives rated
    mechanical power: 11.31 m/s for the shipped NREL 5 MW (two_bladed.yaml's header says so too)."""
    turbine = nrel_5mw()
    performance = rotor_performance(turbine, summary.bem_rated_wind_speed, turbine.schedule.rated_rotor_speed,
                                     turbine.pitch_actuator.min_angle)
    rated = turbine.generator.rated_power / (turbine.generator.efficiency * turbine.drivetrain.gearbox_efficiency)
    assert performance.power == pytest.approx(rated, rel=1e-4)
    assert summary.bem_rated_wind_speed == pytest.approx(11.31, abs=0.01)


def test_the_modes_are_the_modal_models_one_at_a_time(summary):
    """The flap mode is sqrt(k/m), stiffened by the rotation at rated speed; the drivetrain's is the two-inertia
    torsion of the rotor inertia the summary gives; the edgewise mode is the blade's mode sqrt(k/m), modal.py's estimate
    for a blade rigid edgewise; the tower modes are
    near Jonkman's FAST values (0.324 and 0.312 Hz), a little above them without the rotor's and nacelle's rotary
    inertia."""
    turbine = nrel_5mw()
    rigid = replace(turbine, blade_structure=replace(turbine.blade_structure, edge_mode_shape=None))
    blade = blade_modal_properties(turbine)
    assert summary.blade_flap_frequency == pytest.approx(blade.natural_frequency / (2 * math.pi))
    omega = turbine.schedule.rated_rotor_speed
    assert summary.blade_flap_frequency_rated == pytest.approx(
        math.sqrt((blade.stiffness + omega**2 * blade.centrifugal_stiffness) / blade.modal_mass) / (2 * math.pi))
    assert 0.324 < summary.tower_fa_frequency < 0.324 * 1.06 and 0.312 < summary.tower_ss_frequency < 0.312 * 1.1
    rotor = turbine.rotor.hub_inertia + 3 * math.cos(turbine.rotor.cone_angle) ** 2 * (
        blade.second_moment + 2 * 1.5 * blade.first_moment + 1.5**2 * blade.mass)
    assert summary.rotor_inertia == pytest.approx(rotor)
    assert summary.blade_edge_frequency == pytest.approx(blade_edge_mode(turbine).natural_frequency / (2 * math.pi))
    assert summary.blade_edge_modelled
    assert turbine_summary(rigid).blade_edge_frequency == blade_edgewise_frequency(rigid)
    generator = turbine.drivetrain.generator_inertia * 97.0**2
    assert summary.drivetrain_frequency == pytest.approx(
        math.sqrt(turbine.drivetrain.torsional_stiffness * (1 / rotor + 1 / generator)) / (2 * math.pi))


def test_the_text_names_rated_values_cp_max_first_modes_and_the_aerodynamic_options(summary):
    """Five lines: the turbine, its rated values, Cp-max with its tip-speed ratio, the first modes, what the tower
    stands on; then the aerodynamic options, one line each with its source; then the protection's trip levels."""
    lines = format_summary(summary).splitlines()
    assert len(lines) == 5 + 1 + 5 + 1
    assert lines[1].startswith("rated: 5 MW electrical, rotor 12.10 rpm")
    assert lines[2].startswith(f"Cp-max {summary.max_power_coefficient:.4f} at tip-speed ratio")
    assert lines[3].startswith("first modes: blade flap")
    assert lines[4] == "the tower stands on the ground: the tower is clamped there"
    assert lines[5].startswith("aerodynamics")
    assert lines[9] == ("  unsteady_airfoil on: NRELOffshrBsline5MW_Onshore_AeroDyn15.dat UA_Mod = 3 (B-L "
                        "Minnema/Pierce; the plant's is Hansen-Gaunaa-Madsen's, UA_Mod = 4)")
    assert lines[10].startswith("  dynamic_inflow on: NRELOffshrBsline5MW_Onshore_AeroDyn15.dat Wake_Mod = 1 (BEMT)")
    assert lines[11].startswith("protection (the safety system trips and feathers above these") and \
        "rotor 14.28 rpm (1.18 x rated; warning at 13.55), generator 1385.0 rpm" in lines[11]
