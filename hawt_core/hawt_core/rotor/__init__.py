"""Rotor math shared by controllers and analysis: the Coleman transform of one harmonic (``mbc``), hub moments
between the rotating and fixed frames (``hub_frame``) and harmonic estimation over revolutions
(``harmonic_estimator``)."""
