"""A body flat on its base stepped as a translation (:mod:`pipeline.rocking.solids.flat_slide`): its base's polygon,
the closed forms of a box pushed steadily along and across its base, and the contact model with every step solved
(``flat_slides=False``) on real records."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.constants import G
from pipeline.rocking.solids.contact3d import simulate_contact3d
from pipeline.rocking.solids.contact_pose import base_edges
from pipeline.rocking.solids.convex_body import box_body, cylinder_body
from pipeline.rocking.solids.flat_slide import inside

DT = 0.005


def _edges(body):
    out = np.empty((len(body.vertices), 3))
    size = float(np.max(np.linalg.norm(body.vertices, axis=1)))
    m = base_edges(np.ascontiguousarray(body.vertices), size, out)
    return out[:m]


def test_a_box_base_has_its_four_sides():
    edges = _edges(box_body(0.45, 0.9, 1.8, mu=0.3))
    assert len(edges) == 4
    got = sorted((round(nx, 12) + 0.0, round(ny, 12) + 0.0, round(d, 12)) for nx, ny, d in edges)
    assert got == [(-1.0, 0.0, 0.225), (0.0, -1.0, 0.45), (0.0, 1.0, 0.45), (1.0, 0.0, 0.225)]


def test_a_cylinder_base_is_its_inscribed_polygon():
    r, k = 0.2, 32
    edges = _edges(cylinder_body(2 * r, 1.2, mu=0.3, rim_points=k))
    assert len(edges) == k
    assert np.allclose(edges[:, 2], r * math.cos(math.pi / k), rtol=1e-12)
    assert np.allclose(np.hypot(edges[:, 0], edges[:, 1]), 1.0, rtol=1e-12)


@pytest.mark.parametrize(("cx", "cy", "held"), [(0.0, 0.0, True), (0.2249, 0.4499, True), (0.2251, 0.0, False),
                                                (0.0, -0.4501, False), (0.225, 0.0, False)])
def test_inside_the_base_by_its_margin(cx, cy, held):
    edges = _edges(box_body(0.45, 0.9, 1.8, mu=0.3))
    assert inside(cx, cy, edges, len(edges)) is held


def _push(ax_g, ay_g, seconds, tail_s=3.0):
    """A steady push [g] for ``seconds``, then the ground still for ``tail_s`` (sampled at DT)."""
    n_push, n_tail = int(round(seconds / DT)), int(round(tail_s / DT))
    ax = np.concatenate([np.full(n_push, ax_g * G), np.zeros(n_tail)])
    ay = np.concatenate([np.full(n_push, ay_g * G), np.zeros(n_tail)])
    return ax, ay


# a cabinet 0.45 wide (x) and 0.9 deep (y), 1.8 high: tan alpha 0.25 across its width, 0.5 across its depth
CABINET = (0.45, 0.9, 1.8)


def _slide_after_push(push_ms2, mu_g_ms2, t1_s, ramp_s):
    """The distance a block slides flat relative to a ground pushed at ``push_ms2`` until ``t1_s``, the push then
    falling linearly to 0 over ``ramp_s`` (the ground linear between samples), its friction ``mu_g_ms2`` [m s-2]:
    constant slip acceleration, then a cubic over the ramp, then mu g against it to its stop (closed forms) [m]."""
    a = push_ms2 - mu_g_ms2
    u1, x1 = a * t1_s, 0.5 * a * t1_s ** 2
    u2 = u1 + a * ramp_s - push_ms2 * ramp_s / 2.0
    x2 = x1 + u1 * ramp_s + a * ramp_s ** 2 / 2.0 - push_ms2 * ramp_s ** 2 / 6.0
    return x2 + u2 ** 2 / (2.0 * mu_g_ms2)


def test_pushed_along_its_depth_above_its_friction_it_slides_flat_the_closed_form_distance():
    """mu 0.35, between the two tipping tans: pushed along y at 0.45 g for 1 s it slides flat (the friction's
    moment is held by its depth), the closed form's distance, and stops; as with every step solved."""
    mu, push, t = 0.35, 0.45, 1.0
    ax, ay = _push(0.0, push, t)
    got = simulate_contact3d(ax, ay, None, DT, box_body(*CABINET, mu=mu))
    assert got.tilt_max_rad == 0.0 and not got.overturned
    expected = _slide_after_push(push * G, mu * G, t - DT, DT)      # the last sample at the push is at t - DT
    assert got.slide_max_m == pytest.approx(expected, rel=1e-3)
    solved = simulate_contact3d(ax, ay, None, DT, box_body(*CABINET, mu=mu), flat_slides=False)
    assert solved.tilt_max_rad < 1e-9
    assert got.slide_max_m == pytest.approx(solved.slide_max_m, rel=1e-9)


def test_pushed_along_its_depth_below_its_friction_it_stays_where_it_stood():
    """0.3 g along y: above tan alpha across its width (0.25), so beyond the at-rest threshold min(mu, tan
    alpha_min), but its depth holds the push and its friction (0.35) too: nothing moves."""
    ax, ay = _push(0.0, 0.3, 1.0)
    for flat in (True, False):
        got = simulate_contact3d(ax, ay, None, DT, box_body(*CABINET, mu=0.35), flat_slides=flat)
        assert got.tilt_max_rad < 1e-9 and got.slide_max_m < 1e-9


