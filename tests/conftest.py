"""Test-suite isolation: this run's ROS graph is private to it.

A free ROS domain id is reserved for the whole run (``domain_coordinator`` holds
a port for it, so two runs on one machine take different ids) and discovery is
kept on this host. Every node the tests start, in this process or in child
processes, inherits both through the environment.
"""
import os
import sys
from pathlib import Path

import pytest

REPOSITORY = Path(__file__).resolve().parent.parent


def _reserve_domain():
    from domain_coordinator import domain_id

    reservation = domain_id()
    os.environ["ROS_DOMAIN_ID"] = str(reservation.__enter__())
    os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    return reservation


_DOMAIN = _reserve_domain()


def pytest_report_header(config):
    return f"ROS_DOMAIN_ID={os.environ['ROS_DOMAIN_ID']} (reserved for this run), discovery LOCALHOST"


def pytest_unconfigure(config):
    _DOMAIN.__exit__(None, None, None)


@pytest.fixture
def hawt_cli():
    """The command line that runs ``hawt`` in a child process with this environment."""
    return [sys.executable, "-m", "hawt_tools.cli"]
