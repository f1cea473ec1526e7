"""What every hawt core and node agrees on, without ROS.

Modules: ``topics`` (topic and service names, DESIGN §5), ``command_interfaces`` (the
interfaces controllers claim, DESIGN §4.1), ``step_sync`` (matching the inputs of one plant
step), ``parameter_table`` (declarative parameter tables) and ``plant_description`` (the
facts of the plant every node takes from ``plant/description``). Importing any of them
imports no rclpy, so the numeric cores may.
"""
