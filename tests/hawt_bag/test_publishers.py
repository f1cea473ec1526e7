"""Bags that name who published each message: a channel per topic and publisher, every reader reads the topic whole,
and hawt analyze counts the pitch commands the plant refused (an intruder's) apart from the ones it applied."""
import dataclasses

import numpy as np
import pytest

from hawt_analysis.analysis_report import analysis_text
from hawt_analysis.run_analysis import analyze_bag
from hawt_analysis.synthetic_run import synthetic_channels
from hawt_bag.cdr_columns import encode_messages
from hawt_bag.column_writing import TopicData, plant_topics, write_topics
from hawt_bag.interface_files import schema_text
from hawt_bag.msg_definition import parse_schema, short_type_name
from hawt_bag.reader import BagReader
from hawt_bag.recording_parts import join_parts
from hawt_bag.topic_columns import read_topic_columns
from hawt_bag.verification import verify_bag
from hawt_bag.writer import BagWriter
from hawt_node.command_senders import Sample

COMMAND = "/wt1/control/pitch_command"
MBC = "/wt1/mbc"
UNNAMED = "gid 010f5a1b"
"""The recorder's name for a publisher the graph did not name, and the GID the plant's event gives it."""


def _intruder_event(sender: str) -> dict:
    """The plant's intruder event, worded as hawt_plant.plant_node words it, at the intruder's first step."""
    return {"step": 500, "source": "/wt1/plant", "level": 40, "kind": "intruder",
            "detail": f"control/pitch_command step 500 from {sender} refused: only {MBC} may command this plant "
                      "(its later commands are refused and counted)"}


def _sender(publisher: str) -> str:
    """How the plant names the sender that the recorder names ``publisher`` (hawt_node.command_senders)."""
    if publisher == UNNAMED:
        return Sample(None, bytes.fromhex(UNNAMED.removeprefix("gid ")), None, False).who
    return publisher


def _intruder(command: TopicData, steps: np.ndarray) -> TopicData:
    """An intruder's commands at ``steps``: 86 deg and zero torque, each 1 µs before the loop assembler's."""
    columns = {name: np.asarray(values)[steps] for name, values in command.columns.items()}
    columns.update(pitch=np.full((steps.size, 3), 1.5), collective=np.full(steps.size, 1.5),
                   individual=np.zeros((steps.size, 3)), generator_torque=np.zeros(steps.size))
    return TopicData(command.topic, command.type_name, columns, command.log_time[steps] - 1000)


def _write_channel(writer: BagWriter, data: TopicData, publisher: str) -> None:
    """``data`` in the channel of ``publisher``."""
    text = schema_text(data.type_name)
    payloads = encode_messages(parse_schema(text, data.type_name), short_type_name(data.type_name), data.columns,
                               data.log_time.size)
    channel = writer.add_topic(data.topic, data.type_name, definition=text, publisher=publisher)
    for log_time, payload in zip(data.log_time.tolist(), payloads):
        writer.write(channel, log_time, payload)


@pytest.fixture(scope="module")
def channels():
    """A 20 s, 100 Hz run: steps 0-2000."""
    return synthetic_channels(duration=20.0, sample_rate=100.0, seed=4)


def _bag(path, channels, intruder=None, recorded=True):
    """The run under /wt1, its pitch command in mbc's channel; with ``intruder`` (a publisher name) also the plant's
    intruder event naming it and, if ``recorded``, its commands at steps 500-799 in a channel of their own."""
    topics = plant_topics(channels, "/wt1", [_intruder_event(_sender(intruder))] if intruder else [])
    command = next(t for t in topics if t.topic == COMMAND)
    with BagWriter(path) as writer:
        write_topics(writer, [t for t in topics if t is not command])
        _write_channel(writer, command, MBC)
        if intruder and recorded:
            _write_channel(writer, _intruder(command, np.arange(500, 800)), intruder)
    return path


def test_a_topic_of_two_publishers_has_a_channel_each_and_reads_whole(channels, tmp_path):
    """Two channels of the pitch command, each naming its publisher: the readers give one topic, its 2301 messages
    in log-time order with the publisher of each, and bag info one line with both publishers' counts."""
    with BagReader(_bag(tmp_path / "two.mcap", channels, "/intruder")) as reader:
        named = sorted(c.metadata["publisher"] for c in reader.summary.channels.values() if c.topic == COMMAND)
        columns = read_topic_columns(reader, COMMAND, ("step",))
        info = reader.info()
        assert reader.topic_names().count(COMMAND) == 1
    assert named == ["/intruder", MBC]
    assert len(columns) == 2301 and np.all(np.diff(columns.log_time) >= 0)
    assert np.array_equal(columns.fields["step"][columns.publisher == MBC], np.arange(2001))
    assert np.array_equal(columns.fields["step"][columns.publisher == "/intruder"], np.arange(500, 800))
    (topic,) = [t for t in info.topics if t.topic == COMMAND]
    assert (topic.count, topic.publishers) == (2301, ((MBC, 2001), ("/intruder", 300)))
    assert f"| Publishers: {MBC} (2001), /intruder (300)" in info.text()


