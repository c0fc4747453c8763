"""Property: a box pushed steadily from rest in any direction, at any demand, moves as the 3D contact model with every
step's contact problem solved has it, whether its flat steps are taken as a translation (:mod:`pipeline.rocking.solids
.flat_slide`) or not: it stays, slides flat, or tips at the same step."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from pipeline.constants import G
from pipeline.rocking.solids.contact3d import simulate_contact3d
from pipeline.rocking.solids.convex_body import box_body

DT = 0.01


@settings(max_examples=80, deadline=None)
@given(width=st.floats(0.2, 1.5), depth=st.floats(0.2, 1.5), height=st.floats(0.3, 2.5), mu=st.floats(0.1, 0.8),
       yaw_deg=st.floats(0.0, 360.0), push_deg=st.floats(0.0, 360.0), demand=st.floats(0.05, 0.9),
       push_s=st.floats(0.05, 0.6), vertical=st.floats(-0.3, 0.3))
def test_flat_steps_move_a_pushed_box_as_every_step_solved(width, depth, height, mu, yaw_deg, push_deg, demand, push_s,
                                                           vertical):
    n_push, n_tail = max(2, int(round(push_s / DT))), int(round(0.8 / DT))
    ax = np.concatenate([np.full(n_push, demand * G * math.cos(math.radians(push_deg))), np.zeros(n_tail)])
    ay = np.concatenate([np.full(n_push, demand * G * math.sin(math.radians(push_deg))), np.zeros(n_tail)])
    az = np.concatenate([np.full(n_push, vertical * G), np.zeros(n_tail)])
    body = box_body(width, depth, height, mu=mu)
    got = simulate_contact3d(ax, ay, az, DT, body, yaw_deg=yaw_deg)
    solved = simulate_contact3d(ax, ay, az, DT, body, yaw_deg=yaw_deg, flat_slides=False)
    assert got.overturned == solved.overturned
    assert abs(got.tilt_max_rad - solved.tilt_max_rad) <= 1e-6
    assert abs(got.slide_max_m - solved.slide_max_m) <= 1e-6 * (1.0 + solved.slide_max_m)
    assert abs(got.twist_max_rad - solved.twist_max_rad) <= 1e-6
