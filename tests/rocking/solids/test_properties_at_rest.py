"""Property tests of the 3D contact model's at-rest holding over random ground motions: a sampling interval it holds
at once (``calm_until``) holds the body at every step's middle in it by the per-step certificate, checked step by
step (a second algorithm, the one the kernel applies where it does not skip), so that skipping holds the same
steps."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pipeline.constants import G
from pipeline.rocking.solids import at_rest

SETTINGS = settings(max_examples=60, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])


def _step_holds(ax, ay, az, k, n_sub, threshold):
    """The kernel's per-step certificate at the middle of step ``k``, written out again."""
    i, frac = k // n_sub, (k % n_sub + 0.5) / n_sub
    gx, gy, gz = (a[i] + frac * (a[i + 1] - a[i]) for a in (ax, ay, az))
    gv = G + gz
    return gv > 0.0 and math.sqrt(gx * gx + gy * gy) <= threshold * gv


@SETTINGS
@given(seed=st.integers(0, 2**31 - 1), n=st.integers(2, 40), n_sub=st.integers(1, 12),
       threshold=st.floats(0.0, 1.2), level=st.floats(0.05, 2.0), vertical=st.floats(0.0, 1.5))
def test_a_calm_interval_holds_at_every_steps_middle(seed, n, n_sub, threshold, level, vertical):
    rng = np.random.default_rng(seed)
    ax, ay = (level * threshold * G * rng.uniform(-1.0, 1.0, n) for _ in range(2))
    az = vertical * G * rng.uniform(-1.0, 1.0, n)
    for start in range(n - 1):
        calm_to = at_rest.calm_until(ax, ay, az, start, threshold, G)
        assert start <= calm_to <= n - 1
        for k in range(start * n_sub, calm_to * n_sub):
            assert _step_holds(ax, ay, az, k, n_sub, threshold), (start, calm_to, k)


def test_the_calm_edges_at_an_exact_tie_are_checked_step_by_step():
    # demand exactly at the threshold at a sample: not skipped (the margin), each step checked as before
    threshold = 0.5
    ax = np.array([0.0, threshold * G, 0.0])
    zeros = np.zeros(3)
    assert at_rest.calm_until(ax, zeros, zeros, 0, threshold, G) == 0
    assert at_rest.calm_until(ax * (1.0 - 2.0 * at_rest.CALM_MARGIN), zeros, zeros, 0, threshold, G) == 2
