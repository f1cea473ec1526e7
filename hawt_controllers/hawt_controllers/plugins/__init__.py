"""The controller plug-in framework and the plug-ins, one ``<type>.py`` per controller type (no ROS)."""
