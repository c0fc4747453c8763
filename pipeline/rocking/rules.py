"""The planner's scalar rules and the tie rules at exact boundaries, written once: the nominal path
(:mod:`.planner`, plain Python), the sampled path (:mod:`.batch`), the rocking kernel (:mod:`.kernel`) and the
general contact model (:mod:`.contact`) call the same source.

As for :mod:`.kernel`, one source has two paths: each rule is a plain function, and its compiled twin
(``*_compiled``, numba when installed) is what compiled code calls.

Tie rules
---------
A scene can sit exactly on a boundary between two models. Each boundary has one rule, the same in every
model, so that no scene can pass from one model to the other and back without time advancing:

1. **mu = tan(alpha)** (tip or slide first): the block tips before it slides only when
   ``mu > tan(alpha) (1 + TIE_RTOL)`` (:func:`rocks`). At and within ``TIE_RTOL`` above the tie, it slides
   (Shenton 1996: a block tips first only where mu exceeds tan alpha; at the tie both start together and a
   flat-sliding block is exactly at its tipping limit). ``tan`` of a slenderness computed from a width and a
   height (a 3 m x 1.5 m block with mu = 0.5) lands one rounding either side of mu; the tolerance makes both
   sides one case.
2. **|a_h| = mu (g + a_v)** and **|a_h| = tan(alpha) (g + a_v)** (start of slip, uplift): motion starts only
   where the demand strictly exceeds the threshold (``>``); a demand exactly at it leaves the block at rest, in
   the planner's certificate and in every kernel's event test, to within one rounding of the ratio and of the
   linear interpolation between samples (a slip of 1e-21 m was seen on a two-sample record).
3. **g + a_v = 0**: contact is lost where g + a_v <= 0 (``<=``): free flight begins exactly there.
4. **theta = 0 with omega = 0**: the block is at rest (not rocking) there: the kernel starts in rest, and an
   impact whose rebound is below ``rest_ratio * p * alpha`` ends in rest.
5. **alpha at the e = 0 limit** (54.7 deg, Housner's 1 - 1.5 sin^2 alpha = 0): a block rocks only where
   ``alpha < ALPHA_MAX_ROCKING`` strictly (:func:`rocks`); at and beyond it, it slides.
6. **Events at one instant**: more than :data:`MAX_EVENTS_AT_ONE_INSTANT` events (uplifts, impacts, mode
   changes) in a row without time advancing by :func:`min_advance` is a tie the rules above did not resolve.
   A block that is flat there is held at rest to the next sample (flagged ``tie_hold``); one that is not is
   ended there with the verdict of its state (flagged ``stalled``). Neither happens on the bundled records.

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. BSSA 53(2),
403-417 (uplift at a_h = g tan alpha; e = 1 - 1.5 sin^2 alpha > 0 below 54.7 deg).
Shenton, H. W. (1996). Criteria for initiation of slide, rock, and slide-rock rigid-body modes.
J. Eng. Mech. 122(7), 690-693 (a block tips before it slides when mu > tan alpha).
"""

from __future__ import annotations

import math

from ..compiled import jit
from .geometry import ALPHA_MAX_ROCKING

#: Relative tolerance of the tie mu = tan(alpha) (rule 1) [-].
TIE_RTOL = 1e-9
#: Events in a row at one instant after which the tie rule 6 applies [-] (a Zeno cascade of impacts is
#: ended by ``rest_ratio`` long before: one uplift and one impact per instant is the physical count).
MAX_EVENTS_AT_ONE_INSTANT = 64
#: Smallest advance of time that counts as progress, in units of the spacing of doubles at t [-].
ADVANCE_ULPS = 4.0
#: ... and in seconds, near t = 0 [s].
MIN_ADVANCE_S = 1e-14


def motion_threshold(alpha: float, mu: float) -> float:
    """Demand ratio max |a_h| / (g + a_v) above which the block lifts or slips from rest: min(tan alpha, mu) [-]."""
    return min(math.tan(alpha), mu)


def rocks(alpha: float, mu: float) -> bool:
    """True when the block tips before it slides (mu > tan alpha, beyond the tie of rule 1) and pure rocking
    applies (alpha below :data:`~pipeline.rocking.geometry.ALPHA_MAX_ROCKING`, rule 5)."""
    return mu > math.tan(alpha) * (1.0 + TIE_RTOL) and alpha < ALPHA_MAX_ROCKING


def vertical_kept(peak_av_ms2: float, g_ms2: float, vertical_fraction: float) -> bool:
    """True when the simulation keeps a record's vertical whose peak |a_v| is ``peak_av_ms2``: always when
    ``vertical_fraction`` is 0 (the default); otherwise when the peak exceeds that fraction of g, or
    reaches g (free flight is never dropped)."""
    return vertical_fraction <= 0.0 or peak_av_ms2 > vertical_fraction * g_ms2 or peak_av_ms2 >= g_ms2


def min_advance(t: float) -> float:
    """Smallest step of time that advances a clock at ``t`` [s]: a few doubles' spacing there, at least
    :data:`MIN_ADVANCE_S` (a fixed 1e-14 s step no longer moves a double past t = 128 s)."""
    return max(MIN_ADVANCE_S, ADVANCE_ULPS * 2.220446049250313e-16 * abs(t))


motion_threshold_compiled = jit(motion_threshold)
rocks_compiled = jit(rocks)
vertical_kept_compiled = jit(vertical_kept)
min_advance_compiled = jit(min_advance)


@jit
def events_at_instant_compiled(t: float, t_event: float, n_same: int) -> int:
    """Events in a row at one instant after an event at ``t``, the previous one at ``t_event`` (tie rule 6): one
    more when time has not advanced by :func:`min_advance` since, else 0 (for the compiled kernels)."""
    return n_same + 1 if t - t_event < min_advance_compiled(t) else 0
