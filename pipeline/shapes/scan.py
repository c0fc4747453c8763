"""Bodies from a scan: a closed triangle mesh (OBJ, PLY or STL, read with trimesh) made into the rocking geometry of
an irregular object, such as a precariously balanced rock or a statue on an uneven plinth.

**Mass properties** at uniform density, by the divergence theorem over the mesh's signed tetrahedra (trimesh's
``mass_properties``; Mirtich 1996): the volume, the centre of mass G and the inertia about G per unit mass. A mesh
whose faces point inward (negative volume) is turned outward. A point cloud without faces is meshed by its convex
hull, with a warning: the hull fills every concavity, so its volume is an upper bound and its centre of mass and
inertia approximate.

**Settling** on a flat, rigid base: the body turns about G until the face of its convex hull straight below G is
horizontal (the face the downward vertical through G leaves the hull by; repeated until that face is level), then
stands on it with G above the origin. A scan that must turn by more than :data:`MAX_SETTLE_DEG` to stand was not
posed as it stands (z up), or its centre of mass lies outside the footprint it was scanned on: an error naming
the file and the fix.

**Rocking geometry** in a vertical plane at azimuth ``phi`` (in the settled body's axes, from x toward y): the
footprint is the set of the mesh's vertices within a tolerance of the base (the base of a real rock is not flat at
the mm scale, so the tolerance is a stated choice); on each side its extreme point is the pivot, at horizontal
distance ``b_+`` or ``b_-`` from G, so that ``alpha_+- = atan(b_+- / z_G)`` and ``R_+- = sqrt(b_+-^2 + z_G^2)``, and the
moment of inertia about the pivot's line (horizontal, normal to the plane) is ``n^T I_G n + R_+-^2`` per unit mass
(parallel axes). The *static tipping angle* on each side does not depend on a tolerance: the tilt at which G passes
over the lowest point of the hull as the body turns on it (the tipping angle of a rectangle is its alpha).

References
----------
Mirtich, B. (1996). Fast and accurate computation of polyhedral mass properties. Journal of Graphics Tools 1(2),
31-50.
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. BSSA 53(2), 403-417.
"""

from __future__ import annotations

import logging
import math
from pathlib import Path
from typing import NamedTuple

import numpy as np

from ..errors import MeshError
from .mesh_limits import DEFAULT_LIMITS, MeshLimits, check_before_reading, check_body, check_one_body, check_sizes

log = logging.getLogger(__name__)

#: The most a scan may turn to settle on the base below its centre of mass [deg]
MAX_SETTLE_DEG = 10.0
#: Settling turns at most this many times (each levels the hull face below G)
MAX_SETTLE_TURNS = 50
#: A hull face this close to level (1 - |cos|) is level [-]
LEVEL_TOL = 1e-12
#: The tilt grid on which the static tipping angle is bracketed before bisection [deg]
TIPPING_GRID_DEG = 0.01
TIPPING_BISECTIONS = 60
#: The footprint's default tolerance above the lowest point of the settled base [m]
FOOTPRINT_TOL_M = 0.002
#: The grid of horizontal directions a scan's outlines are kept on (:attr:`ScannedShape.outlines`) [deg]
OUTLINE_STEP_DEG = 1.0
SUFFIXES = (".obj", ".ply", ".stl")


class ScannedShape(NamedTuple):
    """A scanned body settled on a flat base (:func:`read_scan`).

    Attributes
    ----------
    path : str
    vertices_m : ndarray, shape (n, 3)
        The settled mesh's vertices: the base at z = 0, G above the origin [m].
    hull_m : ndarray, shape (k, 3)
        The vertices of its convex hull, in the same frame [m].
    com_height_m : float
        Height of the centre of mass above the base [m].
    volume_m3 : float
    inertia_per_mass_m2 : ndarray, shape (3, 3)
        Inertia about G per unit mass, in the settled axes [m2].
    mass_kg : float
        From the given mass, or density x volume (NaN where neither was given: rocking needs none).
    settle_deg : float
        How far the scan turned to stand [deg].
    from_points : bool
        Meshed from a point cloud by its convex hull.
    outlines : Outlines or None
        The hull's outline in the vertical plane of each direction of the :data:`OUTLINE_STEP_DEG` grid
        (:func:`outline_rings`). A stretch of the hull, horizontally by one factor and vertically by another (a draw
        of its sizes), keeps them: the outline of the stretched hull is the stretched outline.
    """

    path: str
    vertices_m: np.ndarray
    hull_m: np.ndarray
    com_height_m: float
    volume_m3: float
    inertia_per_mass_m2: np.ndarray
    mass_kg: float
    settle_deg: float
    from_points: bool
    outlines: Outlines | None = None


