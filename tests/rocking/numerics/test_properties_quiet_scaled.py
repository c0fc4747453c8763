"""Hypothesis property test: the quiet table of a record scaled by a positive factor (the margin's scan) is the
nominal table's values times the factor, value for value (:func:`ground.scaled_quiet_table` against
:func:`ground.quiet_table` of the scaled series): a product with a positive factor is rounded monotonically, so a
chunk's max and min commute with it."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from pipeline.rocking.numerics import ground

accel = st.floats(min_value=-50.0, max_value=50.0, allow_nan=False, allow_subnormal=True)
factors = st.floats(min_value=1e-3, max_value=20.0) | st.sampled_from([0.1, 0.3, 1.0, 1.01, 3.0, 10.0])


@settings(max_examples=200, deadline=None)
@given(st.integers(min_value=1, max_value=300).flatmap(
    lambda n: st.tuples(arrays(np.float64, n, elements=accel), arrays(np.float64, n, elements=accel),
                        st.booleans())), factors)
def test_the_scaled_table_is_the_table_of_the_scaled_record(series, factor):
    ah, av, has_vertical = series
    vertical = av if has_vertical else None
    scaled = ground.scaled_quiet_table(ground.quiet_table(ah, vertical), factor)
    direct = ground.quiet_table(factor * ah, None if vertical is None else factor * vertical)
    np.testing.assert_array_equal(scaled.peak_ah_ms2, direct.peak_ah_ms2)
    np.testing.assert_array_equal(scaled.least_av_ms2, direct.least_av_ms2)
