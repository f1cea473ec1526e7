"""Load analysis of recorded hawt runs: pure numpy/scipy, no ROS.

Modules: `record` (checked channel arrays and their names), `fatigue` (rainflow
DELs), `spectra` (Welch PSD, peaks, nP), `harmonics` (nP amplitudes in the azimuth
domain), `pitch_activity`, `summary` (the ``hawt analyze`` dict), `comparison`
(``hawt compare``), `plots` (PNG reports), `synthetic_run` (test data), and the
analysis of bags: `run_analysis` (``hawt analyze``/``compare`` on MCAP files, read with
hawt_bag) and `analysis_report` (their text and HTML reports).
Nothing is imported here, so ``import hawt_analysis.summary`` stays free of matplotlib.
"""