def test_pushed_across_its_width_it_tips_as_with_every_step_solved():
    """0.3 g along x, above tan alpha across its width (0.25) and below mu: it tips, and the flat steps hand that
    step to the contact problem: the same run as with every step solved."""
    ax, ay = _push(0.3, 0.0, 0.4)
    got = simulate_contact3d(ax, ay, None, DT, box_body(*CABINET, mu=0.35))
    solved = simulate_contact3d(ax, ay, None, DT, box_body(*CABINET, mu=0.35), flat_slides=False)
    assert got.tilt_max_rad > 1e-3
    assert (got.tilt_max_rad, got.slide_max_m, got.overturned) == (solved.tilt_max_rad, solved.slide_max_m,
                                                                   solved.overturned)


def test_a_flat_slide_records_a_tilt_of_zero_at_every_sample():
    ax, ay = _push(0.0, 0.45, 1.0, tail_s=1.0)
    got = simulate_contact3d(ax, ay, None, DT, box_body(*CABINET, mu=0.35), history=True)
    assert np.all(got.tilt_rad == 0.0)


@pytest.fixture
def two_records(make_records):
    from pipeline.config import Config
    from pipeline.records.loader import iter_records

    root = make_records(*(f"peer-at2/RSN1063_NORTHR_RRS{c}.AT2" for c in ("228", "318", "-UP")),
                        *(f"peer-at2/RSN1086_NORTHR_SYL{c}.AT2" for c in ("090", "360", "-UP")))
    return [r for r in iter_records(root, config=Config())]


@pytest.mark.parametrize(("width", "depth", "height", "mu", "yaw"), [(0.45, 0.9, 1.8, 0.15, 30.0),
                                                                     (0.6, 1.2, 2.1, 0.35, 90.0),
                                                                     (0.45, 0.9, 1.98, 0.21, 0.0),
                                                                     (1.2, 0.8, 0.6, 0.15, 0.0)])
def test_on_real_records_as_with_every_step_solved(two_records, width, depth, height, mu, yaw):
    """Rinaldi and Sylmar (both horizontals and the vertical) x boxes that slide flat and slide while they rock:
    the verdict as with every step solved, and the peak tilt and the largest slide within 1e-3 alpha and 1 mm of the
    range that every step solved gives under the record times 1, 0.9999 and 1.0001 (a box whose
    friction is near tan alpha rocks while it slides, and its small peak turns on the last digits: the cabinet 2.1 m
    high, mu 0.35, on Sylmar, peaks at 0.048-0.060 alpha; benchmarks/contact3d_flat.py runs 440 such scenes)."""
    alpha = math.atan(min(width, depth) / height)
    for rec in two_records:
        bx, by = rec.horizontal_ms2[0], -rec.horizontal_ms2[1]
        body = box_body(width, depth, height, mu=mu)
        got = simulate_contact3d(bx, by, rec.vertical_ms2, rec.dt_s, body, yaw_deg=yaw)
        solved = [simulate_contact3d(s * bx, s * by, s * rec.vertical_ms2, rec.dt_s, body, yaw_deg=yaw,
                                     flat_slides=False) for s in (1.0, 0.9999, 1.0001)]
        assert got.overturned == solved[0].overturned
        assert got.slide_max_m > 1e-3                  # it slid
        if not got.overturned:
            tilts, slides = [o.tilt_max_rad for o in solved], [o.slide_max_m for o in solved]
            assert min(tilts) - 1e-3 * alpha <= got.tilt_max_rad <= max(tilts) + 1e-3 * alpha
            assert min(slides) - 1e-3 <= got.slide_max_m <= max(slides) + 1e-3


@pytest.mark.parametrize("push_g", [0.26, 0.4])
def test_at_mu_equal_to_tan_alpha_a_box_slides_flat_with_its_load_on_the_edge(push_g):
    """mu = tan alpha across the width (0.25): a box sliding across it has its normal impulses centred exactly on
    the base's edge, the boundary where it neither tips nor needs to; the flat steps leave those steps to the contact
    problem (their margin). Pushed just above mu g and well above it, it slides flat the closed form's distance, and
    as every step solved has it to 1e-9."""
    mu, t = 0.25, 0.5
    ax, ay = _push(push_g, 0.0, t)
    body = box_body(*CABINET, mu=mu)
    got = simulate_contact3d(ax, ay, None, DT, body)
    solved = simulate_contact3d(ax, ay, None, DT, body, flat_slides=False)
    assert got.tilt_max_rad == 0.0 and solved.tilt_max_rad == 0.0 and not got.overturned
    assert got.slide_max_m == pytest.approx(_slide_after_push(push_g * G, mu * G, t - DT, DT), rel=1e-3)
    assert got.slide_max_m == pytest.approx(solved.slide_max_m, rel=1e-9)
