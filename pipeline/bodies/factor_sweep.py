"""The upward scan of the factor on a record that first overturns a block: the simulated margin's one loop, shared
by every body model (:mod:`.planar`, :mod:`.solids`, :mod:`.scanned`)."""

from __future__ import annotations

import math


def factor_sweep(lift_factor: float, verdict_at, *, settings, overturns_at_one: bool | None = None,
                 stands_below: float = 0.0) -> tuple[float, int]:
    """The upward scan of :func:`~.planar.overturn_scale_simulated`: from the factor that first lifts the block up to 1
    (exclusive), then 1, then up to ``margin_max_factor``, in steps of ``margin_step``; ``verdict_at(factor)``
    judges one (1 overturns, 0 stands, -1 no verdict), except a factor below ``stands_below``, which a certificate
    has shown to stand (nothing simulated). Returns the first factor that overturns (NaN when one has no verdict
    first, ``inf`` when none does) and the scenes simulated."""
    def factors():
        x = lift_factor
        while x < 1.0:
            yield x
            x *= 1.0 + settings.margin_step
        yield 1.0
        x = 1.0 + settings.margin_step
        while x <= settings.margin_max_factor:
            yield x
            x *= 1.0 + settings.margin_step

    runs = 0
    for factor in factors():
        if factor == 1.0 and overturns_at_one is not None:
            v = int(overturns_at_one)                   # the unscaled scene's verdict is known
        elif factor < stands_below:
            continue
        else:
            runs += 1
            v = verdict_at(factor)
        if v != 0:                      # overturns; or free flight: no verdict at or above this factor
            return (factor if v == 1 else math.nan), runs
    return math.inf, runs
