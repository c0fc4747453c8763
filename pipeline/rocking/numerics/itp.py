"""Where an event happens inside a step: the ITP method on a bracket, the bisection's tolerance in fewer evaluations.

An event function f(s) of the step's length s (the state after a Runge-Kutta step of length s, put into the
event's indicator) is non-negative at the step's start and negative at its end. The event is located on a bracket
[lo, hi] with f(lo) >= 0 > f(hi), shrunk until it is at most ``width`` wide; ``hi`` is returned, where the event
has happened. Bisection halves the bracket at each evaluation. ITP (interpolate, truncate, project; Oliveira &
Takahashi 2020) evaluates at

    x_f = (lo f(hi) - hi f(lo)) / (f(hi) - f(lo))                    regula falsi
    x_t = x_f + sigma delta,  delta = KAPPA1 (hi - lo)^KAPPA2 / w0    truncated toward the midpoint x_m
                                                                      (sigma = sign(x_m - x_f); x_m if delta
                                                                      exceeds |x_m - x_f|)
    x_itp = x_t if |x_t - x_m| <= r, else x_m - sigma r               projected onto the minmax interval,
    r = (width / 2) 2^(n_max - j) - (hi - lo) / 2                     n_max = n_bisect + N0, j the evaluations
                                                                      made, w0 the first bracket's width

so that in exact arithmetic it never needs more than N0 evaluations beyond the n_bisect = ceil(log2(w0 / width))
that bisection needs (its minmax optimality; rounding at a bracket of a few ulps has cost one more, within the
caller's guard of EXTRA_GUARD), and converges superlinearly where f is smooth near its root: 8 to 10 evaluations instead
of 48 on the smooth functions of the tests, 21 on average on the planar contact model's events (where it
interpolates the one indicator negative at the bracket's end: the smallest of the indicators, kinked where two
cross, took 42), whose last halvings meet the rounding of the event's indicator.

References
----------
Oliveira, I. F. D. & Takahashi, R. H. C. (2020). An enhancement of the bisection method average performance
preserving minmax optimality. ACM Transactions on Mathematical Software 47(1), 5:1-5:24 (Algorithm 1; the
parameters KAPPA1 = 0.2 / (b - a) and KAPPA2 = 2 of its numerical section).
"""

from __future__ import annotations

import math

from ...compiled import jit_inline

# The method's parameters (Oliveira & Takahashi 2020, section 5), named once
KAPPA1 = 0.2        # truncation factor, as a fraction of 1 / w0 (scale-free in the step's length) [-]
KAPPA2 = 2.0        # truncation exponent [-]
N0 = 8              # evaluations allowed beyond bisection's [-]: the paper's 1 leaves no slack after an early
                    # step that shrinks the bracket little (an event's indicator rising from 0 before it falls), and
                    # the rest is bisection; on the planar contact model's events, 8 took 18.1 evaluations an event
                    # against 22.5 with 1 and 48.5 by bisection (docs/validation.md)
EXTRA_GUARD = 4     # evaluations beyond n_max before the loop ends regardless (rounding: the bracket at ulps) [-]


@jit_inline
def evaluations_cap(w0, width):
    """The most evaluations ITP may make on a bracket of width ``w0`` down to ``width``: bisection's
    ceil(log2(w0 / width)) plus :data:`N0` (n_max; the loop that calls :func:`itp_point` ends at it plus
    :data:`EXTRA_GUARD` whatever rounding does)."""
    if w0 <= width:
        return N0
    return int(math.ceil(math.log2(w0 / width))) + N0


@jit_inline
def itp_point(lo, hi, f_lo, f_hi, j, n_max, width, w0):
    """The next point to evaluate on the bracket [lo, hi] (f(lo) >= 0 > f(hi)) after ``j`` evaluations, of at
    most ``n_max`` (:func:`evaluations_cap`) down to a bracket ``width`` wide, the first bracket ``w0`` wide."""
    mid = 0.5 * (lo + hi)
    span = hi - lo
    r = 0.5 * width * 2.0 ** (n_max - j) - 0.5 * span
    if r < 0.0:
        r = 0.0
    delta = KAPPA1 * span ** KAPPA2 / w0
    x_f = (lo * f_hi - hi * f_lo) / (f_hi - f_lo)          # f_hi < 0 <= f_lo: the denominator is negative
    sigma = 1.0 if mid >= x_f else -1.0
    x_t = x_f + sigma * delta if delta <= abs(mid - x_f) else mid
    x = x_t if abs(x_t - mid) <= r else mid - sigma * r
    if not lo < x < hi:                                    # rounding at a bracket of a few ulps
        x = mid
    return x
