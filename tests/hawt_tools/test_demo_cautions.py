"""``hawt demo`` says when a run did not go as meant, so that its numbers are not taken for the comparison."""
from hawt_tools.commands.demo import CAUTION, cautions

FINISHED = {"time": 30.0, "step": 3000, "source": "plant", "level": 20, "kind": "finished", "detail": "3000 steps"}
LOST = {"time": 12.3, "step": 1230, "source": "mbc", "level": 30, "kind": "contribution_lost",
        "detail": "control/ipc/h1: nothing for step 1230 within 1 s"}


def test_a_run_with_a_lost_contribution_gets_one_line_naming_it_and_its_first_event():
    (line,) = cautions({"baseline.mcap": [FINISHED], "ipc.mcap": [LOST, dict(LOST, step=1500, time=15.0), FINISHED]})
    assert line.startswith(f"{CAUTION} ipc.mcap has 2 warning or error event(s), the first at t=12.30 s, mbc: "
                           "contribution_lost (control/ipc/h1: nothing for step 1230 within 1 s)")
    assert "run it again on a quieter machine" in line


def test_clean_runs_get_no_caution():
    assert cautions({"baseline.mcap": [FINISHED], "ipc.mcap": [FINISHED]}) == []
