"""A scanned body's rocking geometry in one vertical plane, in the form the probabilities scale: the pivots'
distances from G, G's height and the body's second moments about G, so that a sampled size (a factor on the
widths and one on the heights, as a rectangle's are drawn) changes each term as it changes the body.

Two rules place the pivots (:class:`PivotRule`): the footprint's extreme points within a tolerance of the base
(:func:`pipeline.shapes.scan.pivots`, the default), or the points at which each side's static tipping angle puts
them (``b = z_G tan(tipping)``: the threshold of quasi-static overturning, free of a tolerance).

For a body scaled by ``f_w`` across and ``f_h`` up, ``b`` scales by ``f_w``, ``z_G`` by ``f_h``, and the second
moments ``C_uu = <u^2>`` and ``C_zz = <z^2>`` about G (per unit mass) by ``f_w^2`` and ``f_h^2``; the moment of
inertia about the pivot line is ``C_uu + C_zz + R^2`` (parallel axes). A rectangle of width w and height h has
``C_uu = w^2 / 12`` and ``C_zz = h^2 / 12``.
"""

from __future__ import annotations

import math
from enum import IntEnum
from typing import NamedTuple

import numpy as np

from ..rocking.scanned.two_sided_body import TwoSided
from .hull import HullChain
from .scan import FOOTPRINT_TOL_M, ScannedShape, pivots


class PivotRule(IntEnum):
    """Where a scanned body's pivots are taken."""

    footprint = 0       # the footprint's extreme points within the tolerance of the base
    tipping = 1         # where each side's static tipping angle puts them


class PlaneBody(NamedTuple):
    """A body's rocking geometry in one vertical plane.

    Attributes
    ----------
    azimuth_deg : float
        The plane, in the settled body's axes [deg, from x toward y].
    b_plus_m, b_minus_m : float
        Horizontal distance from G to the pivot toward the azimuth and away from it [m].
    com_height_m : float
        Height of G above the base [m].
    second_u_m2, second_z_m2 : float
        Second moments about G per unit mass along the plane's horizontal and the vertical [m2].
    """

    azimuth_deg: float
    b_plus_m: float
    b_minus_m: float
    com_height_m: float
    second_u_m2: float
    second_z_m2: float

    def two_sided(self, *, width_factor: float = 1.0, height_factor: float = 1.0) -> TwoSided:
        """The :class:`~pipeline.rocking.references.asymmetric.TwoSided` of the body scaled by ``width_factor`` across
        and ``height_factor`` up [-]."""
        fw2, fh2 = width_factor * width_factor, height_factor * height_factor
        return TwoSided(self.b_plus_m * width_factor, self.b_minus_m * width_factor, self.com_height_m * height_factor,
                        self.second_u_m2 * fw2 + self.second_z_m2 * fh2)

    def reversed(self) -> PlaneBody:
        """The same plane seen from the other side (azimuth + 180 deg): the pivots swapped."""
        return self._replace(azimuth_deg=(self.azimuth_deg + 180.0) % 360.0, b_plus_m=self.b_minus_m,
                             b_minus_m=self.b_plus_m)


def chain_plane(chain: HullChain) -> PlaneBody:
    """The :class:`PlaneBody` of a hull chain with one pivot per side (:mod:`.hull`: both ends of its flat base,
    each carrying the body up to 90 degrees, as a prism's or a box's): the same body on the same two pivots."""
    if len(chain.pivots_m) != 2:
        raise ValueError(f"a chain of {len(chain.pivots_m)} pivots is not one pivot per side")
    (u_minus, z_minus), (u_plus, z_plus) = chain.pivots_m
    return PlaneBody(chain.azimuth_deg, float(u_plus), float(-u_minus), float(-0.5 * (z_minus + z_plus)),
                     chain.second_u_m2, chain.second_z_m2)


def rectangle_plane(width_m: float, height_m: float) -> PlaneBody:
    """The :class:`PlaneBody` of a rectangular block of full width and height [m]."""
    return PlaneBody(0.0, width_m / 2, width_m / 2, height_m / 2, width_m ** 2 / 12.0, height_m ** 2 / 12.0)


