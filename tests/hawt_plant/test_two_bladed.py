"""The two-bladed NREL 5 MW variant (turbines/nrel_5mw/two_bladed.yaml) and the plant with B = 2: Zalkind & Pao's
AC-11 (and the B = 3 side of AC-10) of literature/notes/seed001_zalkind.md §6."""
import math
from pathlib import Path

import numpy as np
import pytest

import hawt_plant
from hawt_core.rotor.harmonic_estimator import sliding_phasors
from hawt_plant.bem import BemBlade, rotor_performance
from hawt_plant.model import ModelConfig, TurbineModel
from hawt_plant.shear_wind import PowerLawWind
from hawt_plant.turbine import (TurbineDefinitionError, load_turbine, nrel_5mw, nrel_5mw_two_bladed,
                                nrel_5mw_two_bladed_downwind)

FIXED_FRAME = ("hub_tilt_moment", "hub_yaw_moment", "yaw_bearing_tilt_moment", "yaw_bearing_yaw_moment",
               "tower_base_fa_moment", "tower_base_ss_moment")


@pytest.fixture(scope="module")
def two_bladed():
    return nrel_5mw_two_bladed()


def _steady_run(turbine, wind_speed=15.0, seconds=30.0):
    """Open loop at the operating point (commands held) in steady wind with α = 0.14; the last 2 revolutions'
    0P…4P phasors of the blade-1 flap moment and the fixed-frame moments."""
    model = TurbineModel(turbine, PowerLawWind(wind_speed, turbine.hub_height, shear_exponent=0.14))
    first = model.output
    outputs = [model.step(first.pitch, first.generator_torque) for _ in range(int(seconds / 0.01))]
    azimuth = np.array([o.azimuth for o in outputs])
    channels = {"flap_1": np.array([o.root_moment_oop[0] for o in outputs])}
    channels.update({name: np.array([getattr(o, name) for o in outputs]) for name in FIXED_FRAME})
    phasors = sliding_phasors(np.column_stack(list(channels.values())), azimuth).phasors[-1]
    return dict(zip(channels, np.abs(phasors))), outputs


def test_the_variant_is_the_nrel_5mw_blade_on_two_blades_with_the_generator_speeds_unchanged(two_bladed):
    """B = 2, the same blade and tower; rotor speeds × √(3/2), gearbox ratio ÷ √(3/2): the rated generator speed, on
    which the baseline collective controller is tuned, is the NREL 5 MW's."""
    three = nrel_5mw()
    assert two_bladed.rotor.number_of_blades == 2
    for part in ("blade_aerodynamics", "blade_structure", "tower"):
        mine, theirs = getattr(two_bladed, part), getattr(three, part)
        assert all(np.array_equal(getattr(mine, f), getattr(theirs, f)) for f in mine.__dataclass_fields__), part
    factor = math.sqrt(1.5)
    assert two_bladed.schedule.rated_rotor_speed == pytest.approx(three.schedule.rated_rotor_speed * factor, rel=1e-6)
    assert two_bladed.schedule.rated_rotor_speed * two_bladed.drivetrain.gearbox_ratio == pytest.approx(
        three.schedule.rated_rotor_speed * three.drivetrain.gearbox_ratio, rel=1e-6)
    assert two_bladed.description(0.01).blades == 2


def test_the_variant_tip_speed_ratio_is_the_bem_optimum_of_two_blades(two_bladed):
    """The stated optimal tip-speed ratio 9.5 is within 0.25 of the BEM's best at 8 m/s (a step of 0.25)."""
    blade = BemBlade.from_turbine(two_bladed)
    ratios = np.arange(7.0, 11.01, 0.25)
    cp = [rotor_performance(two_bladed, 8.0, r * 8.0 / two_bladed.rotor.tip_radius, 0.0, blade).power_coefficient
          for r in ratios]
    assert abs(ratios[int(np.argmax(cp))] - two_bladed.schedule.optimal_tip_speed_ratio) <= 0.25


def test_a_derived_definition_names_a_definition_beside_it_and_a_chain_has_no_cycle(tmp_path):
    (tmp_path / "a.yaml").write_text("derived_from: b.yaml\nname: a\n")
    (tmp_path / "b.yaml").write_text("derived_from: a.yaml\n")
    with pytest.raises(TurbineDefinitionError, match=r"b.yaml: derived_from: a.yaml derives from it again "
                                                     r"\(a.yaml -> b.yaml -> a.yaml\)"):
        load_turbine(tmp_path / "a.yaml")
    (tmp_path / "c.yaml").write_text("derived_from: ../b.yaml\n")
    with pytest.raises(TurbineDefinitionError, match="c.yaml: derived_from: expected a file name in the same folder"):
        load_turbine(tmp_path / "c.yaml")


@pytest.mark.parametrize("blades", [2, 3])
def test_yaw_bearing_moments_are_the_rotor_and_nacelle_loads_at_the_tower_top(blades):
    """For any B, steady 11.4 m/s: the mean tower-base fore-aft moment is the yaw-bearing tilt moment plus thrust ×
    tower height (within 5 %: the tower's own weight leans with its deflection); the mean yaw-bearing yaw moment is
    the hub yaw moment turned to the vertical minus the rotor torque's part along it, M_z cos τ − Q sin τ (within 5 %
    of Q sin τ: the rotor's side force acts on the overhang too; 3.5-3.7 % with the normal forces' part that the
    blades' flap slope turns along the span, under 3 % before)."""
    turbine = nrel_5mw() if blades == 3 else nrel_5mw_two_bladed()
    model = TurbineModel(turbine, PowerLawWind(11.4, turbine.hub_height))
    first = model.output
    outputs = [model.step(first.pitch, first.generator_torque) for _ in range(500)]
    mean = {name: np.mean([getattr(o, name) for o in outputs]) for name in (
        "tower_base_fa_moment", "yaw_bearing_tilt_moment", "rotor_thrust", "yaw_bearing_yaw_moment",
        "hub_yaw_moment", "aero_torque")}
    assert mean["tower_base_fa_moment"] - mean["yaw_bearing_tilt_moment"] == pytest.approx(
        mean["rotor_thrust"] * turbine.tower.height, rel=0.05)
    tilt = turbine.rotor.shaft_tilt
    torque_part = mean["aero_torque"] * math.sin(tilt)
    assert mean["yaw_bearing_yaw_moment"] == pytest.approx(
        mean["hub_yaw_moment"] * math.cos(tilt) - torque_part, abs=0.05 * torque_part)