class Outlines(NamedTuple):
    """A hull's outline in the vertical plane of each direction of a grid (:func:`outline_rings`).

    Attributes
    ----------
    azimuths_deg : ndarray
        The directions, from x toward y [deg].
    vertices : ndarray of int64
        The outlines' vertices one after the other, each outline counter-clockwise: indices into the hull's.
    starts : ndarray of int64
        Where each outline begins in ``vertices``, and its end (one more than the directions).
    """

    azimuths_deg: np.ndarray
    vertices: np.ndarray
    starts: np.ndarray


class Pivots(NamedTuple):
    """A scanned body's rocking geometry in one vertical plane (:func:`pivots`); ``_plus`` toward the azimuth,
    ``_minus`` away from it.

    Attributes
    ----------
    azimuth_deg : float
        The plane, in the settled body's axes [deg, from x toward y].
    b_plus_m, b_minus_m : float
        Horizontal distance from G to the footprint's extreme point on each side [m].
    alpha_plus, alpha_minus : float
        Slenderness on each side, atan(b / z_G) [rad].
    R_plus_m, R_minus_m : float
        Distance from each pivot to G [m].
    inertia_plus_m2, inertia_minus_m2 : float
        Moment of inertia about each pivot's line per unit mass [m2].
    tipping_plus, tipping_minus : float
        Static tipping angle on each side (G over the hull's lowest point) [rad].
    """

    azimuth_deg: float
    b_plus_m: float
    b_minus_m: float
    alpha_plus: float
    alpha_minus: float
    R_plus_m: float
    R_minus_m: float
    inertia_plus_m2: float
    inertia_minus_m2: float
    tipping_plus: float
    tipping_minus: float


def _load(path: Path, limits: MeshLimits):
    """The file as a closed, outward trimesh of one body (a point cloud by its convex hull), after its size and
    faces are checked against ``limits``; and whether it was points."""
    import trimesh

    if path.suffix.lower() not in SUFFIXES:
        raise MeshError(f"{path}: a mesh file ends in {', '.join(SUFFIXES)}, found {path.suffix!r}; export the scan "
                        "as OBJ, PLY or STL")
    try:
        check_before_reading(path, limits)
    except OSError as exc:
        raise MeshError(f"{path}: cannot be read ({exc.strerror or exc}); check the inventory's mesh path") from exc
    try:
        obj = trimesh.load(path, process=False)
    except Exception as exc:             # trimesh raises many kinds on a damaged file
        raise MeshError(f"{path}: could not be read as a mesh ({exc}); export it again as OBJ, PLY or STL") from exc
    if isinstance(obj, trimesh.Scene):
        parts = [g for g in obj.geometry.values() if isinstance(g, trimesh.Trimesh)]
        obj = trimesh.util.concatenate(parts) if parts else trimesh.PointCloud(np.zeros((0, 3)))
    if isinstance(obj, trimesh.Trimesh) and len(obj.faces):
        check_body(path, np.asarray(obj.vertices, dtype=float))      # as written: processing drops NaN
        obj.process()
    if not isinstance(obj, trimesh.Trimesh) or len(obj.faces) == 0:
        points = np.asarray(getattr(obj, "vertices", np.zeros((0, 3))), dtype=np.float64)
        if len(points) < 4:
            raise MeshError(f"{path}: {len(points)} points and no faces: not a body; export the scan's mesh")
        log.warning("%s: a point cloud (%d points, no faces): meshed by its convex hull, which fills every "
                    "concavity, so the volume is an upper bound and the centre of mass and inertia approximate; "
                    "a closed mesh of the scan gives them exactly", path, len(points))
        return trimesh.Trimesh(points).convex_hull, True
    mesh = obj
    if not mesh.is_watertight:                              # seams of texture or normals may split edges
        mesh.merge_vertices(merge_tex=True, merge_norm=True)
    if not mesh.is_watertight:
        raise MeshError(f"{path}: the mesh is not closed (open edges), so it has no volume or centre of mass; close "
                        "its holes (e.g. MeshLab's Close Holes, or Blender's 3D-Print Toolbox) and export it again")
    check_one_body(path, int(mesh.body_count))
    if mesh.volume < 0.0:                                   # faces pointing inward
        mesh.invert()
    return mesh, False


