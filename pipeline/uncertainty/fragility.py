"""Lognormal fragility functions: maximum-likelihood fits, bootstrap intervals, IM efficiency and sufficiency.

A fragility function P(C | IM = x) = Phi(ln(x / theta) / beta) is a probit regression on ln x:
P = Phi(a + b ln x) with beta = 1 / b and theta = exp(-a / b). Multiple-stripe counts (z_j of
n_j records overturn at level x_j) are fitted by maximizing the binomial likelihood
sum_j [z_j ln p_j + (n_j - z_j) ln(1 - p_j)] (Baker 2015); stripes of all zeros or all ones
are kept (they are informative). The maximum is found by Fisher scoring (iteratively
reweighted least squares), vectorized over many fits at once so that bootstrap replicates
cost one pass. Fractional counts (sums of p_overturn) give the quasi-likelihood fit.

Fit status:

* ``ok``: a finite maximum;
* ``none_overturn``: no stripe has an overturning (theta above the largest level: +inf);
* ``all_overturn``: every record overturns at every level (theta below the smallest: 0);
* ``separated``: every stripe is all 0 or all 1, zeros below ones; the likelihood grows
  without bound as beta -> 0: theta is reported as the geometric mean of the last all-0 and
  the first all-1 level, and beta at its floor :data:`BETA_FLOOR`;
* ``not_bounded``: some record overturns, but the stripes do not bracket 50 % (every stripe's
  fraction is below one half, or every one above): the median lies beyond the tested levels and the
  fit extrapolates the lognormal shape to find it; its interval is open on that side
  (:func:`open_interval`);
* ``extrapolated``: the stripes bracket 50 %, yet the fitted median lies outside the tested levels.

Only ``ok`` and ``separated`` medians are within the levels tested.

Intensity-measure efficiency: the same outcomes fitted against another IM's values (one point
per record and level); a smaller beta means less record-to-record dispersion (Luco & Cornell
2007). Sufficiency: a likelihood-ratio test of adding ln(t_p), the pulse period, as a second
covariate; a small p-value means the outcome still depends on t_p given the IM.

References
----------
Baker, J. W. (2015). Efficient analytical fragility function fitting using dynamic structural
analysis. Earthquake Spectra 31(1), 579-599. Luco, N. & Cornell, C. A. (2007). Structure-specific
scalar intensity measures for near-source and ordinary earthquake ground motions. Earthquake
Spectra 23(2), 357-392. Padgett, J. E., Nielson, B. G. & DesRoches, R. (2008). Selection of
optimal intensity measures in probabilistic seismic demand models of highway bridge portfolios.
EESD 37(5), 711-725.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import IntEnum

import numpy as np
from scipy.special import chdtrc, ndtr

SQRT_2PI = math.sqrt(2.0 * math.pi)


def _pdf(x):
    """Standard normal density."""
    return np.exp(-0.5 * np.asarray(x) ** 2) / SQRT_2PI

#: Smallest dispersion reported (separated stripes) [-].
BETA_FLOOR = 1e-3
#: Clip of the fitted probabilities in the likelihood [-].
P_CLIP = 1e-12


class FitStatus(IntEnum):
    """How a fragility fit ended."""

    ok = 0
    none_overturn = 1
    all_overturn = 2
    separated = 3
    not_bounded = 4
    extrapolated = 5


def probit_irls(X: np.ndarray, y: np.ndarray, n: np.ndarray, *, iterations: int = 60,
                max_coef: float = 1e3) -> tuple[np.ndarray, np.ndarray]:
    """Maximum-likelihood probit regression by Fisher scoring, many problems at once.

    Parameters
    ----------
    X : ndarray, shape (..., m, k)
        Design matrices (a column of ones first).
    y : ndarray, shape (..., m)
        Successes (may be fractional).
    n : ndarray, shape (..., m)
        Trials (0 for an unused row).
    iterations : int
        Scoring steps (converges in under 20 where the maximum is finite).
    max_coef : float
        Bound on the coefficients (a separated problem diverges; it stops there).

    Returns
    -------
    coef : ndarray, shape (..., k)
    loglik : ndarray, shape (...)
        Binomial log-likelihood at ``coef`` (without the constant binomial terms).
    """
    X, y, n = (np.asarray(v, dtype=float) for v in (X, y, n))
    k = X.shape[-1]
    coef = np.zeros(X.shape[:-2] + (k,))
    frac = np.where(n > 0, y / np.where(n > 0, n, 1.0), 0.5)
    for _ in range(iterations):
        eta = np.einsum("...mk,...k->...m", X, coef)
        mu = np.clip(ndtr(eta), P_CLIP, 1 - P_CLIP)
        dens = np.maximum(_pdf(eta), 1e-300)
        w = n * dens * dens / (mu * (1 - mu))
        z = eta + (frac - mu) / dens
        xtw = X * w[..., None]
        a = np.einsum("...mk,...ml->...kl", xtw, X) + 1e-12 * np.eye(k)
        b = np.einsum("...mk,...m->...k", xtw, z)
        new = np.clip(np.linalg.solve(a, b[..., None])[..., 0], -max_coef, max_coef)
        done = np.max(np.abs(new - coef)) < 1e-10
        coef = new
        if done:
            break
    return coef, loglik(X, y, n, coef)


def loglik(X, y, n, coef) -> np.ndarray:
    """Binomial log-likelihood of a probit model (constant terms dropped)."""
    mu = np.clip(ndtr(np.einsum("...mk,...k->...m", X, coef)), P_CLIP, 1 - P_CLIP)
    return np.sum(y * np.log(mu) + (n - y) * np.log(1 - mu), axis=-1)


@dataclass(frozen=True)
class Fit:
    """A lognormal fragility function: median theta [IM units] and dispersion beta [-]."""

    theta: np.ndarray
    beta: np.ndarray
    status: np.ndarray


def fit_stripes(levels: np.ndarray, overturned: np.ndarray, trials: np.ndarray) -> Fit:
    """Maximum-likelihood lognormal fit of stripe counts (vectorized over leading dimensions).

    Parameters
    ----------
    levels : ndarray, shape (L,)
        IM levels x_j [IM units], > 0.
    overturned, trials : ndarray, shape (..., L)
        z_j (may be fractional) and n_j per stripe.
    """
    levels = np.asarray(levels, dtype=float)
    x = np.log(levels)
    z = np.asarray(overturned, dtype=float)
    n = np.asarray(trials, dtype=float)
    X = np.broadcast_to(np.stack([np.ones_like(x), x], axis=-1), z.shape + (2,))
    coef, _ = probit_irls(X, z, n)
    a, b = coef[..., 0], coef[..., 1]
    frac = np.where(n > 0, z / np.where(n > 0, n, 1.0), np.nan)
    none = np.nansum(z, axis=-1) <= 0
    every = np.all((frac >= 1) | (n == 0), axis=-1) & ~none
    # separated: every stripe all 0 then all 1 (levels increasing); the MLE has beta -> 0
    binary = np.all(np.isnan(frac) | (frac == 0) | (frac == 1), axis=-1)
    running = np.maximum.accumulate(np.where(np.isnan(frac), -np.inf, frac), axis=-1)
    separated = binary & np.all(np.isnan(frac) | (frac >= running), axis=-1) & ~none & ~every
    last0 = np.max(np.where(frac == 0, levels, 0.0), axis=-1)
    first1 = np.min(np.where(frac == 1, levels, np.inf), axis=-1)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        beta = np.where(b > 0, 1.0 / b, np.nan)
        theta = np.exp(-a / b)
        theta_sep = np.sqrt(last0 * first1)
    status = np.full(z.shape[:-1], FitStatus.ok, dtype="i1")
    below = np.all(np.isnan(frac) | (frac < 0.5), axis=-1)
    above = np.all(np.isnan(frac) | (frac > 0.5), axis=-1)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        outside = ~((np.exp(-a / b) >= levels.min()) & (np.exp(-a / b) <= levels.max()))
    status = np.where(outside, FitStatus.extrapolated, status)
    status = np.where(below | above, FitStatus.not_bounded, status)
    status = np.where(separated, FitStatus.separated, status)
    status = np.where(none, FitStatus.none_overturn, status)
    status = np.where(every, FitStatus.all_overturn, status)
    theta = np.where(none, np.inf, np.where(every, 0.0, np.where(separated, theta_sep, theta)))
    beta = np.where(none | every, np.nan, np.where(separated, BETA_FLOOR, beta))
    return Fit(theta=theta, beta=beta, status=status.astype("i1"))


def open_interval(fractions: np.ndarray, theta_interval: np.ndarray) -> np.ndarray:
    """The median's interval of a ``not_bounded`` fit, open on the side the stripes do not bound: above the
    levels (every fraction below one half) the upper bound is +inf, below them the lower bound is 0; the other
    bound is the bootstrap's (``theta_interval``)."""
    frac = np.asarray(fractions, dtype=float)
    low, high = float(theta_interval[0]), float(theta_interval[1])
    if np.all(np.isnan(frac) | (frac < 0.5)):
        high = math.inf
    if np.all(np.isnan(frac) | (frac > 0.5)):
        low = 0.0
    return np.array([low, high])


