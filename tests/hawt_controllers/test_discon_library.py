"""hawt_controllers.discon.library: the Bladed DISCON interface through ctypes, specified on a fake library built
here from ``data/fake_discon.c`` (it logs the records it receives and returns fixed demands) and on ROSCO."""
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from hawt_controllers.discon.library import (DisconDemands, DisconFailure, DisconInputs, DisconLibrary,
                                             DisconLoadError, Record, check_library)
from hawt_controllers.discon.rosco_input import read_settings, rosco_files, write_private_input

FAKE_SOURCE = Path(__file__).parent / "data" / "fake_discon.c"
LIMITS = (0.0, 1.5708, 0.1396)
INPUTS = DisconInputs(time=1.25, pitch=[0.11, 0.12, 0.13], generator_speed=120.5, rotor_speed=1.24,
                      generator_torque=41000.0, electrical_power=4.9e6, shaft_power=5.2e6, hub_wind_speed=17.5,
                      root_moment_oop=[6.1e6, 5.2e6, 4.3e6], root_moment_ip=[1.1e6, -0.2e6, -0.9e6], azimuth=2.5,
                      tower_top_fa_accel=0.031, tower_top_ss_accel=-0.012, hub_tilt_moment=1.5e6,
                      hub_yaw_moment=-0.7e6)


def _build(directory: Path, name: str, entry: str = "DISCON") -> Path:
    library = directory / name
    subprocess.run(["gcc", "-shared", "-fPIC", "-O1", f"-DENTRY={entry}", "-o", str(library), str(FAKE_SOURCE)],
                   check=True)
    return library


@pytest.fixture(scope="module")
def fake(tmp_path_factory) -> Path:
    return _build(tmp_path_factory.mktemp("fake"), "libfake_discon.so")


def _infile(directory: Path, fail_at: int = -1) -> Path:
    path = directory / "fake.in"
    path.write_text(f"{directory / 'calls.log'} {fail_at}\n")
    return path


def _logged(directory: Path) -> np.ndarray:
    """Records 1..130 of every call (one row per call; column r - 1 is record r)."""
    return np.loadtxt(directory / "calls.log", ndmin=2)


def test_each_measurement_goes_to_its_record_of_the_bladed_interface(fake, tmp_path):
    """Time, dt, pitches, speeds, torque, powers, wind, moments, azimuth, accelerations: float32 at their records."""
    library = DisconLibrary(fake, _infile(tmp_path), 3, 0.01, LIMITS, individual_pitch=True)
    library.step(INPUTS)
    row = _logged(tmp_path)[0]
    expected = {Record.STATUS: 0, Record.TIME: 1.25, Record.DT: 0.01, Record.PITCH_1: 0.11, Record.PITCH_2: 0.12,
                Record.PITCH_3: 0.13, Record.MIN_PITCH: 0.0, Record.MAX_PITCH: 1.5708, Record.MIN_PITCH_RATE: -0.1396,
                Record.MAX_PITCH_RATE: 0.1396, Record.SHAFT_POWER: 5.2e6, Record.ELECTRICAL_POWER: 4.9e6,
                Record.GENERATOR_SPEED: 120.5, Record.ROTOR_SPEED: 1.24, Record.GENERATOR_TORQUE: 41000.0,
                Record.HUB_WIND_SPEED: 17.5, Record.PITCH_CONTROL: 1, Record.ROOT_MOOP_1: 6.1e6, 31: 5.2e6,
                32: 4.3e6, Record.ROOT_MIP_1: 1.1e6, 70: -0.2e6, 71: -0.9e6, Record.AZIMUTH: 2.5, Record.BLADES: 3,
                Record.TOWER_TOP_FA_ACCEL: 0.031, Record.TOWER_TOP_SS_ACCEL: -0.012, Record.HUB_TILT_MOMENT: 1.5e6,
                Record.HUB_YAW_MOMENT: -0.7e6, Record.GENERATOR_CONTACTOR: 1, Record.SWAP_SIZE: 2048,
                Record.MESSAGE_SIZE: 1024, Record.INFILE_SIZE: len(str(tmp_path / "fake.in")) + 1}
    for record, value in expected.items():
        assert np.float32(row[record - 1]) == np.float32(value), f"record {int(record)}"


