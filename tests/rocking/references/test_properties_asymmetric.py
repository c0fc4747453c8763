"""Property: the two-sided impact rule (pipeline.rocking.references.asymmetric) is the angular momentum balance about
the new pivot, derived a second way (by vectors), and never adds kinetic energy, for any two-sided body."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pipeline.rocking.scanned.two_sided_body import TwoSided


@settings(max_examples=200, deadline=None)
@given(bp=st.floats(0.01, 1.0), bm=st.floats(0.01, 1.0), z=st.floats(0.05, 2.0), ig=st.floats(0.001, 1.0))
def test_the_impact_conserves_angular_momentum_about_the_new_pivot_and_never_adds_energy(bp, bm, z, ig):
    body = TwoSided(bp, bm, z, ig)
    for s in (1.0, -1.0):
        ratio = body.impact_ratio(s)
        # vectors: turning at omega = 1 about the old pivot, G moves with omega x (G - P_old); the angular
        # momentum about the new pivot, I_G omega + (G - P_new) x v_G, equals I_new omega+
        p_old = np.array([s * (bp if s > 0 else bm), 0.0])
        p_new = np.array([-s * (bm if s > 0 else bp), 0.0])
        g_pt = np.array([0.0, z])
        r_old, r_new = g_pt - p_old, g_pt - p_new
        v = np.array([-r_old[1], r_old[0]])                      # omega = 1 (counter-clockwise) x r_old
        h_new = ig + (r_new[0] * v[1] - r_new[1] * v[0])
        _a, _r, i_new = body.side(-s)
        assert ratio == pytest.approx(h_new / i_new, rel=1e-9, abs=1e-12)
        _a, _r, i_old = body.side(s)
        assert i_new * ratio ** 2 <= i_old * (1 + 1e-12)         # kinetic energy never grows


