"""Property: the rocking kernel's next step is the same double whether or not the error control's power is
evaluated (``kernel._next_step`` returns the cap where the controller's step is certainly above it)."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pipeline.rocking.planar.kernel import (
    ERROR_EXPONENT,
    GROWTH_CERTAIN_BELOW,
    MAX_FACTOR,
    MIN_FACTOR,
    SAFETY,
    SAMPLE_INDEX_TOL,
    _next_step,
)


def _controller(hh: float, err: float) -> float:
    """The step-size controller written out (Hairer, Norsett & Wanner 1993, II.4)."""
    return hh * min(MAX_FACTOR, max(MIN_FACTOR, SAFETY * err ** ERROR_EXPONENT))


@pytest.mark.slow                    # 11 s alone: make test-slow keeps make test under 5 min from a fresh clone
@settings(max_examples=3000, deadline=None)
@given(dt=st.floats(1e-4, 0.05), hh_frac=st.floats(1e-6, 1.0), err=st.floats(GROWTH_CERTAIN_BELOW, 1.0),
       left_frac=st.floats(1e-9, 1.0 + SAMPLE_INDEX_TOL), h_max=st.floats(1e-4, 1.0))
def test_the_next_step_is_the_controllers_wherever_it_is_not_capped(dt, hh_frac, err, left_frac, h_max):
    """Whatever is left of the next piece (at most dt, within the sample index's rounding) and h_max, the step
    taken next, min(h, h_max, left), is the same double."""
    hh, left = hh_frac * dt, left_frac * dt
    assert min(_next_step(hh, err, dt, h_max), h_max, left) == min(_controller(hh, err), h_max, left)


@settings(max_examples=500, deadline=None)
@given(dt=st.floats(1e-4, 0.05), err=st.floats(GROWTH_CERTAIN_BELOW, 0.5))
def test_a_full_sample_step_with_a_small_error_skips_the_power(dt, err):
    """A step of a whole sample whose error allows more than a sample: the cap, not hh SAFETY err^-0.2."""
    got = _next_step(dt, err, dt, 1.0)
    assert got != _controller(dt, err) and got >= dt
