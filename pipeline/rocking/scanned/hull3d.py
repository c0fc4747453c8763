"""A body given by its scan, in 3D: its convex hull as the 3D contact model's body (:mod:`..solids.contact3d`), so
that it can slide, twist, rock on an edge or a corner, roll over its hull's facets and lift off under both
horizontals at once, instead of rocking in one vertical plane.

The scan, settled on its flat base (:func:`pipeline.shapes.scan.read_scan`), gives the hull's vertices, the centre of
mass G and the inertia about G per unit mass in its settled axes (uniform density; Mirtich 1996). The contact model
takes the body in its principal axes: the inertia's eigenvectors, ordered as :func:`numpy.linalg.eigh` returns them
and turned into a right-handed frame, and the rotation ``rest`` from them into the settled axes, which is how the body
stands at the start and what its tilt is measured from. Every hull vertex is a candidate contact (the scan's facets
are the body's surface; a curved base is its facets' polygon).

**Overturned** is lying on a side, as for any body, or coming to rest after the record on another face of the hull
tilted beyond the body's smallest static tipping angle (the tilt at which G passes over the hull's lowest point,
:func:`pipeline.shapes.scan.pivots`, the least over the vertical planes of a :data:`TIPPING_STEP_DEG` grid, both
senses): a rock that topples comes to rest on a face short of its side (the granite rocks of the shake-table
benchmark at 72-73 deg). The grid's least is at least the true least, by up to the tipping angle's change over one
step of the grid.

References
----------
Mirtich, B. (1996). Fast and accurate computation of polyhedral mass properties. Journal of Graphics Tools 1(2),
31-50.
"""

from __future__ import annotations

import numpy as np

from ...shapes.scan import ScannedShape, pivots
from ..solids.convex_body import ConvexBody

#: The grid of vertical planes over which the smallest static tipping angle is sought [deg]
TIPPING_STEP_DEG = 5.0


def smallest_tipping_rad(shape: ScannedShape, *, step_deg: float = TIPPING_STEP_DEG) -> float:
    """The least static tipping angle of the settled scan over the vertical planes every ``step_deg``, both senses
    [rad]."""
    return min(min(pv.tipping_plus, pv.tipping_minus)
               for pv in (pivots(shape, float(az)) for az in np.arange(0.0, 180.0, step_deg)))


def scan_body(shape: ScannedShape, *, mu: float, restitution: float = 0.0) -> ConvexBody:
    """The 3D contact model's body of a scan settled on its base.

    Parameters
    ----------
    shape : ScannedShape
        The scan (:func:`~pipeline.shapes.scan.read_scan`): its hull in the settled axes, the base at z = 0.
    mu : float
        Friction coefficient at every contact [-] (``inf``: no sliding).
    restitution : float
        Newton's normal restitution at a contact [-] (0: plastic, Housner's rule at a pivot).

    Returns
    -------
    ConvexBody
        Its hull's vertices about G in its principal axes [m], its principal inertias per unit mass [m2],
        ``rest``, the rotation from those axes into the settled ones, and its smallest static tipping angle.
    """
    inertia = np.asarray(shape.inertia_per_mass_m2, dtype=float)
    moments, axes = np.linalg.eigh(0.5 * (inertia + inertia.T))
    if np.linalg.det(axes) < 0.0:                       # a right-handed frame
        axes[:, 2] = -axes[:, 2]
    about_g = np.asarray(shape.hull_m, dtype=float) - np.array([0.0, 0.0, shape.com_height_m])
    return ConvexBody(np.ascontiguousarray(about_g @ axes), moments, float(mu), float(restitution), rest=axes,
                      tipping_rad=smallest_tipping_rad(shape))