def footprint_extents(shape: ScannedShape, azimuth_deg: float, *, footprint_tol_m: float = FOOTPRINT_TOL_M
                      ) -> tuple[float, float]:
    """(b_+, b_-): the footprint's extreme points along the plane at ``azimuth_deg``, from G [m] (the footprint: the
    vertices within ``footprint_tol_m`` of the base, as :func:`pipeline.shapes.scan.pivots` takes it)."""
    phi = math.radians(azimuth_deg)
    u = shape.vertices_m[shape.vertices_m[:, 2] <= footprint_tol_m] @ np.array([math.cos(phi), math.sin(phi), 0.0])
    return float(u.max()), float(-u.min())


def plane_body(shape: ScannedShape, azimuth_deg: float, *, rule: PivotRule = PivotRule.footprint,
               footprint_tol_m: float = FOOTPRINT_TOL_M) -> PlaneBody:
    """The :class:`PlaneBody` of a settled scan in the vertical plane at ``azimuth_deg`` (see the module)."""
    z = shape.com_height_m
    if rule == PivotRule.tipping:
        piv = pivots(shape, azimuth_deg, footprint_tol_m=footprint_tol_m)
        b_plus, b_minus = z * math.tan(piv.tipping_plus), z * math.tan(piv.tipping_minus)
    else:
        b_plus, b_minus = footprint_extents(shape, azimuth_deg, footprint_tol_m=footprint_tol_m)
    inertia = shape.inertia_per_mass_m2
    second = 0.5 * float(np.trace(inertia)) * np.eye(3) - inertia        # <r r^T> about G from I = tr(C) 1 - C
    phi = math.radians(azimuth_deg)
    d = np.array([math.cos(phi), math.sin(phi), 0.0])
    return PlaneBody(float(azimuth_deg), b_plus, b_minus, z, float(d @ second @ d), float(second[2, 2]))


def weakest_plane(shape: ScannedShape, *, footprint_tol_m: float = FOOTPRINT_TOL_M) -> float:
    """The plane in which the body's footprint reaches least far from G, toward its + side [deg, in [0, 360)]: the
    smallest uplift threshold of a body tipping about its footprint's extreme points (the two-sided model's pivots),
    the outward normal of the footprint's convex-hull edge nearest to G (horizontally), whatever the mesh's rotation.

    The extent b_+(phi) of a convex footprint along a direction phi is its support function, the distance from G to
    the supporting line normal to phi; between two consecutive edge normals it is |v| cos(phi - phi_v) for the hull
    vertex v between them, concave in phi, so its smallest value is at an edge normal: the edge nearest to G. A
    footprint of two points (a knife edge) has the two normals of its segment."""
    foot = np.unique(np.round(shape.vertices_m[shape.vertices_m[:, 2] <= footprint_tol_m, :2], 12), axis=0)
    normals = _edge_normals(foot)
    b_plus = np.max(foot @ normals.T, axis=0)
    k = int(np.argmin(b_plus))
    return float(math.degrees(math.atan2(normals[k, 1], normals[k, 0])) % 360.0)


def _edge_normals(points: np.ndarray) -> np.ndarray:
    """Unit outward normals of the convex hull's edges of 2D ``points`` (two directions for a segment, four axis
    directions for a single point)."""
    from scipy.spatial import ConvexHull, QhullError

    if len(points) >= 3:
        try:
            hull = ConvexHull(points)
            n = hull.equations[:, :2]
            return n / np.linalg.norm(n, axis=1)[:, None]
        except QhullError:              # collinear: a segment
            pass
    if len(points) >= 2:
        span = points.max(axis=0) - points.min(axis=0)
        d = span / np.linalg.norm(span)
        n = np.array([-d[1], d[0]])
        return np.vstack([n, -n, d, -d])
    return np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]])


def equivalent_rectangle(shape: ScannedShape, *, footprint_tol_m: float = FOOTPRINT_TOL_M) -> tuple[float, float]:
    """(height, width) [m] of the rectangle with the body's centre of mass height and its weakest side's alpha
    (:func:`weakest_plane`): what the paper's criterion and the closed forms, written for rectangles, are given for a
    scanned body."""
    az = weakest_plane(shape, footprint_tol_m=footprint_tol_m)
    b = footprint_extents(shape, az, footprint_tol_m=footprint_tol_m)[0]
    return 2.0 * shape.com_height_m, 2.0 * b
