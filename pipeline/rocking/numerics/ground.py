"""The ground between two samples: linear in time, and the instants on such a piece where a threshold is met.

Every model of :mod:`pipeline.rocking` takes the ground acceleration as linear between samples. On one
piece, the start of motion from rest (|a_h| reaching (g + a_v) tan(alpha), or mu for slip) and the loss of
contact with a ground falling faster than gravity (g + a_v reaching 0) are the roots of linear functions,
found exactly here rather than by stepping; a plane's :class:`QuietTable` lets a block at rest pass over
the samples that cannot lift it in runs.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

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


#: Samples per entry of a :class:`QuietTable`
QUIET_CHUNK = 64


class QuietTable(NamedTuple):
    """Per run of :data:`QUIET_CHUNK` samples of one plane's ground, what bounds the uplift test there.

    A block at rest cannot lift at sample j while |a_h[j]| <= (g + a_v[j]) thr and g + a_v[j] > 0; a chunk
    with ``peak_ah_ms2 <= (g + least_av_ms2) thr`` and ``g + least_av_ms2 > 0`` passes that test at every
    sample (rounding is monotonic, so the bound holds in floating point too): the rocking kernel skips it
    whole instead of testing each sample (:func:`pipeline.rocking.planar.kernel._quiet_until`). Shared by
    every block simulated in the plane; empty arrays: no table.

    Attributes
    ----------
    peak_ah_ms2 : ndarray
        max |a_h| over each chunk [m s-2].
    least_av_ms2 : ndarray
        min a_v over each chunk [m s-2] (zeros where the record has no vertical).
    """

    peak_ah_ms2: np.ndarray
    least_av_ms2: np.ndarray


#: No table: the kernel tests every sample
NO_QUIET = QuietTable(np.zeros(0), np.zeros(0))

#: Relative margin of :func:`vector_quiet_table`'s peaks over the horizontal vector's magnitude: a plane's projection
#: c h1 + s h2 (c^2 + s^2 = 1 to a few units in the last place) exceeds |(h1, h2)| by rounding alone, by far less
#: than this [-]
VECTOR_PEAK_MARGIN = 1e-12
#: Absolute margin added to those peaks, for magnitudes so small that the projection's rounding is not relative to
#: them (subnormal accelerations) [m s-2]
VECTOR_PEAK_FLOOR_MS2 = 1e-300


def quiet_table(ah_ms2: np.ndarray, av_ms2: np.ndarray | None) -> QuietTable:
    """The :class:`QuietTable` of a plane's horizontal ``ah_ms2`` and the record's vertical ``av_ms2`` [m s-2]."""
    n = ah_ms2.shape[0]
    n_chunks = -(-n // QUIET_CHUNK)
    pad = n_chunks * QUIET_CHUNK - n
    peak = np.pad(np.abs(ah_ms2), (0, pad)).reshape(n_chunks, QUIET_CHUNK).max(axis=1)
    if av_ms2 is None:
        return QuietTable(np.ascontiguousarray(peak), np.zeros(n_chunks))
    least = np.pad(np.asarray(av_ms2, dtype=np.float64), (0, pad), mode="edge").reshape(n_chunks, QUIET_CHUNK)
    return QuietTable(np.ascontiguousarray(peak), np.ascontiguousarray(least.min(axis=1)))


@jit
def scaled_demand_ratio(h1, h2, c, s, eps, av, has_v, g, vector=False):
    """The demand ratio max_t |eps (c h1 + s h2)| / (g + eps a_v) of the ground in the plane of weights (c, s) scaled
    by ``eps`` > 0, without making the scaled series (the draws and the margin's scan; inf where g + eps a_v <= 0),
    ``av`` the record's vertical (unscaled; not read without one, ``has_v`` False); with ``vector``, of the
    horizontal vector's magnitude eps |(h1, h2)| instead, which bounds every plane's [-].

    Each sample's terms are the products, sum and quotient :func:`~pipeline.rocking.planner.demand_ratio` rounds on
    the scaled series, and the largest of the quotients is exact, so the ratio is the same double as its; without a
    vertical the peak is divided by g once: dividing by a positive constant keeps the order of doubles."""
    r = 0.0
    for i in range(h1.size):
        a = eps * math.sqrt(h1[i] * h1[i] + h2[i] * h2[i]) if vector else abs(eps * (c * h1[i] + s * h2[i]))
        if has_v:
            gv = g + eps * av[i]
            if gv <= 0.0:
                return math.inf
            a = a / gv
        if a > r:
            r = a
    return r if has_v else r / g


def scaled_quiet_table(table: QuietTable, factor: float) -> QuietTable:
    """The :class:`QuietTable` of the same ground scaled by ``factor`` > 0 (the margin's scan): the table's values
    times the factor, equal to :func:`quiet_table` of the scaled series (a product with a positive factor is
    rounded monotonically, so the chunk's max and min commute with it)."""
    return QuietTable(factor * table.peak_ah_ms2, factor * table.least_av_ms2)


def vector_quiet_table(h1_ms2: np.ndarray, h2_ms2: np.ndarray, av_ms2: np.ndarray | None) -> QuietTable:
    """A :class:`QuietTable` that holds for the ground in every vertical plane of two horizontals ``h1_ms2`` and
    ``h2_ms2`` (zeros for one) [m s-2], with the vertical ``av_ms2`` (None: none): each chunk's peak is that of the
    horizontal vector's magnitude, raised by :data:`VECTOR_PEAK_MARGIN` and :data:`VECTOR_PEAK_FLOOR_MS2`, so that it
    is at least |c h1 + s h2| as rounded, whatever the plane (c, s). Its values times a factor eps > 0 hold for the
    ground scaled by eps (a product with a positive factor is rounded monotonically): the draws' planes and
    amplitudes, each draw's kernel passing over the chunks that cannot lift its block."""
    magnitude = np.hypot(h1_ms2, h2_ms2) * (1.0 + VECTOR_PEAK_MARGIN) + VECTOR_PEAK_FLOOR_MS2
    return quiet_table(magnitude, av_ms2)


@jit
def chunk_quiet(table, c, g, thr, has_v):
    """True when no sample of chunk ``c`` of a :class:`QuietTable` can lift a block at rest (``thr``: tan
    alpha, or alpha for the linear model; ``has_v``: the simulation keeps the vertical)."""
    gv = g + table.least_av_ms2[c] if has_v else g
    return gv > 0.0 and table.peak_ah_ms2[c] <= gv * thr
