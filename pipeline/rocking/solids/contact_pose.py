"""How a body of the 3D contact model (:mod:`.contact3d`) stands and how far it has moved from it: its standing pose,
its size, its lowest point, its tilt, heading and lean, and the record of its tilt at the record's samples.

**Overturned** is the body lying on a side: its axis tilted to within :data:`LYING_SLACK_RAD` of the horizontal, or
(with its smallest static tipping angle) at rest on another face tilted beyond it (:class:`Pose`'s ``toppled``).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...compiled import jit, jit_inline
from .convex_body import hull_side

#: The body lies on a side once its tilt is within this of pi/2 [rad]: more than the overlap of a landing step
#: (h times the landing speed over the body's size: 1.6e-4 rad measured, a 0.5 x 0.5 x 1.5 m box on a real record);
#: at that tilt the centre of mass of a box or cylinder less slender than 89.4 deg is beyond its pivot.
LYING_SLACK_RAD = 1e-2
#: Its base: the vertices within this fraction of the body's size above its lowest as it stands [-].
BASE_TOL = 1e-9


class Pose(NamedTuple):
    """How the body stands, for the kernel: its principal axes' orientation as it stands (unit quaternion (w, x, y,
    z)), the body-axis vectors that point up and along x as it stands, its vertices in those standing axes, the
    tilt beyond which a rest on another face is an overturning [rad], and its base's polygon seen from above: its
    edges' outward normals and distances from G's foot (rows (nx, ny, d), :func:`base_edges`) and how many
    (``n_base``; 0: none taken, then its flat steps are off: :mod:`.flat_slide`)."""

    q_rest: np.ndarray
    up: np.ndarray
    x_ref: np.ndarray
    standing: np.ndarray
    toppled: float
    base: np.ndarray
    n_base: int


def pose(vertices: np.ndarray, rest: np.ndarray | None, tipping_rad: float = math.nan, *, base: bool = True) -> Pose:
    """The kernel's :class:`Pose` of a body whose principal axes turn by ``rest`` into the axes it stands in (with
    ``base``, its base's polygon; without, none)."""
    toppled = 0.5 * math.pi - LYING_SLACK_RAD if math.isnan(tipping_rad) else float(tipping_rad)
    if rest is None:
        q_rest, up, x_ref, standing = np.array([1.0, 0.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0]), np.array(
            [1.0, 0.0, 0.0]), vertices
    else:
        rot = np.asarray(rest, dtype=float)
        if not (np.allclose(rot @ rot.T, np.eye(3), atol=1e-9) and np.linalg.det(rot) > 0.0):
            raise ValueError(f"rest is not a rotation matrix (R R^T - I up to "
                             f"{np.abs(rot @ rot.T - np.eye(3)).max():.2g}, det {np.linalg.det(rot):.6g}); give the "
                             "principal axes' orientation as it stands")
        from scipy.spatial.transform import Rotation

        x, y, z, w = Rotation.from_matrix(rot).as_quat()
        q_rest, up, x_ref = np.array([w, x, y, z]), np.ascontiguousarray(rot[2]), np.ascontiguousarray(rot[0])
        standing = np.ascontiguousarray(vertices @ rot.T)
    edges = np.empty((len(standing), 3))
    n_base = base_edges(standing, extent(standing)[0], edges) if base else 0
    return Pose(q_rest, up, x_ref, standing, toppled, edges, int(n_base))


@jit
def extent(vertices):
    """The body's size (its farthest vertex from G) and the height of G above its lowest vertex [m]."""
    size = 0.0
    z0 = 0.0
    for i in range(vertices.shape[0]):
        size = max(size, math.sqrt(vertices[i, 0] ** 2 + vertices[i, 1] ** 2 + vertices[i, 2] ** 2))
        z0 = max(z0, -vertices[i, 2])
    return size, z0


