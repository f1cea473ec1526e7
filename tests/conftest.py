"""Test-suite isolation: this run's ROS graph is private to it.

A free ROS domain id is reserved for the whole run (``domain_coordinator`` holds
a port for it, so two runs on one machine take different ids) and discovery is
kept on this host. Every node the tests start, in this process or in child
processes, inherits both through the environment.

Before any test starts, the shared-memory files that killed DDS participants left in /dev/shm
are removed with Fast DDS's own tool (``fastdds shm clean``: only files whose owner no longer
holds their lock). Fast DDS reopens such files when a new participant takes the same port, and
that can crash or silence it (eProsima/Fast-DDS#6501, #5053). Seen here once: a fresh-clone run on
a machine where a day of runs had left 82 such segments failed three tests that way (a plant
killed by SIGSEGV inside libfastdds, a lockstep graph whose commands never reached its plant, a
viewer that got no data); the same run passed once they were removed.
"""
import importlib.metadata
import os
import re
import shutil
import subprocess
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
_CLEANED = pytest.StashKey[str]()


def _remove_dead_participants_files() -> str:
    """Run ``fastdds shm clean``; what it removed, as a line for the report header."""
    tool = shutil.which("fastdds")
    if tool is None:
        return "shared memory of dead DDS participants: not checked (no fastdds tool on PATH)"
    result = subprocess.run([tool, "shm", "clean"], capture_output=True, text=True, timeout=60)
    counts = dict((what, int(number)) for number, what in
                  re.findall(r"(\d+) zombie (ports|segments) cleaned", result.stdout))
    if result.returncode != 0 or len(counts) != 2:
        return f"shared memory of dead DDS participants: fastdds shm clean failed: {result.stderr.strip()[-300:]}"
    return (f"shared memory of dead DDS participants: {counts['segments']} segments and {counts['ports']} ports "
            "removed")


def pytest_configure(config):
    if not hasattr(config, "workerinput"):  # once, in the process that starts the workers, before any test
        config.stash[_CLEANED] = _remove_dead_participants_files()


def pytest_report_header(config):
    return [f"ROS_DOMAIN_ID={os.environ['ROS_DOMAIN_ID']} (reserved for this run), discovery LOCALHOST",
            config.stash.get(_CLEANED, "")]


@pytest.hookimpl(tryfirst=True)  # before -m deselects by marker
def pytest_collection_modifyitems(items):
    """A test that runs hawt in a shell (the ``hawt_cli`` fixture) and starts no ROS graph is marked ``processes``, so
    ``--quick`` leaves it out.

    The order the files run in is xdist's: ``--dist loadfile`` hands out whole files, those with the most tests
    first, which spreads the files that start ROS graphs among the cores' files. Handing out the graph files first
    was faster but started four graphs at once, whose discovery and realtime runs then raced the tests' probes on a
    2-core machine: the suite's robustness under load comes first."""
    for item in items:
        if "hawt_cli" in getattr(item, "fixturenames", ()) and item.get_closest_marker("ros") is None:
            item.add_marker(pytest.mark.processes)


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
