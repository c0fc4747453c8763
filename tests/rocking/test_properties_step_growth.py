"""Hypothesis property test: below ``kernel.GROWTH_CERTAIN_BELOW`` the step-size controller's factor is its largest,
so skipping the power there leaves every step, and every output, the same doubles (Hairer, Norsett & Wanner 1993,
section II.4: the factor SAFETY err^(-1/5), clipped to [MIN_FACTOR, MAX_FACTOR])."""

from __future__ import annotations

import math

from hypothesis import given
from hypothesis import strategies as st

from pipeline.rocking.planar import kernel

BOUND = kernel.GROWTH_CERTAIN_BELOW

below_bound = (st.sampled_from([5e-324, 1e-300, 1e-12, math.nextafter(BOUND, 0.0)])
               | st.floats(min_value=5e-324, max_value=BOUND, exclude_max=True))


@given(below_bound)
def test_below_the_bound_the_power_gives_the_largest_growth(err):
    factor = min(kernel.MAX_FACTOR, max(kernel.MIN_FACTOR, kernel.SAFETY * err ** kernel.ERROR_EXPONENT))
    assert factor == kernel.MAX_FACTOR


def test_the_bound_is_within_one_percent_of_where_the_growth_stops_being_clipped():
    """Not so far below the exact bound (MAX_FACTOR / SAFETY)^(-5) that the skip never applies."""
    exact = (kernel.MAX_FACTOR / kernel.SAFETY) ** (1.0 / kernel.ERROR_EXPONENT)
    assert 0.98 * exact < BOUND < exact
    assert kernel.SAFETY * (1.02 * exact) ** kernel.ERROR_EXPONENT < kernel.MAX_FACTOR
