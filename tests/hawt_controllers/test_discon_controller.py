"""hawt_controllers.plugins.discon: a DISCON library as a hawt controller — claims, parameters, activation and
the status sequence on the fake library of ``data/fake_discon.c``, and ROSCO holding the NREL 5 MW plant in
the in-process runner (``hawt run``); a library failing in the lockstep ROS graph."""
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from hawt_analysis.run_analysis import analyze_bag
from hawt_controllers.plugins.controller import CollectiveContribution, ControllerFailure
from hawt_controllers.plugins.discon import DisconController
from hawt_controllers.discon.rosco_input import read_settings, rosco_files
from hawt_core.parameter_table import ParameterError
from hawt_core.plant_description import PlantDescription
from hawt_plant.model import TurbineOutput
from hawt_plant.turbine import nrel_5mw
from hawt_tools.graph_file import find_graph
from hawt_tools.graph_file import load_graph
from hawt_tools.in_process import RunRecord, build_run
from hawt_tools.graph_file import package_prefix

FAKE_SOURCE = Path(__file__).parent / "data" / "fake_discon.c"
PLANT = PlantDescription("test", 0.01, 3, 1.2671, 5e6, 43093.55, 97.0, 0.0, 1.5708, 0.1396)


@pytest.fixture(scope="module")
def fake(tmp_path_factory) -> Path:
    library = tmp_path_factory.mktemp("fake") / "libfake_discon.so"
    subprocess.run(["gcc", "-shared", "-fPIC", "-O1", "-o", str(library), str(FAKE_SOURCE)], check=True)
    return library


def _values(fake: Path, directory: Path, fail_at: int = -1, **more) -> dict:
    infile = directory / "fake.in"
    infile.write_text(f"{directory / 'calls.log'} {fail_at}\n")
    return {"library": str(fake), "infile": str(infile), **more}


def _statuses(directory: Path) -> list:
    log = directory / "calls.log"
    return np.loadtxt(log, ndmin=2)[:, 0].tolist() if log.exists() else []


def _output(pitch=(0.1, 0.1, 0.1)) -> TurbineOutput:
    fields = {name: 0.0 for name in TurbineOutput.__dataclass_fields__}
    return TurbineOutput(**{**fields, "pitch": np.asarray(pitch), "root_moment_oop": np.zeros(3),
                            "root_moment_ip": np.zeros(3), "generator_speed": 120.0, "rotor_speed": 1.24,
                            "generator_torque": 40000.0})


def test_it_claims_collective_pitch_and_torque_and_blade_pitch_only_for_individual_pitch(fake, tmp_path):
    assert DisconController.claimed({"individual_pitch": False}) == ("collective_pitch", "generator_torque")
    assert DisconController.claimed({"individual_pitch": True}) == ("collective_pitch", "generator_torque",
                                                                    "blade_pitch")


def test_by_default_it_hosts_the_rosco_wheels_library_with_its_nrel_5mw_input(tmp_path):
    controller = DisconController({}, PLANT)
    library, infile = rosco_files()
    assert controller.library_path == library
    settings = read_settings(controller.infile)
    assert (settings["LoggingLevel"], settings["IPC_ControlMode"]) == ("0", "0")
    assert Path(settings["PerfFileName"].strip('"')).is_file()
    controller.close()


def test_the_ipc_parameters_go_into_the_private_rosco_input(tmp_path):
    controller = DisconController({"individual_pitch": True, "ipc_mode": 1, "ipc_integral_gain": [1e-8, 0.0],
                                   "ipc_azimuth_offset": [0.5236, 0.0]}, PLANT)
    settings = read_settings(controller.infile)
    assert (settings["IPC_ControlMode"], settings["IPC_KI"], settings["IPC_aziOffset"]) == ("1", "1e-08 0", "0.5236 0")


@pytest.mark.parametrize("values, message", [
    ({"library": "/nonexistent/libdiscon.so"}, r"library: /nonexistent/libdiscon.so: no such library file"),
    ({"infile": "/nonexistent/DISCON.IN"}, r"infile: /nonexistent/DISCON.IN: No such file"),
    ({"ipc_mode": 1}, r"ipc_mode: ROSCO's IPC commands each blade; set individual_pitch true"),
    ({"ipc_integral_gain": [1e-8]}, r"ipc_integral_gain: expected 2 values \(1P, 2P\), found 1"),
])
def test_bad_parameters_are_refused_before_the_run_in_one_line_naming_the_parameter(values, message):
    full = {"library": "", "infile": "", "individual_pitch": False, "ipc_mode": 0, "ipc_integral_gain": [0.0, 0.0],
            "ipc_azimuth_offset": [0.0, 0.0], **values}
    with pytest.raises(ParameterError, match=message):
        DisconController.check_values(full)