def bootstrap_stripes(levels: np.ndarray, outcomes: np.ndarray, *, draws: int, seed: int,
                      confidence: float = 0.90) -> tuple[np.ndarray, np.ndarray]:
    """Percentile intervals of theta and beta by resampling *records* (Baker 2015).

    Replicates in which no record overturns (theta = +inf) or every record does (theta = 0) are kept in the
    median's percentiles, so that the interval can be open; replicates without a fit are left out.

    Parameters
    ----------
    levels : ndarray, shape (L,)
    outcomes : ndarray, shape (R, L)
        Per record and level: 1 overturns, 0 stands (or p_overturn), NaN no verdict.
    draws : int
        Bootstrap replicates.
    seed : int
        Seed of the resampling.

    Returns
    -------
    theta_interval, beta_interval : ndarray, shape (2,)
        Lower and upper bounds (NaN where fewer than half of the replicates have a finite fit).
    """
    outcomes = np.asarray(outcomes, dtype=float)
    r = outcomes.shape[0]
    if r == 0 or draws <= 0:
        return np.full(2, np.nan), np.full(2, np.nan)
    rng = np.random.Generator(np.random.PCG64(seed))
    pick = rng.integers(0, r, size=(draws, r))
    sample = outcomes[pick]                                     # (draws, R, L)
    z = np.nansum(sample, axis=1)
    n = np.sum(np.isfinite(sample), axis=1).astype(float)
    fit = fit_stripes(levels, z, n)
    q = [(1 - confidence) / 2 * 100, (1 + confidence) / 2 * 100]
    out = []
    for v, keep in ((fit.theta, ~np.isnan(fit.theta)), (fit.beta, np.isfinite(fit.beta))):
        good = np.sort(v[keep])
        if good.size < draws / 2:
            out.append(np.full(2, np.nan))
            continue
        if np.all(np.isfinite(good)):
            out.append(np.percentile(good, q))
            continue
        # percentiles by rank (np.percentile cannot interpolate next to an infinite replicate)
        idx = np.clip(np.round(np.array(q) / 100 * (good.size - 1)).astype(int), 0, good.size - 1)
        out.append(good[idx].astype(float))
    return out[0], out[1]


