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
tilted beyond the body's smallest static tipping angle: a rock that topples comes to rest on a face short of its side
(the granite rocks of the shake-table benchmark at 72-73 deg). The static tipping angle toward a horizontal
direction is the tilt at which G passes over the hull's lowest point as the body turns about the horizontal axis
normal to it (:func:`tipping_rad`, exact on the hull's outline in that plane); the smallest is sought over the
directions of a :data:`TIPPING_STEP_DEG` grid, so it is at least the true least, by up to the change of the
tipping angle over one step.

References
----------
Mirtich, B. (1996). Fast and accurate computation of polyhedral mass properties. Journal of Graphics Tools 1(2),
31-50.
"""

from __future__ import annotations

import math

import numpy as np

from ...compiled import jit
from ...shapes.scan import OUTLINE_STEP_DEG, Outlines, ScannedShape, outline_rings
from ..solids.convex_body import ConvexBody

#: The grid of horizontal directions over which the smallest static tipping angle is sought [deg]: that of the
#: outlines a scan keeps
TIPPING_STEP_DEG = OUTLINE_STEP_DEG


def tipping_rad(hull_m: np.ndarray, com_height_m: float, azimuth_deg: float) -> float:
    """The static tipping angle of a body standing on its hull toward the horizontal direction ``azimuth_deg`` (from
    x toward y) [rad]: the tilt at which G passes over the lowest point, walking the hull's outline in that vertical
    plane from the base outward (each vertex is the lowest from the tilt its previous edge lies flat to the tilt its
    next edge does; G passes over it at the angle of its arm from the downward vertical); pi/2 at most."""
    from scipy.spatial import ConvexHull

    phi = math.radians(azimuth_deg)
    u = hull_m[:, 0] * math.cos(phi) + hull_m[:, 1] * math.sin(phi)
    w = hull_m[:, 2] - com_height_m
    ring = ConvexHull(np.column_stack([u, w])).vertices
    return float(_walk(np.ascontiguousarray(u[ring]), np.ascontiguousarray(w[ring]),
                       1e-12 * max(float(np.max(np.abs(u))), float(np.max(np.abs(w))))))


@jit
def _walk(u, w, tol):
    """:func:`tipping_rad`'s walk over an outline: its points' offsets ``u`` toward the direction and heights ``w``
    relative to G [m], counter-clockwise; the base's lowest points within ``tol`` [m] [rad]."""
    n = u.size
    low = np.min(w)
    k = -1
    for j in range(n):                                      # the base's end toward +u (the first of equals)
        if w[j] <= low + tol and (k < 0 or u[j] > u[k]):
            k = j
    flat = 0.0
    for _ in range(n):
        nxt = (k + 1) % n
        edge = math.atan2(w[nxt] - w[k], u[nxt] - u[k])
        arm = math.atan2(u[k], -w[k])
        if arm <= edge or edge >= 0.5 * math.pi:
            return min(max(flat, arm), 0.5 * math.pi)
        flat, k = edge, nxt
    return 0.5 * math.pi


@jit
def _smallest_on(hull_m, com_height_m, azimuths_deg, vertices, starts):
    """:func:`smallest_tipping` on the outlines (:class:`~pipeline.shapes.scan.Outlines`' arrays)."""
    best, best_k = math.inf, 0
    for a in range(azimuths_deg.size):
        phi = math.radians(azimuths_deg[a])
        c, s = math.cos(phi), math.sin(phi)
        big = 0.0
        for i in range(hull_m.shape[0]):
            big = max(big, abs(hull_m[i, 0] * c + hull_m[i, 1] * s), abs(hull_m[i, 2] - com_height_m))
        m = starts[a + 1] - starts[a]
        u, w = np.empty(m), np.empty(m)
        for j in range(m):
            i = vertices[starts[a] + j]
            u[j], w[j] = hull_m[i, 0] * c + hull_m[i, 1] * s, hull_m[i, 2] - com_height_m
        angle = _walk(u, w, 1e-12 * big)
        if angle < best:
            best, best_k = angle, a
    return best, azimuths_deg[best_k]


def smallest_tipping(hull_m: np.ndarray, com_height_m: float, *, step_deg: float = TIPPING_STEP_DEG,
                     outlines: Outlines | None = None) -> tuple[float, float]:
    """The least static tipping angle over the horizontal directions every ``step_deg`` [rad], and that direction
    [deg, from x toward y] (the first of equals); ``outlines``: the hull's outline in each of those directions
    (:attr:`~pipeline.shapes.scan.ScannedShape.outlines`), else found here."""
    hull = np.ascontiguousarray(hull_m, dtype=float)
    if outlines is None or len(outlines.azimuths_deg) != len(np.arange(0.0, 360.0, step_deg)):
        outlines = outline_rings(hull, step_deg=step_deg)
    angle, azimuth = _smallest_on(hull, float(com_height_m), outlines.azimuths_deg, outlines.vertices,
                                  outlines.starts)
    return float(angle), float(azimuth)


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
                      tipping_rad=smallest_tipping(shape.hull_m, shape.com_height_m, outlines=shape.outlines)[0])


def scaled_scan(shape: ScannedShape, width_factor: float, height_factor: float) -> ScannedShape:
    """The scan stretched by ``width_factor`` horizontally and ``height_factor`` vertically about G (a draw of its
    sizes): its hull, G's height and its inertia per unit mass (the second moments C = tr(I) / 2 - I scale as
    S C S, S = diag(w, w, h); I = tr(C) - C) [-]."""
    stretch = np.array([width_factor, width_factor, height_factor])
    inertia = np.asarray(shape.inertia_per_mass_m2, dtype=float)
    moments = 0.5 * np.trace(inertia) * np.eye(3) - inertia
    moments = moments * np.outer(stretch, stretch)
    g = np.array([0.0, 0.0, shape.com_height_m])
    return shape._replace(hull_m=(np.asarray(shape.hull_m, dtype=float) - g) * stretch + g * height_factor,
                          vertices_m=(np.asarray(shape.vertices_m, dtype=float) - g) * stretch + g * height_factor,
                          com_height_m=shape.com_height_m * height_factor,
                          volume_m3=shape.volume_m3 * width_factor ** 2 * height_factor,
                          inertia_per_mass_m2=np.trace(moments) * np.eye(3) - moments)