@pytest.mark.parametrize("intruder", ["/intruder", UNNAMED])
def test_analyze_takes_the_applied_commands_and_counts_the_refused_apart(channels, tmp_path, intruder):
    """An intruder's 86 deg at steps 500-799, each recorded before mbc's command of the step, and the plant's intruder
    event naming it (by node, or by GID for one the graph did not name): the pitch command section is the one of the
    run without it, and refused_commands names it with its count and steps, in the JSON and the text."""
    alone = analyze_bag(_bag(tmp_path / "alone.mcap", channels)).summary
    intruded = analyze_bag(_bag(tmp_path / "intruded.mcap", channels, intruder)).summary
    assert intruded["pitch_command"] == alone["pitch_command"]
    assert intruded["refused_commands"] == [{"publisher": intruder, "messages": 300, "first_step": 500,
                                             "last_step": 799}]
    assert alone["refused_commands"] == [] and intruded["warnings"] == []
    assert f"refused commands   300 from {intruder} (steps 500..799), not in the pitch command above" in \
        analysis_text(intruded).splitlines()
    assert "refused commands" not in analysis_text(alone)


def test_a_bag_that_does_not_name_publishers_says_the_refused_commands_are_mixed_in(channels, tmp_path):
    """A bag with mbc's and the intruder's commands in one channel (recorded before hawt named publishers): the
    analysis cannot tell them apart and says so in one warning."""
    topics = plant_topics(channels, "/wt1", [_intruder_event("/intruder")])
    command = next(t for t in topics if t.topic == COMMAND)
    intruder = _intruder(command, np.arange(500, 800))
    mixed = dataclasses.replace(command, columns={name: np.concatenate([np.asarray(values), intruder.columns[name]])
                                                  for name, values in command.columns.items()},
                                log_time=np.concatenate([command.log_time, intruder.log_time]),
                                publish_time=np.concatenate([command.publish_time, command.publish_time[500:800]]))
    with BagWriter(tmp_path / "old.mcap") as writer:
        write_topics(writer, [mixed if t is command else t for t in topics])
    summary = analyze_bag(tmp_path / "old.mcap").summary
    assert summary["refused_commands"] == []
    assert summary["warnings"] == [f"{COMMAND}: the plant refused the commands of /intruder, but the bag does not tell "
                                   "them from the applied ones (it does not name the publisher of each message): the "
                                   "commanded pitch is analysed from all of them"]


def test_an_intruder_the_bag_does_not_hold_is_named_in_a_warning(channels, tmp_path):
    """The plant refused /intruder, but the bag holds only mbc's channel (the recorder did not receive the
    intruder's commands): the pitch command is mbc's, and a warning says the refused commands are not in the bag."""
    alone = analyze_bag(_bag(tmp_path / "alone.mcap", channels)).summary
    summary = analyze_bag(_bag(tmp_path / "unrecorded.mcap", channels, "/intruder", recorded=False)).summary
    assert summary["pitch_command"] == alone["pitch_command"] and summary["refused_commands"] == []
    assert summary["warnings"] == [f"{COMMAND}: the plant refused the commands of /intruder, but the bag holds none "
                                   "by that name (the recorder did not receive them, or knew their publisher by its "
                                   f"GID only): the commanded pitch is that of {MBC}"]


def test_verify_names_the_publishers_of_the_steps_held_twice(channels, tmp_path):
    """Two publishers' different commands for steps 500-799: DUPLICATE, naming both publishers."""
    report = verify_bag(_bag(tmp_path / "two.mcap", channels, "/intruder"))
    assert report.problems == (f"DUPLICATE — {COMMAND} holds 300 steps twice with different content, the first step "
                               f"500 (sent by /intruder, {MBC})",)


def test_joined_parts_keep_one_channel_per_topic_and_publisher(channels, tmp_path):
    """Two parts of a recording, the intruder in both: the joined bag has its channel and mbc's, each message once."""
    first = _bag(tmp_path / "part1.mcap", channels, "/intruder")
    second = tmp_path / "part2.mcap"
    topics = plant_topics(channels, "/wt1")
    with BagWriter(second) as writer:
        _write_channel(writer, _intruder(next(t for t in topics if t.topic == COMMAND), np.arange(700, 900)),
                       "/intruder")
    joined = join_parts([first, second], tmp_path / "joined.mcap")
    counts = _counts(first)
    assert (joined.taken, joined.repeated) == ((sum(counts.values()), 100), (0, 100))
    assert _counts(joined.output) == {**counts, (COMMAND, "/intruder"): 400}


def _counts(path) -> dict:
    """Messages per (topic, publisher) channel."""
    with BagReader(path) as reader:
        counts = reader.summary.statistics.channel_message_counts
        return {(c.topic, c.metadata.get("publisher")): counts.get(c.id, 0) for c in reader.summary.channels.values()}