def _rotation_to(n: np.ndarray, target: np.ndarray) -> np.ndarray:
    """The rotation matrix turning unit vector ``n`` onto unit vector ``target`` about their common normal."""
    v = np.cross(n, target)
    c = float(np.dot(n, target))
    s = float(np.linalg.norm(v))
    if s < 1e-15:
        return np.eye(3)
    k = v / s
    kx = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + s * kx + (1.0 - c) * kx @ kx


def settle(points: np.ndarray, com: np.ndarray, *, path: str = "") -> tuple[np.ndarray, float]:
    """The rotation (about ``com``) that stands the body on a flat base, and its angle [deg] (see the module). The
    hull is built once: turned about G, each face keeps its distance from G and only its normal turns."""
    from scipy.spatial import ConvexHull

    equations = ConvexHull(points).equations
    normals = equations[:, :3]                                   # n . x = c, n outward
    distance = -equations[:, 3] - normals @ com                  # each face's distance from G
    total = np.eye(3)
    down = np.array([0.0, 0.0, -1.0])
    for _ in range(MAX_SETTLE_TURNS):
        turned = normals @ total.T
        facing = turned @ down
        t = np.where(facing > 0.0, distance / np.where(facing > 0.0, facing, 1.0), np.inf)
        n = turned[int(np.argmin(t))]                            # the face the vertical below G leaves the hull by
        if 1.0 - float(np.dot(n, down)) <= LEVEL_TOL:
            angle = math.degrees(math.acos(min(1.0, max(-1.0, total[2, 2]))))
            return total, angle
        total = _rotation_to(n, down) @ total
    raise MeshError(f"{path}: the body did not come to rest on a face of its hull in {MAX_SETTLE_TURNS} turns; "
                    "check that the mesh is one closed body")


def read_scan(path, *, density_kg_m3: float = math.nan, mass_kg: float = math.nan,
              limits: MeshLimits = DEFAULT_LIMITS) -> ScannedShape:
    """Read a scan and settle it on a flat base (see the module).

    Parameters
    ----------
    path : str or Path
        OBJ, PLY or STL, in metres, z up as the object stands.
    density_kg_m3, mass_kg : float
        Either gives the mass (NaN: none; rocking needs none).
    limits : MeshLimits
        The largest file and count of faces read, and the sizes the body may have.

    Raises
    ------
    MeshError
        Too large, unreadable, not closed, not one body, flat or not finite, of a size outside the columns' range,
        or not standing on the base below its centre of mass (the message says the fix).
    """
    path = Path(path)
    try:
        return _read(path, density_kg_m3=density_kg_m3, mass_kg=mass_kg, limits=limits)
    except (MeshError, MemoryError):
        raise
    except Exception as exc:             # trimesh and qhull raise many kinds on a damaged mesh
        raise MeshError(f"{path}: a damaged mesh ({type(exc).__name__}: {exc}); repair it (e.g. MeshLab's "
                        "Cleaning and Repairing filters) or export it again") from exc


def _read(path: Path, *, density_kg_m3: float, mass_kg: float, limits: MeshLimits) -> ScannedShape:
    mesh, from_points = _load(path, limits)
    props = mesh.mass_properties                             # unit density: mass = volume
    volume = float(props["volume"])
    if not volume > 0.0:
        raise MeshError(f"{path}: the mesh encloses no volume ({volume:g} m3); export the scanned body, in metres")
    com = np.asarray(props["center_mass"], dtype=float)
    inertia = np.asarray(props["inertia"], dtype=float) / volume          # about G, per unit mass
    hull = np.asarray(mesh.convex_hull.vertices, dtype=float)
    rot, angle = settle(hull, com, path=str(path))
    if angle > MAX_SETTLE_DEG:
        raise MeshError(f"{path}: as scanned, its centre of mass is not above the base it stands on: it would turn "
                        f"{angle:.1f} deg to settle on another face (the limit is {MAX_SETTLE_DEG:g}); pose the mesh "
                        "as the object stands, z up, or check that it is one body of uniform density")
    settled_hull = (hull - com) @ rot.T
    base = float(settled_hull[:, 2].min())
    settled_hull[:, 2] -= base
    settled = (np.asarray(mesh.vertices, dtype=float) - com) @ rot.T
    settled[:, 2] -= base
    extents = np.ptp(settled_hull, axis=0)
    check_sizes(path, float(extents[2]), (float(extents[0]), float(extents[1])), limits)
    mass = mass_kg if math.isfinite(mass_kg) else density_kg_m3 * volume
    return ScannedShape(str(path), settled, settled_hull, -base, volume, rot @ inertia @ rot.T, float(mass), angle,
                        from_points, outline_rings(settled_hull))