@jit
def base_edges(standing, size, out):
    """The edges of the base's polygon seen from above (the vertices ``standing``, in the axes the body stands in,
    within :data:`BASE_TOL` of ``size`` of the lowest; :func:`~.convex_body.hull_side`) into the rows of ``out``: the
    outward unit normal (nx, ny) and the distance d of the edge's line from G's foot, inside where nx x + ny y <= d;
    how many (0: the base spans no area, or G's foot is not inside it)."""
    n = standing.shape[0]
    zmin = math.inf
    for i in range(n):
        zmin = min(zmin, standing[i, 2])
    keep, tol, m = zmin + BASE_TOL * size, BASE_TOL * size, 0
    for i in range(n):
        if standing[i, 2] > keep:
            continue
        for j in range(i + 1, n):
            if standing[j, 2] > keep:
                continue
            side, ex, ey, length = hull_side(standing, n, i, j, keep, tol)
            if side == 1 or side == -1:             # a hull edge; the others lie on the side of sign ``side``
                nx, ny = side * ey / length, -side * ex / length
                d = nx * standing[i, 0] + ny * standing[i, 1]
                if d <= 0.0:
                    return 0
                out[m, 0], out[m, 1], out[m, 2] = nx, ny, d
                m += 1
    return m


@jit_inline
def lowest(vertices, r):
    """The height of the lowest vertex above G, the body turned by ``r`` [m]."""
    low = math.inf
    for i in range(vertices.shape[0]):
        low = min(low, r[2, 0] * vertices[i, 0] + r[2, 1] * vertices[i, 1] + r[2, 2] * vertices[i, 2])
    return low


@jit_inline
def along(r, u, row):
    """Component ``row`` of the world vector R u."""
    return r[row, 0] * u[0] + r[row, 1] * u[1] + r[row, 2] * u[2]


@jit_inline
def tilt_of(r, up):
    """The tilt from where it stood: the angle of its standing up axis ``up`` from the vertical [rad]."""
    return math.acos(min(1.0, max(-1.0, along(r, up, 2))))


@jit_inline
def heading(r, x_ref):
    """Where its standing x axis ``x_ref`` points, seen from above, from x toward y [rad]."""
    return math.atan2(along(r, x_ref, 1), along(r, x_ref, 0))


@jit_inline
def lean_of(r, up, tilt):
    """Where its standing up axis leans, from x toward y [rad] (NaN upright)."""
    return math.atan2(along(r, up, 1), along(r, up, 0)) if tilt > 0.0 else math.nan


@jit_inline
def record(hist, i, tilt, lean):
    """The tilt and lean at sample ``i`` into ``hist`` (no row: no history kept)."""
    if i < hist.shape[0]:
        hist[i, 0], hist[i, 1] = tilt, lean


@jit_inline
def degrees(angle_rad):
    """An angle [rad] in degrees (NaN stays NaN)."""
    return math.degrees(angle_rad) if math.isfinite(angle_rad) else math.nan


@jit_inline
def lie_down(hist, first, lean):
    """The samples from ``first`` on recorded lying on a side, leaning toward ``lean``."""
    for i in range(first, hist.shape[0]):
        record(hist, i, 0.5 * math.pi, lean)


@jit_inline
def measure(r, x, pose, yaw, hist, k, n_sub, tilt_max, lean_peak, slide_max, twist_max):
    """The body turned by ``r`` with G at ``x`` after step ``k``: its tilt, recorded at a sample, and the run's
    largest tilt (where it leant then), slide and twist so far."""
    tilt = tilt_of(r, pose.up)
    if tilt > tilt_max:
        tilt_max, lean_peak = tilt, lean_of(r, pose.up, tilt)
    if k % n_sub == 0 and k // n_sub < hist.shape[0]:
        record(hist, k // n_sub, tilt, lean_of(r, pose.up, tilt))
    slide_max = max(slide_max, math.sqrt(x[0] * x[0] + x[1] * x[1]))
    if along(r, pose.up, 2) > 0.0:                             # the yaw of its x axis, from where it stood
        turn = (heading(r, pose.x_ref) - yaw + math.pi) % (2.0 * math.pi) - math.pi
        twist_max = max(twist_max, abs(turn))
    return tilt, tilt_max, lean_peak, slide_max, twist_max
