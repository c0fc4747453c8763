"""Properties of a body rolling on its convex hull (pipeline.shapes.hull, pipeline.rocking.scanned.rolling), for random
convex bodies: similitude (a body lambda times larger under the same accelerations, played sqrt(lambda) times
slower, tilts the same at the corresponding instants: theta'' scales as g / L, the only time scale is sqrt(L / g)),
mirror symmetry (the mirrored body under the negated ground motion tilts the other way, each side's peak the other
side's), and the static tipping angle (G over the pivot carrying the body there, or over an edge between two)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from scipy.spatial import ConvexHull

from pipeline.constants import G
from pipeline.rocking.scanned.rolling import roll_on_hull
from pipeline.shapes.hull import chain_from_outline

DT = 0.005
N = 1200


def _body(seed: int, aspect: float):
    """A random convex outline about G (u, z), its base below G, and second moments of the points as a body's."""
    rng = np.random.default_rng(seed)
    pts = rng.normal(size=(40, 2)) * [1.0, aspect]
    hull = pts[ConvexHull(pts).vertices]
    g = hull.mean(axis=0)
    outline = hull - g
    second_u, second_z = float(np.mean(outline[:, 0] ** 2)), float(np.mean(outline[:, 1] ** 2))
    return outline, second_u, second_z


def _pulse(amp_g: float, period_s: float, dt: float) -> np.ndarray:
    t = np.arange(N) * dt
    return np.where(t < period_s, amp_g * G * np.sin(2 * np.pi * t / period_s), 0.0)


body_args = dict(seed=st.integers(0, 10_000), aspect=st.floats(1.0, 4.0), amp_g=st.floats(0.05, 0.8),
                 period_s=st.floats(0.2, 1.5))


@settings(max_examples=40, deadline=None)
@given(**body_args, lam=st.floats(0.25, 4.0))
@example(seed=10000, aspect=3.0, amp_g=0.75, period_s=0.75, lam=3.0)         # found on a fresh clone
def test_a_body_lambda_times_larger_under_the_motion_played_slower_tilts_the_same(seed, aspect, amp_g, period_s, lam):
    outline, su, sz = _body(seed, aspect)
    try:
        small = chain_from_outline(0.3 * outline, 0.09 * su, 0.09 * sz)
    except ValueError:
        return                                   # no edge below G: not a body that stands
    large = chain_from_outline(0.3 * lam * outline, 0.09 * lam ** 2 * su, 0.09 * lam ** 2 * sz)
    slow = math.sqrt(lam)
    a = _pulse(amp_g, period_s, DT)
    h1, h2 = np.zeros(N), np.zeros(N)
    r1 = roll_on_hull(a, DT, small, theta_out=h1)
    r2 = roll_on_hull(a, DT * slow, large, theta_out=h2)
    if r1.verdict != r2.verdict:
        # an unstable balance reached (seed 10000, aspect 3, 0.75 g, 0.75 s, lambda 3: the one that stood peaked at
        # 1.498 rad): rounding decides there; up to the standing one's largest sampled tilt the motions are the same
        stood = h1 if r1.verdict == 0 else h2
        k = int(np.argmax(np.abs(stood))) + 1
        np.testing.assert_allclose(h2[:k], h1[:k], rtol=1e-6, atol=1e-9)
        assert k > 1 and abs(stood[k - 1]) > 0.1
        return
    np.testing.assert_allclose(h2, h1, rtol=1e-6, atol=1e-9)
    if r1.verdict == 1:
        assert r2.t_overturn == pytest.approx(slow * r1.t_overturn, rel=1e-6)


@settings(max_examples=40, deadline=None)
@given(**body_args)
def test_the_mirrored_body_under_the_negated_motion_tilts_the_other_way(seed, aspect, amp_g, period_s):
    outline, su, sz = _body(seed, aspect)
    try:
        one = chain_from_outline(0.3 * outline, 0.09 * su, 0.09 * sz)
    except ValueError:
        return
    mirrored = outline * [-1.0, 1.0]
    other = chain_from_outline(0.3 * mirrored[::-1], 0.09 * su, 0.09 * sz)     # counter-clockwise again
    a = _pulse(amp_g, period_s, DT)
    h1, h2 = np.zeros(N), np.zeros(N)
    r1 = roll_on_hull(a, DT, one, theta_out=h1)
    r2 = roll_on_hull(-a, DT, other, theta_out=h2)
    assert r1.verdict == r2.verdict
    np.testing.assert_allclose(h2, -h1, rtol=1e-9, atol=1e-12)
    assert r1.theta_max_plus == pytest.approx(r2.theta_max_minus, rel=1e-9, abs=1e-12)
    assert one.tipping_rad() == pytest.approx(other.tipping_rad()[::-1], abs=1e-12)


@settings(max_examples=100, deadline=None)
@given(seed=st.integers(0, 10_000), aspect=st.floats(1.0, 4.0))
def test_g_is_over_the_carrying_pivot_at_each_tipping_angle(seed, aspect):
    outline, su, sz = _body(seed, aspect)
    try:
        chain = chain_from_outline(outline, su, sz)
    except ValueError:
        return
    for side, tip in zip((1.0, -1.0), chain.tipping_rad()):
        theta = side * tip
        if tip == pytest.approx(math.pi / 2) or any(abs(theta - b) < 1e-12 for b in chain.bounds_rad):
            continue                                            # at 90 degrees, or G over an edge between pivots
        carrying = [k for k in range(len(chain.pivots_m)) if chain.bounds_rad[k] < theta < chain.bounds_rad[k + 1]]
        assert len(carrying) == 1
        u, z = chain.pivots_m[carrying[0]]
        assert abs(u * math.cos(theta) + z * math.sin(theta)) < 1e-9   # G's horizontal offset from that pivot
