"""Each asset's probability of overturning in one earthquake: its lognormal fragility at the shaking of its site.

With a fragility of median theta and dispersion beta, and the shaking at the site lognormal with median m (the
ShakeMap grid value) and log standard deviation sigma,

    P(overturn | event) = Phi( ln(m e^(k sigma) / theta) / sqrt(beta^2 + sigma^2) ),

the convolution of the two lognormals (k = 0; k > 0 takes the shaking at its median times e^(k sigma), as
regulators ask for). sigma = 0 gives the fragility at the median shaking.

A fragility is only known over the levels its stripes tested. Where the fit did not bound the median (nothing
overturned, or everything did), the probability is not given: its bounds are (``p_low``, ``p_high``), read as
:func:`~pipeline.uncertainty.hazard.annual_rate_upper` reads the hazard: overturning certain above the top level
tested for the upper bound, never below the lowest for the lower one. Where it did, the bounds come from the
bootstrap interval of the median.

References
----------
Worden, C. B., Thompson, E. M., Hearne, M. & Wald, D. J. (2020). ShakeMap Manual Online. U.S. Geological Survey
(grid values are medians; the uncertainty is the standard deviation of ln IM).
Baker, J. W. (2015). Efficient analytical fragility function fitting using dynamic structural analysis. Earthquake
Spectra 31(1), 579-599.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import IntEnum

import numpy as np
from scipy.special import ndtr

from ..uncertainty.fragility import FitStatus


class Level(IntEnum):
    """An asset's inspection priority after the event (from its probability of overturning)."""

    none = 0
    low = 1
    medium = 2
    high = 3


class Basis(IntEnum):
    """What an asset's probability rests on."""

    fitted = 0             # the fragility's fit, at shaking within the levels tested
    extrapolated = 1       # the fit, at a median shaking outside the levels tested
    bounds_only = 2        # the fit did not bound the median: only p_low and p_high are given
    cannot_rock = 3        # the block is too wide to rock (alpha >= 54.7 deg): it cannot overturn
    no_fragility = 4       # the fragility run has no fit for the block
    unjudged = 5           # the fit, with records or samples without a verdict: p_high counts them as overturning


@dataclass(frozen=True)
class Fragilities:
    """Per asset, the lognormal fragility and what it was fitted over (SI units of the IM)."""

    median: np.ndarray
    beta: np.ndarray
    median_low: np.ndarray
    median_high: np.ndarray
    status: np.ndarray
    #: the lowest and highest level tested [SI]
    level_min: float
    level_max: float
    can_rock: np.ndarray
    #: the fit with the records and samples without a verdict counted as overturning (NaN: none had no verdict)
    median_unjudged: np.ndarray | None = None
    beta_unjudged: np.ndarray | None = None
    #: the lowest level at which some record's nominal scene slid [SI] (inf: none slid)
    slides_from: np.ndarray | None = None


@dataclass(frozen=True)
class EventRisk:
    """Per asset, P(overturn | event), its bounds, what it rests on, and the probability that ranks it."""

    p: np.ndarray
    p_low: np.ndarray
    p_high: np.ndarray
    basis: np.ndarray
    #: the probability the ranking and the level use: p, or p_high where p is not given; where records or samples
    #: had no verdict, at least the probability with them counted as overturning
    p_rank: np.ndarray
    #: the site's median shaking reaches a level at which the asset slid in the fragility's stripes
    sliding: np.ndarray


