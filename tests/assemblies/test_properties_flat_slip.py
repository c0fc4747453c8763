"""Hypothesis: for any ground and friction, a block sliding alone, or a squat statue sliding on a plinth that holds,
ends where the planar sliding kernel (a second algorithm) puts one Coulomb block (the stack's slip is followed after
the record, the ground still, to its stop: the kernel's record is padded with a still ground); the ground reversed
reverses every slip; and any level slip ends stuck or hands its episode on, never in between."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from pipeline.assemblies import n_block as nbm
from pipeline.assemblies.flat_slip import STUCK, UNFINISHED, simulate_flat_slip
from pipeline.assemblies.n_block_verdicts import judge_n_block
from pipeline.assemblies.stack import StackBody
from pipeline.rocking.simulate import slide

G = 9.80665
DT = 0.01
#: grounds that end at 0, so that the still ground after them is the kernel's padding
ground = st.lists(st.floats(-0.55 * G, 0.55 * G), min_size=2, max_size=300).map(lambda a: np.array(a + [0.0]))
friction = st.floats(0.05, 0.5)
#: a still ground after the record, long enough for any slip here to stop (|u'| < 0.55 g x 3 s, mu g >= 0.05 g) [s]
STILL_S = 40.0


def _still_after(ah):
    """The record followed by a still ground [m s-2]."""
    return np.concatenate([ah, np.zeros(int(STILL_S / DT))])


@settings(max_examples=150, deadline=None)
@given(ah=ground, mu=friction)
def test_one_block_ends_where_the_sliding_kernel_puts_it(ah, mu):
    block = StackBody(1.6, 0.5, 300.0, mu)                  # tan alpha 3.2: it slides, never tips
    got = judge_n_block(nbm.n_block([block]), ah, DT, mu=(mu,)).offset_m[0]
    want = slide(_still_after(ah), DT, mu=mu).sliding_end_m
    assert abs(got - want) <= 1e-9 + 1e-7 * abs(want)


@settings(max_examples=150, deadline=None)
@given(ah=ground, mu=friction)
def test_a_statue_on_a_plinth_that_holds_ends_where_one_block_would(ah, mu):
    plinth, statue = StackBody(3.0, 0.4, 5000.0, 5.0), StackBody(1.4, 1.0, 800.0, mu)   # statue: tan alpha 1.4
    got = judge_n_block(nbm.n_block([plinth, statue]), ah, DT, mu=(5.0, mu))
    want = slide(_still_after(ah), DT, mu=mu).sliding_end_m
    assert got.offset_m[0] == 0.0
    assert abs(got.offset_m[1] - want) <= 1e-9 + 1e-7 * abs(want)


@settings(max_examples=150, deadline=None)
@given(ah=ground, mus=st.tuples(friction, friction, friction), t0=st.floats(0.0, 1.0))
def test_the_ground_reversed_reverses_every_slip(ah, mus, t0):
    nb = nbm.n_block([StackBody(2.0, 0.3, 900.0, mus[0]), StackBody(1.8, 0.3, 700.0, mus[1]),
                      StackBody(1.6, 0.3, 500.0, mus[2])])
    plus = simulate_flat_slip(nb, mus, ah, DT, t0_s=t0)
    minus = simulate_flat_slip(nb, mus, -ah, DT, t0_s=t0)
    assert plus.end in (STUCK, UNFINISHED)
    assert (plus.end, plus.t_end_s, plus.events) == (minus.end, minus.t_end_s, minus.events)
    assert np.allclose(plus.offsets_m, [-x for x in minus.offsets_m], rtol=0.0, atol=1e-12)
    assert abs(plus.base_shift_m + minus.base_shift_m) <= 1e-12
