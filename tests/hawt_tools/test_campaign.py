"""`hawt campaign` on real Dask workers: every case once, resumable, the same on a cluster as locally, a killed
worker or a Ctrl-C loses nothing (and what it wrote says incomplete until resumed), a case equals the lockstep ROS
graph's run bit for bit, and a --scheduler where no Dask scheduler answers is refused within the timeout."""
import http.server
import json
import math
import re
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import List

import numpy as np
import pandas
import pytest
import yaml

from hawt_analysis.campaign_report import lifetime_text
from hawt_bag.step_comparison import step_differences
from hawt_tools.campaign import SCHEDULER_TIMEOUT, plan_cases, read_lifetime, run_case, write_tables
from hawt_tools.campaign_file import case_overrides, load_campaign

pytestmark = pytest.mark.processes  # Dask clusters and hawt commands in a shell: not in --quick

CAMPAIGN = """\
wind: {speeds: [12, 16, 20], seeds: [1]}
duration: 10
transient: 2
controllers:
  baseline: {graph: baseline}
  ipc_1p: {graph: ipc, arguments: {ipc_h2: false, ipc_h3: false}}
"""
CASES = 6
HAWT = [sys.executable, "-m", "hawt_tools.cli"]


class _Command:
    """A command in a child process whose output lines are read as they come."""

    def __init__(self, arguments: List[str], preexec_fn=None) -> None:
        self.process = subprocess.Popen(arguments, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                        preexec_fn=preexec_fn)
        self.lines: List[str] = []
        self.changed = threading.Condition()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        for line in self.process.stdout:
            with self.changed:
                self.lines.append(line)
                self.changed.notify_all()

    def wait_for(self, text: str, timeout: float = 300.0) -> None:
        with self.changed:
            assert self.changed.wait_for(lambda: any(text in line for line in self.lines), timeout), \
                "".join(self.lines[-30:])

    def finish(self, timeout: float = 600.0) -> int:
        code = self.process.wait(timeout)
        self.process.stdout.close()
        return code


def _wait_until(condition, what: str, timeout: float = 120.0) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, f"no {what} after {timeout:g} s"
        time.sleep(0.05)


def _scheduler_address(path: Path) -> str | None:
    """The address the dask scheduler wrote, or None while the file is missing or not yet complete (it is written,
    not renamed into place: a fresh-clone run once read it empty)."""
    try:
        return json.loads(path.read_text())["address"]
    except (OSError, ValueError, KeyError):
        return None


def _rows(output: Path) -> dict:
    """Stored cases by key, without the wall time."""
    rows = [json.loads(path.read_text()) for path in (output / "cases").glob("*.json")]
    return {row["key"]: {k: v for k, v in row.items() if k != "wall_s"} for row in rows}


