"""hawt bag verify: every stepped topic checked for lost and repeated steps, and the file for its summary."""
import dataclasses
import json
import struct

import numpy as np
import pytest
from mcap.writer import IndexType, Writer

from hawt_analysis.synthetic_run import synthetic_channels
from hawt_bag.cdr_columns import encode_messages
from hawt_bag.column_writing import TopicData, plant_topics, write_topics
from hawt_bag.interface_files import schema_text
from hawt_bag.msg_definition import parse_schema
from hawt_bag.verification import verify_bag
from hawt_bag.writer import BagWriter
from hawt_tools.cli import main

EVENTS = [{"step": 100, "source": "controller_manager", "level": 20, "kind": "switch", "detail": "ipc_h1 active"},
          {"step": 100, "source": "/wt1/mbc", "level": 20, "kind": "switch", "detail": "ipc_h1 ramps in"}]


@pytest.fixture(scope="module")
def topics():
    """A 10 s, 100 Hz run (steps 0-1000) as the plant topics under /wt1, with two events at step 100."""
    return plant_topics(synthetic_channels(duration=10.0, sample_rate=100.0), "/wt1", EVENTS)


def _bag(path, topics):
    with BagWriter(path) as writer:
        write_topics(writer, topics)
    return path


def _named(topics, ending):
    return next(t for t in topics if t.topic.endswith(ending))


def _replaced(topics, data):
    return [data if t.topic == data.topic else t for t in topics]


def _rows(data, rows, log_time=None):
    """The topic with only these rows (in this order), optionally at other log times."""
    return dataclasses.replace(data, columns={k: np.asarray(v)[rows] for k, v in data.columns.items()},
                               log_time=np.asarray(data.log_time)[rows] if log_time is None else log_time,
                               publish_time=np.asarray(data.publish_time)[rows])


def _without_steps(data, steps):
    return _rows(data, np.flatnonzero(~np.isin(data.columns["step"], steps)))


def _step_twice(data, step, changed=None):
    """The topic with step ``step`` recorded again 1 ms later, field ``changed`` altered in the repeat."""
    rows = np.insert(np.arange(data.log_time.size), step + 1, step)
    repeat = _rows(data, rows, np.insert(data.log_time, step + 1, data.log_time[step] + 1_000_000))
    if changed is not None:
        repeat.columns[changed][step + 1] += 0.01
    return repeat


def _ipc_windows(ranges):
    """control/ipc/h1 publishing only over the given step ranges (a controller active twice)."""
    steps = np.concatenate([np.arange(first, last + 1) for first, last in ranges]).astype(np.uint64)
    return TopicData("/wt1/control/ipc/h1", "hawt_msgs/msg/HarmonicPitch",
                     {"step": steps, "harmonic": np.ones(steps.size, np.uint32), "cos": np.zeros(steps.size),
                      "sin": np.zeros(steps.size)}, 10_000_000 * steps.astype(np.int64))


def test_a_complete_bag_passes_with_one_line_per_stepped_topic(tmp_path, topics):
    """Every step of every topic once: OK, each stepped topic with its count and steps 0-1000."""
    report = verify_bag(_bag(tmp_path / "complete.mcap", topics))
    assert report.ok and report.problems == ()
    assert report.text().splitlines() == [
        "/wt1/control/pitch_command: 1001 messages, steps 0-1000, no gap",
        "/wt1/plant/blade_loads: 1001 messages, steps 0-1000, no gap",
        "/wt1/plant/state: 1001 messages, steps 0-1000, no gap",
        "verify: OK — 3 topics, no gap",
    ]


def test_stepped_topics_are_found_from_the_schemas_under_any_namespace(tmp_path, topics):
    """Every type with a step field is checked, under any namespace; events (two at step 100: a record type,
    not a sample) and /clock (no step) are not."""
    moved = [dataclasses.replace(t, topic=t.topic.replace("/wt1/", "/farm/wt7/")) for t in topics]
    clock = TopicData("/clock", "rosgraph_msgs/msg/Clock", {"clock.sec": np.arange(3)}, np.arange(3))
    steps = np.arange(1001, dtype=np.uint64)
    blade_pitch = TopicData("/farm/wt7/control/blade_pitch", "hawt_msgs/msg/BladePitch",
                            {"step": steps, "controller": np.full(steps.size, "/farm/wt7/blade_sine"),
                             "increment": np.zeros((steps.size, 3))}, 10_000_000 * steps.astype(np.int64))
    report = verify_bag(_bag(tmp_path / "farm.mcap", moved + [_ipc_windows([(0, 1000)]), clock, blade_pitch]))
    assert [t.coverage.topic for t in report.topics] == [
        "/farm/wt7/control/blade_pitch", "/farm/wt7/control/pitch_command", "/farm/wt7/plant/blade_loads",
        "/farm/wt7/plant/state", "/wt1/control/ipc/h1"]
    assert [t.contiguous for t in report.topics] == [False, True, True, True, False]
    assert report.ok


