"""The controller cores are plain numpy/scipy: importable without ROS, docstring examples hold."""

import doctest
import importlib
import os
import subprocess
import sys
from pathlib import Path

import pytest

CORES = [
    "hawt_controllers.collective",
    "hawt_controllers.exceptions",
    "hawt_controllers.filters",
    "hawt_controllers.ipc",
    "hawt_controllers.ipc_tuning",
    "hawt_controllers.limits",
    "hawt_controllers.mbc",
    "hawt_controllers.pi",
    "hawt_controllers.saturation",
]


def test_importing_the_cores_does_not_import_rclpy():
    """A fresh interpreter that imports every core has no rclpy module loaded."""
    package_root = Path(__file__).resolve().parents[2] / "hawt_controllers"
    code = f"import sys; import {', '.join(CORES)}; print('rclpy' in sys.modules)"
    env = dict(os.environ, PYTHONPATH=str(package_root))
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True)
    assert result.stdout.strip().splitlines()[-1] == "False"


@pytest.mark.parametrize(
    "name",
    ["hawt_controllers.collective", "hawt_controllers.ipc", "hawt_controllers.ipc_tuning", "hawt_controllers.mbc"],
)
def test_docstring_examples_hold(name):
    """The examples in the cores' docstrings run and give the printed results."""
    result = doctest.testmod(importlib.import_module(name))
    assert result.attempted > 0 and result.failed == 0
