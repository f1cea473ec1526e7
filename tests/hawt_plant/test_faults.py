"""hawt_plant.faults: the faults entries, and what each fault does to the published or physical quantity from its
step."""
import dataclasses
import math

import numpy as np
import pytest

from hawt_core.parameter_table import ParameterError
from hawt_plant.faults import Fault, PlantFaults, fault_event, parse_faults
from hawt_plant.turbine import nrel_5mw

DT = 0.01
ACTUATOR = nrel_5mw().pitch_actuator
START = 3
"""The step the faults below start at."""


@dataclasses.dataclass(frozen=True)
class _Output:
    """What PlantFaults reads of a model's output (a TurbineOutput has these and more)."""

    time: float
    azimuth: float
    root_moment_oop: np.ndarray
    pitch: np.ndarray


class _Model:
    """A model whose step k+1 has M_oop = (k+1) * (1, 2, 3) MN*m, azimuth 0.1 (k+1) and the commanded pitch."""

    def __init__(self) -> None:
        self.k, self.commands, self.grid_connected = 0, [], True

    def disconnect_grid(self) -> None:
        self.grid_connected = False

    def output(self, pitch) -> _Output:
        return _Output(self.k * DT, 0.1 * self.k % (2 * math.pi), self.k * np.array([1e6, 2e6, 3e6]),
                       np.asarray(pitch, dtype=float))

    def step(self, pitch, generator_torque) -> _Output:
        self.commands.append((pitch, generator_torque if self.grid_connected else 0.0))  # as TurbineModel applies it
        self.k += 1
        return self.output(pitch)


def _run(entry: str, steps: int = 6):
    """Step the model ``steps`` times under one fault with the command pitch 0.1 + 0.01 k per blade, torque 4e4."""
    model, faults = _Model(), PlantFaults(parse_faults([entry], DT), 3, ACTUATOR)
    published = [faults.measure(0, model.output([0.1, 0.1, 0.1]))]
    for k in range(steps):
        published.append(faults.step(model, k, np.full(3, 0.1 + 0.01 * k), 4e4))
    return model, published


@pytest.mark.parametrize("entry, expected", [
    ("load_bias blade=2 moment=2e6 at=0.03", Fault("load_bias", 3, "load_bias blade=2 moment=2e6 at=0.03", 2, 2e6)),
    ("load_gain blade=1 factor=0.5 at=0", Fault("load_gain", 0, "load_gain blade=1 factor=0.5 at=0", 1, 0.5)),
    ("load_dead blade=3 at=20", Fault("load_dead", 2000, "load_dead blade=3 at=20", 3)),
    ("azimuth_offset angle=-0.2 at=1", Fault("azimuth_offset", 100, "azimuth_offset angle=-0.2 at=1", 0, -0.2)),
    ("pitch_runaway blade=1 to=fine at=30", Fault("pitch_runaway", 3000, "pitch_runaway blade=1 to=fine at=30", 1,
                                                  to="fine")),
    ("grid_loss  at=40", Fault("grid_loss", 4000, "grid_loss  at=40")),
])
def test_an_entry_names_the_fault_its_device_and_its_first_step(entry, expected):
    """Each kind's keys become the fault's fields; ``at`` [s] becomes the step at/dt."""
    assert parse_faults([entry, ""], DT) == (expected,)


@pytest.mark.parametrize("entries, message", [
    (["sensor_bias blade=2 at=1"], "entry 'sensor_bias blade=2 at=1': expected one of load_bias, "),
    (["load_bias blade=2 at=1"], "entry 'load_bias blade=2 at=1': moment missing"),
    (["load_dead blade=2 at=1 moment=3"], "load_dead takes blade, at, found 'moment'"),
    (["load_dead blade=2 at=-1"], "at: expected 0..1e+06, found -1"),
    (["load_dead blade=2 at=0.015"], "at: 0.015 s is not a whole number of steps of dt 0.01 s"),
    (["load_dead blade=0 at=1"], "blade: expected 1..1000, found 0"),
    (["load_dead blade=1.5 at=1"], "blade: expected a whole number"),
    (["load_gain blade=1 factor=nan at=1"], "factor: expected -100..100, found nan"),
    (["load_dead blade=1 at"], "expected key=value, found 'at'"),
    (["pitch_runaway blade=1 to=up at=1"], "to: expected feather or fine, found 'up'"),
    (["grid_loss at=1", "grid_loss at=2"], "entry 'grid_loss at=2': the same sensor or actuator as entry 'grid_loss "
                                           "at=1' (one fault each)"),
])
def test_a_bad_entry_is_refused_in_one_line_naming_it(entries, message):
    """ParameterError (the plant's parameter check refuses it before anything starts) naming faults and the entry."""
    with pytest.raises(ParameterError, match="^faults: ") as refused:
        parse_faults(entries, DT)
    assert message in str(refused.value) and "\n" not in str(refused.value)


