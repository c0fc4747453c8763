"""Binomial intervals, robustness classes and the sequential stopping rule.

A scene's probability of overturning is estimated from n samples of which k overturn.
The Wilson score interval (two-sided, ``confidence``) bounds it; the interval decides the
class:

* ``robust_stand``: the upper bound is below ``robust_below`` (default 0.1);
* ``robust_overturn``: the lower bound is above ``robust_above`` (default 0.9);
* ``sensitive``: neither (the verdict can go either way under the declared uncertainty).

A draw without a verdict (a model that stops where the base would slide or lift off, a ground falling
faster than gravity, a cap) is unknown, never standing: the interval spans it
(:func:`spanning_interval`: the lower bound counts such draws as standing, the upper as overturning),
and a scene is ``robust_stand`` only where that interval says so and fewer than
:data:`UNKNOWN_STAND_LIMIT` of its draws are unknown.

Sequential rule: samples are drawn in batches; after each batch the interval is recomputed
and sampling stops as soon as the interval lies wholly below ``robust_below`` or wholly above
``robust_above``; or wholly between the two (``sensitive`` is then decided) and at most
``2 p_halfwidth`` wide, so that a sensitive scene's p is estimated to a stated precision
(:func:`pipeline.uncertainty.scenes.scene_probability`); or when the largest number of samples is
reached. Stopping on the data changes the interval's coverage;
``tests/uncertainty/test_properties_uncertainty.py`` measures the rule's error rates on Bernoulli streams
of known p.

References
----------
Wilson, E. B. (1927). Probable inference, the law of succession, and statistical inference.
JASA 22(158), 209-212. Agresti, A. & Coull, B. A. (1998). Approximate is better than "exact"
for interval estimation of binomial proportions. Am. Stat. 52(2), 119-126.
"""

from __future__ import annotations

import math
from enum import IntEnum
from functools import lru_cache
from statistics import NormalDist

import numpy as np

#: A scene is ``robust_stand`` only where fewer than this fraction of its draws have no verdict [-].
UNKNOWN_STAND_LIMIT = 0.1


class Robustness(IntEnum):
    """How firmly the declared uncertainty decides a scene's verdict."""

    robust_stand = 0
    sensitive = 1
    robust_overturn = 2


def wilson_interval(k, n, *, confidence: float = 0.90) -> tuple[np.ndarray, np.ndarray]:
    """Two-sided Wilson score interval of a binomial proportion.

    Parameters
    ----------
    k, n : int or array_like
        Successes (overturning samples) and trials; NaN bounds where n = 0.
    confidence : float
        Two-sided confidence level [-].

    Returns
    -------
    low, high : ndarray
        Bounds in [0, 1].

    References
    ----------
    Wilson (1927): centre (k + z^2/2) / (n + z^2), half-width
    z sqrt(k (n - k) / n + z^2 / 4) / (n + z^2).
    """
    k = np.asarray(k, dtype=float)
    n = np.asarray(n, dtype=float)
    z = normal_quantile(0.5 + confidence / 2.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        centre, half = _centre_half(k, n, z, np.sqrt)
        # k = 0 and k = n have the exact bounds 0 and 1 (not 1e-16 off)
        low = np.where(n > 0, np.where(k <= 0, 0.0, np.clip(centre - half, 0.0, 1.0)), np.nan)
        high = np.where(n > 0, np.where(k >= n, 1.0, np.clip(centre + half, 0.0, 1.0)), np.nan)
    return low, high


def spanning_interval(k: int, unknown: int, drawn: int, *, confidence: float = 0.90) -> tuple[float, float]:
    """Wilson bounds on p that span the draws without a verdict.

    Parameters
    ----------
    k : int
        Draws that overturn.
    unknown : int
        Draws without a verdict.
    drawn : int
        Every draw, with and without a verdict.
    confidence : float
        Two-sided confidence level [-].

    Returns
    -------
    low, high : float
        The lower Wilson bound of k / drawn (the unknown draws counted as standing) and the upper one of
        (k + unknown) / drawn (counted as overturning); NaN where nothing was drawn.
    """
    z = normal_quantile(0.5 + confidence / 2.0)
    return _wilson_bound(float(k), float(drawn), z, upper=False), _wilson_bound(float(k + unknown), float(drawn), z,
                                                                                upper=True)


def _centre_half(k, n, z: float, sqrt):
    """Wilson's (1927) centre and half-width for ``k`` of ``n`` at the normal quantile ``z`` (arrays with ``np.sqrt``,
    floats with ``math.sqrt``: the same operations in the same order, the same doubles)."""
    centre = (k + z * z / 2.0) / (n + z * z)
    half = z * sqrt(k * (n - k) / n + z * z / 4.0) / (n + z * z)
    return centre, half


def _wilson_bound(k: float, n: float, z: float, *, upper: bool) -> float:
    """One bound of :func:`wilson_interval`, in floats: the sequential rule asks for it after every batch of every
    scene, where numpy's cost per call on scalars, not the arithmetic, would be the work."""
    if not n > 0:
        return math.nan
    if (k >= n) if upper else (k <= 0):
        return 1.0 if upper else 0.0
    centre, half = _centre_half(k, n, z, math.sqrt)
    return min(max(centre + half if upper else centre - half, 0.0), 1.0)


@lru_cache(maxsize=8)
def normal_quantile(q: float) -> float:
    """The standard normal quantile of ``q`` (computed once per confidence)."""
    return NormalDist().inv_cdf(q)


def classify(low: float, high: float, *, below: float, above: float) -> int | None:
    """The :class:`Robustness` the interval decides, or None while it straddles a threshold."""
    if math.isnan(low):
        return None
    if high < below:
        return Robustness.robust_stand
    if low > above:
        return Robustness.robust_overturn
    if low > below and high < above:
        return Robustness.sensitive
    return None


def final_class(low: float, high: float, *, below: float, above: float, unknown_fraction: float = 0.0) -> int:
    """The class once sampling has ended: an undecided interval is ``sensitive`` (it cannot
    exclude probabilities between the thresholds), and so is one that would stand while
    :data:`UNKNOWN_STAND_LIMIT` or more of the draws (``unknown_fraction``) have no verdict;
    -1 where nothing was drawn."""
    if math.isnan(low):
        return -1
    decided = classify(low, high, below=below, above=above)
    if decided == Robustness.robust_stand and unknown_fraction >= UNKNOWN_STAND_LIMIT:
        decided = Robustness.sensitive
    return int(Robustness.sensitive if decided is None else decided)
