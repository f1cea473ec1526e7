"""Step-by-step replay of a lockstep run's plant topics through the same controllers gives the same commands."""
import signal
import subprocess

import numpy as np
import pytest

from hawt_bag.reader import BagReader
from hawt_bag.topic_columns import read_topic_columns

pytestmark = pytest.mark.ros


def _commands(path) -> dict:
    """One command per step (a step the plant sent again after resend_period is answered again, identically)."""
    with BagReader(path) as reader:
        fields = read_topic_columns(reader, "/rp/control/pitch_command").fields
    _, first = np.unique(np.asarray(fields["step"]), return_index=True)
    return {name: np.asarray(values)[first] for name, values in fields.items()}


def test_replaying_plant_topics_through_cpc_and_mbc_reproduces_every_pitch_command_bit_for_bit(hawt_cli, tmp_path):
    """Record baseline (plant, cpc, mbc); replay its plant topics through a fresh cpc + mbc; commands are equal."""
    run, replayed = tmp_path / "run.mcap", tmp_path / "replayed.mcap"
    result = subprocess.run([*hawt_cli, "launch", "baseline", "namespace:=rp", "duration:=3", "shear_exponent:=0.2",
                             "--record", str(run), "-p", "plant.wait_for_subscribers:=3"],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    controllers = subprocess.Popen([*hawt_cli, "launch", "controllers", "namespace:=rp", "--record", str(replayed)],
                                   stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        for line in controllers.stdout:  # the recorder must be on the command topic before the first step
            if "recording /rp/control/pitch_command" in line:
                break
        replay = subprocess.run([*hawt_cli, "replay", str(run), "--topics", "/rp/plant/blade_loads",
                                 "/rp/plant/state", "--step-trigger", "/rp/control/pitch_command",
                                 "--wait-timeout", "30"], capture_output=True, text=True, timeout=120)
        assert replay.returncode == 0, replay.stderr
    finally:
        controllers.send_signal(signal.SIGINT)
        controllers.communicate(timeout=60)
    recorded, reproduced = _commands(run), _commands(replayed)
    assert len(recorded["step"]) == 300
    assert np.array_equal(reproduced["step"], recorded["step"])
    for field in ("pitch", "generator_torque", "collective", "individual", "flags"):
        assert np.array_equal(reproduced[field], recorded[field]), field
