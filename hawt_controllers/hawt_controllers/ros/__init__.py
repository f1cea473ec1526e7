"""The ROS 2 nodes around the controller cores: the generic controller node, mbc, controller_manager."""
