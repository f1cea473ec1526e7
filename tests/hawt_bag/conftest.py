"""Fixtures of the bag tests: child processes of ``hawt`` and a probe node that watches the graph."""
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ros_helpers import Probe, Processes  # noqa: E402


@pytest.fixture
def processes(hawt_cli):
    """Start child processes (``processes.hawt(...)``); whatever still runs is killed after the test."""
    children = Processes(hawt_cli)
    yield children
    children.close()


@pytest.fixture
def probe():
    """A node of this test process watching the graph."""
    node = Probe()
    yield node
    node.close()