def convolved(median: np.ndarray, log_sd: np.ndarray, theta: np.ndarray, beta: np.ndarray, *,
              k_sigma: float = 0.0) -> np.ndarray:
    """Phi(ln(m e^(k sigma) / theta) / sqrt(beta^2 + sigma^2)), elementwise; theta = inf gives 0, theta = 0
    gives 1; a zero spread gives the step at theta."""
    m, s = np.asarray(median, dtype=float), np.nan_to_num(np.asarray(log_sd, dtype=float), nan=0.0)
    theta, beta = np.asarray(theta, dtype=float), np.asarray(beta, dtype=float)
    shaking = m * np.exp(k_sigma * s)
    spread = np.sqrt(np.nan_to_num(beta, nan=0.0) ** 2 + s ** 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.log(shaking / theta) / spread
        step = np.where(shaking >= theta, 1.0, 0.0)
    out = np.where(spread > 0, ndtr(z), step)
    out = np.where(np.isinf(theta), 0.0, out)
    return np.where(theta == 0, 1.0, out)


def exceedance(median: np.ndarray, log_sd: np.ndarray, level: float, *, k_sigma: float = 0.0) -> np.ndarray:
    """P(IM at the site > ``level``): the lognormal of the site (a zero sigma: the step)."""
    return convolved(median, log_sd, np.full(np.shape(median), level), np.zeros(np.shape(median)),
                     k_sigma=k_sigma)


def event_risk(median: np.ndarray, log_sd: np.ndarray, frag: Fragilities, *, k_sigma: float = 0.0) -> EventRisk:
    """Each asset's probability of overturning at its site's shaking (the module's rules); its level is
    :func:`levels` of ``p_rank`` (or of a larger probability the caller has, such as a station record's).

    Parameters
    ----------
    median, log_sd : ndarray
        The site's median IM [SI] and standard deviation of ln IM [-] (NaN: none, taken as 0 by the caller's
        choice; pass the default the caller states).
    frag : Fragilities
        The assets' fragilities.
    k_sigma : float
        The shaking taken at its median times exp(k sigma) [-].
    """
    status = np.asarray(frag.status)
    p = convolved(median, log_sd, frag.median, frag.beta, k_sigma=k_sigma)
    p_low = convolved(median, log_sd, frag.median_high, frag.beta, k_sigma=k_sigma)
    p_high = convolved(median, log_sd, frag.median_low, frag.beta, k_sigma=k_sigma)
    shaking = np.asarray(median) * np.exp(k_sigma * np.nan_to_num(np.asarray(log_sd, dtype=float), nan=0.0))
    basis = np.where((shaking < frag.level_min) | (shaking > frag.level_max), Basis.extrapolated, Basis.fitted)
    none = status == FitStatus.none_overturn
    every = status == FitStatus.all_overturn
    p = np.where(none | every, math.nan, p)
    p_low = np.where(none, 0.0, np.where(every, exceedance(median, log_sd, frag.level_min, k_sigma=k_sigma), p_low))
    p_high = np.where(none, exceedance(median, log_sd, frag.level_max, k_sigma=k_sigma),
                      np.where(every, 1.0, p_high))
    basis = np.where(none | every, Basis.bounds_only, basis)
    missing = ~np.isfinite(frag.median) & ~none
    basis = np.where(missing, Basis.no_fragility, basis)
    p, p_low, p_high = (np.where(missing, math.nan, a) for a in (p, p_low, p_high))
    rigid = ~np.asarray(frag.can_rock, dtype=bool)
    p, p_low, p_high = (np.where(rigid, 0.0, a) for a in (p, p_low, p_high))
    basis = np.where(rigid, Basis.cannot_rock, basis)
    p_rank = np.where(np.isfinite(p), p, p_high)
    if frag.median_unjudged is not None and frag.beta_unjudged is not None:
        # records without a verdict are unknown, never standing: P with them counted as overturning bounds p_high
        # and the rank from above (the fit of the judged records alone may read safer than they allow)
        has = np.isfinite(frag.median_unjudged) & ~rigid & ~missing
        p_unjudged = convolved(median, log_sd, frag.median_unjudged, frag.beta_unjudged, k_sigma=k_sigma)
        p_high = np.where(has, np.fmax(p_high, p_unjudged), p_high)
        p_rank = np.where(has, np.fmax(p_rank, p_unjudged), p_rank)
        basis = np.where(has & (basis != Basis.bounds_only), Basis.unjudged, basis)
    sliding = (np.zeros(np.shape(median), dtype=bool) if frag.slides_from is None
               else np.nan_to_num(shaking, nan=0.0) >= frag.slides_from)
    return EventRisk(p, p_low, p_high, basis.astype(np.int8), p_rank, sliding)


def levels(p: np.ndarray, thresholds: tuple[float, float, float], *, at_least_low=None) -> np.ndarray:
    """The inspection level of each probability: high at or above ``thresholds[2]``, medium at or above
    ``thresholds[1]``, low at or above ``thresholds[0]``, else none (NaN: high, since nothing is known);
    ``at_least_low`` (a mask): never none there (an asset the screening found sliding at the site's shaking)."""
    low, medium, high = thresholds
    p = np.asarray(p, dtype=float)
    out = np.full(p.shape, Level.none, dtype=np.int8)
    if at_least_low is not None:
        out[np.asarray(at_least_low, dtype=bool)] = Level.low
    out[p >= low] = Level.low
    out[p >= medium] = Level.medium
    out[(p >= high) | np.isnan(p)] = Level.high
    return out
