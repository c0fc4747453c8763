"""Properties of a scan's static tipping angle in 3D (pipeline.rocking.scanned.hull3d.tipping_rad) for random convex
bodies standing on their base: turning the body about the vertical turns its tipping angles with it, stretching it
uniformly leaves them, and G passes over the hull's lowest point in that plane at that tilt (a second reading, by
the lowest point at each tilt, as pipeline.shapes.scan's grid does)."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import ConvexHull

from pipeline.rocking.scanned.hull3d import tipping_rad


def _standing(seed: int) -> tuple[np.ndarray, float]:
    """A random convex body as a hull standing on a square base (z = 0) below its points' mean, with G at that
    mean's height [m]."""
    rng = np.random.default_rng(seed)
    top = rng.normal(size=(30, 3)) * [0.3, 0.4, 0.3] + [0.0, 0.0, 1.0]
    base = np.array([[x, y, 0.0] for x in (-0.25, 0.25) for y in (-0.25, 0.25)])
    pts = np.vstack([base, top[top[:, 2] > 0.05]])
    hull = pts[ConvexHull(pts).vertices]
    return hull, 0.5


def _turned(hull: np.ndarray, deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return hull @ np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 10_000), azimuth=st.floats(0.0, 360.0), turn=st.floats(-180.0, 180.0))
def test_turning_the_body_about_the_vertical_turns_its_tipping_angles(seed, azimuth, turn):
    hull, zg = _standing(seed)
    assert math.isclose(tipping_rad(_turned(hull, turn), zg, azimuth + turn), tipping_rad(hull, zg, azimuth),
                        abs_tol=1e-9)


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 10_000), azimuth=st.floats(0.0, 360.0), scale=st.floats(0.1, 10.0))
def test_a_body_stretched_uniformly_tips_at_the_same_angles(seed, azimuth, scale):
    hull, zg = _standing(seed)
    assert math.isclose(tipping_rad(scale * hull, scale * zg, azimuth), tipping_rad(hull, zg, azimuth), abs_tol=1e-9)


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 10_000), azimuth=st.floats(0.0, 360.0))
def test_g_is_above_the_lowest_point_when_tilted_by_the_tipping_angle(seed, azimuth):
    """Just short of its tipping angle the body's lowest point in that plane is still beyond G toward the tilt;
    just past it, no longer."""
    hull, zg = _standing(seed)
    phi = tipping_rad(hull, zg, azimuth)
    a = math.radians(azimuth)
    u, w = hull[:, 0] * math.cos(a) + hull[:, 1] * math.sin(a), hull[:, 2] - zg
    if phi >= 0.5 * math.pi:
        return

    def offset(tilt: float) -> float:        # the lowest point's horizontal offset from G after the tilt
        k = int(np.argmin(w * math.cos(tilt) - u * math.sin(tilt)))
        return float(u[k] * math.cos(tilt) + w[k] * math.sin(tilt))

    size = float(np.max(np.abs(hull)))
    assert offset(phi - 1e-6) > 0.0 and offset(phi + 1e-6) <= 1e-9 * size