@pytest.fixture(scope="module")
def campaign_file(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("campaign") / "small.yaml"
    path.write_text(CAMPAIGN)
    return path


@pytest.fixture(scope="module")
def local_campaign(campaign_file) -> tuple:
    """The small campaign run on two local workers: its output folder and what it printed."""
    output = campaign_file.parent / "local"
    result = subprocess.run([*HAWT, "campaign", str(campaign_file), "-o", str(output), "--workers", "2"],
                            capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return output, result.stdout


@pytest.fixture(scope="module")
def local_run(local_campaign) -> Path:
    return local_campaign[0]


def test_every_case_runs_once_into_the_tables_and_a_rerun_skips_them(local_run, campaign_file, hawt_cli,
                                                                     local_campaign):
    """Before the work, the campaign says how long it expects to take (its graph's speed measured here); each case
    is stored once; a rerun finds them all done."""
    assert re.search(rf"running {CASES} on 2 Dask worker\(s\) \(local cluster\): expected about .+ \({CASES} x "
                     rf"\d+ s at \d+x real time, measured here\)", local_campaign[1]), local_campaign[1]
    rows = _rows(local_run)
    assert len(rows) == CASES and sorted((r["controller"], r["wind_speed"]) for r in rows.values()) == sorted(
        (name, speed) for name in ("baseline", "ipc_1p") for speed in (12.0, 16.0, 20.0))
    table = pandas.read_parquet(local_run / "cases.parquet")
    assert len(table) == CASES and table["del.root_moment_oop_1"].gt(0).all()
    assert pandas.read_csv(local_run / "cases.csv")["key"].tolist() == table["key"].tolist()
    lifetime = pandas.read_csv(local_run / "lifetime.csv")
    assert set(lifetime["controller"]) == {"baseline", "ipc_1p"} and lifetime["value"].notna().all()
    assert (local_run / "report.html").is_file()
    again = subprocess.run([*hawt_cli, "campaign", str(campaign_file), "-o", str(local_run)], capture_output=True,
                           text=True, timeout=300)
    assert again.returncode == 0, again.stderr[-2000:]
    assert f"{CASES} already done" in again.stdout and "[1/" not in again.stdout


def test_on_a_cluster_with_a_worker_killed_every_case_is_stored_once_and_equal_to_the_local_run(
        local_run, campaign_file, hawt_cli, tmp_path):
    """A dask scheduler and two dask worker processes on localhost; one worker is killed (SIGKILL) once the first
    case has finished: its task runs again on the other, and the results are the local run's."""
    dask = [str(Path(sys.executable).parent / "dask")]
    address_file = tmp_path / "scheduler.json"
    scheduler = subprocess.Popen([*dask, "scheduler", "--scheduler-file", str(address_file), "--port", "0",
                                  "--no-dashboard"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    workers = [subprocess.Popen([*dask, "worker", "--scheduler-file", str(address_file), "--nthreads", "1",
                                 "--no-nanny", "--no-dashboard"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
               for _ in range(2)]
    try:
        from distributed import Client

        _wait_until(lambda: _scheduler_address(address_file), "address in the scheduler's file")
        address = _scheduler_address(address_file)
        with Client(address, timeout=60) as client:
            client.wait_for_workers(2, timeout=120)
        output = tmp_path / "cluster"
        command = _Command([*hawt_cli, "campaign", str(campaign_file), "-o", str(output), "--scheduler", address])
        command.wait_for("[1/")
        workers[0].kill()
        assert command.finish() == 0, "".join(command.lines[-30:])
        assert f"[{CASES}/{CASES}]" in "".join(command.lines)
        assert len(list((output / "cases").glob("*.json"))) == CASES
        assert _rows(output) == _rows(local_run)
    finally:
        for process in (*workers, scheduler):
            process.kill()
            process.wait()


def test_a_campaign_interrupted_with_ctrl_c_keeps_what_finished_and_resumes(hawt_cli, tmp_path):
    """Ctrl-C once the first case is reported. The cases are 30 s here (about 2 s of wall time each, one worker):
    with the small campaign's 10 s a fresh-clone suite once finished all six before the test's Ctrl-C arrived.
    The campaign is started with SIGINT ignored, as a script's background job is (and as a test runner's worker once
    passed it on): Ctrl-C must stop it all the same."""
    campaign_file = tmp_path / "longer.yaml"
    campaign_file.write_text(CAMPAIGN.replace("duration: 10", "duration: 30"))
    output = tmp_path / "interrupted"
    command = _Command([*hawt_cli, "campaign", str(campaign_file), "-o", str(output), "--workers", "1"],
                       preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN))
    command.wait_for("[1/")
    command.process.send_signal(signal.SIGINT)
    assert command.finish() == 130, "".join(command.lines[-30:])
    finished = len(list((output / "cases").glob("*.json")))
    assert 1 <= finished < CASES and "run the same command again to resume" in "".join(command.lines)
    incomplete = f"incomplete: {finished} of {CASES} cases"
    assert f"{incomplete} (missing: " in "".join(command.lines)
    assert set(pandas.read_csv(output / "lifetime.csv")["cases"]) == {incomplete}
    assert f"<h1>hawt campaign: longer.yaml — {incomplete}</h1>" in (output / "report.html").read_text()
    rerun = subprocess.run([*hawt_cli, "campaign", str(campaign_file), "-o", str(output), "--workers", "1"],
                           capture_output=True, text=True, timeout=600)
    assert rerun.returncode == 0, rerun.stdout[-2000:] + rerun.stderr[-2000:]
    assert f"{finished} already done" in rerun.stdout
    assert len(list((output / "cases").glob("*.json"))) == CASES
    assert set(pandas.read_csv(output / "lifetime.csv")["cases"]) == {f"all {CASES} cases"}
    assert "incomplete" not in rerun.stdout and "incomplete" not in (output / "report.html").read_text()


def _row(controller: str, speed: float, seed: int) -> dict:
    """A case's row with the numbers the lifetime table reads."""
    return {"controller": controller, "wind_speed": speed, "seed": seed, "del.root_moment_oop_1": 5e6 + seed,
            "power.mean": 4e6, "wohler": {"root_moment_oop_1": 10.0}}


def test_the_lifetime_table_of_part_of_a_campaign_says_incomplete_and_names_the_missing_cases(tmp_path):
    """In every row of lifetime.csv, as a pandas reader sees it, and heading its text (the command's summary, the
    report, `hawt compare`); a bin named by its speed alone has lost all its seeds."""
    path = tmp_path / "seeds.yaml"
    path.write_text(CAMPAIGN.replace("seeds: [1]", "seeds: 2"))
    campaign = load_campaign(path)
    rows = [_row("baseline", speed, seed) for speed in (12.0, 16.0, 20.0) for seed in (1, 2)]
    rows += [_row("ipc_1p", 12.0, 1), _row("ipc_1p", 12.0, 2), _row("ipc_1p", 16.0, 1)]
    write_tables(campaign, rows, tmp_path / "partial")
    lifetime = pandas.read_csv(tmp_path / "partial" / "lifetime.csv")
    assert set(lifetime["cases"]) == {"incomplete: 9 of 12 cases"}
    assert set(lifetime["missing"]) == {"ipc_1p at 16 m/s (seed 2), 20 m/s"}
    assert lifetime_text(read_lifetime(tmp_path / "partial")).splitlines()[0] == \
        "incomplete: 9 of 12 cases (missing: ipc_1p at 16 m/s (seed 2), 20 m/s)"
    rows += [_row("ipc_1p", 16.0, 2), _row("ipc_1p", 20.0, 1), _row("ipc_1p", 20.0, 2)]
    write_tables(campaign, rows, tmp_path / "complete")
    assert set(pandas.read_csv(tmp_path / "complete" / "lifetime.csv")["cases"]) == {"all 12 cases"}
    assert "incomplete" not in lifetime_text(read_lifetime(tmp_path / "complete"))
    both = read_lifetime(tmp_path / "partial", "partial/") + read_lifetime(tmp_path / "complete", "complete/")
    assert lifetime_text(both).splitlines()[0] == ("partial/baseline, partial/ipc_1p: incomplete: 9 of 12 cases "
                                                   "(missing: ipc_1p at 16 m/s (seed 2), 20 m/s)")


@pytest.mark.ros
def test_a_recorded_case_equals_the_lockstep_ros_graph_bit_for_bit(hawt_cli, tmp_path):
    """The small campaign's 16 m/s ipc_1p case, run alone with --bags, and `hawt launch` of the same graph with the
    campaign's plant settings."""
    campaign_file = tmp_path / "one_case.yaml"
    campaign_file.write_text(CAMPAIGN.replace("speeds: [12, 16, 20]", "speeds: [16]")
                             .replace("  baseline: {graph: baseline}\n", ""))
    output = tmp_path / "bags"
    result = subprocess.run([*hawt_cli, "campaign", str(campaign_file), "-o", str(output), "--workers", "1",
                             "--bags"], capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    case = output / "bags" / "ipc_1p_16ms_seed1.mcap"
    launched = tmp_path / "launched.mcap"
    overrides = [word for text in case_overrides(load_campaign(campaign_file), 16.0, 1) for word in ("-p", text)]
    result = subprocess.run([*hawt_cli, "launch", "ipc", "ipc_h2:=false", "ipc_h3:=false", *overrides,
                             "--record", str(launched)], capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr[-2000:]
    topics = ("/wt1/plant/blade_loads", "/wt1/plant/state", "/wt1/control/pitch_command")
    assert step_differences(launched, case, topics) == []


def test_compare_reads_campaign_folders(local_run, hawt_cli):
    """Lifetime DELs and AEP of every controller of the campaign, changes against the first."""
    result = subprocess.run([*hawt_cli, "compare", str(local_run)], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    header, *rows = result.stdout.splitlines()
    assert header.split() == ["baseline", "ipc_1p", "change"] and rows[-1].startswith("AEP [GWh]")
    assert "%" in rows[0], "the second controller's change against the first"


@pytest.mark.parametrize("arguments, message", [
    (["--scheduler", "foo"], "--scheduler foo: expected tcp://HOST:PORT with a port of 1 to 65535"),
    (["--scheduler", "tcp://127.0.0.1:99999"], "--scheduler tcp://127.0.0.1:99999: expected tcp://HOST:PORT"),
    (["-o", "FILE"], "-o FILE: is a file; expected a folder"),
    (["-o", "/nonexistent/out"], "-o /nonexistent/out: the folder /nonexistent does not exist"),
], ids=["not an address", "port out of range", "output is a file", "no parent folder"])
def test_a_campaign_that_could_not_deliver_is_refused_before_any_case_runs(hawt_cli, campaign_file, tmp_path,
                                                                            arguments, message):
    """A scheduler that is no address and an output that is a file or under no folder: one line, exit 2, before
    any case runs (an existing file was once the end of a whole case's work), and the file is left as it was."""
    existing = tmp_path / "results.txt"
    existing.write_text("kept\n")
    arguments = [str(existing) if word == "FILE" else word for word in arguments]
    message = message.replace("FILE", str(existing))
    result = subprocess.run([*hawt_cli, "campaign", str(campaign_file), *arguments], capture_output=True, text=True,
                            timeout=120)
    assert result.returncode == 2 and result.stderr.startswith(f"hawt campaign: {message}"), result.stderr
    assert len(result.stderr.strip().splitlines()) == 1 and existing.read_text() == "kept\n"


def _listener(greeting: bytes):
    """A loopback port that accepts connections and sends each ``greeting`` (nothing: it says nothing), its
    tcp:// address; closed on exit."""
    server = socket.create_server(("127.0.0.1", 0))
    accepted = []

    def accept() -> None:
        while True:
            try:
                connection, _ = server.accept()
            except OSError:  # shut down
                return
            connection.sendall(greeting)
            accepted.append(connection)

    threading.Thread(target=accept, daemon=True).start()
    yield f"tcp://127.0.0.1:{server.getsockname()[1]}"
    server.shutdown(socket.SHUT_RDWR)
    server.close()
    for connection in accepted:
        connection.close()


@pytest.fixture
def silent_port():
    yield from _listener(b"")


@pytest.fixture
def other_protocol_port():
    """Answers at once, as some web servers do (distributed read these bytes as frame lengths: 3.07 EiB)."""
    yield from _listener(b"HTTP/1.0 400 Bad request\r\nContent-Length: 0\r\n\r\n")


@pytest.fixture
def http_port():
    """Python's HTTP server, which waits for a request line that Dask's handshake never sends."""
    class Quiet(http.server.BaseHTTPRequestHandler):
        def log_message(self, *arguments) -> None:
            pass

    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Quiet)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    yield f"tcp://127.0.0.1:{server.server_address[1]}"
    server.shutdown()
    server.server_close()


@pytest.fixture
def closed_port():
    """A loopback port bound and not listening: a connection is refused (and no other process can take it)."""
    with socket.socket() as bound:
        bound.bind(("127.0.0.1", 0))
        yield f"tcp://127.0.0.1:{bound.getsockname()[1]}"


NO_ANSWER = f"no Dask scheduler answered within {SCHEDULER_TIMEOUT:g} s (the port accepts connections but says nothing)"


@pytest.mark.parametrize("port, message", [
    ("silent_port", NO_ANSWER),
    ("http_port", NO_ANSWER),
    ("other_protocol_port", "no Dask scheduler answered (the port answers in another protocol: "),
    ("closed_port", "cannot connect (Connection refused)"),
], ids=["accepts and never answers", "HTTP server", "answers in another protocol", "nothing listening"])
def test_a_scheduler_address_where_no_dask_scheduler_answers_is_refused_before_any_work(
        hawt_cli, campaign_file, tmp_path, request, port, message):
    """One line, exit 2, nothing printed or written, within the connection timeout (the subprocess's 120 s only
    guards against the hang this once was)."""
    address = request.getfixturevalue(port)
    output = tmp_path / "out"
    result = subprocess.run([*hawt_cli, "campaign", str(campaign_file), "-o", str(output), "--scheduler", address],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 2 and result.stderr.startswith(f"hawt campaign: --scheduler {address}: {message}"), \
        result.stderr
    assert len(result.stderr.strip().splitlines()) == 1 and result.stdout == "" and not output.exists()


def test_a_case_whose_safety_system_trips_says_so_and_its_commanded_rate_is_the_controllers(tmp_path):
    """A cpc stuck at fine pitch at 16 m/s: the overspeed protection trips and feathers the turbine. The case's row
    names the trip, and its largest commanded pitch rate is the loop assembler's command (the stuck cpc's, from the
    operating point down to fine pitch at the actuator's 8 deg/s), as control/pitch_command and hawt analyze have
    it, not the safety system's feathering (a new user's tripped case read 29.4 deg/s)."""
    baseline = Path(__file__).resolve().parents[2] / "hawt_controllers" / "hawt_controllers" / "data" / \
        "nrel5mw_baseline.yaml"
    tuning = yaml.safe_load(baseline.read_text())
    tuning["parameters"].update(proportional_gain=0.0, integral_gain=0.0, max_pitch=0.001)
    stuck = tmp_path / "stuck.yaml"
    stuck.write_text(yaml.safe_dump(tuning))
    path = tmp_path / "trip.yaml"
    path.write_text(f"wind: {{speeds: [16], seeds: [1]}}\nduration: 30\ntransient: 0\ncontrollers:\n"
                    f"  stuck: {{graph: baseline, parameters: ['cpc.controller_file:={stuck}']}}\n")
    campaign = load_campaign(path)
    (case,) = plan_cases(campaign)
    row = run_case(case, campaign)
    assert row["trips"].startswith("protection_trip at t="), row["trips"]
    assert row["pitch.max_command_rate"] <= math.radians(8.0) * (1 + 1e-9)


@pytest.mark.parametrize("dlc, seed, fault, trip", [
    ("2.3", 3, "grid loss: the generator off the grid, its torque 0 at t=20.25 s", "protection_trip at t=20.26 s"),
    ("2.1", 1, "pitch actuator of blade 1 running away to feather (1.5708 rad) at its rate limit 0.139626 rad/s at "
               "t=15.00 s", "protection_trip at t=17.23 s"),
])
def test_a_fault_case_names_the_fault_that_acted_and_the_trip_that_answered_it(tmp_path, dlc, seed, fault, trip):
    """DLC 2.3 at 13 m/s, the grid lost at the extreme operating gust's peak: the grid monitor trips the protection
    at the next step. DLC 2.1, blade 1's pitch running away to feather in turbulence: the pitch asymmetry trips it
    2.23 s later. Each case's row names the fault as the plant's event has it, at its time (5 s transient + 10 s,
    + 5.25 s for the gust's peak), and the trip."""
    path = tmp_path / "fault.yaml"
    path.write_text(f"dlc: {dlc}\nwind: {{speeds: [13], seeds: [{seed}]}}\nduration: 30\ntransient: 5\n"
                    "controllers:\n  baseline: {graph: baseline}\n")
    campaign = load_campaign(path)
    (case,) = plan_cases(campaign)
    row = run_case(case, campaign)
    assert (row["faults"], row["trips"]) == (fault, trip)


def test_a_campaign_of_several_dlcs_runs_each_into_its_folder_and_tables_the_design_loads_over_them(tmp_path,
                                                                                                  hawt_cli):
    """DLC 1.4 at rated (both ECD directions) and DLC 2.3 with the grid lost at the gust's peak: each DLC's tables
    in dlc-N.N, then the largest γ_f·F_k of every channel over both, with the DLC and case that govern it, printed
    and in ultimate.csv."""
    path = tmp_path / "ultimate.yaml"
    path.write_text("dlc:\n  1.4: {speeds: [11.4]}\n  2.3: {speeds: [13.4], seeds: [3]}\nduration: 30\n"
                    "transient: 5\nwind: {turbulence_class: B}\ncontrollers:\n  baseline: {graph: baseline}\n")
    output = tmp_path / "out"
    result = subprocess.run([*hawt_cli, "campaign", str(path), "-o", str(output), "--workers", "2"],
                            capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr
    assert (output / "dlc-1.4" / "ultimate.csv").is_file() and (output / "dlc-2.3" / "ultimate.csv").is_file()
    over = pandas.read_csv(output / "ultimate.csv")
    each = pandas.concat([pandas.read_csv(output / f"dlc-{dlc}" / "ultimate.csv", dtype={"dlc": str})
                          for dlc in ("1.4", "2.3")], ignore_index=True)
    for _, row in over.iterrows():
        mine = each[each["channel"] == row["channel"]]
        assert abs(row["design"]) == mine["design"].abs().max()
        assert f"{row['dlc']:g}" == mine.loc[mine["design"].abs().idxmax(), "dlc"]
    assert "ultimate loads over DLC 1.4, 2.3: design load = the largest γ_f × characteristic load" in result.stdout
    assert re.search(r"baseline, blade 1 root out-of-plane: DLC (1\.4 \(γ_f 1\.35\), 11\.4 m/s ECD|2\.3 \(γ_f 1\.1\), "
                     r"13\.4 m/s EOG)", result.stdout)
    page = (output / "report.html").read_text(encoding="utf-8")  # the design loads over both, linking each DLC's report
    assert "ultimate loads over DLC 1.4, 2.3" in page and (output / "design_loads.png").is_file()
    assert all(f'href="dlc-{dlc}/report.html"' in page for dlc in ("1.4", "2.3"))


def test_compare_reads_design_loads_from_campaign_folders_of_one_dlc_or_several(tmp_path, capsys):
    """hawt compare of campaign folders also puts their design loads side by side (ultimate.csv), changes against the
    first; a folder of several DLCs has only those (its DLCs' folders hold the lifetime tables)."""
    from hawt_tools.cli import main

    def folder(name, flap, with_lifetime):
        path = tmp_path / name
        path.mkdir()
        pandas.DataFrame([{"controller": "ipc", "channel": "root_moment_oop_1", "characteristic": flap / 1.35,
                           "factor": 1.35, "design": flap, "dlc": "1.4", "case": "11.4 m/s ECD +",
                           "basis": "largest extreme of the cases"}]).to_csv(path / "ultimate.csv", index=False)
        if with_lifetime:
            pandas.DataFrame([{"controller": "ipc", "quantity": "AEP [J]", "m": math.nan, "value": 3.6e13,
                               "cases": "all 2 cases", "missing": ""}]).to_csv(path / "lifetime.csv", index=False)
        return str(path)

    assert main(["compare", folder("before", 20.0e6, True), folder("after", 18.0e6, False)]) == 0
    out = capsys.readouterr().out
    assert "ultimate loads, DLC 1.4: design load = γ_f 1.35 × characteristic load" in out
    row = next(line for line in out.splitlines() if line.startswith("blade 1 root out-of-plane design"))
    assert row.split()[-4:] == ["20", "18", "-10.0", "%"]
    assert "before/ipc, blade 1 root out-of-plane: 11.4 m/s ECD + (largest extreme of the cases)" in out
    assert main(["compare", "--json", str(tmp_path / "after")]) == 0
    assert json.loads(capsys.readouterr().out)["ultimate"][0]["design"] == 18.0e6


def test_the_cases_that_govern_the_design_loads_run_again_to_the_bit_and_draw_their_time_series(tmp_path):
    """DLC 1.4 at rated, both ECD directions: each channel's governing case, run again, reaches exactly the
    characteristic load of the table (a case is deterministic), and the report draws those series."""
    from hawt_analysis.campaign_report import write_campaign_report
    from hawt_tools.campaign import governing_series, lifetime_table, ultimate_table

    path = tmp_path / "ecd.yaml"
    path.write_text("dlc: 1.4\nwind: {speeds: [11.4]}\nduration: 30\ntransient: 5\n"
                    "controllers:\n  baseline: {graph: baseline}\n")
    campaign = load_campaign(path)
    rows = [run_case(case, campaign) for case in plan_cases(campaign)]
    ultimate = ultimate_table(campaign, rows)
    series = governing_series(campaign, ultimate)
    assert {e["channel"] for e in series} == {e["channel"] for e in ultimate}
    for entry in ultimate:
        (mine,) = [s for s in series if s["channel"] == entry["channel"]]
        assert mine["case"] == entry["case"]
        extreme = mine["values"][np.argmax(np.abs(mine["values"]))]
        assert extreme == entry["characteristic"]
    page = write_campaign_report("hawt campaign: ecd.yaml", rows, lifetime_table(campaign, rows), tmp_path, {},
                                 ultimate, series).read_text(encoding="utf-8")
    assert (tmp_path / "governing_cases.png").is_file() and "the cases that govern the design loads" in page
