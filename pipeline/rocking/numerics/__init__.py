"""The compiled integrators' shared numerics: the Dormand-Prince step, its dense output and event location
(dopri.py), the ground's linear pieces and their crossings (ground.py)."""
