"""What every hawt node process shares, above hawt_core and below the nodes and the CLI.

Modules: ``node_main`` (a node's process: start, spin, flush, stop), ``parameters`` (declaring a
parameter table on a node), ``events`` (``control/events``), ``qos`` (the control loop's QoS
profiles) and ``scheduling`` (realtime priority of node processes).
"""
