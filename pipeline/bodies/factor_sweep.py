"""The upward scan of the factor on a record that first overturns a block: the simulated margin's one loop, shared
by every body model (:mod:`.planar`, :mod:`.solids`, :mod:`.scanned`, :mod:`.scanned3d`).

Overturning is not monotonic in amplitude (Zhang & Makris 2001), so the factor is scanned upward, never bisected
over a range it has not scanned: in steps of ``margin_step`` (1 %) up to ``margin_fine_to`` (x1.5, the largest
margin that changes a recommendation), then in steps that double from ``margin_step`` up to ``margin_coarse_step``
(10 %); a factor there that overturns is bisected back against the last one that stood, down to ``margin_step``.
What holds: the margin overturns and a factor at most ``margin_step`` below it stands (or it is the first factor
scanned); every factor scanned below it stands; up to ``margin_fine_to``, a window of overturning narrower than
``margin_step`` can be missed, above it one narrower than the step there.

References
----------
Zhang, J. & Makris, N. (2001). Rocking response of free-standing blocks under cycloidal pulses. Journal of
Engineering Mechanics 127(5), 473-483.
"""

from __future__ import annotations

import math
from collections.abc import Iterator


def scan_factors(lift_factor: float, *, settings) -> Iterator[float]:
    """The factors of the upward scan: from ``lift_factor`` up to 1 (exclusive) and from 1 up to ``margin_fine_to``
    growing by ``margin_step``, then by steps doubling from it up to ``margin_coarse_step``, up to
    ``margin_max_factor`` (1 always among them; the limit itself too where the coarse steps end short of it by more
    than a fine step)."""
    fine, top = 1.0 + settings.margin_step, settings.margin_max_factor
    x = lift_factor
    while x < 1.0:
        yield x
        x *= fine
    yield 1.0
    x, step, last = fine, settings.margin_step, 1.0
    while x <= top:
        yield x
        last = x
        if x >= settings.margin_fine_to:
            step = min(2.0 * step, max(settings.margin_coarse_step, settings.margin_step))
        x *= 1.0 + (settings.margin_step if x < settings.margin_fine_to else step)
    if last * (1.0 + settings.margin_step) <= top:
        yield top                                       # the coarse steps end short of the limit: the limit itself


def factor_sweep(lift_factor: float, verdict_at, *, settings, overturns_at_one: bool | None = None,
                 stands_below: float = 0.0) -> tuple[float, int]:
    """The upward scan of :func:`scan_factors`; ``verdict_at(factor)`` judges one (1 overturns, 0 stands, -1 no
    verdict), except a factor below ``stands_below``, which a certificate has shown to stand (nothing simulated).
    A factor above ``margin_fine_to`` that does not stand is bisected back against the last factor that stood to
    ``margin_step``. Returns the first factor that overturns (NaN when one has no verdict first, ``inf`` when none
    does) and the scenes simulated."""
    runs, last = 0, math.nan
    for factor in scan_factors(lift_factor, settings=settings):
        if factor == 1.0 and overturns_at_one is not None:
            v = int(overturns_at_one)                   # the unscaled scene's verdict is known
        elif factor < stands_below:
            last = factor
            continue
        else:
            runs += 1
            v = verdict_at(factor)
        if v == 0:
            last = factor
            continue
        if factor > settings.margin_fine_to and not math.isnan(last):     # a coarse step: bisect back
            factor, v, more = _bisect(last, factor, v, verdict_at, settings.margin_step)
            runs += more
        return (factor if v == 1 else math.nan), runs      # overturns; or no verdict at or above this factor
    return math.inf, runs


def _bisect(stands: float, moves: float, verdict: int, verdict_at, step: float) -> tuple[float, int, int]:
    """Between a factor that stands and a larger one whose verdict is not 'stands' (``verdict``), the smallest
    factor found not to stand, by geometric bisection until the two are within ``1 + step``: that factor, its
    verdict and the scenes simulated."""
    runs = 0
    while moves > stands * (1.0 + step):
        mid = math.sqrt(stands * moves)
        v = verdict_at(mid)
        runs += 1
        if v == 0:
            stands = mid
        else:
            moves, verdict = mid, v
    return moves, verdict, runs
