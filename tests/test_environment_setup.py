"""What ./hawt's set-up keeps between commands to start quickly (scripts/env.sh, scripts/setup.sh): the same
environment and the same compiled kernels as asking colcon and Python every time."""
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PATHS = ("AMENT_PREFIX_PATH", "CMAKE_PREFIX_PATH", "COLCON_PREFIX_PATH", "LD_LIBRARY_PATH", "PYTHONPATH")
pytestmark = pytest.mark.processes


def environment_of(command: str, values: dict) -> dict:
    """The path variables after ``command`` in bash, from a plain login's environment plus ``values``."""
    listing = "; ".join(f'echo "{name}=${{{name}:-}}"' for name in PATHS)
    done = subprocess.run(["bash", "-c", f"set -eo pipefail; {command}; {listing}"], cwd=ROOT, check=True,
                          capture_output=True, text=True,
                          env={"HOME": os.environ["HOME"], "PATH": "/usr/bin:/bin", **values})
    return dict(line.split("=", 1) for line in done.stdout.splitlines())


def test_env_sh_sets_the_paths_colcons_setup_sets_from_its_memo_as_without_it(tmp_path):
    """A user's own PYTHONPATH (here one no run has seen, so the first source asks colcon) stays on the path."""
    own = {"PYTHONPATH": str(tmp_path)}
    asked = environment_of("source scripts/env.sh", own)
    kept = environment_of("source scripts/env.sh", own)
    assert kept == asked
    assert str(tmp_path) in asked["PYTHONPATH"].split(":")
    assert str(ROOT / "ros2_ws" / "install" / "hawt_plant") in asked["AMENT_PREFIX_PATH"].split(":")
    colcon = environment_of("source ros2_ws/install/setup.bash", own)
    assert all(colcon[name] in asked[name] for name in PATHS)


def test_setup_names_the_kernel_folder_python_names():
    """scripts/setup.sh keeps the folder of the compiled kernels beside the sources' sizes and times; the folder it
    kept is the one hawt_plant.kernel_cache gives for the sources' content."""
    subprocess.run(["bash", str(ROOT / "scripts" / "setup.sh")], check=True, capture_output=True)
    kept = (ROOT / "ros2_ws" / ".hawt-kernels").read_text().splitlines()[-1]
    asked = subprocess.run([str(ROOT / ".venv" / "bin" / "python"), "-m", "hawt_plant.kernel_cache"], check=True,
                           capture_output=True, text=True,
                           env={**os.environ, "PYTHONPATH": f"{ROOT / 'hawt_plant'}:{ROOT / 'hawt_core'}"})
    assert kept == asked.stdout.strip()
    assert (Path(kept) / ".hawt-complete").is_file()


def test_setup_with_nothing_changed_stops_at_the_digest_the_completed_steps_kept():
    """scripts/setup.sh keeps one digest of everything its steps read when they all complete; a digest that differs
    (here one made stale by hand) sends it through the steps, which find nothing to do and keep the same digest."""
    stamp = ROOT / "ros2_ws" / ".hawt-setup"
    subprocess.run(["bash", str(ROOT / "scripts" / "setup.sh")], check=True, capture_output=True)
    kept = stamp.read_text()
    stamp.write_text("stale\n")
    done = subprocess.run(["bash", str(ROOT / "scripts" / "setup.sh")], check=True, capture_output=True, text=True)
    assert stamp.read_text() == kept
    assert done.stderr == ""  # every step found its own part done