def test_steps_missing_from_plant_state_fail_naming_the_topic_the_count_and_the_first_gap(tmp_path, topics):
    """Steps 300-309 and 500 lost from plant/state: GAP, 11 steps in 2 gaps, the first after step 299."""
    state = _without_steps(_named(topics, "plant/state"), [*range(300, 310), 500])
    report = verify_bag(_bag(tmp_path / "gap.mcap", _replaced(topics, state)))
    assert not report.ok
    assert report.verdict() == "verify: GAP — /wt1/plant/state misses 11 steps in 2 gaps, the first after step 299"
    assert ("/wt1/plant/state: 990 messages, steps 0-1000, GAP: misses 11 steps in 2 gaps, first missing 300, 500"
            in report.text().splitlines())
    state_check = report.topics[-1]
    assert state_check.coverage.gaps == ((300, 309), (500, 500))


def test_a_resent_identical_step_is_reported_but_not_an_error(tmp_path, topics):
    """The plant sending step 400 again, field for field the same: counted as resent, the bag passes."""
    loads = _step_twice(_named(topics, "plant/blade_loads"), 400)
    report = verify_bag(_bag(tmp_path / "resent.mcap", _replaced(topics, loads)))
    assert report.ok
    assert "/wt1/plant/blade_loads: 1002 messages, steps 0-1000, no gap, 1 resent" in report.text().splitlines()
    assert report.verdict() == ("verify: OK — 3 topics, no gap, 1 resent (a step the lockstep plant sent again, "
                                "identical; analysed once)")


def test_a_step_recorded_twice_with_different_content_is_an_error(tmp_path, topics):
    """Step 400 of the pitch command twice with different pitch: DUPLICATE naming the topic and the step."""
    command = _step_twice(_named(topics, "control/pitch_command"), 400, changed="pitch")
    report = verify_bag(_bag(tmp_path / "duplicate.mcap", _replaced(topics, command)))
    assert not report.ok
    assert report.verdict() == ("verify: DUPLICATE — /wt1/control/pitch_command holds 1 step twice with different "
                                "content, the first step 400")
    assert report.topics[0].coverage.resent == 0 and report.topics[0].coverage.conflicts == (400,)


def test_an_unfinished_bag_fails_and_points_to_recover(tmp_path, topics):
    """A bag cut just before its summary (a recorder killed before finishing): UNFINISHED, naming recover."""
    data = _bag(tmp_path / "complete.mcap", topics).read_bytes()
    (summary_start,) = struct.unpack_from("<Q", data, len(data) - 28)  # footer: opcode, length, summary_start, …
    path = tmp_path / "unfinished.mcap"
    path.write_bytes(data[:summary_start])
    report = verify_bag(path)
    assert not report.ok and report.topics == ()
    assert report.verdict().startswith(f"verify: UNFINISHED — {path}: truncated or unfinished MCAP")
    assert f"'hawt bag recover {path}'" in report.verdict()


def test_a_finished_bag_without_summary_statistics_fails_and_points_to_recover(tmp_path):
    """A file written without a summary section: its steps are still checked, but it fails, naming recover."""
    path = tmp_path / "no_summary.mcap"
    text = schema_text("hawt_msgs/msg/TurbineState")
    payloads = encode_messages(parse_schema(text, "hawt_msgs/msg/TurbineState"), "hawt_msgs/TurbineState",
                               {"step": np.arange(5, dtype=np.uint64)}, 5)
    with open(path, "wb") as stream:
        writer = Writer(stream, index_types=IndexType.NONE, repeat_channels=False, repeat_schemas=False,
                        use_statistics=False, use_summary_offsets=False)
        writer.start(profile="ros2", library="test")
        schema = writer.register_schema("hawt_msgs/msg/TurbineState", "ros2msg", text.encode())
        channel = writer.register_channel("/plant/state", "cdr", schema)
        for step, payload in enumerate(payloads):
            writer.add_message(channel, step, payload, step)
        writer.finish()
    report = verify_bag(path)
    assert [t.coverage.ranges for t in report.topics] == [((0, 4),)]
    assert report.verdict() == (f"verify: NO SUMMARY — {path} has no summary section with statistics; "
                                f"'hawt bag recover {path}' writes a complete copy")


def test_a_controller_topic_with_windows_is_reported_but_not_an_error(tmp_path, topics):
    """control/ipc/h1 active over steps 200-499 and 700-899: its ranges are listed, the bag passes."""
    report = verify_bag(_bag(tmp_path / "windows.mcap", topics + [_ipc_windows([(200, 499), (700, 899)])]))
    assert report.ok
    assert ("/wt1/control/ipc/h1: 500 messages, steps 200-499, 700-899 (windows allowed)"
            in report.text().splitlines())
    assert report.verdict() == "verify: OK — 4 topics, no gap"


