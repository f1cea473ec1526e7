"""hawt bag recover on damaged bytes: a damaged chunk is skipped, every intact chunk after it kept, the loss named."""
import io
import struct
from collections import Counter

import pytest
from mcap.data_stream import ReadDataStream
from mcap.reader import make_reader
from mcap.records import Chunk, Message
from mcap.stream_reader import breakup_chunk

from hawt_analysis.synthetic_run import synthetic_channels
from hawt_bag.column_writing import plant_topics, write_topics
from hawt_bag.reader import BagReader
from hawt_bag.recover import recover_bag
from hawt_bag.verification import verify_bag
from hawt_bag.writer import BagWriter
from hawt_tools.cli import main


@pytest.fixture(scope="module")
def intact(tmp_path_factory):
    """A finished 6 s, 100 Hz plant bag under /wt1 (3 topics, steps 0-600) in chunks of 8 kB (about 30)."""
    path = tmp_path_factory.mktemp("intact") / "run.mcap"
    with BagWriter(path, chunk_size=8000) as writer:
        write_topics(writer, plant_topics(synthetic_channels(duration=6.0, sample_rate=100.0), "/wt1"))
    return path


def _chunks(path):
    """Each chunk of a finished bag, in file order: (first byte, first byte of the next chunk or of the data end,
    its messages as (topic, log time, data))."""
    data = path.read_bytes()
    with open(path, "rb") as stream:
        summary = make_reader(stream).get_summary()
    indexes = sorted(summary.chunk_indexes, key=lambda index: index.chunk_start_offset)
    data_end = struct.unpack_from("<Q", data, len(data) - 8 - 20)[0] - 13  # footer's summary start - data end record
    found = []
    for index, following in zip(indexes, [i.chunk_start_offset for i in indexes[1:]] + [data_end]):
        start = index.chunk_start_offset
        chunk = Chunk.read(ReadDataStream(io.BytesIO(data[start + 9:start + index.chunk_length])))
        found.append((start, following, [(summary.channels[m.channel_id].topic, m.log_time, m.data)
                                          for m in breakup_chunk(chunk) if isinstance(m, Message)]))
    return found


def _messages(path):
    with BagReader(path) as reader:
        return [(m.topic, m.log_time, m.data) for m in reader.messages()]


def _damaged(intact, path, *chunk_numbers):
    """A copy of ``intact`` with 64 bytes inverted in the middle of each of these chunks."""
    data = bytearray(intact.read_bytes())
    for start, end, _ in (_chunks(intact)[k] for k in chunk_numbers):
        middle = (start + end) // 2 - 32
        data[middle:middle + 64] = bytes(b ^ 0xFF for b in data[middle:middle + 64])
    path.write_bytes(bytes(data))
    return path


def _without(intact, *chunk_numbers):
    lost = {message for k in chunk_numbers for message in _chunks(intact)[k][2]}
    return [message for message in _messages(intact) if message not in lost]


def test_a_damaged_chunk_is_skipped_and_every_message_of_every_other_chunk_is_kept(intact, tmp_path):
    """64 bytes damaged in the middle of chunk 12: recover keeps every message of the other chunks, names the
    skipped bytes (chunk 12 and its message indexes), the messages lost per topic and the log times around them;
    the recovered bag reads, and verify finds in each topic exactly the steps the report says were lost."""
    chunks = _chunks(intact)
    start, end, lost = chunks[12]
    result = recover_bag(_damaged(intact, tmp_path / "run.mcap", 12))
    assert _messages(result.output) == _without(intact, 12)
    (span,) = result.spans
    assert (span.start, span.end) == (start, end) and "CRCValidationError" in span.reason
    assert span.lost == Counter(topic for topic, _, _ in lost)
    assert (span.before, span.after) == (chunks[11][2][-1][1], chunks[13][2][0][1])
    assert result.stopped == "end of data section" and result.orphans == 0
    assert {check.coverage.topic: (check.coverage.missing, len(check.coverage.gaps))
            for check in verify_bag(result.output).topics} == {topic: (count, 1) for topic, count in span.lost.items()}
    lines = result.text().splitlines()
    assert lines[1] == (f"skipped damaged bytes {start}-{end} ({span.reason}): lost "
                        f"{', '.join(f'{topic} {count}' for topic, count in sorted(span.lost.items()))}; "
                        f"last message kept before it at log time {span.before / 1e9:.3f} s, "
                        f"first after it at log time {span.after / 1e9:.3f} s")