def im_dispersion(im_values: np.ndarray, outcomes: np.ndarray, covariate: np.ndarray | None = None
                  ) -> tuple[float, float, float]:
    """Fit the outcomes against one IM (one point per record and level); dispersion and sufficiency.

    Parameters
    ----------
    im_values : ndarray
        The IM of each scaled record [IM units] (non-positive or NaN points are dropped).
    outcomes : ndarray
        1 / 0 (or p_overturn) per point, NaN for no verdict.
    covariate : ndarray, optional
        ln(t_p) per point for the sufficiency test.

    Returns
    -------
    theta, beta : float
        The fitted median [IM units] and dispersion [-] (inf beta: the IM does not increase the
        probability of overturning; NaN: no overturning or no standing point).
    sufficiency_p : float
        p-value of the likelihood-ratio test for adding ``covariate`` (NaN without one).
    """
    x = np.asarray(im_values, dtype=float)
    y = np.asarray(outcomes, dtype=float)
    ok = np.isfinite(x) & (x > 0) & np.isfinite(y)
    if covariate is not None:
        ok &= np.isfinite(covariate)
    x, y = np.log(x[ok]), y[ok]
    if y.size < 3 or np.all(y <= 0) or np.all(y >= 1):
        return np.nan, np.nan, np.nan
    n = np.ones_like(y)
    X = np.stack([np.ones_like(x), x], axis=-1)
    coef, ll1 = probit_irls(X, y, n)
    a, b = coef
    with np.errstate(over="ignore"):
        theta, beta = (float(np.exp(-a / b)), float(1.0 / b)) if b > 0 else (np.nan, np.inf)
    p_suff = np.nan
    if covariate is not None:
        c = np.asarray(covariate, dtype=float)[ok]
        coef2, ll2 = probit_irls(np.column_stack([X, c]), y, n)
        p_suff = float(chdtrc(1.0, max(2.0 * (float(ll2) - float(ll1)), 0.0)))
    return theta, beta, p_suff


def fragility_curve(x, theta: float, beta: float) -> np.ndarray:
    """Phi(ln(x / theta) / beta) [-]; without a finite beta: 0 for theta = inf (nothing overturns), 1 for
    theta = 0 (everything overturns), NaN otherwise (no fit)."""
    x = np.asarray(x, dtype=float)
    if np.isfinite(beta):
        return ndtr(np.log(x / theta) / beta)
    value = 0.0 if theta == np.inf else 1.0 if theta == 0 else np.nan
    return np.full_like(x, value)
