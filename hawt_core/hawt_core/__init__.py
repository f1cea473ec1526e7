"""What every hawt core and node agrees on, without ROS.

Modules: ``topics`` (topic and service names, DESIGN §5), ``command_interfaces`` (the
interfaces controllers claim, DESIGN §4.1), ``step_sync`` (matching the inputs of one plant
step), ``parameter_table`` (declarative parameter tables), ``node_role`` (what a node is to the
engines, registered under the ``hawt.nodes`` entry points), ``plant_description`` (the facts of
the plant every node takes from ``plant/description``), ``exceptions`` and ``validation`` (the
errors and checks the cores share), ``rotor`` (the Coleman transform of one harmonic, hub moments
between frames, harmonic estimation), ``scheduling`` (a realtime priority) and ``stop_signals``.
Importing any of them imports no rclpy, so the numeric cores may.
"""
