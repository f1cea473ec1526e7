"""MCAP bags of hawt runs (DESIGN §7).

Library modules need no ROS: `writer` (BagWriter), `reader` (BagReader, BagInfo),
`topic_columns` (a topic as numpy arrays), `cdr_columns` (vectorised CDR),
`recover`, `column_writing` (bags from arrays), `plant_run` and `run_analysis`
(``hawt analyze``/``compare``), `analysis_report`. The nodes are `recorder` and
`replayer` (rclpy). Nothing is imported here, so importing a library module never
loads rclpy.
"""
