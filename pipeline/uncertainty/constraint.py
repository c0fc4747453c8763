"""The constraint that standing fragile rocks put on a hazard model's logic tree.

Per end branch b of the tree and rock i (Purvance et al. 2008; Baker et al. 2013; Rood et al. 2020):

* the annual rate of toppling, the fragility integrated over the branch's hazard curve,
  lambda_ib = integral P(topple | im) |d lambda_b / d im| d im (:func:`toppling_rates`, the integral of
  :func:`.hazard.annual_rate` for many fragility draws at once);
* the probability that the rock stood through its age T_i, averaged over the age's uncertainty and over the
  fragility's draws (the fragility's own uncertainty, carried as draws rather than a point):
  L_ib = mean_d E_T[exp(-lambda_ib(d) T_i)] (:func:`survival_likelihood`);
* the likelihood of the branch given every rock (:func:`combine`): the product over the rocks (rocks
  toppled independently of one another), or, the conservative choice where the same earthquakes shake every
  rock of a site, the likelihood of the most constraining rock alone (the one whose survival the prior
  predicts least: the smallest sum_b w_b L_ib);
* the posterior weight w'_b = w_b L_b / sum_b w_b L_b (Bayes' rule; :func:`posterior_weights`).

References
----------
Anderson, J. G. & Brune, J. N. (1999). Methodology for using precarious rocks in Nevada to test seismic hazard
models. BSSA 89(2), 456-467. Purvance, M. D., Brune, J. N., Abrahamson, N. A. & Anderson, J. G. (2008).
Consistency of precariously balanced rocks with probabilistic seismic hazard estimates in southern California.
BSSA 98(6), 2629-2640. Baker, J. W., Whitney, J. W., Hanks, T. C., Abrahamson, N. A. & Board, M. P. (2013). Use
of fragile geologic structures as indicators of unexceeded ground motions and direct constraints on probabilistic
seismic hazard analysis. BSSA 103(3), 1898-1911. Rood, A. H., Rood, D. H., Stirling, M. W. et al. (2020).
Earthquake hazard uncertainties improved using precariously balanced rocks. AGU Advances 1(4), e2020AV000182.
"""

from __future__ import annotations

import dataclasses
from enum import Enum
from typing import NamedTuple

import numpy as np
from scipy.special import ndtr

from ..errors import ConstraintError
from .ages import Age
from .hazard import GAUSS, HazardCurve

#: Curves whose integration weights are held in memory at once (each about 13 kB on 50 levels).
CURVES_AT_ONCE = 1000


class Combine(Enum):
    """How the rocks of one site combine into one likelihood per branch."""

    #: the most constraining rock alone (conservative where the same earthquakes shake every rock)
    strongest = "strongest"
    #: the product over the rocks (rocks toppled independently of one another: overstates the constraint
    #: where the same earthquakes shake them)
    independent = "independent"


class FragilityDraws(NamedTuple):
    """A rock's lognormal fragility: its fit and draws of it [IM in SI units]."""

    theta: float
    beta: float
    #: draws of the median (inf: nothing overturned in that draw; 0: everything did) and of the dispersion
    theta_draws: np.ndarray
    beta_draws: np.ndarray
    #: the largest IM level at which the fragility was tested (inf: not known)
    top_level: float


def toppling_rates(curve: HazardCurve, theta, beta) -> np.ndarray:
    """The annual rate of toppling for each (theta, beta) of a lognormal fragility on ``curve`` [1/yr].

    The same integral as :func:`.hazard.annual_rate`: the curve log-log between its points, 32-point
    Gauss-Legendre in ln im on each segment, nothing below the first point, P(C | im_max) lambda(im_max) above the
    last; vectorized over the draws. A median of +inf gives 0, a median of 0 gives lambda at the first level.

    Parameters
    ----------
    curve : HazardCurve
    theta, beta : array_like, shape (n,)
        Medians [SI] and dispersions [-].
    """
    return toppling_rates_many([curve], theta, beta)[0]


def toppling_rates_many(curves, theta, beta) -> np.ndarray:
    """:func:`toppling_rates` on many curves, shape (curves, n) [1/yr]: the fragility is evaluated once per set of
    levels the curves share (a logic tree's branches usually share them all)."""
    theta, beta = np.atleast_1d(np.asarray(theta, dtype=float)), np.atleast_1d(np.asarray(beta, dtype=float))
    out = np.empty((len(curves), theta.size))
    groups: dict[bytes, list[int]] = {}
    for b, c in enumerate(curves):
        groups.setdefault(np.asarray(c.levels, dtype=float).tobytes(), []).append(b)
    for members in groups.values():
        p = _fragility(_gauss_points(curves[members[0]].levels), theta, beta)           # (n, points)
        for k in range(0, len(members), CURVES_AT_ONCE):                               # memory bounded
            chunk = members[k:k + CURVES_AT_ONCE]
            out[chunk] = (p @ np.stack([_gauss_weights(curves[b]) for b in chunk], axis=1)).T
    return out