def test_ac11_two_blades_in_shear_flap_is_1p_and_the_fixed_frame_is_2p(two_bladed):
    """AC-11: B = 2, α = 0.14, 15 m/s, no IPC: the blade flap moment's largest harmonic is 1P; the main-bearing
    (hub tilt, yaw), yaw-bearing and tower-base moments' largest harmonic is 2P; at the main bearing 1P and 3P are
    under 5 % of it (the tower keeps some of its side-side mode, 0.31 Hz, near 1P = 0.25 Hz, after 30 s)."""
    amplitude, _ = _steady_run(two_bladed)
    assert int(np.argmax(amplitude["flap_1"][1:])) + 1 == 1
    for name in FIXED_FRAME:
        assert int(np.argmax(amplitude[name][1:])) + 1 == 2, name
    for name in FIXED_FRAME[:2]:
        assert max(amplitude[name][1], amplitude[name][3]) < 0.05 * amplitude[name][2], name


def test_ac10_three_blades_in_shear_have_no_main_bearing_2p_and_meet_eq_20_by_themselves():
    """AC-10 (plant side): B = 3, α = 0.14, 15 m/s: the main-bearing 2P is under 1 % of the two-bladed rotor's, and
    the hub 1P phasors (the main-bearing moments turned into the rotating frame) satisfy m_hy = j m_hz within 1 %."""
    from hawt_analysis.load_transfer import main_bearing_to_hub

    amplitude, outputs = _steady_run(nrel_5mw(), seconds=20.0)
    two, _ = _steady_run(nrel_5mw_two_bladed(), seconds=20.0)
    assert amplitude["hub_tilt_moment"][2] < 0.01 * two["hub_tilt_moment"][2]
    azimuth = np.array([o.azimuth for o in outputs])
    hub = main_bearing_to_hub(np.array([o.hub_tilt_moment for o in outputs]),
                              np.array([o.hub_yaw_moment for o in outputs]), azimuth)
    y1, z1 = sliding_phasors(np.column_stack(hub), azimuth).phasors[-1, :, 1]
    assert abs(y1 - 1j * z1) < 0.01 * abs(y1)


def _flap_by_azimuth(turbine, tower_shadow: bool, seconds: float = 12.0) -> tuple[float, float, float]:
    """Uniform 15 m/s, commands held: blade 1's mean flap moment, and its mean within 3 deg of pointing down
    (azimuth 180 deg) and of 150 deg."""
    model = TurbineModel(turbine, PowerLawWind(15.0, turbine.hub_height, shear_exponent=0.0),
                         ModelConfig(tower_shadow=tower_shadow))
    first = model.output
    outputs = [model.step(first.pitch, first.generator_torque) for _ in range(int(seconds / 0.01))][-600:]
    azimuth = np.degrees([o.azimuth for o in outputs]) % 360.0
    flap = np.array([o.root_moment_oop[0] for o in outputs])
    return flap.mean(), flap[np.abs(azimuth - 180.0) < 3.0].mean(), flap[np.abs(azimuth - 150.0) < 3.0].mean()


def test_a_downwind_rotor_crosses_the_tower_wake_and_its_coning_relieves_the_flap_moment(two_bladed):
    """rotor.position downwind (two_bladed_downwind.yaml): behind the tower, blade 1's flap moment drops by more
    than a fifth as it points down through the wake (measured: 27 %) (the upwind rotor's potential-flow dip is under 5 %; no dip
    without the shadow), and the blades coned downwind carry a smaller mean flap moment (the centrifugal load
    now opposes the thrust), as Zalkind & Pao's downwind SUMR is designed to."""
    downwind = nrel_5mw_two_bladed_downwind()
    assert downwind.rotor.downwind and not two_bladed.rotor.downwind
    up_mean, up_down, up_beside = _flap_by_azimuth(two_bladed, True)
    down_mean, down_down, down_beside = _flap_by_azimuth(downwind, True)
    assert down_down < 0.8 * down_beside
    assert abs(up_down - up_beside) < 0.05 * up_beside
    _, still_down, still_beside = _flap_by_azimuth(downwind, False)
    assert abs(still_down - still_beside) < 0.05 * still_beside
    assert down_mean < 0.8 * up_mean


def test_a_rotor_position_other_than_upwind_or_downwind_is_refused_by_name(tmp_path):
    packaged = Path(hawt_plant.__file__).parent / "turbines" / "nrel_5mw"
    (tmp_path / "turbine.yaml").write_text((packaged / "turbine.yaml").read_text())
    (tmp_path / "airfoils").symlink_to(packaged / "airfoils")
    (tmp_path / "sideways.yaml").write_text("derived_from: turbine.yaml\nrotor:\n  position: sideways\n")
    with pytest.raises(TurbineDefinitionError, match="sideways.yaml: rotor.position: expected one of upwind, "
                                                     "downwind, found 'sideways'"):
        load_turbine(tmp_path / "sideways.yaml")
