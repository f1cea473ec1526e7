"""MCAP bags of hawt runs (DESIGN §7).

Library modules need no ROS: `writer` (BagWriter), `reader` (BagReader, BagInfo),
`topic_columns` (a topic as numpy arrays), `cdr_columns` (vectorised CDR),
`recover`, `column_writing` (bags from arrays), `plant_run` (a run's topics as the
channel arrays the analysis takes), `step_coverage` and `verification` (``hawt bag
verify``). The analysis of a bag (``hawt analyze``/``compare``) is hawt_analysis's. The nodes are `recorder` and
`replayer` (rclpy). Nothing is imported here, so importing a library module never
loads rclpy.
"""
