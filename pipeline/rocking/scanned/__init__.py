"""Bodies given by their scans: rolling on the hull in a plane (rolling.py), rocking on one pivot per side
(two_sided.py), and the planes a scan is judged in and one plane's scene (planes.py)."""