def test_a_blade_the_rotor_does_not_have_is_refused_when_the_turbine_is_known():
    with pytest.raises(ParameterError, match=r"blade: expected 1..3, found 4 \(the rotor has 3 blades\)"):
        PlantFaults(parse_faults(["pitch_stuck blade=4 at=1"], DT), 3, ACTUATOR)


@pytest.mark.parametrize("entry, blade_2", [
    ("load_bias blade=2 moment=5e5 at=0.03", lambda k: 2e6 * k + 5e5),
    ("load_gain blade=2 factor=0.5 at=0.03", lambda k: 1e6 * k),
    ("load_frozen blade=2 at=0.03", lambda k: 2e6 * (START - 1)),
    ("load_dead blade=2 at=0.03", lambda k: math.nan),
])
def test_a_load_sensor_fault_changes_the_published_moment_of_its_blade_from_its_step_on(entry, blade_2):
    """Steps before the fault publish the truth; from the fault's step, blade 2's M_oop is biased, scaled, the reading
    of the step before, or NaN; the other blades, the azimuth and the commands are untouched."""
    model, published = _run(entry)
    for k, out in enumerate(published):
        truth = k * np.array([1e6, 2e6, 3e6])
        expected = truth if k < START else np.array([truth[0], blade_2(k), truth[2]])
        np.testing.assert_array_equal(out.root_moment_oop, expected, err_msg=f"step {k}")
        assert out.azimuth == 0.1 * k % (2 * math.pi)
    assert all(np.all(pitch == 0.1 + 0.01 * k) and torque == 4e4 for k, (pitch, torque) in enumerate(model.commands))


def test_an_azimuth_offset_shifts_the_published_azimuth_from_its_step_on_wrapped():
    _, published = _run("azimuth_offset angle=6.2 at=0.03")
    assert [out.azimuth for out in published] == [0.1 * k % (2 * math.pi) if k < START else
                                                  (0.1 * k + 6.2) % (2 * math.pi) for k in range(7)]


@pytest.mark.parametrize("entry, blade_1, torque", [
    ("pitch_stuck blade=1 at=0.03", lambda k: 0.1 + 0.01 * (START - 1), 4e4),
    ("pitch_runaway blade=1 to=feather at=0.03", lambda k: ACTUATOR.max_angle, 4e4),
    ("pitch_runaway blade=1 to=fine at=0.03", lambda k: ACTUATOR.min_angle, 4e4),
    ("grid_loss at=0.03", lambda k: 0.1 + 0.01 * k, 0.0),
])
def test_an_actuator_or_grid_fault_changes_the_command_the_physics_gets_from_its_step_on(entry, blade_1, torque):
    """The command over step k < 3 is the controllers'; from step 3 blade 1's actuator is driven to the angle it had
    at step 3 (stuck: here the command of step 2, which the model follows at once) or to its limit (runaway), or the
    generator is off the grid, its torque 0 (grid loss); the other blades get their commands; the published moments
    are the truth."""
    model, published = _run(entry)
    for k, (pitch, applied_torque) in enumerate(model.commands):
        commanded = 0.1 + 0.01 * k
        expected = [commanded if k < START else blade_1(k), commanded, commanded]
        np.testing.assert_array_equal(pitch, expected, err_msg=f"step {k}")
        assert applied_torque == (4e4 if k < START else torque)
    assert all(np.all(out.root_moment_oop == k * np.array([1e6, 2e6, 3e6])) for k, out in enumerate(published))


def test_without_faults_the_output_and_the_command_pass_through_as_the_same_objects():
    """A run without faults is the run it was: nothing is copied."""
    model, faults = _Model(), PlantFaults((), 3, ACTUATOR)
    first = model.output([0.1] * 3)
    pitch = np.full(3, 0.2)
    assert faults.measure(0, first) is first
    faults.step(model, 0, pitch, 4e4)
    assert model.commands[0][0] is pitch and model.commands[0][1] == 4e4


@pytest.mark.parametrize("entry, level, text", [
    ("load_dead blade=2 at=20", 30, "blade-root load sensor of blade 2 dead: M_oop NaN from step 2000 (t=20 s; faults "
                                    "entry 'load_dead blade=2 at=20')"),
    ("pitch_runaway blade=1 to=feather at=5", 40,
     "pitch actuator of blade 1 running away to feather (1.5708 rad) at its rate limit 0.139626 rad/s from step 500"),
    ("grid_loss at=40", 40, "grid loss: the generator off the grid, its torque 0 from step 4000"),
])
def test_a_fault_is_a_warning_for_a_sensor_and_an_error_for_an_actuator_or_the_grid(entry, level, text):
    (fault,) = parse_faults([entry], DT)
    assert PlantFaults((fault,), 3, ACTUATOR).starting(fault.step) == (fault,)
    found_level, kind, detail = fault_event(fault, DT, ACTUATOR)
    assert (found_level, kind) == (level, "fault") and detail.startswith(text)
