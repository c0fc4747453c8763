"""The hand-back to the box's exact model (:mod:`pipeline.rocking.solids.alternate`) against the contact model alone,
a second algorithm for the same physics: the same verdicts and peaks on scenes where the box slides, then rocks on an
edge without slipping again, at a fraction of the cost."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from support.alternation import DT_S, handed_and_alone, sine_then_still
from support.spies import count_calls

import pipeline.rocking.solids.alternate as alternate_module
import pipeline.rocking.solids.box_handback as box_handback
from pipeline.constants import G
from pipeline.rocking.solids.alternate import alternate, cannot_tip_over
from pipeline.rocking.solids.box3d import EDGE, Box, simulate_box
from pipeline.rocking.solids.box_handback import BOX_EDGES, box_model, edge_state
from pipeline.rocking.solids.contact3d import prepare, simulate_contact3d
from pipeline.rocking.solids.contact_scene import contact_scene, handoff
from pipeline.rocking.solids.handoff3d import base_corner

CABINET = Box(0.3, 0.6, 1.05, 0.35)       # tan alpha 0.29 across its width, mu 0.35: it slides, then rocks


def _model():
    """The cabinet's exact model as the alternation takes it."""
    return box_model(CABINET, dt_s=DT_S, g_ms2=G, rtol=1e-7, atol_alpha=1e-9)


@pytest.fixture
def exact_calls(monkeypatch) -> list[int]:
    """The exact model's runs the alternation makes (a spy on its calls)."""
    return count_calls(monkeypatch, box_handback, "simulate_box")


@pytest.mark.parametrize("amplitude_g, frequency_hz, azimuth_deg", [
    (0.4, 1.0, 30.0), (0.4, 2.0, 30.0), (0.5, 1.0, 30.0), (0.6, 1.0, 0.0), (0.6, 2.0, 0.0), (0.6, 2.0, 30.0)])
def test_as_the_contact_model_alone(amplitude_g, frequency_hz, azimuth_deg, exact_calls):
    ax, ay = sine_then_still(amplitude_g, frequency_hz, azimuth_deg)
    exact = simulate_box(ax, ay, None, DT_S, CABINET)
    assert exact.flag != 0                                       # the exact model stops: its base would slide
    handed, alone = handed_and_alone(ax, ay, CABINET, exact, _model())
    assert exact_calls                                           # handed back at least once
    assert handed.overturned == alone.overturned
    if not alone.overturned:
        assert handed.tilt_max_rad == pytest.approx(alone.tilt_max_rad, rel=0.03)
    assert handed.integrated_steps < alone.integrated_steps


def test_a_cap_on_hand_backs_ends_with_the_contact_model(monkeypatch, exact_calls):
    monkeypatch.setattr(alternate_module, "MAX_HANDBACKS", 1)
    ax, ay = sine_then_still(0.6, 2.0, 30.0)
    start = handoff(simulate_box(ax, ay, None, DT_S, CABINET), CABINET, 0.0, DT_S)
    handed = alternate(ax, ay, None, DT_S, _model(), 0.0, start, g_ms2=G)
    alone = simulate_contact3d(ax, ay, None, DT_S, CABINET.convex(), start=start)
    assert len(exact_calls) == 1
    assert handed.overturned == alone.overturned and handed.edge == -1


