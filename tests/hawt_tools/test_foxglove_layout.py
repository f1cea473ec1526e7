"""The shipped Foxglove layout: generated from hawt_tools.foxglove_layout, and every path names a real field."""
import json
import re
from pathlib import Path

from hawt_bag.interface_files import schema_text
from hawt_bag.msg_definition import parse_msg
from hawt_tools.foxglove_layout import layout_text

SHIPPED = Path(__file__).resolve().parents[2] / "hawt_tools" / "foxglove" / "hawt_layout.json"
TYPES = {"plant/blade_loads": "hawt_msgs/msg/BladeLoads", "plant/state": "hawt_msgs/msg/TurbineState",
         "control/events": "hawt_msgs/msg/ControlEvent"}


def _values(tree) -> list:
    if isinstance(tree, dict):
        return [v for key, v in tree.items() if key in ("value", "topicPath")] + \
            [found for v in tree.values() for found in _values(v)]
    if isinstance(tree, list):
        return [found for v in tree for found in _values(v)]
    return []


def test_the_shipped_layout_is_the_generated_one():
    """hawt_layout.json equals what ``python -m hawt_tools.foxglove_layout`` writes."""
    assert SHIPPED.read_text() == layout_text()


def test_every_path_of_the_layout_is_a_field_of_its_topics_type():
    """Each series and topic path names a topic of /wt1 with a known type and, after the dot, one of its fields
    (array index within B = 3)."""
    paths = _values(json.loads(SHIPPED.read_text()))
    assert len(paths) >= 15
    for path in paths:
        match = re.fullmatch(r"/wt1/(\w+/\w+)(?:\.(\w+)(?:\[(\d)\])?)?", path)
        assert match and match[1] in TYPES, path
        if match[2]:
            type_name = TYPES[match[1]]
            fields = {f.name: f for f in parse_msg(schema_text(type_name).split("\n" + "=" * 80)[0], type_name).fields}
            assert match[2] in fields, path
            assert (match[3] is not None) == bool(fields[match[2]].array) and int(match[3] or 0) < 3, path
