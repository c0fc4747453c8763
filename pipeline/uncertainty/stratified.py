"""The random orientation's mean over the planes it cycles through, and its interval by successive differences.

The draws of a block of unknown orientation are spread over the grid's planes in cycles, each plane once a cycle
(:func:`~.orientations.plane_order`): a sample stratified by plane. Its mean, sum_j w_j ybar_j with w_j = n_j / n,
has the variance sum_j w_j^2 sigma_j^2 / n_j, which is small wherever the probability changes with the plane
(a plateau of planes that overturn beside planes that stand), where the binomial p (1 - p) / n of Wilson's
interval is not. With one or a few draws a plane, sigma_j^2 / n_j is estimated from neighbouring planes: the
planes in azimuth order (cyclic: 180 deg is 0 deg), Var(ybar_j) ~ (ybar_j - ybar_{j+1})^2 / 2, which is
unbiased where neighbours have the same probability and too large (conservative) where they differ. Where every
plane's fraction is the same it is 0, and the interval is the mean alone (the random orientation then keeps
Wilson's interval).

References
----------
Cochran, W. G. (1977). Sampling Techniques, 3rd ed., Wiley, chapters 5A (one unit per stratum: collapsed
strata) and 8 (systematic sampling: the variance estimated from successive differences).
Wolter, K. M. (2007). Introduction to Variance Estimation, 2nd ed., Springer, chapter 8 (variance estimation for
systematic sampling: the successive-difference estimators).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .robust import normal_quantile


class StratifiedMean(NamedTuple):
    """A stratified mean and its two-sided interval (bounds clipped to [0, 1])."""

    mean: float
    low: float
    high: float


def successive_difference_interval(fractions: np.ndarray, counts: np.ndarray, *,
                                   confidence: float = 0.90) -> StratifiedMean:
    """The mean of draws spread over planes, and its normal interval from the successive-difference variance.

    Parameters
    ----------
    fractions : ndarray, shape (J,)
        Per plane, in azimuth order, the fraction of its draws that overturn [-].
    counts : ndarray, shape (J,)
        Per plane, its draws (each at least 1) [-].
    confidence : float
        Two-sided confidence level [-].

    Returns
    -------
    StratifiedMean
        sum_j w_j fractions_j (w_j = counts_j / sum counts: the plain mean of the draws) and
        mean -+ z sqrt(sum_j w_j^2 (fractions_j - fractions_{j+1})^2 / 2), the last plane's neighbour the first.
    """
    ybar = np.asarray(fractions, dtype=float)
    n = np.asarray(counts, dtype=float)
    if ybar.size < 2 or np.any(n < 1):
        raise ValueError(f"the successive-difference interval needs two or more planes, each with a draw; got "
                         f"{ybar.size} planes with counts {n.tolist()}")
    w = n / n.sum()
    mean = float(np.sum(w * ybar))
    variance = float(np.sum(w * w * (ybar - np.roll(ybar, -1)) ** 2) / 2.0)
    half = normal_quantile(0.5 + confidence / 2.0) * math.sqrt(variance)
    return StratifiedMean(mean, max(0.0, mean - half), min(1.0, mean + half))