def test_the_exact_state_lies_on_the_edge():
    """Where the contact model stops on an edge, the exact model's state has that edge level and turns about it,
    within the contact model's own resolution of where it was."""
    ax, ay = sine_then_still(0.6, 2.0, 0.0)
    start = handoff(simulate_box(ax, ay, None, DT_S, CABINET), CABINET, 0.0, DT_S)
    out = simulate_contact3d(ax, ay, None, DT_S, CABINET.convex(), start=start, edges=BOX_EDGES)
    assert out.edge >= 0 and out.t_end_s == pytest.approx(round(out.t_end_s / DT_S) * DT_S)
    y = edge_state(out, CABINET)
    assert y.mode == EDGE and y.pivot == out.edge
    rot = Rotation.from_quat([y.q[1], y.q[2], y.q[3], y.q[0]])
    a, b = rot.apply(base_corner(CABINET, out.edge)), rot.apply(base_corner(CABINET, (out.edge + 1) % 4))
    assert np.linalg.norm(y.q) == pytest.approx(1.0, abs=1e-12)
    assert a[2] == pytest.approx(b[2], abs=1e-12)                        # the edge level
    rate = y.rate_rad_s
    assert np.linalg.norm(np.cross(rate, b - a)) <= 1e-12 * np.linalg.norm(rate) * np.linalg.norm(b - a)
    q = np.asarray(out.q_end)
    moved = (rot * Rotation.from_quat([q[1], q[2], q[3], q[0]]).inv()).magnitude()
    assert moved < 1e-4                                                  # levelled by less than a step's sink
    assert np.linalg.norm(rate - out.rate_end_rad_s) <= 1e-3 * np.linalg.norm(out.rate_end_rad_s)


def test_a_history_is_the_contact_model_alone():
    ax, ay = sine_then_still(0.6, 2.0, 0.0)

    def never(*args, **kwargs):
        raise AssertionError("the alternation ran for a history")

    exact = simulate_box(ax, ay, None, DT_S, CABINET)
    scene, out = contact_scene(ax, -ay, None, DT_S, CABINET, 0.0, 0.28, g_ms2=G, history=True, exact=exact,
                               alternated=never)
    assert out.tilt_rad is not None and scene.theta_over_alpha is not None


@pytest.mark.parametrize("share", [0.98, 1.02])
def test_the_end_of_record_certificate_is_housners_free_rocking_threshold(share):
    """The cabinet upright turning about an edge of its narrower side at ``share`` of the rate whose kinetic energy
    lifts G from h to R = sqrt(b^2 + h^2) (Housner 1963: ``I_O w^2 / 2 = g (R - h)``, ``I_O = 4 R^2 / 3`` for a box)
    cannot tip over below it and can above it; turning about its wider side at that rate it may (the certificate
    takes the lowest barrier)."""
    b, d, h = CABINET.half_width_m, CABINET.half_depth_m, CABINET.half_height_m
    big_r = math.hypot(b, h)
    rate = share * math.sqrt(2.0 * G * (big_r - h) / (4.0 * big_r ** 2 / 3.0))
    q, corner = np.array([1.0, 0.0, 0.0, 0.0]), base_corner(CABINET, 0)            # corner 0 at (+b, +d, -h)
    assert b < d and cannot_tip_over((q, np.array([0.0, rate, 0.0]), corner), _model(), G) == (share < 1.0)
    wide = math.sqrt(2.0 * G * (math.hypot(d, h) - h) / (4.0 * (d * d + h * h) / 3.0))
    assert not cannot_tip_over((q, np.array([-0.99 * wide, 0.0, 0.0]), corner), _model(), G)


def test_runs_on_prepared_arrays_are_runs_on_fresh_ones():
    """The alternation's contact runs share one body's arrays (:func:`~.contact3d.prepare`), made fresh in place
    before each: a run on arrays another scene's runs left behind gives, double for double, what a run on arrays made
    for it gives (a second path: the arrays made anew, as a run without them makes them)."""
    body = CABINET.convex()
    prepared = prepare(body, DT_S)
    for amplitude_g, frequency_hz, azimuth_deg in [(0.6, 2.0, 30.0), (0.4, 1.0, 30.0), (0.6, 2.0, 0.0)]:
        ax, ay = sine_then_still(amplitude_g, frequency_hz, azimuth_deg)
        start = handoff(simulate_box(ax, ay, None, DT_S, CABINET), CABINET, 0.0, DT_S)
        for edges in (BOX_EDGES, None):
            reused = simulate_contact3d(ax, ay, None, DT_S, body, start=start, edges=edges, prepared=prepared)
            fresh = simulate_contact3d(ax, ay, None, DT_S, body, start=start, edges=edges)
            assert reused.steps > 0 and (reused.edge >= 0) == (edges is not None)
            for name, value in fresh._asdict().items():
                np.testing.assert_array_equal(getattr(reused, name), value, err_msg=name)
