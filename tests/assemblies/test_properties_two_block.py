"""Hypothesis: an impact or a plastic stop between two stacked blocks never gains energy, the equations conserve it
in free motion, and any stack under any ground ends with a verdict or a flag."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pipeline.assemblies.stack import StackBody
from pipeline.assemblies.two_block import (
    Motion,
    accelerations,
    kinetic_energy,
    potential_energy,
    projected_rates,
    two_block,
)
from pipeline.assemblies.two_block_run import FALLS_NONE, FALLS_STACK, FALLS_TOP, simulate_two_block
from pipeline.errors import BlockParameterError

sizes = st.floats(0.1, 2.0)
corners = st.sampled_from([1, -1])


def _pair(w1, h1, w2, h2, offset_share):
    offset = offset_share * 0.45 * w1
    try:
        return two_block(StackBody(w1, h1, 700.0 * w1 * h1, 0.8), StackBody(w2, h2, 900.0 * w2 * h2, 0.8, offset))
    except BlockParameterError:
        return None


@settings(max_examples=300, deadline=None)
@given(w1=sizes, h1=sizes, w2=sizes, h2=sizes, share=st.floats(-1, 1), s1=corners, s2=corners,
       phi=st.floats(-0.5, 0.5), w=st.tuples(st.floats(-3, 3), st.floats(-3, 3)),
       joint=st.sampled_from([1, 2]), stop=st.booleans(), other_shut=st.booleans())
def test_an_impact_or_a_stop_never_gains_energy(w1, h1, w2, h2, share, s1, s2, phi, w, joint, stop, other_shut):
    """Whatever the blocks, the state and the joint: the kinetic energy after the impulse is at most the energy
    before (the B-orthogonal projection of the module), to rounding."""
    tb = _pair(w1, h1, w2, h2, share)
    if tb is None:
        return
    j1, j2 = (s1, 0 if other_shut else s2) if joint == 1 else (0 if other_shut else s1, s2)
    # the impacting joint at 0 rotation; a shut joint's rates consistent with it
    phi1, phi2 = (0.0, 0.0 if j2 == 0 else phi) if joint == 1 else (phi if j1 else 0.0, phi if j1 else 0.0)
    w1r, w2r = w
    if j1 == 0:
        w1r = 0.0
    if j2 == 0:
        w2r = w1r
    y = Motion(phi1, phi2, w1r, w2r)
    after = ((-j1, j2) if joint == 1 else (j1, -j2))
    if stop:
        after = (0, after[1]) if joint == 1 else (after[0], 0)
    before_e = kinetic_energy(tb, y, j1, j2)
    r1, r2 = projected_rates(tb, y, (j1, j2), after)
    after_e = kinetic_energy(tb, Motion(phi1, phi2, r1, r2), *after)
    assert after_e <= before_e * (1 + 1e-12) + 1e-12


@pytest.mark.parametrize("j1, j2", [(1, 1), (1, -1), (-1, 1), (1, 0), (0, -1)])
@given(phi=st.tuples(st.floats(0.0, 0.3), st.floats(0.0, 0.3)), w=st.tuples(st.floats(-2, 2), st.floats(-2, 2)))
@settings(max_examples=40, deadline=None)
def test_free_motion_conserves_energy(j1, j2, phi, w):
    """No ground: d(T + V)/dt = 0 in every mode, by central differences along the motion (the equations' mass matrix,
    velocity terms and gravity written consistently with the energy)."""
    tb = two_block(StackBody(0.6, 1.0, 420.0, 0.8), StackBody(0.3, 1.2, 260.0, 0.8, 0.05))
    p1 = abs(phi[0]) * (j1 if j1 else 0)
    p2 = p1 + abs(phi[1]) * (j2 if j2 else 0)
    w1 = w[0] if j1 else 0.0
    w2 = w[1] if j2 else w1
    y = Motion(p1, p2, w1, w2)
    d1, d2 = accelerations(tb, y, j1, j2, 0.0, 0.0)
    h = 1e-5

    def energy(s):
        yy = Motion(p1 + s * w1 + 0.5 * s * s * d1, p2 + s * w2 + 0.5 * s * s * d2, w1 + s * d1, w2 + s * d2)
        return kinetic_energy(tb, yy, j1, j2) + potential_energy(tb, yy, j1, j2)

    rate = (energy(h) - energy(-h)) / (2 * h)
    scale = kinetic_energy(tb, y, j1, j2) + 680.0 * 9.81 * 0.1 + 1.0
    assert abs(rate) <= 1e-6 * scale * max(1.0, math.hypot(w1, w2))
    assert np.isfinite(rate)


@settings(max_examples=60, deadline=None)
@given(w1=sizes, h1=sizes, w2=sizes, h2=sizes, share=st.floats(-1, 1), seed=st.integers(0, 2**31 - 1),
       pga_g=st.floats(0.05, 2.0), vertical=st.booleans())
def test_any_stack_under_any_ground_ends_with_a_verdict_or_a_flag(w1, h1, w2, h2, share, seed, pga_g, vertical):
    """Random stacks under random grounds (white noise, 2 s at 100 Hz, a vertical of half the horizontal's peak or
    none): every run ends (within the caps), a fall is one of the three outcomes, and a run that stands without a
    flag ends at rest (both joints shut: the final rates 0)."""
    tb = _pair(w1, h1, w2, h2, share)
    if tb is None:
        return
    rng = np.random.default_rng(seed)
    ah = rng.standard_normal(200)
    ah *= pga_g * 9.80665 / np.max(np.abs(ah))
    av = 0.5 * rng.standard_normal(200) * pga_g * 9.80665 / 3.0 if vertical else None
    out = simulate_two_block(tb, ah, 0.01, av_ms2=av)
    assert out.falls in (FALLS_NONE, FALLS_TOP, FALLS_STACK)
    if out.falls == FALLS_NONE and out.status == 0:
        assert (out.final.w1, out.final.w2) == (0.0, 0.0)
