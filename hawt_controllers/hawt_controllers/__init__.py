"""Controller cores of the hawt toolkit: pure numpy/scipy, no ROS.

Modules: ``mbc`` (Coleman transform), ``filters``, ``saturation``, ``pi``, ``exceptions``,
``limits`` (per-blade pitch limits), ``collective`` (NREL 5 MW baseline of
Jonkman et al. 2009), ``ipc`` (one harmonic's IPC law) and ``ipc_tuning``
(gain and phase-offset design). The ROS nodes wrap these cores.
"""
