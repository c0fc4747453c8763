"""Property tests of what a convex body needs to overturn (pipeline.rocking.solids.tip_barrier) over random boxes,
turned about the vertical: the barrier is a lower bound of G's height balanced over the nearer base edge (the
closed form), within the sampling's allowance on the circle at its tipping angle, whichever way the box is turned
in its own axes."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pipeline.rocking.solids.contact_pose import LYING_SLACK_RAD
from pipeline.rocking.solids.convex_body import box_body
from pipeline.rocking.solids.tip_barrier import DIRECTIONS, tip_barrier

SETTINGS = settings(max_examples=60, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])


@SETTINGS
@given(width=st.floats(0.1, 2.0), depth=st.floats(0.1, 2.0), height=st.floats(0.1, 4.0),
       yaw_deg=st.floats(0.0, 360.0))
def test_a_box_needs_at_least_the_barrier_and_not_much_more(width, depth, height, yaw_deg):
    body = box_body(width, depth, height, mu=0.6)
    c, s = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))
    turned = body.vertices @ np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
    tipping = math.atan(min(width, depth) / height)
    barrier = tip_barrier(turned, body.inertia, 0.5 * math.pi - LYING_SLACK_RAD, tipping_rad=tipping)
    exact = math.hypot(0.5 * min(width, depth), 0.5 * height)
    reach = 0.5 * math.sqrt(width ** 2 + depth ** 2 + height ** 2)
    assert barrier.height_m <= exact
    # a circle at the tipping angle passes over the nearer edge: the barrier within the circles' allowance of it
    assert barrier.height_m >= exact - reach * math.pi * math.sin(tipping) / DIRECTIONS - 1e-12
    assert barrier.low_m <= 0.5 * height < barrier.height_m
