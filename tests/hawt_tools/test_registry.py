"""Controllers found by type: a controller that is one module and one entry point, outside the repository, runs with
one graph entry on every engine (hawt launch, --composed, hawt run, a campaign), and a type nobody registered is
refused before anything starts."""
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from hawt_bag.reader import BagReader
from hawt_bag.topic_columns import read_topic_columns

pytestmark = pytest.mark.ros

MODULE = '''"""A constant pitch offset per blade on ``blade_pitch``: a controller written outside hawt."""
from hawt_controllers.plugins.controller import BladeContribution, Controller
from hawt_core.command_interfaces import BLADE_PITCH
from hawt_core.parameter_table import ParameterSpec


class PitchOffsetController(Controller):
    TYPE = "pitch_offset"
    PARAMETERS = (ParameterSpec("offset", 0.01, "pitch added to every blade", "rad", minimum=-0.1, maximum=0.1),)

    @classmethod
    def claimed(cls, values):
        return (BLADE_PITCH,)

    def update(self, step, loads, state=None):
        return (BladeContribution((self.values["offset"],) * self.plant.blades),)
'''

GRAPH = """launch:
- node: {pkg: hawt_plant, exec: plant, name: plant, namespace: wt1, on_exit: shutdown,
         param: [{name: duration, value: 1.0}, {name: wind_speed, value: 14.0}]}
- node: {pkg: hawt_controllers, exec: cpc, name: cpc, namespace: wt1}
- node: {pkg: hawt_controllers, exec: mbc, name: mbc, namespace: wt1}
- node: {pkg: hawt_controllers, exec: controller, name: offset, namespace: wt1,
         param: [{name: type, value: pitch_offset}, {name: offset, value: 0.02}]}
"""


@pytest.fixture
def outside(tmp_path: Path) -> dict:
    """A folder holding the module and its distribution's entry point, on PYTHONPATH of the processes started."""
    (tmp_path / "pitch_offset_controller.py").write_text(MODULE)
    info = tmp_path / "pitch_offset_controller-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: pitch-offset-controller\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text("[hawt.controllers]\npitch_offset = pitch_offset_controller:"
                                           "PitchOffsetController\n")
    (tmp_path / "graph.yaml").write_text(GRAPH)
    return {**os.environ, "PYTHONPATH": f"{tmp_path}{os.pathsep}{os.environ.get('PYTHONPATH', '')}"}


def _hawt(arguments, env, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "hawt_tools.cli", *arguments], env=env, cwd=cwd,
                          capture_output=True, text=True, timeout=600)


def _columns(path: Path, topic: str, *names: str) -> dict:
    """The fields of each step's first message on ``topic`` (a lockstep step answered again is in a bag twice)."""
    with BagReader(path) as reader:
        fields = read_topic_columns(reader, f"/wt1/{topic}", ("step", *names)).fields
    _, first = np.unique(fields["step"], return_index=True)
    return {name: fields[name][first] for name in ("step", *names)}


def test_a_controller_from_outside_runs_on_every_engine_through_its_entry_point(outside, tmp_path: Path):
    """The outside controller's offset reaches every blade's command; the lockstep graph's commands, in processes
    and composed, equal hawt run's bit for bit; a campaign runs it."""
    for arguments in (["run", "graph.yaml", "--record", "run.mcap"],
                      ["launch", "graph.yaml", "--record", "launch.mcap"],
                      ["launch", "graph.yaml", "--composed", "--record", "composed.mcap"]):
        result = _hawt(arguments, outside, tmp_path)
        assert result.returncode == 0, (result.stderr + result.stdout)[-3000:]
    commands = [_columns(tmp_path / name, "control/pitch_command", "pitch", "collective")
                for name in ("run.mcap", "launch.mcap", "composed.mcap")]
    for other in commands[1:]:
        for name in ("step", "pitch", "collective"):
            np.testing.assert_array_equal(commands[0][name], other[name])
    increments = _columns(tmp_path / "run.mcap", "control/blade_pitch", "increment")["increment"]
    assert len(increments) == 100 and np.all(increments == 0.02)
    settled = commands[0]["pitch"][50:] - commands[0]["collective"][50:, None]
    np.testing.assert_allclose(settled, 0.02, atol=1e-12)  # unsaturated at 14 m/s: the offset is added as is
    (tmp_path / "campaign.yaml").write_text("wind: {speeds: [14], seeds: [1]}\nduration: 10\ntransient: 1\n"
                                            "controllers:\n  offset: {graph: graph.yaml}\n")
    campaign = _hawt(["campaign", "campaign.yaml", "-o", "campaign", "--workers", "1"], outside, tmp_path)
    assert campaign.returncode == 0, (campaign.stderr + campaign.stdout)[-3000:]
    rows = (tmp_path / "campaign" / "cases.csv").read_text().splitlines()
    assert len(rows) == 2 and rows[1].startswith("offset,14.0,1,")


def test_a_type_nobody_registered_is_refused_before_anything_starts(tmp_path: Path):
    (tmp_path / "graph.yaml").write_text(GRAPH.replace("value: pitch_offset", "value: pitch_ofset"))
    result = _hawt(["run", "graph.yaml"], dict(os.environ), tmp_path)
    assert result.returncode == 2
    assert result.stderr.strip().splitlines()[-1].endswith(
        "node 'offset': type: no controller type 'pitch_ofset'; registered (hawt.controllers entry points): "
        "blade_sine, coleman_excitation, cpc, discon, ipc, lqg_ipc, main_bearing_ipc, repetitive_cpc, repetitive_ipc")
