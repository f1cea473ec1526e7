"""The hawt command line: what a user types is what the command receives."""
import pytest

from hawt_tools.cli import parse_command_line


@pytest.mark.parametrize("argv", [
    ["launch", "ipc", "--composed", "duration:=10", "seed:=3"],
    ["launch", "--composed", "ipc", "duration:=10", "seed:=3"],
    ["launch", "ipc", "duration:=10", "--composed", "seed:=3"],
])
def test_graph_arguments_may_come_before_or_after_the_options(argv):
    """NAME:=VALUE words are the graph's arguments wherever they stand among the options."""
    args = parse_command_line(argv)
    assert (args.graph, args.composed, sorted(args.arguments)) == ("ipc", True, ["duration:=10", "seed:=3"])


def test_a_stray_word_is_refused_with_its_name(capsys):
    """A word that is neither an option nor NAME:=VALUE stops the command and is named."""
    with pytest.raises(SystemExit):
        parse_command_line(["launch", "ipc", "--composed", "stray"])
    assert "unrecognized arguments: stray" in capsys.readouterr().err


def test_a_reader_that_stops_early_ends_the_command_quietly(hawt_cli, tmp_path):
    """``hawt bag info BAG | head -1``: the first line reaches the reader, then the command ends with exit 0 and
    nothing on stderr, not a BrokenPipeError traceback (the listing is far longer than a pipe holds)."""
    import subprocess

    import numpy as np

    from hawt_bag.column_writing import TopicData, write_topics
    from hawt_bag.writer import BagWriter

    bag = tmp_path / "many_topics.mcap"
    with BagWriter(bag) as writer:
        write_topics(writer, [TopicData(f"/topic_number_{i}/plant/blade_loads", "hawt_msgs/msg/BladeLoads",
                                        {"step": np.arange(1, dtype=np.uint64)}, np.zeros(1, dtype=np.int64))
                              for i in range(2000)])
    info = subprocess.Popen([*hawt_cli, "bag", "info", str(bag)], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    first = info.stdout.readline()
    info.stdout.close()
    assert first and info.wait(timeout=120) == 0
    assert info.stderr.read() == b""
