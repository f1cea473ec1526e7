"""Controllers of the hawt toolkit, in layers (docs/architecture.md §2 has the table of allowed imports):

- ``laws``: the control laws and the math they run on (PI, filters, the baseline collective law, one harmonic's
  IPC, repetitive control, LQG), plain numpy/scipy;
- ``plugins``: the controller plug-in framework (``controller``, ``loop_assembly``, ``switching``, ``registry``) and
  the plug-ins, one ``<type>.py`` each, found by type through the ``hawt.controllers`` entry points;
- ``discon``: Bladed-style DISCON libraries (ROSCO) called through ctypes;
- ``design``: tuning, linear models and LQG design from the plant, the only layer that imports hawt_plant;
- ``ros``: the nodes (one generic controller node, the loop assembler, the controller manager).
"""
