"""The contact model's long steps (pipeline.rocking.solids.long_steps): which steps merge, that an impact ahead
keeps them short, and that a body stepped with them rocks as the planar kernel does (Housner's impacts) and as it
does with every step short, in fewer steps."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.constants import G
from pipeline.rocking.block import BlockShape, dynamics
from pipeline.rocking.planner import simulate_scene
from pipeline.rocking.settings import SimulationConfig
from pipeline.rocking.solids import long_steps
from pipeline.rocking.solids.attitude import rotation_matrix
from pipeline.rocking.solids.contact3d import CONTACT_GAP_M, simulate_contact3d
from pipeline.rocking.solids.convex_body import box_body
from pipeline.rocking.solids.long_steps import impact_ahead, last_passed, steps_merged
from pipeline.rocking.solids.near_ground import listed, near

DT = 0.005
T = np.arange(0.0, 6.0, DT)


@pytest.mark.parametrize("n_sub, h_s, merged", [
    (10, 5e-4, 2),              # a 200 Hz record: 1 ms (5 steps of 1 ms a sample; 2.5 ms is beyond 1.3 ms)
    (20, 5e-4, 2),              # 100 Hz
    (3, 1.25e-3 / 3, 3),        # the shake table's 800 Hz: one step a sample
    (4, 3.125e-4, 4),           # 1.25 ms in four steps: 4 divides 4
    (7, 5e-4, 1),               # 7 has no divisor but 1 and 7, and 3.5 ms is beyond 1.3 ms
    (1, 1e-3, 1),
])
def test_steps_merge_within_a_sample_up_to_the_long_step(n_sub, h_s, merged):
    assert steps_merged(n_sub, h_s) == merged


def test_no_step_merges_where_the_long_step_is_shorter_than_a_step(monkeypatch):
    monkeypatch.setattr(long_steps, "LONG_STEP_S", 1e-4)
    assert steps_merged(10, 5e-4) == 1


def _leaning_box(tilt_rad: float, rate_rad_s: float, *, coming_down: bool):
    """A 0.4 x 0.6 x 1.6 m box on one edge of its base, tilted by ``tilt_rad`` about y (the base's far edge raised
    by 0.4 sin(tilt)), turning about y at ``rate_rad_s`` about its pivot, its far edge ``coming_down`` or going up:
    its vertices, rotation, G, velocities, list of the vertices near the ground, and the far
    edge's vertical velocities [m/s]."""
    body = box_body(0.4, 0.6, 1.6, mu=0.8)
    vertices = np.ascontiguousarray(body.vertices, dtype=float)
    q = np.array([math.cos(tilt_rad / 2.0), 0.0, math.sin(tilt_rad / 2.0), 0.0])
    r = rotation_matrix(q)
    arms = vertices @ r.T
    base = vertices[:, 2] < 0.0
    pivot = arms[base][np.argmin(arms[base, 2])]
    far = base & (arms[:, 2] > pivot[2] + 1e-6)
    x = np.array([0.0, 0.0, -pivot[2]])
    for sign in (1.0, -1.0):
        w = np.array([0.0, sign * rate_rad_s, 0.0])
        v = -np.cross(w, pivot)                                    # the pivot on the ground does not move
        down = v[2] + np.cross(w, arms[far])[:, 2]
        if np.all(down < 0.0) == coming_down:
            break
    nr = near(vertices)
    assert listed(vertices, r, x[2], CONTACT_GAP_M, nr) > 0
    return (vertices, r, x, v, w, nr), down


@pytest.mark.parametrize("tilt_rad, ahead", [(1e-3, True), (1.2e-3, True), (1.4e-3, False), (0.01, False),
                                             (0.05, False)])
def test_a_far_edge_coming_down_within_the_long_step_is_an_impact_ahead(tilt_rad, ahead):
    """The box falling back onto its base at 0.5 rad/s: its far edge, 0.4 sin(tilt) above the ground, comes down at
    about 0.2 m/s; within twice a step of 1.3 ms it falls 0.52 mm, so it lands within that at a tilt of 1e-3 and
    1.2e-3 rad (0.40 and 0.48 mm up) and not at 1.4e-3, 0.01 and 0.05 rad (0.56, 4.0 and 20 mm)."""
    state, down = _leaning_box(tilt_rad, 0.5, coming_down=True)
    assert down.size == 2 and np.all(np.abs(down + 0.2) < 0.01)        # the far edge comes down at about 0.2 m/s
    assert impact_ahead(*state, CONTACT_GAP_M, 1.3e-3) == ahead


def test_a_far_edge_going_up_is_no_impact_ahead():
    state, down = _leaning_box(1e-3, 0.5, coming_down=False)
    assert np.all(down > 0.19)
    assert not impact_ahead(*state, CONTACT_GAP_M, 1.3e-3)


def test_a_fast_spin_brings_the_vertices_outside_the_list_near_enough_to_count():
    """At 0.05 rad the far edge (20 mm up) is not near landing at 0.5 rad/s, but at 400 rad/s any vertex could
    sweep about 2 m in 2 x 1.3 ms: the list's bound on the other vertices, less that, is no longer above the ground."""
    state, _ = _leaning_box(0.05, 400.0, coming_down=False)
    assert impact_ahead(*state, CONTACT_GAP_M, 1.3e-3)


def test_the_time_a_tilt_passes_an_angle_is_linear_within_the_step():
    assert last_passed(1.0, 1.002, 0.1, 0.3, 0.15, math.nan) == pytest.approx(1.0005, abs=1e-15)
    assert last_passed(1.0, 1.002, 0.1, 0.3, 0.1, math.nan) == 1.0                 # from the angle itself
    assert last_passed(1.0, 1.002, 0.1, 0.3, 0.3, 0.5) == 0.5                      # not yet past it
    assert last_passed(1.0, 1.002, 0.3, 0.1, 0.15, 0.5) == 0.5                     # passed downward


@pytest.mark.parametrize("amp_g, period_s", [(0.3, 0.5), (0.25, 0.8), (0.5, 0.3), (0.45, 1.0), (0.4, 0.8)])
def test_long_steps_rock_a_deep_box_as_the_planar_kernel_in_fewer_steps(amp_g, period_s, monkeypatch):
    """The 0.4 x 4 x 2 m box of the planar-kernel test (test_contact3d.py) on a 1 ms step (DT = 5 ms: two of
    0.5 ms merged): the same verdict as the kernel and as every step short, the peak within 1 % of both, and
    fewer steps integrated wherever it rocks beyond 0.1 alpha."""
    ah = np.where(T < period_s, amp_g * G * np.sin(2 * np.pi * T / period_s), 0.0)
    block = dynamics([BlockShape(height_m=2.0, width_m=0.4, mu=0.8)])[0]
    planar = simulate_scene(ah, None, DT, block=block, settings=SimulationConfig(contact_model=False))
    body = box_body(0.4, 4.0, 2.0, mu=0.8)
    long = simulate_contact3d(ah, np.zeros_like(ah), None, DT, body)
    monkeypatch.setattr(long_steps, "LONG_STEP_S", 0.0)
    short = simulate_contact3d(ah, np.zeros_like(ah), None, DT, body)
    assert long.overturned == short.overturned == planar.overturned
    if not planar.overturned:
        assert long.tilt_max_rad / block.alpha == pytest.approx(planar.theta_max, rel=0.01)
        assert long.tilt_max_rad == pytest.approx(short.tilt_max_rad, rel=0.01)
    if planar.theta_max > 0.1:
        assert long.integrated_steps < short.integrated_steps
