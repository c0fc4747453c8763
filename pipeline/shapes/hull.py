"""A scanned body's contact with the ground in one vertical plane, pivot by pivot, as it rolls on its convex hull.

A rigid body on a flat ground touches it with the lowest point of its convex hull. Tilted by theta in a vertical
plane, that point is a vertex of the hull's outline in the plane (the body's points projected on the plane), and
which vertex it is depends only on theta: vertex k is the lowest for theta between the tilts at which its two edges
lie flat. The outline, ordered from the far end of the - side through the base to the far end of the + side, is
therefore a chain of pivots, each with the tilt interval on which it carries the body. The body at rest sits on the
base edge below its centre of mass (theta = 0). A body whose sides are straight, such as a rectangle, has one pivot
per side up to 90 degrees of tilt: the planar rocking block.

No tolerance enters: the pivots are the outline's vertices, however close to the base (a rock's base that is not
flat at the millimetre scale becomes a run of pivots over which it rolls).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..errors import MeshError
from .scan import ScannedShape

#: The chain ends at the first pivot whose far edge lies flat beyond this tilt, and that pivot's interval ends at
#: it [rad]: at 90 degrees the body has overturned
END_TILT_RAD = 0.5 * math.pi


class HullChain(NamedTuple):
    """The pivots of a body in one plane (:func:`hull_chain`), in the form the rolling kernel takes.

    Attributes
    ----------
    pivots_m : ndarray, shape (n, 2)
        Each pivot's position relative to the centre of mass G at rest: along the plane's + direction and up [m].
    bounds_rad : ndarray, shape (n + 1,)
        Pivot k carries the body for tilts in [bounds_rad[k], bounds_rad[k + 1]] [rad]; increasing, 0 at ``rest``.
    rest : int
        Index of the bound at theta = 0: the base edge between pivots rest - 1 and rest.
    second_u_m2, second_z_m2 : float
        The body's second moments about G per unit mass along the plane and up [m2]; their sum is its moment of
        inertia about the axis normal to the plane.
    azimuth_deg : float
        The plane [deg, from the settled body's x axis toward y].
    """

    pivots_m: np.ndarray
    bounds_rad: np.ndarray
    rest: int
    second_u_m2: float
    second_z_m2: float
    azimuth_deg: float

    @property
    def inertia_m2(self) -> float:
        """Moment of inertia about G per unit mass, about the axis normal to the plane [m2]."""
        return self.second_u_m2 + self.second_z_m2

    def base_tan_alpha(self) -> float:
        """tan alpha of the nearer of the base edge's two ends: the uplift acceleration over g of the weaker side
        [-]."""
        near = self.pivots_m[self.rest - 1: self.rest + 1]
        return float(np.min(np.abs(near[:, 0]) / -near[:, 1]))

    def tipping_rad(self) -> tuple[float, float]:
        """(toward +, toward -): the static tipping angles, the tilt at which G passes over the pivot then
        carrying the body (G above pivot k at the tilt atan2(u_k, -z_k); where that lies before the pivot's
        interval, G passed over it at the interval's start, on the edge) [rad, both positive]. A rectangle's are
        its alpha."""
        u, z = self.pivots_m[:, 0], self.pivots_m[:, 1]
        over = np.arctan2(u, -z)
        plus = minus = END_TILT_RAD
        for k in range(self.rest, len(u)):
            if over[k] <= self.bounds_rad[k + 1]:
                plus = max(float(over[k]), float(self.bounds_rad[k]))
                break
        for k in range(self.rest - 1, -1, -1):
            if over[k] >= self.bounds_rad[k]:
                minus = -min(float(over[k]), float(self.bounds_rad[k + 1]))
                break
        return plus, minus

    def scaled(self, *, width_factor: float = 1.0, height_factor: float = 1.0) -> HullChain:
        """The chain of the body stretched by ``width_factor`` along the plane and ``height_factor`` up (a draw's
        sizes, as a rectangle's are drawn): the pivots move, the tilts at which the edges lie flat change, the
        second moments scale by the squares."""
        piv = self.pivots_m * np.array([width_factor, height_factor])
        d = np.diff(piv, axis=0)
        tilt = np.arctan2(d[:, 1], d[:, 0])
        bounds = self.bounds_rad.copy()
        bounds[1:-1] = tilt - tilt[self.rest - 1]
        bounds[self.rest] = 0.0
        return self._replace(pivots_m=piv, bounds_rad=bounds, second_u_m2=self.second_u_m2 * width_factor ** 2,
                             second_z_m2=self.second_z_m2 * height_factor ** 2)


def _outline(points_uz: np.ndarray) -> np.ndarray:
    """The convex outline of points in the plane, counter-clockwise."""
    from scipy.spatial import ConvexHull

    return points_uz[ConvexHull(points_uz).vertices]


def chain_from_outline(outline: np.ndarray, second_u_m2: float, second_z_m2: float, *, azimuth_deg: float = 0.0
                       ) -> HullChain:
    """The :class:`HullChain` of a convex outline (counter-clockwise vertices relative to G, u and z [m]) resting
    on its edge below G, with the body's second moments about G (per unit mass, along the plane and up) [m2]."""
    n = len(outline)
    edges = np.roll(outline, -1, axis=0) - outline
    below = [k for k in range(n) if edges[k, 0] > 0 and outline[k, 0] <= 0.0 <= outline[(k + 1) % n, 0]]
    if not below:
        raise MeshError("the outline has no edge below its centre of mass: it does not stand on a base")
    base = min(below, key=lambda k: outline[k, 1] + outline[(k + 1) % n, 1])
    v = np.roll(outline, -base, axis=0)
    tilt = np.roll(np.arctan2(edges[:, 1], edges[:, 0]), -base)     # the tilt at which edge k lies flat
    tilt = (tilt - tilt[0] + math.pi) % (2.0 * math.pi) - math.pi
    plus, plus_bounds = [], []
    for k in range(1, n + 1):                                        # the + side: vertices 1, 2, ... of the base
        plus.append(v[k % n])
        plus_bounds.append(tilt[k % n])
        if not 0.0 < tilt[k % n] < END_TILT_RAD:
            break
    minus, minus_bounds = [], []
    for k in range(0, -n, -1):                                      # the - side: vertices 0, -1, ...
        minus.append(v[k % n])
        minus_bounds.append(tilt[(k - 1) % n])
        if not -END_TILT_RAD < tilt[(k - 1) % n] < 0.0:
            break
    bounds = np.array(minus_bounds[::-1] + [0.0] + plus_bounds)
    bounds[0], bounds[-1] = -END_TILT_RAD, END_TILT_RAD              # the ends: overturned at 90 degrees
    return HullChain(np.array(minus[::-1] + plus, dtype=float), bounds, len(minus), float(second_u_m2),
                     float(second_z_m2), float(azimuth_deg))


def hull_chain(shape: ScannedShape, azimuth_deg: float) -> HullChain:
    """The pivots of a settled scan in the vertical plane at ``azimuth_deg`` (see the module)."""
    phi = math.radians(azimuth_deg)
    d = np.array([math.cos(phi), math.sin(phi), 0.0])
    pts = shape.hull_m if len(shape.hull_m) else shape.vertices_m
    uz = np.column_stack([pts @ d, pts[:, 2] - shape.com_height_m])
    inertia = shape.inertia_per_mass_m2
    second = 0.5 * float(np.trace(inertia)) * np.eye(3) - inertia        # <r r^T> about G from I = tr(C) 1 - C
    return chain_from_outline(_outline(uz), float(d @ second @ d), float(second[2, 2]), azimuth_deg=azimuth_deg)


def rectangle_chain(width_m: float, height_m: float) -> HullChain:
    """The :class:`HullChain` of a rectangular block of full width and height [m]: one pivot per side."""
    b, h = width_m / 2.0, height_m / 2.0
    outline = np.array([[-b, -h], [b, -h], [b, h], [-b, h]])
    return chain_from_outline(outline, width_m ** 2 / 12.0, height_m ** 2 / 12.0)
