"""Properties of the slide-rock model's landing (pipeline.assemblies.slide_rock.landing), by Hypothesis: a landing
never gains energy (the kinetic energy summed over the blocks' velocities, each block's 1/2 m v^2 + 1/2 I w^2), and a
mirrored landing mirrors its outcome."""

from __future__ import annotations

import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from pipeline.assemblies import n_block as nbm
from pipeline.assemblies import slide_rock as srm
from pipeline.assemblies.slide_rock_parts import Parts, SlideRock, parts_of
from pipeline.assemblies.stack import StackBody
from pipeline.assemblies.stack_pose import slide_rock_pose

sizes = st.floats(0.1, 0.6)
heights = st.floats(0.3, 1.8)
masses = st.floats(100.0, 3000.0)


def _stack(b0, h0, m0, b1, h1, m1, mu1) -> tuple[nbm.NBlock, SlideRock, Parts]:
    """Two uniform blocks of half sizes b, h [m] and masses m [kg], the joint's friction mu1, the floor's 1."""
    nb = nbm.n_block([StackBody(2 * b0, 2 * h0, m0, 1.0), StackBody(2 * b1, 2 * h1, m1, mu1)])
    return nb, *parts_of(nb, (1.0, mu1))


def _kinetic(nb: nbm.NBlock, pivot: int, state: tuple) -> float:
    """The blocks' kinetic energy [J] from their centres' velocities and rates (:func:`slide_rock_pose`'s)."""
    _, v = slide_rock_pose(nb, state, pivot)
    return sum(0.5 * nb.m[k] * (v[0, k] ** 2 + v[1, k] ** 2) + 0.5 * nb.i[k] * v[2, k] ** 2 for k in range(2))


@settings(max_examples=300, deadline=None)
@given(sizes, heights, masses, sizes, heights, masses, st.floats(0.02, 1.0), st.floats(0.01, 2.0),
       st.floats(-0.9, 0.9), st.floats(-1.0, 1.0))
def test_a_landing_never_gains_energy(b0, h0, m0, b1, h1, m1, mu1, w, u_share, du):
    """Wherever the landing's law holds, the kinetic energy after it is at most the energy before."""
    nb, sr, parts = _stack(b0, h0, m0, b1, h1, m1, mu1)
    u = u_share * min(b0, b1) * 0.5
    before = (0.0, u, -w, du)
    ld = srm.landing(sr, parts, 1, before, 0.0)
    assume(ld.holds)                                 # about 57 % of these draws hold, 16 % of them sliding
    assert _kinetic(nb, -1, (0.0, u, ld.dphi, ld.du)) <= _kinetic(nb, 1, before) * (1.0 + 1e-12) + 1e-12


@settings(max_examples=200, deadline=None)
@given(sizes, heights, masses, sizes, heights, masses, st.floats(0.02, 1.0), st.floats(0.01, 2.0),
       st.floats(-0.9, 0.9), st.floats(-1.0, 1.0))
def test_a_mirrored_landing_mirrors(b0, h0, m0, b1, h1, m1, mu1, w, u_share, du):
    """The landing on the other side (the pivot, the offset and every rate mirrored) gives the mirrored rates, the
    same joint state mirrored and the same verdict on the law."""
    _, sr, parts = _stack(b0, h0, m0, b1, h1, m1, mu1)
    u = u_share * min(b0, b1) * 0.5
    right, left = srm.landing(sr, parts, 1, (0.0, u, -w, du), 0.0), srm.landing(sr, parts, -1, (0.0, -u, w, -du), 0.0)
    assert right.holds == left.holds
    assert np.allclose((right.dphi, right.du), (-left.dphi, -left.du), rtol=1e-12, atol=1e-14)
    assert right.slip == -left.slip
