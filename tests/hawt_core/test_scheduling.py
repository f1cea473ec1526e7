"""Realtime scheduling of node processes (hawt launch --priority)."""
import os
import subprocess
import sys

import pytest

from hawt_tools.cli import main
from hawt_core.scheduling import PRIORITY_VARIABLE, SchedulingError, check_priority, set_priority

PERMITTED = os.geteuid() == 0
"""Root may use SCHED_FIFO; another user gets the one-line refusal (both are specified below)."""

_REPORT_POLICY = ("import os; from hawt_core.scheduling import priority_from_environment; "
                  "priority_from_environment(); print(os.sched_getscheduler(0), os.sched_getparam(0).sched_priority)")


@pytest.mark.parametrize("priority", [0, 100, -5])
def test_a_priority_outside_1_to_99_is_refused_with_the_range(priority):
    with pytest.raises(SchedulingError, match=rf"priority {priority}: SCHED_FIFO takes 1\.\.99"):
        set_priority(priority)


def test_checking_a_priority_leaves_this_process_as_it_was():
    before = os.sched_getscheduler(0), os.sched_getparam(0).sched_priority
    try:
        check_priority(50)
    except SchedulingError as refusal:
        assert not PERMITTED and "CAP_SYS_NICE" in str(refusal)
    assert (os.sched_getscheduler(0), os.sched_getparam(0).sched_priority) == before


def test_a_node_process_takes_its_priority_from_the_launcher_environment():
    """What hawt launch --priority sets for each node process; node_main applies it before rclpy starts."""
    result = subprocess.run([sys.executable, "-c", _REPORT_POLICY], capture_output=True, text=True,
                            env={**os.environ, PRIORITY_VARIABLE: "40"})
    if PERMITTED:
        assert result.returncode == 0, result.stderr
        assert result.stdout.split() == [str(os.SCHED_FIFO), "40"]
    else:
        assert "CAP_SYS_NICE" in result.stderr


def test_hawt_launch_refuses_a_bad_priority_in_one_line_with_exit_code_2(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["launch", "example", "--priority", "120"])
    assert exit_.value.code == 2
    assert capsys.readouterr().err.strip() == "hawt launch: argument --priority: 120: expected a whole number from 1 to 99"
