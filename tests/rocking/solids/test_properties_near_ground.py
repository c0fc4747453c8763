"""Property: the contact model's list of vertices near the ground (:mod:`pipeline.rocking.solids.near_ground`) gives,
at every step of any motion, exactly the contacts a look at every vertex gives, in the same order."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from pipeline.rocking.solids.attitude import rotation
from pipeline.rocking.solids.near_ground import listed, near


def _quaternion(axis_angle: np.ndarray) -> np.ndarray:
    angle = float(np.linalg.norm(axis_angle))
    if angle == 0.0:
        return np.array([1.0, 0.0, 0.0, 0.0])
    return np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * axis_angle / angle])


def _product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    w1, v1, w2, v2 = a[0], a[1:], b[0], b[1:]
    return np.concatenate([[w1 * w2 - v1 @ v2], w1 * v2 + w2 * v1 + np.cross(v1, v2)])


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(4, 400), steps=st.integers(1, 120),
       turn=st.floats(1e-5, 0.2), sink=st.floats(-0.05, 0.05), gap=st.sampled_from([0.0, 1e-9, 1e-3]))
def test_the_list_gives_every_contact_in_order(seed, n, steps, turn, sink, gap):
    rng = np.random.default_rng(seed)
    vertices = rng.normal(size=(n, 3)) * rng.uniform(0.05, 2.0, size=3)
    vertices -= vertices.mean(axis=0)
    nr = near(vertices)
    q = _quaternion(rng.normal(size=3) * rng.uniform(0, np.pi))
    rm = np.empty((3, 3))
    reach = float(np.max(np.linalg.norm(vertices, axis=1)))
    for _ in range(steps):
        q = _product(q, _quaternion(rng.normal(size=3) * turn * rng.uniform(0, 2)))
        q /= np.linalg.norm(q)
        rotation(q, rm)
        heights = vertices @ rm[2]
        # G placed so that the lowest vertex is near the ground: touching, sunk or just above it
        z_g = -heights.min() + sink * reach * rng.uniform(-1, 1)
        expected = [i for i in range(n) if z_g + rm[2, 0] * vertices[i, 0] + rm[2, 1] * vertices[i, 1]
                    + rm[2, 2] * vertices[i, 2] <= gap]
        n_look = listed(vertices, rm, z_g, gap, nr)
        looked = range(n) if n_look < 0 else nr.members[:n_look]
        found = [int(i) for i in looked if z_g + rm[2, 0] * vertices[i, 0] + rm[2, 1] * vertices[i, 1]
                 + rm[2, 2] * vertices[i, 2] <= gap]
        assert found == expected
        assert n_look < 0 or list(nr.members[:n_look]) == sorted(nr.members[:n_look])
