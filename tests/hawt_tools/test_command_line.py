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
