"""The ITP step (:mod:`pipeline.rocking.numerics.itp`) driven on a Python function as the planar contact model drives
it on an event's indicator (:func:`pipeline.rocking.planar.contact._event_step`), for the tests."""

from __future__ import annotations

from pipeline.rocking.numerics.itp import EXTRA_GUARD, evaluations_cap, itp_point

BITS = 48                                          # the planar contact model's bracket: the step times 2^-48


def itp_root(f, h: float, *, bits: int = BITS) -> tuple[float, float, int]:
    """The bracket's end past the root of f on [0, h] (f(0) >= 0 > f(h)), its other end and the evaluations."""
    lo, hi, f_lo, f_hi = 0.0, h, max(f(0.0), 0.0), f(h)
    width = h * 2.0 ** -bits
    n_max = evaluations_cap(h, width)
    j = 0
    while hi - lo > width and j < n_max + EXTRA_GUARD:
        x = itp_point(lo, hi, f_lo, f_hi, j, n_max, width, h)
        fx = f(x)
        if fx < 0.0:
            hi, f_hi = x, fx
        else:
            lo, f_lo = x, fx
        j += 1
    return hi, lo, j
