"""Bodies in 3D on two horizontals: the cylinder rocking and rolling on its rim, the box on an edge or a corner
(and the certificate that leaves it in its width's plane), their scenes, and their small compiled helpers."""
