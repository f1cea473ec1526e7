"""hawt analyze / compare on bags: the DESIGN §8 numbers of hawt_analysis, read from the plant topics."""
import json
import subprocess

import numpy as np
import pytest

from hawt_analysis.run_analysis import analyze_bag
from hawt_analysis.summary import summarize
from hawt_analysis.synthetic_run import synthetic_channels
from hawt_bag.cdr_columns import encode_messages
from hawt_bag.column_writing import plant_topics, write_topics
from hawt_bag.errors import BagError
from hawt_bag.interface_files import schema_text
from hawt_bag.msg_definition import parse_schema, short_type_name
from hawt_bag.reader import BagReader
from hawt_bag.plant_run import load_plant_run
from hawt_bag.writer import BagWriter

DESIGN_KEYS = {"duration_s", "del", "harmonics", "psd", "pitch", "rotor_speed", "power", "conventions"}
EVENTS = [{"step": 100, "source": "controller_manager", "level": 20, "kind": "switch", "detail": "ipc_h1 active"},
          {"step": 2500, "source": "mbc", "level": 30, "kind": "saturation", "detail": ""}]


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Two synthetic 60 s, 100 Hz runs written as bags (the first under /wt1 with events) and their channels."""
    folder = tmp_path_factory.mktemp("bags")
    made = {}
    for name, namespace, seed in (("a.mcap", "/wt1", 0), ("b.mcap", "", 1)):
        channels = synthetic_channels(duration=60.0, sample_rate=100.0, seed=seed)
        with BagWriter(folder / name) as writer:
            write_topics(writer, plant_topics(channels, namespace, EVENTS if seed == 0 else ()))
        made[name] = (folder / name, channels)
    return made


def _run(hawt_cli, *arguments):
    return subprocess.run([*hawt_cli, *arguments], capture_output=True, text=True, timeout=120)


def test_analyze_json_has_the_design_keys_and_the_dels_of_hawt_analysis(hawt_cli, runs):
    """--json: the DESIGN §8 keys; every DEL equals hawt_analysis.summarize on the same arrays; events listed."""
    path, channels = runs["a.mcap"]
    result = _run(hawt_cli, "analyze", str(path), "--json")
    assert result.returncode == 0, result.stderr
    summary = json.loads(result.stdout)
    assert DESIGN_KEYS <= set(summary)
    reference = summarize(channels)
    assert set(summary["del"]) == set(reference["del"]) and len(summary["del"]) == 14  # 3 × 2 blade, 8 steel
    for name, entry in reference["del"].items():
        assert summary["del"][name]["value"] == pytest.approx(entry["value"], rel=1e-9), name
        assert summary["del"][name]["m"] == entry["m"]
    assert summary["bag"]["namespace"] == "/wt1"
    assert [(e["step"], e["kind"]) for e in summary["events"]] == [(100, "switch"), (2500, "saturation")]
    assert summary["pitch_command"]["steps"] == 6001


def test_bag_channels_are_the_arrays_that_were_written(runs):
    """The plant topics give back the written channels: time from the header stamps, per-blade arrays (n, B)."""
    path, channels = runs["a.mcap"]
    with BagReader(path) as reader:
        run = load_plant_run(reader)
    assert set(run.channels) == set(channels)
    for name, values in channels.items():
        if name == "time":
            assert np.allclose(run.channels[name], values, rtol=0, atol=1e-9)
        else:
            assert np.array_equal(run.channels[name], values), name
    assert run.steps.tolist() == list(range(6001))


def test_analyze_text_and_report(hawt_cli, runs, tmp_path):
    """The readable table shows DELs, 1P-3P and events; --report writes an index page with its figures."""
    path, _ = runs["a.mcap"]
    report = tmp_path / "report"
    result = _run(hawt_cli, "analyze", str(path), "--report", str(report))
    assert result.returncode == 0, result.stderr
    for text in ("damage-equivalent loads", "root_moment_oop_1", "1P", "3P", "pitch (measured)",
                 "events (2):", "ipc_h1 active"):
        assert text in result.stdout
    index = (report / "index.html").read_text()
    for figure in ("time_series.png", "spectra.png", "del.png"):
        assert (report / figure).stat().st_size > 10_000 and f'src="{figure}"' in index
    assert json.loads((report / "summary.json").read_text())["del"]


def test_compare_gives_each_run_against_the_first(hawt_cli, runs):
    """Two runs: labels by file name, the reference's change 0, the other's change from the DELs."""
    (a, _), (b, _) = runs["a.mcap"], runs["b.mcap"]
    result = _run(hawt_cli, "compare", str(a), str(b), "--json")
    assert result.returncode == 0, result.stderr
    comparison = json.loads(result.stdout)
    assert comparison["labels"] == ["a.mcap", "b.mcap"]
    entry = comparison["del"]["root_moment_oop_1"]
    assert entry["change_percent"][0] == 0.0
    assert entry["change_percent"][1] == pytest.approx(100 * (entry["value"][1] / entry["value"][0] - 1))
    text = _run(hawt_cli, "compare", str(a), str(b)).stdout
    (row,) = [line for line in text.splitlines() if line.startswith("DEL root_moment_oop_1 ")]
    assert row.endswith(f"{entry['change_percent'][1]:+.1f} %")
    assert "warning" not in result.stderr


def test_compare_warns_in_one_line_when_the_runs_differ_in_length(hawt_cli, runs, tmp_path):
    """A 30 s run against a 60 s one is compared, and stderr says they cover different records."""
    short = tmp_path / "short.mcap"
    with BagWriter(short) as writer:
        write_topics(writer, plant_topics(synthetic_channels(duration=30.0, sample_rate=100.0, seed=1), ""))
    result = _run(hawt_cli, "compare", str(runs["a.mcap"][0]), str(short))
    assert result.returncode == 0, result.stderr
    assert result.stderr.strip().splitlines()[-1] == ("hawt compare: warning: the runs differ in length (a.mcap "
                                                      "60 s, short.mcap 30 s): their DELs and spectra cover "
                                                      "different records")


def test_two_turbines_need_a_namespace(runs, tmp_path):
    """With /wt1 and /wt2 in one bag the turbine must be chosen; --namespace picks it."""
    _, channels = runs["a.mcap"]
    path = tmp_path / "two.mcap"
    with BagWriter(path) as writer:
        write_topics(writer, plant_topics(channels, "/wt1") + plant_topics(channels, "/wt2"))
    with BagReader(path) as reader:
        with pytest.raises(BagError, match=r"several turbines in the bag \(/wt1, /wt2\): choose one with --namespace"):
            load_plant_run(reader)
        assert load_plant_run(reader, "wt2").namespace == "/wt2"


@pytest.mark.parametrize("damage, message", [
    ("missing state", "missing topic /plant/state"),
    ("not mcap", "not an MCAP file"),
    ("truncated", "truncated or unfinished MCAP"),
])
def test_bad_bags_exit_2_with_one_line_naming_the_file(hawt_cli, runs, tmp_path, damage, message):
    """analyze and bag info on a bag without plant/state, a non-MCAP file or a cut file: exit 2, one line."""
    path = tmp_path / "bad.mcap"
    _, channels = runs["b.mcap"]
    if damage == "missing state":
        with BagWriter(path) as writer:
            write_topics(writer, [t for t in plant_topics(channels) if not t.topic.endswith("state")])
    elif damage == "not mcap":
        path.write_text("launch: []\n")
    else:
        path.write_bytes(runs["b.mcap"][0].read_bytes()[:50_000])
    commands = [("analyze", str(path))] + ([] if damage == "missing state" else [("bag", "info", str(path))])
    for command in commands:
        result = _run(hawt_cli, *command)
        assert result.returncode == 2
        assert result.stderr.count("\n") == 1 and f"{path}: " in result.stderr and message in result.stderr


def test_an_event_without_a_stamp_gets_the_plant_time_of_its_step(runs, tmp_path):
    """controller_manager and mbc do not know the plant's time: their events show the time of their step, not 0."""
    _, channels = runs["a.mcap"]
    topics = plant_topics(channels, "/wt1", EVENTS)
    for name in ("header.stamp.sec", "header.stamp.nanosec"):
        topics[-1].columns[name][:] = 0  # both events unstamped
    bag = tmp_path / "unstamped.mcap"
    with BagWriter(bag) as writer:
        write_topics(writer, topics)
    with BagReader(bag) as reader:
        events = load_plant_run(reader).events
    assert [e["step"] for e in events] == [100, 2500]
    assert [e["time"] for e in events] == pytest.approx([channels["time"][100], channels["time"][2500]])