def test_the_demands_are_read_back_from_records_42_to_47_and_55(fake, tmp_path):
    """Per-blade pitch 42-44, collective 45, torque 47, pitch override 55, as the library wrote them (float32)."""
    demands = DisconLibrary(fake, _infile(tmp_path), 3, 0.01, LIMITS).step(INPUTS)
    assert demands == DisconDemands(tuple(float(np.float32(v)) for v in (0.01, 0.02, 0.03)),
                                    float(np.float32(0.05)), 12345.0, 0, 0)


def test_status_is_0_on_the_first_call_then_1_and_minus_1_on_the_last(fake, tmp_path):
    """Bladed's status sequence: 0 first, 1 running, -1 at close (with the last inputs); none after close."""
    library = DisconLibrary(fake, _infile(tmp_path), 3, 0.01, LIMITS)
    for _ in range(3):
        library.step(INPUTS)
    library.close()
    library.close()
    calls = _logged(tmp_path)
    assert calls[:, 0].tolist() == [0, 1, 1, -1]
    assert np.float32(calls[-1, Record.TIME - 1]) == np.float32(INPUTS.time)
    with pytest.raises(DisconFailure, match="after its last call"):
        library.step(INPUTS)


def test_an_instance_that_never_ran_makes_no_last_call(fake, tmp_path):
    DisconLibrary(fake, _infile(tmp_path), 3, 0.01, LIMITS).close()
    assert not (tmp_path / "calls.log").exists()


def test_two_instances_in_one_process_each_run_their_own_copy_of_the_library(fake, tmp_path):
    """The fake refuses a second first call in one loaded image, as ROSCO does: each instance loads a copy."""
    first, second = (DisconLibrary(fake, _infile(tmp_path), 3, 0.01, LIMITS) for _ in range(2))
    first.step(INPUTS)
    second.step(INPUTS)
    first.step(INPUTS)
    assert _logged(tmp_path)[:, 0].tolist() == [0, 0, 1]


def test_the_private_copy_is_removed_on_close(fake, tmp_path):
    library = DisconLibrary(fake, _infile(tmp_path), 3, 0.01, LIMITS)
    folder = library._image.directory
    assert folder.is_dir()
    library.close()
    assert not folder.exists()


def test_a_failure_raises_with_the_library_message_and_stops_the_instance(fake, tmp_path):
    """aviFAIL < 0: DisconFailure with avcMSG; no more calls, not even the last one."""
    library = DisconLibrary(fake, _infile(tmp_path, fail_at=1), 3, 0.01, LIMITS)
    library.step(INPUTS)
    with pytest.raises(DisconFailure, match=r"libfake_discon.so failed at t = 1.25 s: fake failure"):
        library.step(INPUTS)
    with pytest.raises(DisconFailure, match="stopped after its failure: fake failure"):
        library.step(INPUTS)
    library.close()
    assert _logged(tmp_path)[:, 0].tolist() == [0, 1]


def test_a_missing_library_is_a_one_line_load_error(tmp_path):
    with pytest.raises(DisconLoadError, match=r"nothing.so: no such library file"):
        DisconLibrary(tmp_path / "nothing.so", _infile(tmp_path), 3, 0.01, LIMITS)


def test_a_library_without_the_discon_symbol_is_a_load_error(tmp_path):
    library = _build(tmp_path, "libother.so", entry="OTHER")
    with pytest.raises(DisconLoadError, match=r"libother.so has no DISCON symbol"):
        DisconLibrary(library, _infile(tmp_path), 3, 0.01, LIMITS)


def test_a_file_that_is_no_library_is_a_load_error(tmp_path):
    (tmp_path / "libtext.so").write_text("not a library")
    with pytest.raises(DisconLoadError, match=r"libtext.so is not a shared library \(no ELF header\)$"):
        DisconLibrary(tmp_path / "libtext.so", _infile(tmp_path), 3, 0.01, LIMITS)


def test_rosco_passes_the_library_check():
    check_library(rosco_files()[0])


def test_a_folder_is_no_library(tmp_path):
    with pytest.raises(DisconLoadError, match=r"is not a regular file$"):
        check_library(tmp_path)


def test_an_object_file_is_no_shared_library(tmp_path):
    subprocess.run(["gcc", "-c", "-fPIC", "-o", str(tmp_path / "fake.o"), str(FAKE_SOURCE)], check=True)
    with pytest.raises(DisconLoadError, match=r"fake.o is not a shared library \(ELF type 1: a relocatable object, "
                                              r"not a shared object\)$"):
        check_library(tmp_path / "fake.o")


