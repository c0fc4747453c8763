"""A rigid convex body for the 3D contact model (:mod:`.contact3d`), per unit mass: its hull's vertices about its
centre of mass G in its principal axes, its principal inertias, friction and restitution; the uniform box and
cylinder; and the at-rest threshold of the body standing on its base (:func:`base_threshold`) or resting on
other contacts (:func:`support_threshold`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...compiled import jit, jit_inline


class ConvexBody(NamedTuple):
    """A rigid convex body, per unit mass.

    Attributes
    ----------
    vertices : ndarray, shape (n, 3)
        Its hull's vertices about G in its principal axes, z up when it stands [m].
    inertia : ndarray, shape (3,)
        Its principal moments of inertia about G per unit mass [m2].
    mu : float
        Friction coefficient at every contact [-].
    restitution : float
        Newton's normal restitution at a contact [-] (0: plastic, which gives Housner's rule at a pivot).
    rest : ndarray, shape (3, 3), or None
        The rotation from its principal axes into the axes it stands in, z up (a scan's settled pose); None: they
        are the same (a box, a cylinder). Its tilt is measured from that pose.
    tipping_rad : float
        Its smallest static tipping angle [rad]: a body found at rest after the record on another face of its hull,
        tilted beyond it, has overturned (toppled onto that face). NaN: only lying on a side counts (a box or a
        cylinder, which cannot rest tilted otherwise).
    """

    vertices: np.ndarray
    inertia: np.ndarray
    mu: float
    restitution: float = 0.0
    rest: np.ndarray | None = None
    tipping_rad: float = math.nan


def box_body(width_m: float, depth_m: float, height_m: float, *, mu: float, restitution: float = 0.0
             ) -> ConvexBody:
    """A uniform box (width along x, depth along y) by its eight corners."""
    b, d, h = width_m / 2.0, depth_m / 2.0, height_m / 2.0
    corners = np.array([[sx * b, sy * d, sz * h] for sz in (-1, 1) for sy in (-1, 1) for sx in (-1, 1)])
    inertia = np.array([(d * d + h * h) / 3.0, (b * b + h * h) / 3.0, (b * b + d * d) / 3.0])
    return ConvexBody(corners, inertia, mu, restitution)


def cylinder_body(diameter_m: float, height_m: float, *, mu: float, restitution: float = 0.0,
                  rim_points: int = 32) -> ConvexBody:
    """A uniform solid cylinder by ``rim_points`` points on each rim (the inscribed polygon: its radius toward a
    side is r cos(pi / rim_points), 0.5 % short of r at 32 points)."""
    r, h = diameter_m / 2.0, height_m / 2.0
    phi = 2.0 * np.pi * np.arange(rim_points) / rim_points
    rim = np.column_stack([r * np.cos(phi), r * np.sin(phi)])
    vertices = np.vstack([np.column_stack([rim, np.full(rim_points, z)]) for z in (-h, h)])
    side = r * r / 4.0 + (2.0 * h) ** 2 / 12.0
    return ConvexBody(vertices, np.array([side, side, r * r / 2.0]), mu, restitution)


@jit
def base_threshold(vertices, mu):
    """min(mu, tan alpha_min): the demand ratio at or below which the body standing on its base neither slides nor
    tips (alpha_min: the smallest static tipping angle, about the base hull's edge nearest below G) [-]."""
    n = vertices.shape[0]
    zmin = vertices[0, 2]
    for i in range(n):
        zmin = min(zmin, vertices[i, 2])
    size = 0.0
    for i in range(n):
        size = max(size, abs(vertices[i, 0]), abs(vertices[i, 1]), abs(vertices[i, 2]))
    return min(mu, inscribed(vertices, n, zmin + 1e-12 * size, 1e-12 * size) / -zmin)


@jit_inline
def support_threshold(arms, n, mu):
    """min(mu, tan alpha) of a body resting on the contacts at the first ``n`` rows of ``arms`` (their positions
    from G in the ground's axes, z up [m]): the demand ratio at or below which it neither slides nor tips about the
    edge of the polygon they span nearest below G (tan alpha = that distance over G's height above the lowest) [-];
    0 where G is not above the polygon's inside."""
    height, size = 0.0, 0.0
    for i in range(n):
        height = max(height, -arms[i, 2])
        size = max(size, abs(arms[i, 0]), abs(arms[i, 1]), abs(arms[i, 2]))
    if height <= 0.0:
        return 0.0
    return min(mu, inscribed(arms, n, math.inf, 1e-12 * size) / height)


@jit_inline
def hull_side(points, n, i, j, z_keep, tol):
    """Whether the line from ``points[i]`` to ``points[j]``, seen from above, is an edge of the convex hull of the
    first ``n`` points at or below the height ``z_keep`` (``tol`` [m]: points this near the line are on it): the side
    every other such point lies on (1 left, -1 right, 0 all on the line), or 2 where they lie on both sides or the two
    points are nearer than ``tol`` (no edge); with the line's direction (ex, ey) and length [m]."""
    ex, ey = points[j, 0] - points[i, 0], points[j, 1] - points[i, 1]
    length = math.sqrt(ex * ex + ey * ey)
    if length <= tol:
        return 2, ex, ey, length
    side = 0
    for m in range(n):
        if points[m, 2] > z_keep:
            continue
        cr = ex * (points[m, 1] - points[i, 1]) - ey * (points[m, 0] - points[i, 0])
        if abs(cr) <= tol * length:
            continue
        sgn = 1 if cr > 0 else -1
        if side == 0:
            side = sgn
        elif sgn != side:
            return 2, ex, ey, length
    return side, ex, ey, length


@jit_inline
def inscribed(points, n, z_keep, tol):
    """The distance [m] from the origin to the nearest edge of the convex hull, seen from above, of the first ``n``
    ``points`` at or below the height ``z_keep`` (``tol`` [m]: points this near a line are on it); 0 where the origin
    is not inside that hull, or the points span no area (a line: an edge holds nothing)."""
    nearest, spanned = math.inf, False
    for i in range(n):
        if points[i, 2] > z_keep:
            continue
        for j in range(n):
            if j == i or points[j, 2] > z_keep:
                continue
            side, ex, ey, length = hull_side(points, n, i, j, z_keep, tol)
            if side == 2:
                continue
            origin = ex * (-points[i, 1]) - ey * (-points[i, 0])      # the origin's side, times the length
            if side != 0 and origin * side < 0.0:
                return 0.0
            spanned = spanned or side != 0
            nearest = min(nearest, abs(origin) / length)
    return nearest if spanned else 0.0
