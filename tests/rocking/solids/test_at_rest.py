"""A body of the 3D contact model at rest off its base (pipeline.rocking.solids.at_rest): the threshold of the
contacts it rests on against statics (the nearest edge of their polygon over G's height, or friction), and a
hexagonal prism lying on its next face, 60 degrees over, under a steady push across it: below the threshold it stays
exactly where it lies, nothing integrated after the step that found it still; at the threshold it stays; above it, it
rolls on or slides, the slide the closed form's."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

from pipeline.constants import G
from pipeline.rocking.scanned.hull3d import scan_body
from pipeline.rocking.solids.contact3d import simulate_contact3d
from pipeline.rocking.solids.contact_start import Start
from pipeline.rocking.solids.convex_body import ConvexBody, support_threshold
from pipeline.shapes.scan import read_scan

DT = 0.002
N = 1000                                         # 2 s of a steady push
TAN_30 = math.tan(math.radians(30.0))


def _arms(xy, height):
    return np.array([[x, y, -height] for x, y in xy], dtype=float)


@pytest.mark.parametrize("half_x, half_y, height, mu, expected", [
    (0.15, 0.3, 0.26, 2.0, 0.15 / 0.26),        # tipping about the nearer long edge
    (0.4, 0.2, 0.5, 2.0, 0.2 / 0.5),
    (0.4, 0.2, 0.5, 0.3, 0.3),                  # friction first
])
def test_the_threshold_of_a_rectangle_of_contacts_is_statics(half_x, half_y, height, mu, expected):
    arms = _arms([(sx * half_x, sy * half_y) for sx in (-1, 1) for sy in (-1, 1)], height)
    assert support_threshold(arms, 4, mu) == pytest.approx(expected, rel=1e-12)


def test_the_threshold_of_a_triangle_is_its_nearest_edge_over_the_height():
    """G's foot at the origin inside the triangle (-0.2, -0.1), (0.3, -0.1), (0, 0.4): the nearest edge is y = -0.1."""
    arms = _arms([(-0.2, -0.1), (0.3, -0.1), (0.0, 0.4)], 0.25)
    assert support_threshold(arms, 3, 5.0) == pytest.approx(0.1 / 0.25, rel=1e-12)


@pytest.mark.parametrize("xy", [
    [(0.1, -0.1), (0.5, -0.1), (0.3, 0.3)],     # G's foot outside the triangle
    [(-0.2, 0.0), (0.2, 0.0)],                  # an edge: no inside
    [(-0.2, 0.1), (0.0, 0.1), (0.2, 0.1)],      # three on a line beside G's foot: an edge still
])
def test_contacts_that_cannot_hold_the_body_give_no_threshold(xy):
    assert support_threshold(_arms(xy, 0.3), len(xy), 2.0) == 0.0


def test_only_the_first_n_rows_count():
    arms = np.vstack([_arms([(sx * 0.2, sy * 0.2) for sx in (-1, 1) for sy in (-1, 1)], 0.4),
                      _arms([(5.0, 5.0)], 0.4)])
    assert support_threshold(arms, 4, 9.0) == pytest.approx(0.5, rel=1e-12)


@pytest.fixture(scope="module")
def hexagon(tmp_path_factory) -> ConvexBody:
    """A regular hexagonal prism (circumradius 0.3 m, 0.6 m long along y) settled on a side face: on its next face,
    60 degrees over, G stands 0.26 m above the middle of a 0.3 x 0.6 m rectangle: tan alpha = tan 30."""
    angles = np.radians(np.arange(0.0, 360.0, 60.0))
    points = np.array([[0.3 * math.cos(a), y, 0.3 * math.sin(a)] for a in angles for y in (-0.3, 0.3)])
    path = tmp_path_factory.mktemp("hexagon") / "hexagon.obj"
    trimesh.convex.convex_hull(points).export(path)
    return scan_body(read_scan(path), mu=2.0)


def _on_next_face(body: ConvexBody, sense: float) -> Start:
    """The prism still on its next face (turned by 60 degrees in ``sense`` about its long axis)."""
    turn = Rotation.from_euler("y", sense * 60.0, degrees=True).as_matrix() @ body.rest
    x, y, z, w = Rotation.from_matrix(turn).as_quat()
    low = int(np.argmin((body.vertices @ turn.T)[:, 2]))
    return Start(0.0, np.array([w, x, y, z]), np.zeros(3), body.vertices[low].copy(), tilt_max_rad=math.radians(60.0))


def _push(hexagon, sense, demand, mu):
    body = hexagon._replace(mu=mu)
    ax = np.full(N, demand * G)
    return simulate_contact3d(ax, np.zeros(N), None, DT, body, start=_on_next_face(body, sense), history=True)


@pytest.mark.parametrize("sense", [1.0, -1.0])
@pytest.mark.parametrize("mu, limit", [(2.0, TAN_30), (0.3, 0.3)])
def test_below_the_threshold_it_is_held_where_it_lies(hexagon, sense, mu, limit):
    got = _push(hexagon, sense, -0.97 * limit, mu)
    assert got.integrated_steps == 1
    assert np.allclose(np.degrees(got.tilt_rad[1:]), 60.0, atol=1e-9)          # (sample 0: before the start)
    assert got.overturned and math.degrees(got.tilt_end_rad) == pytest.approx(60.0, abs=1e-9)
    assert got.t_end_s == pytest.approx((N - 1) * DT, abs=DT)  # held to the record's end, where it rests


@pytest.mark.parametrize("sense", [1.0, -1.0])
def test_at_the_threshold_it_stays(hexagon, sense):
    """|a_h| = tan alpha g exactly: equilibrium, whether the rounding of the threshold holds it or steps it."""
    got = _push(hexagon, sense, TAN_30, 2.0)
    assert np.allclose(np.degrees(got.tilt_rad[1:]), 60.0, atol=1e-6)


@pytest.mark.parametrize("sense", [1.0, -1.0])
def test_above_the_tipping_threshold_it_rolls_on(hexagon, sense):
    got = _push(hexagon, sense, 1.03 * TAN_30, 2.0)
    assert np.nanmax(np.abs(np.degrees(got.tilt_rad[1:]) - 60.0)) > 20.0


def test_above_the_friction_threshold_it_slides_the_closed_forms_distance(hexagon):
    """mu 0.3: the push 1.03 mu g for 2 s, then friction mu g stops it: 0.5 a t^2 + (a t)^2 / (2 mu g), a = 0.03 mu g,
    the same as on its base."""
    got = _push(hexagon, 1.0, -1.03 * 0.3, 0.3)
    a, t = 0.03 * 0.3 * G, (N - 1) * DT
    start = _on_next_face(hexagon, 1.0)                  # G starts where the pivot's turn from standing put it
    turn = Rotation.from_quat(np.r_[start.q[1:], start.q[0]]).as_matrix()
    stood = float(np.hypot(*(hexagon.rest @ start.pivot_m - turn @ start.pivot_m)[:2]))
    assert got.slide_max_m - stood == pytest.approx(0.5 * a * t * t + (a * t) ** 2 / (2 * 0.3 * G), rel=2e-3)
    assert math.degrees(got.tilt_end_rad) == pytest.approx(60.0, abs=1e-6)
