"""A logic tree's hazard as one curve per branch on common levels: the weighted mean, the fractiles, and the
level at which a curve reaches a rate.

* The mean hazard curve is the weighted mean of the branches' annual rates of exceedance. (OpenQuake averages
  the probabilities of exceedance in its investigation time; for one year and rates below 1e-2 the two agree to
  better than 1 %.)
* A fractile q at a level is the weighted quantile of the branches' rates there, read from their weighted
  empirical distribution: the rates sorted, the weights accumulated, q interpolated linearly between them (the
  definition of OpenQuake's quantile curves; OpenQuake interpolates between probabilities, rockscreen between rates,
  and on the shipped example the prior fractiles equal OpenQuake's exported ones to 2.4e-6).
* The level at a rate (a uniform-hazard level) is read from a curve log-log between its points; NaN where the
  curve does not reach the rate within its levels.

References
----------
McGuire, R. K., Cornell, C. A. & Toro, G. R. (2005). The case for using mean seismic hazard. Earthquake Spectra
21(3), 879-886. Pagani, M. et al. (2014). OpenQuake engine: an open hazard (and risk) software for the Global
Earthquake Model. Seismol. Res. Lett. 85(3), 692-702.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import ConstraintError
from .hazard import HazardCurve


def common_levels(curves) -> np.ndarray:
    """The levels every branch's curve covers [SI]: the union of their levels from the highest first level to the
    lowest last one (a curve that ended at a rate of 0 covers every level above its last).

    Raises
    ------
    ConstraintError
        When the curves share fewer than two levels.
    """
    low = max(float(c.levels[0]) for c in curves)
    high = min(math.inf if c.ended_at_zero else float(c.levels[-1]) for c in curves)
    grid = np.unique(np.concatenate([c.levels for c in curves]))
    grid = grid[(grid >= low) & (grid <= high)]
    if grid.size < 2:
        raise ConstraintError(f"the branches' curves share {grid.size} level(s) (from {low:.4g} to {high:.4g}); "
                              "give every branch's curve on the same levels")
    return grid


def rates_on(curve: HazardCurve, grid: np.ndarray) -> np.ndarray:
    """The curve's annual rates at ``grid`` [1/yr]: log-log between its points, 0 above the last level of a
    curve that ended at a rate of 0 (NaN outside the curve otherwise)."""
    lv, rt = np.log(curve.levels), np.log(curve.rates)
    g = np.log(np.asarray(grid, dtype=float))
    out = np.exp(np.interp(g, lv, rt))
    out = np.where(g < lv[0] - 1e-12, np.nan, out)
    return np.where(g > lv[-1] + 1e-12, 0.0 if curve.ended_at_zero else np.nan, out)


def mean_curve(rates: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """The weighted mean of the branches' rates (rows) at each level (columns) [1/yr]."""
    return np.asarray(weights, dtype=float) @ np.asarray(rates, dtype=float)


def fractile_curve(rates: np.ndarray, weights: np.ndarray, q: float) -> np.ndarray:
    """The weighted fractile ``q`` of the branches' rates (rows) at each level (columns) [1/yr]."""
    rates = np.asarray(rates, dtype=float)
    w = np.asarray(weights, dtype=float)
    out = np.empty(rates.shape[1])
    for k in range(rates.shape[1]):
        order = np.argsort(rates[:, k], kind="stable")
        out[k] = np.interp(q, np.cumsum(w[order]), rates[order, k])
    return out


def level_at_rate(grid: np.ndarray, rates: np.ndarray, target: float) -> float:
    """The level [SI] at which a curve's rate of exceedance equals ``target`` [1/yr], log-log between the points
    that bracket it (the first crossing from below the levels); NaN where the curve does not reach it."""
    grid, rates = np.asarray(grid, dtype=float), np.asarray(rates, dtype=float)
    for k in range(len(grid) - 1):
        r0, r1 = rates[k], rates[k + 1]
        if r0 >= target >= r1 and r0 > 0:
            if r1 <= 0:
                return float(grid[k])                 # the rate drops to 0 after this level
            if r0 == r1:
                return float(grid[k])
            f = math.log(r0 / target) / math.log(r0 / r1)
            return float(math.exp(math.log(grid[k]) + f * math.log(grid[k + 1] / grid[k])))
    return math.nan
