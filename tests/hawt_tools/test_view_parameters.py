"""hawt_tools.view: protocol parameter names and the values set through them."""
import pytest

from hawt_tools.view import coerce, parameter_name, split_parameter_name


@pytest.mark.parametrize("node, name", [("/wt1/ipc_h1", "integral_gain"), ("/plant", "gains.ki"), ("/a/b/c", "x")])
def test_a_parameter_name_splits_back_into_node_and_parameter(node, name):
    """``/ns/node.param`` (a node name has no dot, a parameter name may): the split undoes the join."""
    assert split_parameter_name(parameter_name(node, name)) == (node, name)


@pytest.mark.parametrize("text", ["integral_gain", "wt1/ipc_h1.ki", "/wt1/ipc_h1", "/wt1/ipc_h1."])
def test_a_name_that_is_not_node_dot_parameter_is_refused_naming_it(text):
    with pytest.raises(ValueError, match=f"parameter {text!r}: expected /NODE.PARAMETER"):
        split_parameter_name(text)


@pytest.mark.parametrize("value, current, expected", [
    (2, 1.5, 2.0), ([1, 2], [0.5, 0.5], [1.0, 2.0]), (2, 3, 2), (True, 1.0, True), ("a", 1.0, "a"),
    ([1, 2], [1, 2], [1, 2]), (2.5, None, 2.5)])
def test_a_whole_number_for_a_float_parameter_is_set_as_a_float_and_nothing_else_changes(value, current, expected):
    """JSON writes 2.0 as 2; the node's float parameter would refuse an integer."""
    result = coerce(value, current)
    assert result == expected and type(result) is type(expected)
    if isinstance(expected, list):
        assert [type(item) for item in result] == [type(item) for item in expected]