def test_the_commanded_pitch_rate_is_the_largest_change_from_one_step_to_the_next(tmp_path):
    """A command that moves 0.08 deg a step (8 deg/s) and reverses every step or two reads 8 deg/s, not the
    16 deg/s that a second-order difference gives at the record's first step."""
    channels = synthetic_channels(duration=20.0, sample_rate=100.0, seed=2)
    triangle = np.array([0.0, 1.0, 0.0, -1.0])[np.arange(channels["time"].size) % 4]
    channels["pitch"] = np.repeat((np.deg2rad(10.0) + np.deg2rad(0.08) * triangle)[:, None], 3, axis=1)
    bag = tmp_path / "reversing.mcap"
    with BagWriter(bag) as writer:
        write_topics(writer, plant_topics(channels, ""))
    command = analyze_bag(bag).summary["pitch_command"]
    assert command["max_rate_rad_s"]["max"] == pytest.approx(np.deg2rad(8.0), rel=1e-9)


def test_a_malformed_command_is_counted_reported_and_skipped_not_the_whole_command_section(hawt_cli, tmp_path):
    """One pitch command of 2 values among 2001 of 3 (a rogue or broken publisher): analyze still gives the commanded
    pitch of every step and says, in one warning, how many messages it skipped and the first one's step."""
    channels = synthetic_channels(duration=20.0, sample_rate=100.0, seed=2)
    topics = plant_topics(channels, "")
    command = next(t for t in topics if t.topic == "/control/pitch_command")
    short = {name: np.asarray(column)[500:501, :2] if name == "pitch" else np.asarray(column)[500:501]
             for name, column in command.columns.items()}
    definitions = parse_schema(schema_text(command.type_name), command.type_name)
    payload, = encode_messages(definitions, short_type_name(command.type_name), short, 1)
    bag = tmp_path / "malformed.mcap"
    with BagWriter(bag) as writer:
        write_topics(writer, topics)
        writer.write(writer.channels[(command.topic, None)], int(command.log_time[500]) + 1, payload)
    analysis = analyze_bag(bag)
    assert analysis.summary["pitch_command"]["steps"] == channels["time"].size
    assert analysis.summary["warnings"] == ["/control/pitch_command: 1 malformed message(s) skipped (pitch and "
                                            "individual must hold 3 values; the first at step 500 holds 2 and 3)"]
    result = _run(hawt_cli, "analyze", str(bag))
    assert result.returncode == 0 and "1 malformed message(s) skipped" in result.stderr
