"""Hypothesis property test: the demand ratio of a record scaled by a positive factor (the margin's scan), taken
without making the scaled series, is the ratio :func:`pipeline.rocking.planner.demand_ratio` gives the scaled
series, double for double: with a vertical by :func:`ground.scaled_demand_ratio`'s one pass (inf where g + a_v
reaches 0), without one as the factor times the unscaled peak over g (a product with a positive factor is rounded
monotonically, so the peak commutes with it)."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from pipeline.constants import G
from pipeline.rocking.numerics import ground
from pipeline.rocking.planner import demand_ratio

accel = st.floats(min_value=-50.0, max_value=50.0, allow_nan=False, allow_subnormal=True)
factors = st.floats(min_value=1e-3, max_value=20.0) | st.sampled_from([0.1, 0.3, 1.0, 1.01, 3.0, 10.0])


@settings(max_examples=300, deadline=None)
@given(st.integers(min_value=1, max_value=300).flatmap(
    lambda n: st.tuples(arrays(np.float64, n, elements=accel), arrays(np.float64, n, elements=accel))), factors)
def test_the_scaled_ratio_is_the_ratio_of_the_scaled_record(series, factor):
    ah, av = series
    direct = demand_ratio(factor * ah, factor * av, g_ms2=G)
    assert ground.scaled_demand_ratio(ah, av, factor, G) == direct         # inf where g + f a_v <= 0 somewhere
    assert factor * float(np.max(np.abs(ah))) / G == demand_ratio(factor * ah, None, g_ms2=G)
