"""Hypothesis property tests of the ITP step (:mod:`pipeline.rocking.numerics.itp`): on any function with one sign
change on the step, non-negative before its root and negative after it, the bracket ends within its width past the
root, and no more evaluations are made than bisection's count plus N0 (and the guard's few where rounding at a
bracket of a few ulps costs some)."""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as st
from itp_driver import BITS, itp_root

from pipeline.rocking.numerics.itp import EXTRA_GUARD, evaluations_cap

steps = st.floats(1e-6, 10.0)
fractions = st.floats(0.0, 1.0)
wiggles = st.floats(-0.9, 0.9)
waves = st.floats(0.0, 200.0)
powers = st.sampled_from([1, 2, 3])


@settings(deadline=None)                                # the first example compiles the step
@given(steps, fractions, wiggles, waves, powers)
def test_the_bracket_ends_past_the_root_within_its_width(h, fraction, c, k, power):
    root = fraction * h

    def f(s: float) -> float:
        # one sign change at the root (an odd power of root - s, times a factor kept positive), wiggling between
        d = root - s
        return math.copysign(abs(d) ** power, d) * (1.0 + c * math.sin(k * s / h)) if d != 0.0 else 0.0

    if not f(h) < 0.0:                                   # the root at the step's end: no event inside the step
        return
    hi, lo, evaluations = itp_root(f, h)
    width = h * 2.0 ** -BITS
    assert f(hi) < 0.0 and hi - lo <= width                  # ended by its width, not by the loop's cap
    assert root - 2 * math.ulp(h) <= hi <= root + width + 4 * math.ulp(h)
    # bisection's count plus N0 in exact arithmetic (the minmax guarantee); rounding at a bracket of a few ulps
    # may take one or two more, within the loop's guard
    assert evaluations <= evaluations_cap(h, width) + EXTRA_GUARD