def test_a_library_of_another_architecture_is_refused_before_it_is_loaded(fake, tmp_path):
    """The fake with its ELF header's e_machine (bytes 18-19, this machine's byte order) made SPARC's, 2."""
    image = bytearray(fake.read_bytes())
    image[18:20] = (2).to_bytes(2, sys.byteorder)
    (tmp_path / "libsparc.so").write_bytes(bytes(image))
    with pytest.raises(DisconLoadError, match=r"libsparc.so is built for another machine \(64-bit [a-z]+-endian, "
                                              r"ELF machine 2; this \w+ machine is 64-bit [a-z]+-endian, ELF "
                                              r"machine \d+\)$"):
        check_library(tmp_path / "libsparc.so")


def test_a_library_whose_dependency_is_missing_is_refused_naming_the_dependency(tmp_path):
    """Linked against libgone.so, which is then removed: the loader's own reason, before any call."""
    subprocess.run(["gcc", "-shared", "-fPIC", "-o", str(tmp_path / "libgone.so"), "-x", "c", "/dev/null"],
                   check=True)
    library = tmp_path / "libneeds.so"
    subprocess.run(["gcc", "-shared", "-fPIC", "-o", str(library), str(FAKE_SOURCE), f"-L{tmp_path}",
                    "-Wl,--no-as-needed", "-lgone"], check=True)
    (tmp_path / "libgone.so").unlink()
    with pytest.raises(DisconLoadError, match=r"libneeds.so: cannot load: .*libgone.so: cannot open shared object"):
        check_library(library)


def test_an_unreadable_input_file_is_a_load_error(fake, tmp_path):
    with pytest.raises(DisconLoadError, match=r"missing.in: cannot read the input file"):
        DisconLibrary(fake, tmp_path / "missing.in", 3, 0.01, LIMITS)


def test_more_blades_than_the_interface_carries_are_refused(fake, tmp_path):
    with pytest.raises(DisconLoadError, match="1 to 3 blades, found 4"):
        DisconLibrary(fake, _infile(tmp_path), 4, 0.01, LIMITS)


def test_inputs_of_another_length_than_b_are_refused(fake, tmp_path):
    library = DisconLibrary(fake, _infile(tmp_path), 3, 0.01, LIMITS)
    with pytest.raises(ValueError, match="pitch: expected length B=3, found 2"):
        library.step(DisconInputs(**{**INPUTS.__dict__, "pitch": [0.1, 0.1]}))


def test_a_private_rosco_input_has_absolute_paths_and_the_settings_asked_for(tmp_path):
    """ROSCO reads PerfFileName relative to DISCON.IN's folder: the private copy names it absolutely."""
    _, infile = rosco_files()
    written = read_settings(write_private_input(infile, tmp_path / "DISCON.IN", {"IPC_ControlMode": "1",
                                                                                 "IPC_KI": "1e-08 0"}))
    original = read_settings(infile)
    assert Path(written["PerfFileName"].strip('"')) == infile.parent / original["PerfFileName"].strip('"')
    assert (written["IPC_ControlMode"], written["IPC_KI"]) == ("1", "1e-08 0")
    assert {k: v for k, v in written.items() if k not in ("PerfFileName", "IPC_ControlMode", "IPC_KI")} \
        == {k: v for k, v in original.items() if k not in ("PerfFileName", "IPC_ControlMode", "IPC_KI")}
    with pytest.raises(KeyError, match="no setting IPC_Gain"):
        write_private_input(infile, tmp_path / "other.IN", {"IPC_Gain": "1"})


def test_two_rosco_instances_run_side_by_side_and_start_from_the_measured_pitch(tmp_path):
    """ROSCO refuses a second start in one image; two instances each start, at the pitch they are given."""
    library, infile = rosco_files()
    private = write_private_input(infile, tmp_path / "DISCON.IN", {"LoggingLevel": "0"})
    first, second = (DisconLibrary(library, private, 3, 0.01, LIMITS) for _ in range(2))
    for instance, pitch in ((first, 0.20), (second, 0.25)):
        demands = instance.step(DisconInputs(**{**INPUTS.__dict__, "pitch": [pitch] * 3}))
        assert demands.collective == pytest.approx(pitch, abs=1e-6)
        assert demands.pitch_override == 0
    first.close()
    second.close()
