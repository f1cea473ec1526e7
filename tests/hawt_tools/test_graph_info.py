"""hawt list's text of a discovered graph."""
from hawt_tools.graph_info import GraphSnapshot, TopicInfo


def test_a_node_name_several_nodes_share_is_listed_once_with_their_count():
    """Two graphs started in one ROS_DOMAIN_ID (a new user's demo beside a launch) give each name twice: the
    listing names it once and says why it matters, instead of repeating it."""
    snapshot = GraphSnapshot(nodes=("/wt1/mbc", "/wt1/mbc", "/wt1/plant", "/wt1/cpc", "/wt1/cpc"),
                             topics=(TopicInfo("/wt1/plant/blade_loads", ("hawt_msgs/msg/BladeLoads",), 2, 4),))
    lines = snapshot.text().splitlines()
    assert lines[:4] == [
        "nodes (5):",
        "  /wt1/mbc  (2 nodes of this name: several graphs in this ROS_DOMAIN_ID? their topics mix)",
        "  /wt1/plant",
        "  /wt1/cpc  (2 nodes of this name: several graphs in this ROS_DOMAIN_ID? their topics mix)"]