def test_two_damaged_chunks_are_two_spans_and_the_chunks_between_them_are_kept(intact, tmp_path):
    """Chunks 5 and 20 damaged: two spans, each naming its chunk; every message of the others is kept."""
    chunks = _chunks(intact)
    result = recover_bag(_damaged(intact, tmp_path / "run.mcap", 5, 20))
    assert _messages(result.output) == _without(intact, 5, 20)
    assert [(span.start, span.end) for span in result.spans] == [chunks[5][:2], chunks[20][:2]]
    assert [sum(span.lost.values()) for span in result.spans] == [len(chunks[5][2]), len(chunks[20][2])]


def test_a_chunk_length_past_the_end_of_the_file_is_skipped_without_reading_it(intact, tmp_path):
    """Chunk 12's length field set to 2^62: not a record (no allocation of that size); the scan finds chunk 13,
    and since chunk 12 cannot be framed its message indexes are not read: the messages lost are unknown."""
    chunks = _chunks(intact)
    data = bytearray(intact.read_bytes())
    data[chunks[12][0] + 1:chunks[12][0] + 9] = struct.pack("<Q", 2 ** 62)
    path = tmp_path / "run.mcap"
    path.write_bytes(bytes(data))
    result = recover_bag(path)
    assert _messages(result.output) == _without(intact, 12)
    (span,) = result.spans
    assert (span.start, span.end, span.lost) == (chunks[12][0], chunks[12][1], None)
    assert span.reason == f"McapError: record length {2 ** 62} runs past the end of the file"
    assert "lost an unknown number of messages (message indexes unreadable)" in result.text()


def test_a_bag_cut_inside_a_chunk_keeps_the_chunks_before_the_cut(intact, tmp_path):
    """A finished bag cut in the middle of chunk 12 (a disk that filled): the chunks before it are kept, reading
    stops at chunk 12 naming its byte, and no span is reported (nothing after the cut was skipped)."""
    chunks = _chunks(intact)
    start, end, _ = chunks[12]
    path = tmp_path / "run.mcap"
    path.write_bytes(intact.read_bytes()[:(start + end) // 2])
    result = recover_bag(path)
    assert _messages(result.output) == _without(intact, *range(12, len(chunks)))
    assert result.spans == ()
    assert result.stopped.startswith(f"byte {start}: McapError: record length ")
    assert result.stopped.endswith(" runs past the end of the file; no intact chunk after it")


def test_a_lost_channel_record_is_taken_from_the_summary_else_its_messages_are_counted(intact, tmp_path):
    """Chunk 0 holds the schema and channel records. Damaged in a finished bag, the summary's copies let every
    later chunk be kept; in a bag without summary (writer killed) the later messages are skipped and counted."""
    chunks = _chunks(intact)
    finished = recover_bag(_damaged(intact, tmp_path / "finished.mcap", 0))
    assert _messages(finished.output) == _without(intact, 0) and finished.orphans == 0
    assert finished.spans[0].before is None
    data = (tmp_path / "finished.mcap").read_bytes()
    killed = tmp_path / "killed.mcap"
    killed.write_bytes(data[:chunks[20][0]])
    result = recover_bag(killed)
    assert result.counts == {} and result.stopped == "end of file"
    assert result.orphans == sum(len(messages) for _, _, messages in chunks[1:20])
    assert result.text().splitlines()[-1] == f"skipped {result.orphans} messages whose channel record was lost"


def test_hawt_bag_recover_prints_the_recovery_and_the_damaged_span(intact, tmp_path, capsys):
    """The command prints what it recovered, then one line per damaged span; exit 0."""
    path = _damaged(intact, tmp_path / "run.mcap", 12)
    assert main(["bag", "recover", str(path)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith(f"recovered {len(_without(intact, 12))} messages into {tmp_path / 'run.recovered.mcap'}")
    assert out[1].startswith(f"skipped damaged bytes {_chunks(intact)[12][0]}-{_chunks(intact)[12][1]} ")
    assert len(out) == 2


def test_hawt_bag_recover_of_a_file_with_no_readable_message_says_so_in_one_line_and_writes_nothing(intact, tmp_path,
                                                                                                     capsys):
    """A recording killed before its first chunk was written (its first 5000 bytes, as a new user cut one) holds
    no message to rescue: exit 2, one line saying so and where reading stopped, and no empty bag beside it."""
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(intact.read_bytes()[:_chunks(intact)[0][0] + 100])
    assert main(["bag", "recover", str(cut)]) == 2
    out = capsys.readouterr()
    assert out.out == "" and out.err.count("\n") == 1
    assert out.err.startswith(f"hawt bag: {cut}: nothing to recover, no readable message (reading stopped at: ")
    assert not (tmp_path / "cut.recovered.mcap").exists()
