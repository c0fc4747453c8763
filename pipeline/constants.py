"""Physical constants, unit factors and fixed names, named once for the whole package."""

#: Standard acceleration of gravity [m s-2] (CGPM 1901; also UDUNITS ``standard_free_fall``).
G = 9.80665

#: Centimetre to metre, and metre to centimetre.
CM_TO_M = 0.01
M_TO_CM = 100.0

#: The gravity value the Shahi & Baker (2014) MATLAB code uses [m s-2] (981 cm/s^2).
G_MATLAB = 9.81

#: The reference paper, named in full wherever it is cited (docstrings, outputs' provenance, report).
REFERENCE_PAPER = ('"Rocking Blocks Stability under Critical Pulses from Near-Fault Earthquakes Using a Novel '
                   'Energy Based Approach", Applied Sciences (MDPI)')

#: Sub-directory of an output directory holding the run state (lock, caches, manifest).
STATE_DIR = ".rockscreen"