def outline_rings(hull_m: np.ndarray, *, step_deg: float = OUTLINE_STEP_DEG) -> Outlines:
    """For each horizontal direction every ``step_deg`` from x toward y [deg], the vertices of the hull's outline in
    that vertical plane (the hull's points ``hull_m`` [m] projected on it), counter-clockwise (:class:`Outlines`)."""
    from scipy.spatial import ConvexHull

    azimuths = np.arange(0.0, 360.0, step_deg)
    rings = []
    for az in azimuths:
        phi = math.radians(float(az))
        u = hull_m[:, 0] * math.cos(phi) + hull_m[:, 1] * math.sin(phi)
        rings.append(np.asarray(ConvexHull(np.column_stack([u, hull_m[:, 2]])).vertices, dtype=np.int64))
    return Outlines(azimuths, np.concatenate(rings), np.concatenate([[0], np.cumsum([len(r) for r in rings])]))


def _tipping(u: np.ndarray, w: np.ndarray) -> float:
    """The static tipping angle toward +u [rad] of a body whose hull points, relative to G, are at horizontal
    offset ``u`` and height ``w``: the first tilt at which the lowest point's horizontal offset from G, ``u cos
    phi + w sin phi``, reaches zero (the lowest point minimises ``w cos phi - u sin phi``)."""
    def offset(phi: float) -> float:
        k = int(np.argmin(w * math.cos(phi) - u * math.sin(phi)))
        return float(u[k] * math.cos(phi) + w[k] * math.sin(phi))

    # from a small tilt on: flat, the base's points tie for lowest (the tilt's direction breaks the tie)
    grid = np.radians(np.arange(TIPPING_GRID_DEG, 90.0 + TIPPING_GRID_DEG, TIPPING_GRID_DEG))
    heights = np.outer(np.cos(grid), w) - np.outer(np.sin(grid), u)
    k = np.argmin(heights, axis=1)
    offsets = u[k] * np.cos(grid) + w[k] * np.sin(grid)
    below = np.flatnonzero(offsets <= 0.0)
    if below.size == 0:
        return math.pi / 2
    j = int(below[0])
    lo, hi = (float(grid[j - 1]) if j > 0 else 0.0), float(grid[j])
    for _ in range(TIPPING_BISECTIONS):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if offset(mid) > 0.0 else (lo, mid)
    return hi


def pivots(shape: ScannedShape, azimuth_deg: float, *, footprint_tol_m: float = FOOTPRINT_TOL_M) -> Pivots:
    """The rocking geometry of a settled scan in the vertical plane at ``azimuth_deg`` (see the module)."""
    phi = math.radians(azimuth_deg)
    d = np.array([math.cos(phi), math.sin(phi), 0.0])
    n = np.array([-math.sin(phi), math.cos(phi), 0.0])               # the pivot lines' direction
    z = shape.com_height_m
    pts = shape.vertices_m
    foot = pts[:, 2] <= footprint_tol_m                          # every vertex that close to the base
    u_foot = pts[foot] @ d
    b_plus, b_minus = float(u_foot.max()), float(-u_foot.min())
    hull = shape.hull_m
    u, w = hull @ d, hull[:, 2] - z
    i_n = float(n @ shape.inertia_per_mass_m2 @ n)
    r_plus, r_minus = math.hypot(b_plus, z), math.hypot(b_minus, z)
    return Pivots(float(azimuth_deg), b_plus, b_minus, math.atan2(b_plus, z), math.atan2(b_minus, z), r_plus,
                  r_minus, i_n + r_plus ** 2, i_n + r_minus ** 2, _tipping(u, w), _tipping(-u, w))
