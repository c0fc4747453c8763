"""How long a rock has stood: its exposure age and the probability of surviving that long.

A rock's age T is given as a normal distribution (a cosmogenic-nuclide age: mean and one standard deviation),
truncated at zero, or as a table of ages and their weights. The probability that a rock whose annual rate of
toppling is lambda stood through its age is the Poisson survival exp(-lambda T) averaged over T:

* normal N(m, s^2) truncated to T > 0 (the moment-generating function of the truncated normal):
  E[exp(-lambda T)] = exp(-lambda m + lambda^2 s^2 / 2) Phi((m - lambda s^2) / s) / Phi(m / s),
  computed in logarithms (``log_ndtr``) so that it neither overflows nor underflows;
* a table: sum_k w_k exp(-lambda T_k), the weights normalised to 1.

References
----------
Purvance, M. D., Brune, J. N., Abrahamson, N. A. & Anderson, J. G. (2008). Consistency of precariously balanced
rocks with probabilistic seismic hazard estimates in southern California. BSSA 98(6), 2629-2640 (the survival
probability exp(-lambda T)). Johnson, N. L., Kotz, S. & Balakrishnan, N. (1994). Continuous Univariate
Distributions, vol. 1, 2nd ed., Wiley, section 10.1 (the truncated normal's moment-generating function).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum
from pathlib import Path

import numpy as np
from scipy.special import log_ndtr

from ..errors import ConstraintError
from ..tables import read_csv_table

#: A standard deviation below this fraction of the mean is an exact age [-].
EXACT_SD = 1e-9
#: The two layouts of an ages table.
AGES_HEADER = "rock,age_yr,age_sd_yr  (or rock,age_yr,weight: one row per age of a table)"


class AgeKind(Enum):
    """How an age is given."""

    normal = "normal"      # mean and standard deviation, truncated at 0
    table = "table"        # ages and their weights


@dataclass(frozen=True)
class Age:
    """A rock's exposure age [yr] and its uncertainty."""

    kind: AgeKind
    #: the mean [yr] (the weighted mean of a table)
    mean_yr: float
    #: the standard deviation [yr] (of the untruncated normal; a table's weighted one)
    sd_yr: float
    #: a table's ages [yr] (empty for a normal)
    values_yr: tuple = ()
    #: a table's weights, summing to 1
    weights: tuple = ()

    def survival(self, rate_per_yr) -> np.ndarray:
        """E[exp(-rate T)] over the age [-], for each rate [1/yr] (any shape)."""
        lam = np.asarray(rate_per_yr, dtype=float)
        if self.kind is AgeKind.table:
            t = np.asarray(self.values_yr)
            return np.tensordot(np.exp(-lam[..., None] * t), np.asarray(self.weights), axes=([-1], [0]))
        if self.sd_yr <= EXACT_SD * self.mean_yr:       # the age as good as exact (and the closed form's ratio finite)
            return np.exp(-lam * self.mean_yr)
        m, s = self.mean_yr, self.sd_yr
        log_e = -lam * m + 0.5 * (lam * s) ** 2 + log_ndtr((m - lam * s * s) / s) - log_ndtr(m / s)
        return np.exp(log_e)


def normal_age(mean_yr: float, sd_yr: float) -> Age:
    """An age of mean ``mean_yr`` [yr] and standard deviation ``sd_yr`` [yr], truncated at 0.

    Raises
    ------
    ConstraintError
        For a mean that is not positive or a standard deviation that is negative (or not finite).
    """
    if not (math.isfinite(mean_yr) and mean_yr > 0):
        raise ConstraintError(f"age {mean_yr!r} yr: an exposure age must be a positive number of years")
    if not (math.isfinite(sd_yr) and sd_yr >= 0):
        raise ConstraintError(f"age standard deviation {sd_yr!r} yr: must be >= 0 (0: the age is exact)")
    return Age(AgeKind.normal, float(mean_yr), float(sd_yr))


def table_age(values_yr, weights) -> Age:
    """An age given by a table of ages [yr] and their weights (normalised here).

    Raises
    ------
    ConstraintError
        For an age that is not positive or a weight that is negative, or weights summing to 0.
    """
    t, w = np.asarray(values_yr, dtype=float), np.asarray(weights, dtype=float)
    if t.size == 0 or np.any(~np.isfinite(t)) or np.any(t <= 0):
        raise ConstraintError(f"ages {t.tolist()} yr: every age of a table must be a positive number of years")
    if np.any(~np.isfinite(w)) or np.any(w < 0) or not w.sum() > 0:
        raise ConstraintError(f"weights {w.tolist()}: must be numbers >= 0, not all 0")
    w = w / w.sum()
    mean = float(np.sum(w * t))
    return Age(AgeKind.table, mean, float(math.sqrt(max(np.sum(w * (t - mean) ** 2), 0.0))),
               tuple(t.tolist()), tuple(w.tolist()))


def read_ages(path: Path) -> dict[str, Age]:
    """The ages of an ages CSV, by rock id.

    Two layouts: ``rock,age_yr,age_sd_yr`` (one row per rock: a normal age) or ``rock,age_yr,weight`` (one row
    per age of each rock's table).

    Raises
    ------
    ConstraintError
        Naming the file, the line and the value, with the layout expected.
    """
    header, rows = read_csv_table(Path(path), what="ages", expected_header=AGES_HEADER, required=("rock", "age_yr"))
    tabled = "weight" in header
    if not tabled and "age_sd_yr" not in header:
        raise ConstraintError(f"{path}, line 1: neither an age_sd_yr nor a weight column; expected {AGES_HEADER}")
    seen: dict[str, list[tuple[float, float]]] = {}
    for _line, where, cells in rows:
        rock = cells["rock"]
        if not rock:
            raise ConstraintError(f"{where}: no rock id")
        second = "weight" if tabled else "age_sd_yr"
        values = []
        for name in ("age_yr", second):
            try:
                values.append(float(cells[name]))
            except ValueError:
                raise ConstraintError(f"{where}: {name} = {cells[name]!r} is not a number; an unknown age cannot "
                                      "constrain anything: leave the rock out of the ages file") from None
        if rock in seen and not tabled:
            raise ConstraintError(f"{where}: rock {rock!r} given twice; one row per rock (mean and standard "
                                  "deviation), or a weight column for a table of ages")
        seen.setdefault(rock, []).append((values[0], values[1]))
    out = {}
    for rock, pairs in seen.items():
        try:
            out[rock] = (table_age([a for a, _ in pairs], [w for _, w in pairs]) if tabled
                         else normal_age(*pairs[0]))
        except ConstraintError as exc:
            raise ConstraintError(f"{path}: rock {rock!r}: {exc}") from None
    if not out:
        raise ConstraintError(f"{path}: no rows; expected {AGES_HEADER}")
    return out
