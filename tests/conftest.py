"""Test-suite isolation: this run's ROS graph is private to it.

A free ROS domain id is reserved for the whole run (``domain_coordinator`` holds
a port for it, so two runs on one machine take different ids) and discovery is
kept on this host. Every node the tests start, in this process or in child
processes, inherits both through the environment.
"""
import importlib.metadata
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


@pytest.fixture(scope="session")
def rosco_case():
    """The locator of ROSCO's test cases in the installed rosco wheel: a path relative to ``Examples/Test_Cases``
    -> that file or folder (found through the distribution's files)."""
    def case(relative: str) -> Path:
        return Path(importlib.metadata.distribution("rosco").locate_file(f"Examples/Test_Cases/{relative}"))

    return case


@pytest.fixture(scope="session")
def imported_deck(tmp_path_factory, rosco_case):
    """A deck's path relative to ROSCO's test cases -> the folder its ``hawt turbine import`` was written to (each
    deck imported once a run)."""
    from hawt_tools.turbine_import import import_deck, write_turbine

    folders = {}

    def folder(deck: str) -> Path:
        if deck not in folders:
            folders[deck] = tmp_path_factory.mktemp(Path(deck).stem)
            write_turbine(import_deck(rosco_case(deck)), folders[deck])
        return folders[deck]

    return folder
