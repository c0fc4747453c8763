"""The ITP step (:mod:`pipeline.rocking.numerics.itp`) brackets a root as bisection does, to the same width, in no more
evaluations than bisection's plus N0, and in far fewer where the function is smooth: checked against roots known in
closed form and against bisection on the same functions. The planar contact model, which locates its events with
it, is checked against its closed forms and the rocking kernel in ``tests/rocking/planar/test_contact.py``."""

from __future__ import annotations

import math

import pytest
from itp_driver import BITS, itp_root

from pipeline.rocking.numerics.itp import N0, evaluations_cap


def bisection_root(f, h: float, *, bits: int = BITS) -> tuple[float, int]:
    """The same bracket by bisection (the contact model's former location)."""
    lo, hi = 0.0, h
    for _ in range(bits):
        mid = 0.5 * (lo + hi)
        if f(mid) < 0.0:
            hi = mid
        else:
            lo = mid
    return hi, bits


CLOSED_FORMS = [
    # (f, h, root): smooth, a root inside; rising from 0 before falling (an indicator just after a transition);
    # linear with its root near 0; a root at the step's very start
    (lambda s: math.cos(s) - 0.5, 2.0, math.pi / 3.0),
    (lambda s: 0.3 - s ** 3 - 0.1 * s, 1.0, None),
    (lambda s: s * (0.0642 - s), 0.005 * 20, 0.0642),
    (lambda s: 1e-3 - s, 0.005, 1e-3),
    (lambda s: -s, 0.005, 0.0),
]


@pytest.mark.parametrize("f, h, root", CLOSED_FORMS)
def test_brackets_the_root_to_the_width(f, h, root):
    hi, lo, evaluations = itp_root(f, h)
    width = h * 2.0 ** -BITS
    assert f(hi) < 0.0 and hi - lo <= width
    assert evaluations <= evaluations_cap(h, width)            # minmax: bisection's count plus N0 at most
    if root is not None:
        assert root - 2 * math.ulp(root) <= hi <= root + width + 2 * math.ulp(hi)
    b_hi, _ = bisection_root(f, h)
    assert abs(hi - b_hi) <= width + 2 * math.ulp(hi)             # the same bracket, within its width


@pytest.mark.parametrize("f, h", [(lambda s: math.cos(s) - 0.5, 2.0), (lambda s: 0.3 - s ** 3 - 0.1 * s, 1.0),
                                  (lambda s: math.exp(-s) - 0.2, 3.0)])
def test_smooth_roots_take_a_few_evaluations(f, h):
    # superlinear near a simple root (Oliveira & Takahashi 2020): 8 to 10 here, against bisection's 48
    assert itp_root(f, h)[2] <= 12


def test_a_step_function_still_ends_within_the_cap():
    # no interpolation helps on a jump: the projection makes it bisection, and the cap holds
    h = 0.005
    hi, lo, evaluations = itp_root(lambda s: 1.0 if s < 0.0031 else -1.0, h)
    assert hi - lo <= h * 2.0 ** -BITS and lo < 0.0031 <= hi
    assert evaluations <= BITS + N0


def test_the_cap_of_a_bracket_already_narrow():
    assert evaluations_cap(1e-20, 1e-19) == N0
    assert evaluations_cap(1.0, 2.0 ** -48) == 48 + N0

