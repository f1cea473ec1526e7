"""Every lifecycle transition from a shell reaches the same state as a switch: hawt lifecycle and hawt switch.

A realtime switching graph runs; the test drives it as a user with the two shell commands and
waits on conditions (the state the node reports, the manager's list), never on a clock. The graph runs composed
(every node in one process, each still a ROS node on DDS, with its own lifecycle services): the commands see the
same services as in separate processes, and a realtime graph idling through the commands costs a third of the CPU
(20 s of it: 6.2 CPU-s composed, 16.3 in processes). Switching across processes is `test_switching_realtime`'s.
"""
import subprocess
import time

import pytest
from launched_graph import CLI, LaunchedGraph

pytestmark = pytest.mark.ros

NS = "lc"


def _hawt(*arguments):
    """A hawt command against this test's graph (its namespace given: nothing to discover first)."""
    named = [*arguments, "--namespace", NS]
    return subprocess.run([*CLI, *named], capture_output=True, text=True, timeout=90)


def _listed(name: str) -> str:
    """The state controller_manager lists for ``name``."""
    listing = _hawt("list").stdout
    rows = [line.split() for line in listing.splitlines() if line.strip().startswith(f"/{NS}/{name} ")]
    return rows[0][1] if rows else ""


def _until(condition, what: str, timeout: float = 60.0) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, f"not reached within {timeout:g} s: {what}"
        time.sleep(0.2)


@pytest.fixture(scope="module")
def graph():
    with LaunchedGraph(["switching", "--mode", "realtime", "--composed", f"namespace:={NS}", "duration:=600",
                        "-p", "plant.report_period:=1"]) as launched:
        launched.wait_for_line("t=1.0 s", 120.0)
        for name in ("ipc_h1", "ipc_h1_retuned"):  # configured once the plant's description reached them
            _until(lambda: _hawt("lifecycle", name).stdout.strip() == f"{name}: inactive", f"{name} configured", 120.0)
        yield launched.lines


def test_a_standard_activate_reaches_the_state_of_a_switch_and_deactivate_by_switch_undoes_it(graph):
    """hawt lifecycle ipc_h1 activate: the node is active and controller_manager lists it active; hawt switch
    --deactivate ipc_h1 then brings both back to inactive."""
    result = _hawt("lifecycle", "ipc_h1", "activate")
    assert result.returncode == 0 and result.stdout.strip() == "ipc_h1: active", result.stderr
    _until(lambda: _listed("ipc_h1") == "active", "controller_manager lists ipc_h1 active")
    assert _hawt("switch", "--deactivate", "ipc_h1").returncode == 0
    _until(lambda: _hawt("lifecycle", "ipc_h1").stdout.strip() == "ipc_h1: inactive", "ipc_h1 inactive")
    _until(lambda: _listed("ipc_h1") == "inactive", "controller_manager lists ipc_h1 inactive")


def test_a_standard_activate_that_the_manager_refuses_goes_back_to_inactive(graph):
    """With ipc_h1 active (hawt switch), a second claimant of harmonic/1 asked by lifecycle transition is refused by
    controller_manager and returns to inactive; a lifecycle deactivate of ipc_h1 then reaches the manager too."""
    assert _hawt("switch", "--activate", "ipc_h1").returncode == 0
    _until(lambda: _listed("ipc_h1") == "active", "ipc_h1 active")
    assert _hawt("lifecycle", "ipc_h1_retuned", "activate").returncode == 0
    _until(lambda: _hawt("lifecycle", "ipc_h1_retuned").stdout.strip() == "ipc_h1_retuned: inactive",
           "the refused ipc_h1_retuned back to inactive")
    _until(lambda: _listed("ipc_h1_retuned") == "inactive", "controller_manager lists ipc_h1_retuned inactive")
    assert _hawt("lifecycle", "ipc_h1", "deactivate").returncode == 0
    _until(lambda: _listed("ipc_h1") == "inactive", "ipc_h1 deactivated by lifecycle transition")


def test_cleanup_and_configure_from_a_shell(graph):
    """cleanup unconfigures an inactive controller (the manager lists it so); configure brings it back inactive, and it
    activates again (then inactive once more, as the graph began: each test leaves the graph as it found it)."""
    cleanup = _hawt("lifecycle", "blade_sine", "cleanup")
    assert cleanup.stdout.strip() == "blade_sine: unconfigured", cleanup.stderr
    _until(lambda: _listed("blade_sine") == "unconfigured", "blade_sine unconfigured in the list")
    assert _hawt("lifecycle", "blade_sine", "configure").stdout.strip() == "blade_sine: inactive"
    _until(lambda: _listed("blade_sine") == "inactive", "blade_sine inactive in the list")
    assert _hawt("switch", "--activate", "blade_sine").returncode == 0
    _until(lambda: _listed("blade_sine") == "active", "blade_sine active after its reconfiguration")
    assert _hawt("switch", "--deactivate", "blade_sine").returncode == 0
    _until(lambda: _listed("blade_sine") == "inactive", "blade_sine inactive again")


def test_a_controller_the_manager_does_not_know_is_refused_in_one_line_naming_those_it_knows(graph):
    """hawt lifecycle ipc_h9 activate (a typo): exit 2 and one line naming the graph's controllers, as hawt switch
    answers a typo (it waited 30 s for the typo's services, then asked whether the graph was running)."""
    result = _hawt("lifecycle", "ipc_h9", "activate")
    assert result.returncode == 2 and result.stderr.count("\n") == 1, result.stderr
    assert result.stderr.startswith(f"hawt lifecycle: ipc_h9: no such controller (known: /{NS}/blade_sine, /{NS}/cpc, ")


def test_hawt_list_of_a_namespace_without_a_manager_names_the_namespaces_that_have_one(graph):
    """hawt list --namespace /wt2 while the graph runs in /lc: the error names /lc (it only asked whether the
    graph was running)."""
    result = subprocess.run([*CLI, "list", "--namespace", "/wt2"], capture_output=True, text=True, timeout=90)
    assert result.returncode == 1 and result.stderr.count("\n") == 1, result.stderr
    assert result.stderr.rstrip().endswith(f"the graph's controller managers: /{NS}"), result.stderr
