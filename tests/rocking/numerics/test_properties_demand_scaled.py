"""Hypothesis property test: the demand ratio of a record scaled by a positive factor (the draws and the margin's
scan), taken by :func:`ground.scaled_demand_ratio` without making the scaled series, is the ratio
:func:`pipeline.rocking.planner.demand_ratio` gives the scaled series, double for double: in a record's own plane
(weights 1, 0) and in a plane between two horizontals, with a vertical (inf where g + a_v reaches 0) and without."""

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
    lambda n: st.tuples(arrays(np.float64, n, elements=accel), arrays(np.float64, n, elements=accel),
                        arrays(np.float64, n, elements=accel))), factors, st.floats(min_value=0.0, max_value=180.0))
def test_the_scaled_ratio_is_the_ratio_of_the_scaled_record(series, factor, azimuth_deg):
    h1, h2, av = series
    c, s = float(np.cos(np.radians(azimuth_deg))), float(np.sin(np.radians(azimuth_deg)))
    none = np.zeros(0)
    for (w1, w2), along in (((1.0, 0.0), h1), ((c, s), c * h1 + s * h2)):
        assert ground.scaled_demand_ratio(h1, h2, w1, w2, factor, av, True, G, False) == \
            demand_ratio(factor * along, factor * av, g_ms2=G)               # inf where g + f a_v <= 0 somewhere
        assert ground.scaled_demand_ratio(h1, h2, w1, w2, factor, none, False, G, False) == \
            demand_ratio(factor * along, None, g_ms2=G)
