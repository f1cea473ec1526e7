"""The docstring examples of the controller cores and of hawt_core hold (that cores import no rclpy: tests/test_layering.py)."""

import doctest
import importlib

import pytest


@pytest.mark.parametrize(
    "name",
    ["hawt_controllers.laws.collective", "hawt_controllers.laws.ipc", "hawt_controllers.laws.ipc_tuning", "hawt_core.rotor.mbc",
     "hawt_controllers.plugins.loop_assembly", "hawt_core.arrays"],
)
def test_docstring_examples_hold(name):
    """The examples in the cores' docstrings run and give the printed results."""
    result = doctest.testmod(importlib.import_module(name))
    assert result.attempted > 0 and result.failed == 0