def test_ipc_parameters_for_a_library_that_is_not_rosco_are_refused(fake, tmp_path):
    with pytest.raises(ParameterError, match="ipc_mode, ipc_integral_gain, ipc_azimuth_offset: .* not a ROSCO"):
        DisconController(_values(fake, tmp_path, individual_pitch=True, ipc_mode=1), PLANT)


def test_a_library_without_discon_fails_configure_naming_the_library(tmp_path):
    other = tmp_path / "libother.so"
    subprocess.run(["gcc", "-shared", "-fPIC", "-DENTRY=OTHER", "-o", str(other), str(FAKE_SOURCE)], check=True)
    with pytest.raises(ParameterError, match="library: .*libother.so has no DISCON symbol"):
        DisconController(_values(other, tmp_path), PLANT)


def test_individual_demands_become_the_collective_and_blade_increments(fake, tmp_path):
    """The fake demands 0.01, 0.02, 0.03 rad: collective 0.02, increments -0.01, 0, 0.01; torque 12345 N*m."""
    controller = DisconController(_values(fake, tmp_path, individual_pitch=True), PLANT)
    controller.on_activate(None, (), None)
    collective, blades = controller.update(0, _output(), _output())
    assert collective.pitch == pytest.approx(0.02) and collective.generator_torque == 12345.0
    assert blades.increment == pytest.approx((-0.01, 0.0, 0.01), abs=1e-8)
    assert collective.pitch + np.asarray(blades.increment) == pytest.approx([0.01, 0.02, 0.03])


def test_collective_demands_come_from_record_45(fake, tmp_path):
    controller = DisconController(_values(fake, tmp_path), PLANT)
    controller.on_activate(None, (), None)
    (collective,) = controller.update(0, _output(), _output())
    assert collective.pitch == pytest.approx(0.05)


def test_inactive_it_does_not_call_the_library_and_an_activation_starts_a_fresh_one(fake, tmp_path):
    """Inactive: no call, the measured pitch and torque out (unpublished). Each activation: status 0 on a new copy,
    with the replaced controller's collective as every blade's measured pitch; a deactivation: status -1."""
    controller = DisconController(_values(fake, tmp_path), PLANT)
    (idle,) = controller.update(0, _output((0.1, 0.2, 0.3)), _output())
    assert (idle.pitch, idle.generator_torque) == (pytest.approx(0.2), 40000.0) and _statuses(tmp_path) == []
    for step in range(2):
        controller.on_activate(0.0, (CollectiveContribution(0.25, 41000.0),), None)
        controller.update(1, _output(), _output())
        controller.update(2, _output(), _output())
        controller.on_deactivate(0.0)
        controller.update(3, _output(), _output())
    calls = np.loadtxt(tmp_path / "calls.log", ndmin=2)
    assert calls[:, 0].tolist() == [0, 1, -1, 0, 1, -1]
    assert calls[0, [3, 32, 33]] == pytest.approx([0.25] * 3)  # records 4, 33, 34 of the first call
    assert calls[1, [3, 32, 33]] == pytest.approx([0.1] * 3)


def test_a_failing_library_is_a_controller_failure_with_its_message(fake, tmp_path):
    controller = DisconController(_values(fake, tmp_path, fail_at=0), PLANT)
    controller.on_activate(None, (), None)
    with pytest.raises(ControllerFailure, match="fake failure"):
        controller.update(0, _output(), _output())


@pytest.fixture(scope="module")
def settled():
    """``settled(graph, wind_speed, seconds)``: ``hawt run GRAPH`` in steady wind for ``seconds``; the plant's
    description and its outputs of the last 20 s. Each run once a module (ROSCO at 18 m/s serves two tests)."""
    runs = {}

    def run(graph: str, wind_speed: float, seconds: float):
        if (graph, wind_speed, seconds) not in runs:
            built = build_run(load_graph(find_graph(graph), {"wind_speed": str(wind_speed), "duration": str(seconds)},
                                         package_prefix))
            outputs = []
            for _ in range(round(seconds / built.description.dt)):
                built.step()
                outputs.append(built.output)
            runs[graph, wind_speed, seconds] = built.description, outputs[-2000:]
        return runs[graph, wind_speed, seconds]
    return run


