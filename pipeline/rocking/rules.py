"""The planner's scalar rules, written once: the nominal path (:mod:`.planner`, plain Python) and the
sampled path (:mod:`.batch`, compiled) call the same source.

As for :mod:`.kernel`, one source has two paths: each rule is a plain function, and its compiled twin
(``*_compiled``, numba when installed) is what compiled code calls.

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. BSSA 53(2),
403-417 (uplift at a_h = g tan alpha; e = 1 - 1.5 sin^2 alpha > 0 below 54.7 deg).
Shenton, H. W. (1996). Criteria for initiation of slide, rock, and slide-rock rigid-body modes.
J. Eng. Mech. 122(7), 690-693 (a block tips before it slides when mu > tan alpha).
"""

from __future__ import annotations

import math

from ..blocks import ALPHA_MAX_ROCKING
from .kernel import jit


def motion_threshold(alpha: float, mu: float) -> float:
    """Demand ratio max |a_h| / (g + a_v) above which the block lifts or slips from rest: min(tan alpha, mu) [-]."""
    return min(math.tan(alpha), mu)


def rocks(alpha: float, mu: float) -> bool:
    """True when the block tips before it slides (mu > tan alpha) and pure rocking applies (alpha below
    :data:`~pipeline.blocks.ALPHA_MAX_ROCKING`)."""
    return mu > math.tan(alpha) and alpha < ALPHA_MAX_ROCKING


def vertical_kept(peak_av_ms2: float, g_ms2: float, vertical_fraction: float) -> bool:
    """True when the simulation keeps a record's vertical whose peak |a_v| is ``peak_av_ms2``: always when
    ``vertical_fraction`` is 0 (the default); otherwise when the peak exceeds that fraction of g, or
    reaches g (free flight is never dropped)."""
    return vertical_fraction <= 0.0 or peak_av_ms2 > vertical_fraction * g_ms2 or peak_av_ms2 >= g_ms2


motion_threshold_compiled = jit(motion_threshold)
rocks_compiled = jit(rocks)
vertical_kept_compiled = jit(vertical_kept)
