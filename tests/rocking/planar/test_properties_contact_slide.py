"""Hypothesis: the general contact model's slide mode, one Runge-Kutta step to each sample's end (exact for the cubic
slip) cut where the slip rate dips to 0 inside a sample, slides a block that cannot rock as Coulomb's sliding kernel
does (a second algorithm, exact per sample), on coarse samples whose slip stops and starts inside a sample."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pipeline.constants import G
from pipeline.rocking.block import Block
from pipeline.rocking.simulate import from_rest, slide

#: a coarse sampling interval, so that slips stop and start inside samples [s]
DT = 0.05
#: a block too squat to rock (alpha above 54.7 deg): it slides
HALF_WIDTH_M, HALF_HEIGHT_M = 1.0, 0.5


def _block(mu: float) -> Block:
    r = math.hypot(HALF_WIDTH_M, HALF_HEIGHT_M)
    return Block(p=math.sqrt(3 * G / (4 * r)), alpha=math.atan(HALF_WIDTH_M / HALF_HEIGHT_M), e=0.0, R_m=r, mu=mu,
                 g_ms2=G)


@settings(max_examples=200, deadline=None)
@given(ah=st.lists(st.floats(-0.8 * G, 0.8 * G), min_size=2, max_size=120).map(lambda a: np.array(a + [0.0])),
       mu=st.floats(0.05, 0.6))
def test_the_slide_mode_slides_as_coulombs_kernel(ah, mu):
    general = from_rest(ah, None, DT, block=_block(mu))
    # the kernel's record followed by a still ground, as the general model follows a slip after the record
    coulomb = slide(np.concatenate([ah, np.zeros(int(60.0 / DT))]), DT, mu=mu)
    assert not general.overturned
    assert general.slip_end_m == pytest.approx(coulomb.sliding_end_m, rel=1e-9, abs=1e-12)
    assert general.slip_max_m == pytest.approx(coulomb.sliding_max_m, rel=1e-9, abs=1e-12)
