"""The certificate that a box's other base axis never lifts nor slips (pipeline.rocking.solids.box_planar), checked
against the 3D model (a second algorithm: where the certificate holds, the 3D box never leaves the edges of its depth
axis,
never slides, and follows the planar scene), and at its exact boundaries (flat: uplift at |a_y| h = c (g + a_v),
slip at |a_h| = mu (g + a_v))."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.rocking.scene import Physics
from pipeline.rocking.solids.box3d import Box, simulate_box
from pipeline.rocking.solids.box_planar import (
    other_axis_certificate,
    planar_box_scene,
    width_block,
    width_components,
)

G = 9.80665
DT = 0.005


def _pulse(amplitude_ms2: float, period_s: float, *, start_s: float = 0.0, n: int = 1600) -> np.ndarray:
    t = np.arange(n) * DT - start_s
    return np.where((t >= 0) & (t < period_s), amplitude_ms2 * np.sin(2 * np.pi * t / period_s), 0.0)


def _box(h_m: float, w_m: float, d_m: float, mu: float = 0.9) -> Box:
    return Box(half_width_m=w_m / 2, half_depth_m=d_m / 2, half_height_m=h_m / 2, mu=mu)


# (box, along, across, vertical): records on which the box rocks in the plane of its width and its other axis holds
CASES = [
    ("cabinet", _box(1.8, 0.4, 0.9), _pulse(0.35 * G, 0.6), _pulse(0.12 * G, 0.45, start_s=0.2), None),
    ("deep column", _box(2.0, 0.3, 1.2), _pulse(0.2 * G, 0.5), _pulse(0.2 * G, 0.5, start_s=0.1),
     _pulse(0.15 * G, 0.3, start_s=0.05)),
    ("square", _box(1.5, 0.25, 0.25), _pulse(0.25 * G, 0.5), _pulse(0.05 * G, 0.7, start_s=0.3), None),
    ("wide slab", _box(1.0, 0.3, 2.0), _pulse(0.45 * G, 0.4), _pulse(0.3 * G, 0.4, start_s=0.15), None),
]


def _three_d(box: Box, along, across, vertical):
    return simulate_box(np.asarray(along), np.asarray(across), vertical, DT, box, azimuth_deg=0.0,
                        rtol=1e-9, atol_alpha=1e-10)


@pytest.mark.parametrize("label,box,along,across,vertical", CASES, ids=[c[0] for c in CASES])
def test_where_certified_the_3d_box_stays_on_the_edges_and_follows_the_planar_scene(label, box, along, across,
                                                                                     vertical):
    # the record's components: x = h1 along the width (azimuth 0), y = -h2 along the depth
    cs = planar_box_scene(along, -across, vertical, DT, box, 0.0)
    assert cs.other_axis.certified and cs.scene is not None, cs.other_axis
    assert cs.scene.theta_max > 0.05                     # it rocks: the certificate is not the trivial one at rest
    out = _three_d(box, along, across, vertical)
    assert out.corner_s == 0.0 and out.flag == 0 and not out.overturned
    alpha = width_block(box).alpha
    assert out.theta_max_rad / alpha == pytest.approx(cs.scene.theta_max, abs=1e-4)


@pytest.mark.parametrize("label,box,along,across,vertical", CASES, ids=[c[0] for c in CASES])
def test_the_certificate_is_not_vacuous_the_3d_box_reaches_a_corner_under_a_larger_across_motion(
        label, box, along, across, vertical):
    """Scaling the across component until the certificate fails, then further: the 3D box leaves its edges
    (lands on a corner, or is flagged) only past the certified range, never inside it."""
    certified_up_to, corner_at = 0.0, math.inf
    for factor in np.linspace(1.0, 12.0, 23):
        cs = planar_box_scene(along, -factor * across, vertical, DT, box, 0.0)
        out = _three_d(box, along, factor * across, vertical)
        left_edges = out.corner_s > 0.0 or out.flag != 0 or out.overturned
        if cs.other_axis.certified:
            assert not left_edges, factor
            certified_up_to = factor
        elif left_edges:
            corner_at = min(corner_at, factor)
    assert certified_up_to >= 1.0
    assert certified_up_to < corner_at < math.inf


@pytest.mark.parametrize("d_over_w", [0.5, 1.0, 3.0])
@pytest.mark.parametrize("vertical_g", [0.0, 0.2, -0.2])
def test_flat_box_uplift_about_the_depth_edge_is_certified_up_to_its_exact_boundary(d_over_w, vertical_g):
    box = _box(1.6, 0.4, 0.4 * d_over_w)
    n = 400
    av = np.full(n, vertical_g * G) if vertical_g else None
    boundary = (G + vertical_g * G) * box.half_depth_m / box.half_height_m        # |a_y| h = c (g + a_v)
    along = np.zeros(n)
    at = other_axis_certificate(along, np.full(n, boundary), av, box, theta_max_rad=0.0, friction_demand=0.0)
    assert at.certified and at.lift_margin == pytest.approx(0.0, abs=1e-12)
    above = other_axis_certificate(along, np.full(n, boundary * (1 + 1e-9)), av, box, theta_max_rad=0.0,
                                   friction_demand=0.0)
    assert not above.certified and above.lift_margin < 0.0
    # the 3D model agrees at both: flat at the boundary, lifted about a depth edge just above it
    assert _three_d(box, along, np.full(n, boundary), av).theta_max_rad == 0.0
    assert _three_d(box, along, np.full(n, boundary * 1.01), av).theta_max_rad > 0.0


def test_flat_box_slip_is_certified_up_to_mu_g_exactly():
    box = _box(1.0, 0.8, 0.8, mu=0.5)                       # squat: slips before it lifts
    n = 200
    a = box.mu * G / math.sqrt(2.0)                        # |a_h| = mu g along the diagonal
    at = other_axis_certificate(np.full(n, a), np.full(n, a), None, box, theta_max_rad=0.0,
                                friction_demand=0.0)
    assert at.certified and at.slip_margin == pytest.approx(0.0, abs=1e-12)
    above = other_axis_certificate(np.full(n, a * 1.000001), np.full(n, a), None, box, theta_max_rad=0.0,
                                   friction_demand=0.0)
    assert not above.certified


def test_what_is_never_certified():
    box = _box(1.5, 0.3, 0.6)
    along = _pulse(0.25 * G, 0.5)
    ok = dict(theta_max_rad=0.1, friction_demand=0.2)
    assert other_axis_certificate(along, 0.0 * along, None, box, **ok).certified
    alpha = math.atan2(box.half_width_m, box.half_height_m)
    assert not other_axis_certificate(along, 0.0 * along, None, box, theta_max_rad=alpha,
                                      friction_demand=0.2).certified            # at the tipping point
    assert not other_axis_certificate(along, 0.0 * along, None, box, theta_max_rad=0.1,
                                      friction_demand=box.mu).certified         # friction saturated in its plane
    assert not other_axis_certificate(along, 0.0 * along, np.full_like(along, -G), box, **ok).certified  # flight
    # a record that lifts the box at rest about a depth edge: nothing to certify, and no planar run
    across = np.full(1600, 1.0001 * G * box.half_depth_m / box.half_height_m)
    lifted = planar_box_scene(along, -across, None, DT, box, 0.0)
    assert lifted.scene is None and not lifted.other_axis.certified
    assert not other_axis_certificate(along, across, None, box, theta_max_rad=0.0, friction_demand=0.0).certified
    # a planar run that overturns goes to the 3D model
    strong = planar_box_scene(_pulse(1.5 * G, 0.8), np.zeros(1600), None, DT, box, 0.0)
    assert strong.scene is not None and strong.scene.overturned and not strong.other_axis.certified
    # the planar model that drops a vertical (vertical_fraction > 0) is not the 3D model, which keeps it
    from pipeline.rocking.settings import SimulationConfig

    weak_v = 0.01 * _pulse(G, 0.3)
    dropped = planar_box_scene(along, np.zeros(1600), weak_v, DT, box, 0.0,
                               settings=SimulationConfig(vertical_fraction=0.05))
    assert dropped.scene is not None and dropped.scene.physics == Physics.rocking
    assert not dropped.other_axis.certified


@pytest.mark.parametrize("azimuth_deg", [0.0, 35.0, 90.0, 200.0])
def test_width_components_rotate_with_the_box(azimuth_deg):
    """A motion along the box's width (at the models' azimuth ``azimuth_deg``) is all along, none across, in every
    orientation of the record's components."""
    a = _pulse(2.0, 0.5)
    phi = math.radians(azimuth_deg)
    h1, h2 = a * math.cos(phi), -a * math.sin(phi)           # x = h1, y = -h2
    along, across = width_components(h1, h2, azimuth_deg)
    assert np.allclose(along, a, atol=1e-12) and np.allclose(across, 0.0, atol=1e-12)
