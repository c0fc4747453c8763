"""Write the example scans of this folder (from the project root: ``.venv/bin/python examples/scans/make_scans.py``).

* ``leaning-statue.obj``: a statue of 1.2 m on a 0.40 x 0.30 m base whose top leans 0.12 m toward +x, so that its
  centre of mass sits off the middle of its base: it tips more easily toward +x than toward -x.
* ``box-0.3x3.0x1.5.obj``: a rectangular block 0.3 m wide (x), 3.0 m deep (y) and 1.5 m high, the tests' rectangle
  given as a mesh.

Both are closed triangle meshes in metres, z up as the object stands (OBJ, written with trimesh).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh

HERE = Path(__file__).resolve().parent


def leaning_statue() -> trimesh.Trimesh:
    base = np.array([[-0.20, -0.15, 0.0], [0.20, -0.15, 0.0], [0.20, 0.15, 0.0], [-0.20, 0.15, 0.0]])
    top = base * np.array([0.7, 0.7, 0.0]) + np.array([0.12, 0.0, 1.2])
    return trimesh.convex.convex_hull(np.vstack([base, top]))


def box(width_m: float, depth_m: float, height_m: float) -> trimesh.Trimesh:
    mesh = trimesh.creation.box(extents=(width_m, depth_m, height_m))
    mesh.apply_translation((0.0, 0.0, height_m / 2))
    return mesh


if __name__ == "__main__":
    leaning_statue().export(HERE / "leaning-statue.obj")
    box(0.3, 3.0, 1.5).export(HERE / "box-0.3x3.0x1.5.obj")