def test_verify_exits_0_on_a_complete_bag_and_1_on_a_gap_with_the_verdict_last(tmp_path, topics, capsys):
    """hawt bag verify: one line per topic then the verdict on stdout; exit 0 if OK, 1 on a gap."""
    complete = _bag(tmp_path / "complete.mcap", topics)
    gap = _bag(tmp_path / "gap.mcap", _replaced(topics, _without_steps(_named(topics, "plant/state"), [507])))
    assert main(["bag", "verify", str(complete)]) == 0
    assert capsys.readouterr().out.splitlines()[-1] == "verify: OK — 3 topics, no gap"
    assert main(["bag", "verify", str(gap)]) == 1
    out = capsys.readouterr()
    assert out.out.splitlines()[-1] == ("verify: GAP — /wt1/plant/state misses 1 step in 1 gap, "
                                        "the first after step 506") and out.err == ""


def test_verify_json_is_one_object_with_the_same_facts(tmp_path, topics, capsys):
    """--json: the file, ok, the verdict and each topic's count, ranges, gaps and repeats."""
    path = _bag(tmp_path / "gap.mcap", _replaced(topics, _without_steps(_named(topics, "plant/state"), [10, 11])))
    assert main(["bag", "verify", str(path), "--json"]) == 1
    report = json.loads(capsys.readouterr().out)
    assert (report["file"], report["ok"]) == (str(path), False)
    assert report["verdict"] == "verify: GAP — /wt1/plant/state misses 2 steps in 1 gap, the first after step 9"
    state = report["topics"][-1]
    assert state == {"topic": "/wt1/plant/state", "count": 999, "first_step": 0, "last_step": 1000,
                     "contiguous": True, "ranges": [[0, 9], [12, 1000]],
                     "gaps": [{"first_missing": 10, "last_missing": 11}], "missing": 2, "resent": 0,
                     "conflicts": [], "conflict_publishers": [],
                     "problems": [report["verdict"].removeprefix("verify: ")]}


@pytest.mark.parametrize("content, message", [(None, "no such file"), (b"launch: []\n", "not an MCAP file"),
                                              ("folder", "a folder; expected an MCAP file (FILE.mcap)")])
def test_verify_exits_2_with_one_line_naming_a_missing_or_foreign_file(tmp_path, capsys, content, message):
    """A missing file, one that is not MCAP or a folder (a user's runs folder) is bad input: exit 2, one line on
    stderr naming the file and what it is."""
    path = tmp_path / "bad.mcap"
    if content == "folder":
        path.mkdir()
    elif content is not None:
        path.write_bytes(content)
    assert main(["bag", "verify", str(path)]) == 2
    out = capsys.readouterr()
    assert out.out == "" and out.err.count("\n") == 1 and out.err.startswith(f"hawt bag: {path}: {message}")


def test_analyze_warns_of_the_gap_verify_reports_and_analyses_the_longest_run(tmp_path, topics, capsys):
    """analyze on a bag whose plant/state misses steps 300-309: one warning line on stderr and in --json
    naming the gap as verify does; the numbers come from steps 310-1000."""
    path = _bag(tmp_path / "gap.mcap", _replaced(topics, _without_steps(_named(topics, "plant/state"),
                                                                        list(range(300, 310)))))
    gap = verify_bag(path).topics[-1].coverage.gap_text()
    assert main(["analyze", str(path), "--json"]) == 0
    out = capsys.readouterr()
    summary = json.loads(out.out)
    warning = f"steps missing: {gap}; analysing steps 310-1000, the longest run both plant topics hold"
    assert summary["warnings"] == [warning]
    assert out.err == f"hawt analyze: warning: {warning}\n"
    assert (summary["bag"]["first_step"], summary["bag"]["last_step"]) == (310, 1000)


def test_analyze_warns_of_steps_the_pitch_command_misses_as_verify_names_them(tmp_path, topics, capsys):
    """analyze on a bag whose control/pitch_command misses steps 400-409 (a realtime loop assembler that answered
    late, a recorder that fell behind): a warning naming the gap as verify does, since the command's pitch activity
    is then over the steps the bag holds."""
    path = _bag(tmp_path / "gap.mcap", _replaced(topics, _without_steps(_named(topics, "control/pitch_command"),
                                                                        list(range(400, 410)))))
    gap = next(t.coverage for t in verify_bag(path).topics if t.coverage.topic.endswith("pitch_command")).gap_text()
    assert gap == "/wt1/control/pitch_command misses 10 steps in 1 gap, the first after step 399"
    assert main(["analyze", str(path), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["warnings"] == [f"{gap}; the command's pitch activity is over the steps it holds"]