def _gauss_points(levels: np.ndarray) -> np.ndarray:
    """ln im at the Gauss points of every segment, then at the last level (the tail term)."""
    x, _ = GAUSS
    lv = np.log(levels)
    half = 0.5 * np.diff(lv)
    u = half[:, None] * x[None, :] + (0.5 * (lv[1:] + lv[:-1]))[:, None]   # (segments, 32)
    return np.append(u.ravel(), lv[-1])


def _gauss_weights(curve: HazardCurve) -> np.ndarray:
    """|d lambda / d ln im| d ln im at :func:`_gauss_points`, then lambda(im_max) for the tail [1/yr]."""
    x, w = GAUSS
    lv, rt = np.log(curve.levels), np.log(curve.rates)
    half = 0.5 * np.diff(lv)
    s = -np.diff(rt) / np.diff(lv)                                          # each segment's log-log slope
    u = half[:, None] * x[None, :] + (0.5 * (lv[1:] + lv[:-1]))[:, None]
    lam = np.exp(rt[:-1, None] - s[:, None] * (u - lv[:-1, None]))
    return np.append((half[:, None] * w[None, :] * s[:, None] * lam).ravel(), curve.rates[-1])


def _fragility(ln_im: np.ndarray, theta: np.ndarray, beta: np.ndarray) -> np.ndarray:
    """Phi(ln(im / theta) / beta) for every draw (rows) and ln im (columns); 0 for theta = inf, 1 for theta = 0."""
    with np.errstate(divide="ignore", invalid="ignore"):
        z = (ln_im[None, :] - np.log(theta)[:, None]) / beta[:, None]
    p = ndtr(z)
    p = np.where(np.isinf(theta)[:, None] & (theta > 0)[:, None], 0.0, p)
    return np.where((theta == 0)[:, None], 1.0, p)


def toppling_rates_upper(curves, theta: float, beta: float, top: float) -> np.ndarray:
    """Upper bounds of the toppling rate on each curve where the fragility is extrapolated above its top tested level
    ``top`` [SI]: the fragility below it, toppling certain above it [1/yr] (as :func:`.hazard.annual_rate_upper`);
    NaN where ``top`` is not known."""
    if not np.isfinite(top):
        return np.full(len(curves), np.nan)
    from .hazard import exceedance_rate

    below, lam_top = [], []
    for c in curves:
        keep = c.levels < top
        lam_top.append(exceedance_rate(c, top))
        below.append(dataclasses.replace(c, levels=np.append(c.levels[keep], top),
                                         rates=np.append(c.rates[keep], lam_top[-1])))
    ok = np.array([b.levels.size >= 2 for b in below])
    lam_top_a = np.array(lam_top)
    out = lam_top_a.copy()                                     # nothing tested below the first level: all certain
    if ok.any():
        rates = toppling_rates_many([b for b, good in zip(below, ok) if good], [theta], [beta])[:, 0]
        p_top = float(_fragility(np.array([np.log(top)]), np.array([theta]), np.array([beta]))[0, 0])
        out[ok] = rates + (1.0 - p_top) * lam_top_a[ok]       # the tail term at top replaced by certain toppling
    return out


def survival_likelihood(rates: np.ndarray, age: Age) -> np.ndarray:
    """P(the rock stood through its age | branch): E over the draws (last axis) and the age of exp(-rate T) [-].

    Parameters
    ----------
    rates : ndarray, shape (..., draws)
        Toppling rates [1/yr] of each branch and fragility draw.
    """
    return np.mean(age.survival(rates), axis=-1)


def combine(likelihoods: np.ndarray, prior: np.ndarray, rule: Combine) -> tuple[np.ndarray, int]:
    """One likelihood per branch from every rock's (``likelihoods``: rocks x branches).

    Returns
    -------
    likelihood : ndarray, shape (branches,)
    chosen : int
        The most constraining rock's index (``strongest``), -1 for ``independent``.
    """
    lik = np.asarray(likelihoods, dtype=float)
    if rule is Combine.independent:
        return np.prod(lik, axis=0), -1
    predicted = lik @ np.asarray(prior, dtype=float)          # each rock's prior probability of standing
    chosen = int(np.argmin(predicted))
    return lik[chosen], chosen


def posterior_weights(prior: np.ndarray, likelihood: np.ndarray) -> np.ndarray:
    """Bayes' rule over the end branches: w_b L_b / sum w_b L_b [-].

    Raises
    ------
    ConstraintError
        When every branch makes the rocks' survival impossible (sum w_b L_b = 0).
    """
    joint = np.asarray(prior, dtype=float) * np.asarray(likelihood, dtype=float)
    total = float(joint.sum())
    if not total > 0:
        raise ConstraintError("under every branch the rocks could not have stood through their ages (likelihood 0): "
                              "the rocks, their fragility or their ages contradict the whole hazard model; check the "
                              "ages' units (years) and the fragility's IM and component")
    return joint / total
