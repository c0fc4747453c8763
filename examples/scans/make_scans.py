"""Write the example scans of this folder (from the project root: ``.venv/bin/python examples/scans/make_scans.py``).

* ``leaning-statue.obj``: a statue of 1.2 m on a 0.40 x 0.30 m base whose top leans 0.12 m toward +x, so that its
  centre of mass sits off the middle of its base: it tips more easily toward +x than toward -x.
* ``balanced-rock.obj``: a precariously balanced rock of about 0.13 m3, an irregular ovoid (semi-axes 0.30, 0.22,
  0.45 m) tilted 22 deg and resting on a small flat cut of its underside: its weakest plane has alpha 7.1 deg to
  one side and 18.5 deg to the other.
* ``box-0.3x3.0x1.5.obj``: a rectangular block 0.3 m wide (x), 3.0 m deep (y) and 1.5 m high, the tests' rectangle
  given as a mesh.

All are closed triangle meshes in metres, z up as the object stands (OBJ, written with trimesh).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import trimesh

HERE = Path(__file__).resolve().parent


def leaning_statue() -> trimesh.Trimesh:
    base = np.array([[-0.20, -0.15, 0.0], [0.20, -0.15, 0.0], [0.20, 0.15, 0.0], [-0.20, 0.15, 0.0]])
    top = base * np.array([0.7, 0.7, 0.0]) + np.array([0.12, 0.0, 1.2])
    return trimesh.convex.convex_hull(np.vstack([base, top]))


def balanced_rock(*, seed: int = 7, points: int = 400, tilt_deg: float = 22.0, cut_m: float = 0.05) -> trimesh.Trimesh:
    """The convex hull of points on a rough ellipsoid (semi-axes 0.30, 0.22, 0.45 m), tilted about y and cut flat
    ``cut_m`` above its lowest point, the cut the base."""
    rng = np.random.default_rng(seed)
    u = rng.normal(size=(points, 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    p = u * np.array([0.30, 0.22, 0.45]) * (1 + 0.06 * rng.uniform(-1, 1, (points, 1)))
    t = math.radians(tilt_deg)
    p = p @ np.array([[math.cos(t), 0, math.sin(t)], [0, 1, 0], [-math.sin(t), 0, math.cos(t)]]).T
    base = p[:, 2].min() + cut_m
    p[:, 2] = np.maximum(p[:, 2], base) - base
    return trimesh.convex.convex_hull(p)


def box(width_m: float, depth_m: float, height_m: float) -> trimesh.Trimesh:
    mesh = trimesh.creation.box(extents=(width_m, depth_m, height_m))
    mesh.apply_translation((0.0, 0.0, height_m / 2))
    return mesh


if __name__ == "__main__":
    leaning_statue().export(HERE / "leaning-statue.obj")
    balanced_rock().export(HERE / "balanced-rock.obj")
    box(0.3, 3.0, 1.5).export(HERE / "box-0.3x3.0x1.5.obj")
