"""Property: the stages' sin and cos of alpha s - theta, rotated from the step's start, agree with math.sin and
math.cos to a few units in the last place wherever the rotation is used (|d| <= ROTATION_MAX_RAD)."""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as st

from pipeline.rocking.numerics.dopri import ROTATION_MAX_RAD, _rotated

ULP_OF_ONE = 2.0 ** -52


@settings(max_examples=2000, deadline=None)
@given(phi0=st.floats(-2.0, 2.0), d=st.floats(-ROTATION_MAX_RAD, ROTATION_MAX_RAD))
def test_the_rotated_sine_and_cosine_are_maths_to_rounding(phi0, d):
    """|error| <= 4 ulp of 1: the values are at most 1 in magnitude, and the rotation's four products and two
    sums each round once (math.sin and math.cos of phi0 - d, computed in the same doubles, are the reference)."""
    sin_r, cos_r = _rotated(math.sin(phi0), math.cos(phi0), d)
    phi = phi0 - d
    assert abs(sin_r - math.sin(phi)) <= 4 * ULP_OF_ONE
    assert abs(cos_r - math.cos(phi)) <= 4 * ULP_OF_ONE


@given(phi0=st.floats(-2.0, 2.0))
def test_no_change_of_theta_gives_the_start_back(phi0):
    """d = 0: the start's own doubles."""
    assert _rotated(math.sin(phi0), math.cos(phi0), 0.0) == (math.sin(phi0), math.cos(phi0))
