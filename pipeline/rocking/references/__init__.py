"""Second algorithms and inputs for the tests and benchmarks: the solve_ivp reference of planar rocking
(reference.py) and of two-sided rocking (asymmetric.py), idealized pulses (excitation.py)."""