@pytest.mark.parametrize("wind_speed", [14.0, 18.0, 22.0])
def test_rosco_holds_rated_speed_and_power_in_steady_wind_above_rated(settled, wind_speed):
    """Region 3: the last 20 s of 60 s at rated rotor speed (within 0.5 %) and rated power (within 0.5 %)."""
    description, last = settled("rosco", wind_speed, 60.0)
    speed = np.mean([o.rotor_speed for o in last])
    power = np.mean([o.electrical_power for o in last])
    assert speed == pytest.approx(description.rated_rotor_speed, rel=0.005)
    assert power == pytest.approx(description.rated_power, rel=0.005)


@pytest.mark.parametrize("wind_speed", [6.0, 8.0])
def test_rosco_tracks_its_optimal_tip_speed_ratio_in_steady_wind_below_rated(settled, wind_speed):
    """Region 2: fine pitch, and the tip-speed ratio within 2 % of DISCON.IN's VS_TSRopt (ROSCO tracks it on its
    wind-speed estimate, whose Cp surface is not this plant's)."""
    _, last = settled("rosco", wind_speed, 90.0)
    tip_speed_ratio = np.mean([o.rotor_speed for o in last]) * 63.0 / wind_speed
    assert tip_speed_ratio == pytest.approx(float(read_settings(rosco_files()[1])["VS_TSRopt"]), rel=0.02)
    assert max(max(o.pitch) for o in last) < math.radians(0.5)


def test_rosco_ipc_takes_the_1p_out_of_the_blade_root_moments(settled):
    """Steady sheared wind at 18 m/s: ROSCO's IPC cuts the blade-root moment's swing to under a third of ROSCO's
    collective control's: the azimuth and Coleman conventions agree (a wrong azimuth would not)."""
    swings = [np.ptp([o.root_moment_oop[0] for o in settled(graph, 18.0, 60.0)[1]]) for graph in ("rosco", "rosco_ipc")]
    assert swings[1] < swings[0] / 3


def test_a_switch_from_rosco_to_cpc_and_ipc_and_back_starts_each_collective_where_the_other_left_it():
    """Turbulence, switches at steps 800 and 1400: the incoming collective pitch starts within 0.01 deg of the
    outgoing one's last, the torque within 1 % of rated (ROSCO restarts its torque from its own law on its own filtered
    generator speed, 0.64 % below cpc's last command here; cpc starts from ROSCO's last command), and the run stays
    within 10 % of rated speed."""
    run = build_run(load_graph(find_graph("rosco_ipc"), {
        "wind_speed": "18.0", "duration": "20", "wind_type": "turbulent", "seed": "2",
        "schedule": "['800 +cpc +ipc_h1 +ipc_h2 -rosco', '1400 +rosco -cpc -ipc_h1 -ipc_h2']"}, package_prefix))
    record, speed = RunRecord(), []
    for _ in range(2000):
        run.step(record)
        speed.append(run.output.rotor_speed)
    assert [e["kind"] for e in run.events] == ["switch", "switch"]
    collective = record.rows["control/collective"]
    for step in (800, 1400):
        before, after = collective[step - 1], collective[step]
        assert math.degrees(abs(after["pitch"] - before["pitch"])) < 0.01
        rated_torque = run.description.rated_generator_torque
        assert abs(after["generator_torque"] - before["generator_torque"]) < 0.01 * rated_torque
    assert np.abs(np.asarray(speed) / run.description.rated_rotor_speed - 1).max() < 0.1


CAMPAIGN = """\
wind: {{speeds: [12], seeds: [1]}}
duration: 10
controllers:
  rosco: {{graph: rosco, parameters: ["rosco.library:={library}"]}}
"""


def _engine_command(engine: str, library: Path, directory: Path) -> list:
    """``hawt run``, ``hawt launch`` (recording into directory/out) or ``hawt campaign`` (into directory/out) of
    the rosco graph with ``library`` as its DISCON library."""
    if engine == "campaign":
        campaign = directory / "campaign.yaml"
        campaign.write_text(CAMPAIGN.format(library=library))
        return ["campaign", str(campaign), "-o", str(directory / "out")]
    return [engine, "rosco", "-p", f"rosco.library:={library}", "--record", str(directory / "out")]


