"""The ground between two samples: linear in time, and the instants on such a piece where a threshold is met.

Every model of :mod:`pipeline.rocking` takes the ground acceleration as linear between samples. On one
piece, the start of motion from rest (|a_h| reaching (g + a_v) tan(alpha), or mu for slip) and the loss of
contact with a ground falling faster than gravity (g + a_v reaching 0) are the roots of linear functions,
found exactly here rather than by stepping.
"""

from __future__ import annotations

from ...compiled import jit


@jit
def exceed_fraction(a0, a1, v0, v1, g, thr):
    """First fraction x in [0, 1] where |a| > (g + v) thr on a linear piece, or -1.

    Uplift from rest (thr = tan(alpha), or alpha for the linear model) and the
    start of slip (thr = mu) are both this test.
    """
    best = -1.0
    for sig in (1.0, -1.0):
        l0 = sig * a0 - (g + v0) * thr
        l1 = sig * a1 - (g + v1) * thr
        if l0 > 0.0:
            return 0.0
        if l1 > 0.0:
            x = -l0 / (l1 - l0)
            if best < 0.0 or x < best:
                best = x
    return best


@jit
def flight_fraction(v0, v1, g):
    """First fraction x in [0, 1] where g + v <= 0 on a linear piece of the vertical, or -1."""
    l0, l1 = g + v0, g + v1
    if l0 <= 0.0:
        return 0.0
    if l1 <= 0.0:
        return l0 / (l0 - l1)
    return -1.0
