"""A mesh file measured before it is read: its size on disk and its count of faces, against stated limits, so that
reading a scan stays bounded in memory and time whatever the file (a 5-million-face mesh, an export at the wrong
scale). The count reads the file as a stream and keeps nothing: a binary STL states it in its header, a PLY in its
``element face`` line, and an OBJ has one ``f`` line per polygon. Then the read mesh is held to what a body is:
finite coordinates, not flat, one connected body, and sizes within the range the inventory's columns accept.
"""

from __future__ import annotations

import re
import struct
from pathlib import Path
from typing import NamedTuple

import numpy as np

from ..errors import MeshError

#: Bytes read at a time while counting an OBJ's faces
CHUNK_BYTES = 1 << 20
#: A PLY header is at most this long [bytes]
PLY_HEADER_BYTES = 1 << 16
_PLY_FACES = re.compile(rb"^element\s+face\s+(\d+)\s*$", re.MULTILINE)
#: The sizes a block may have, as the inventory's size columns and a scan's extents are held to them [m]: from a
#: small figurine to a tall obelisk or rock pillar
SIZE_RANGE_M = (0.01, 100.0)


class MeshLimits(NamedTuple):
    """The largest mesh a scan may be (``[blocks] max_mesh_faces`` and ``max_mesh_mb``).

    Attributes
    ----------
    max_faces : int
        Faces (triangles or polygons) [-].
    max_mb : float
        The file's size [MB, 1e6 bytes].
    size_range_m : tuple of float
        The body's extents, as the inventory's size columns accept them [m].
    """

    max_faces: int = 2_000_000
    max_mb: float = 500.0
    size_range_m: tuple[float, float] = SIZE_RANGE_M


#: The limits by default (``[blocks]``'s defaults are these)
DEFAULT_LIMITS = MeshLimits()


def check_before_reading(path: Path, limits: MeshLimits) -> int:
    """The file's count of faces, after its size and that count are checked against ``limits``.

    Raises
    ------
    MeshError
        Naming the file, what it holds, the limit and the setting that raises it.
    """
    size = path.stat().st_size
    if size > limits.max_mb * 1e6:
        raise MeshError(f"{path}: {size / 1e6:,.0f} MB, more than [blocks] max_mesh_mb = {limits.max_mb:g}; "
                        "decimate the scan (a rocking body needs its shape to about a millimetre: some 100,000 "
                        "faces) or raise the setting")
    faces = count_faces(path)
    if faces > limits.max_faces:
        raise MeshError(f"{path}: {faces:,} faces, more than [blocks] max_mesh_faces = {limits.max_faces:,}; "
                        "decimate the scan (e.g. MeshLab's Quadric Edge Collapse to 200,000 faces) or raise the "
                        "setting")
    return faces


def count_faces(path: Path) -> int:
    """Faces of an STL, PLY or OBJ file, read as a stream (0 for a point cloud; -1 where the format is unknown)."""
    suffix = path.suffix.lower()
    with open(path, "rb") as fh:
        head = fh.read(PLY_HEADER_BYTES)
        if suffix == ".ply":
            m = _PLY_FACES.search(head.split(b"end_header", 1)[0])
            return int(m.group(1)) if m else 0
        if suffix == ".stl":
            if len(head) >= 84 and not head[:5].lower() == b"solid":            # binary: the header states it
                return int(struct.unpack("<I", head[80:84])[0])
            return _count_lines(fh, head, b"facet")
        if suffix == ".obj":
            return _count_lines(fh, head, b"f")
    return -1


def _count_lines(fh, head: bytes, keyword: bytes) -> int:
    """Lines starting with ``keyword`` followed by white space, over the whole file (``head`` its start)."""
    count, tail, chunk = 0, b"\n", head
    while chunk:
        text = tail + chunk
        lines = text.split(b"\n")
        tail = lines.pop()                      # the last line may continue in the next chunk
        count += sum(1 for line in lines if line.lstrip().split(b" ", 1)[0].split(b"\t", 1)[0] == keyword)
        chunk = fh.read(CHUNK_BYTES)
    return count + (1 if tail.lstrip().split(b" ", 1)[0] == keyword else 0)


def check_body(path: Path, vertices: np.ndarray) -> None:
    """A mesh as written is a body: finite coordinates, extent in every direction.

    Raises
    ------
    MeshError
        Naming what the mesh is instead, and the fix.
    """
    if not np.all(np.isfinite(vertices)):
        bad = int(np.sum(~np.all(np.isfinite(vertices), axis=1)))
        raise MeshError(f"{path}: {bad} vertices with NaN or infinite coordinates; the export is damaged: export the "
                        "scan again")
    extents = np.ptp(vertices, axis=0) if len(vertices) else np.zeros(3)
    if not np.min(extents) > 1e-9 * max(float(np.max(extents)), 1e-300):
        raise MeshError(f"{path}: flat (its extents {', '.join(f'{e:.4g}' for e in extents)} m): a surface, not a "
                        "body; export the closed scan of the whole object")


def check_one_body(path: Path, body_count: int) -> None:
    """A closed mesh is one connected body, not several screened as one rigid body.

    Raises
    ------
    MeshError
        Naming the count, and the fix.
    """
    if body_count > 1:
        raise MeshError(f"{path}: {body_count} separate bodies in one mesh, which would be screened as one rigid "
                        "body; export each object to its own file (one row of the inventory each)")


def check_sizes(path: Path, height_m: float, base_m: tuple[float, float], limits: MeshLimits) -> None:
    """The settled body's height and base extents within the range the inventory's columns accept.

    Raises
    ------
    MeshError
        Naming each size, the range, and the likely unit when a factor of 1000 or 100 brings it in range.
    """
    lo, hi = limits.size_range_m
    for what, value in (("tall", height_m), ("wide", max(base_m)), ("deep", min(base_m))):
        if lo <= value <= hi:
            continue
        hint = next((f" (exported in {unit}? it would be {value / f:.4g} m)" for unit, f in
                     (("millimetres", 1000.0), ("centimetres", 100.0)) if lo <= value / f <= hi), "")
        raise MeshError(f"{path}: the body is {value:.4g} m {what}, outside the {lo:g}-{hi:g} m the inventory's "
                        f"size columns accept{hint}; export the scan in metres")