@pytest.mark.parametrize("engine", ["run", "launch", "campaign"])
@pytest.mark.parametrize("kind, reason", [
    ("text", "is not a shared library (no ELF header)"),
    ("no DISCON", "has no DISCON symbol"),
    ("missing", ": no such library file"),
])
def test_a_library_that_cannot_be_discon_is_refused_by_every_engine_before_anything_starts(
        hawt_cli, tmp_path, engine, kind, reason):
    """A text file, a shared library exporting OTHER instead of DISCON, no file: exit 2, one line naming the
    parameter, the file and what is wrong; nothing printed or written before it (no bag, no campaign folder)."""
    library = {"text": tmp_path / "libtext.so", "no DISCON": tmp_path / "libother.so",
               "missing": tmp_path / "libmissing.so"}[kind]
    if kind == "text":
        library.write_text("not a library\n")
    elif kind == "no DISCON":
        subprocess.run(["gcc", "-shared", "-fPIC", "-DENTRY=OTHER", "-o", str(library), str(FAKE_SOURCE)], check=True)
    result = subprocess.run([*hawt_cli, *_engine_command(engine, library, tmp_path)], capture_output=True,
                            text=True, timeout=120)
    assert result.returncode == 2, result.stdout[-2000:] + result.stderr[-2000:]
    assert result.stderr.startswith(f"hawt {engine}: ") and len(result.stderr.strip().splitlines()) == 1
    assert f"rosco.library: {library}{'' if reason.startswith(':') else ' '}{reason}" in result.stderr
    assert result.stdout == "" and not (tmp_path / "out").exists()


def test_importing_the_core_does_not_import_rclpy():
    code = "import sys, hawt_controllers.plugins.discon; print('rclpy' in sys.modules)"
    assert subprocess.run([sys.executable, "-c", code], capture_output=True, text=True).stdout.strip() == "False"


FAIL_AT = 200


@pytest.mark.ros
def test_a_library_failing_in_the_lockstep_graph_is_reported_and_the_safety_system_feathers(fake, tmp_path,
                                                                                             hawt_cli):
    infile = tmp_path / "fake.in"
    infile.write_text(f"{tmp_path / 'calls.log'} {FAIL_AT}\n")
    bag = tmp_path / "failing.mcap"
    result = subprocess.run([*hawt_cli, "launch", "rosco", "duration:=8", "-p", f"rosco.library:={fake}",
                             "-p", f"rosco.infile:={infile}", "--record", str(bag)],
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    analysis = analyze_bag(bag)
    events = {(e["step"], e["source"].rsplit("/", 1)[-1], e["kind"]): e for e in analysis.run.events}
    failed = events[(FAIL_AT, "rosco", "controller_failed")]
    assert "fake failure" in failed["detail"]
    assert (FAIL_AT, "plant", "watchdog") in events and (800, "plant", "finished") in events
    channels = analysis.run.channels
    after = channels["time"] > channels["time"][-1] - 1.0
    assert np.all(channels["generator_torque"][after] == 0.0), "generator torque off once tripped"
    assert np.all(np.diff(channels["pitch"][channels["time"] > FAIL_AT * 0.01], axis=0) >= -1e-12), \
        "pitch only moves towards feather after the failure"
    assert channels["pitch"].max() <= math.pi / 2 + 1e-9
    command = analysis.run.pitch_command
    assert np.all(np.isfinite(command["pitch"])) and command["pitch"].max() <= math.pi / 2 + 1e-9


@pytest.mark.ros
def test_rosco_holds_the_plant_in_the_realtime_graph(tmp_path, hawt_cli):
    """mode:=realtime (the plant steps on the wall clock and nobody waits): steady 18 m/s, 15 s; ROSCO's collective
    commands reach the plant and hold it within 2 % of rated rotor speed and power over the last 5 s."""
    bag = tmp_path / "realtime.mcap"
    result = subprocess.run([*hawt_cli, "launch", "rosco", "mode:=realtime", "wind_speed:=18.0", "duration:=15",
                             "--record", str(bag)], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    analysis = analyze_bag(bag)
    assert not [e for e in analysis.run.events if e["kind"] in ("watchdog", "controller_failed")]
    channels = analysis.run.channels
    last = channels["time"] > channels["time"][-1] - 5.0
    assert last.sum() > 100
    turbine = nrel_5mw().description(0.01)
    assert np.mean(channels["rotor_speed"][last]) == pytest.approx(turbine.rated_rotor_speed, rel=0.02)
    assert np.mean(channels["electrical_power"][last]) == pytest.approx(turbine.rated_power, rel=0.02)
