"""A site's hazard curve and the mean annual rate of overturning.

The hazard curve is a CSV of two columns, ``<im>_<unit>,annual_rate`` (as OpenQuake's
``hazard_curve-*.csv`` or the USGS hazard tool give them, reduced to one IM): the IM levels,
increasing, and their annual rates of exceedance, decreasing. Accepted units (converted to SI):

* accelerations (pga, sa, ap): ``g``, ``ms2`` (m s-2), ``cms2`` or ``gal`` (cm s-2);
* velocities (pgv): ``ms`` (m s-1), ``cms`` (cm s-1);
* Arias intensity (arias): ``ms`` (m s-1).

Lines starting with ``#`` are comments (OpenQuake's metadata line is one).

Rate of overturning (Cornell & Krawinkler 2000; Baker 2015, eq. 1):
lambda_C = integral P(C | im) |d lambda / d im| d im, with the curve interpolated log-log
between its points (lambda = lambda_k (im / im_k)^-s_k on each segment, integrated by 32-point
Gauss-Legendre in ln im), nothing below the first point, and P(C | im_max) lambda(im_max) for
the tail above the last. The probability in t years (Poisson): 1 - exp(-lambda_C t).

References
----------
Cornell, C. A. & Krawinkler, H. (2000). Progress and challenges in seismic performance
assessment. PEER Center News 3(2). Baker (2015), Earthquake Spectra 31(1), eq. 1.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..constants import G
from ..errors import HazardError
from .fragility import fragility_curve

#: Unit suffix -> factor to SI, per kind of IM.
UNITS = {"acceleration": {"g": G, "ms2": 1.0, "cms2": 0.01, "gal": 0.01},
         "velocity": {"ms": 1.0, "cms": 0.01}}
#: Kind of each IM that can be read from a hazard curve.
IM_KIND = {"pga": "acceleration", "sa": "acceleration", "ap": "acceleration", "pgv": "velocity",
           "arias": "velocity"}
GAUSS = np.polynomial.legendre.leggauss(32)


@dataclass(frozen=True)
class HazardCurve:
    """IM levels [SI] and their annual rates of exceedance [1/yr], with what the file says it is."""

    im: str
    levels: np.ndarray
    rates: np.ndarray
    path: str
    #: the file's own title: its comment lines before the header, joined ("" when it has none)
    title: str = ""
    #: True when the file labels itself synthetic (the word appears in its comments): not a real site's hazard
    synthetic: bool = False
    #: the unit the file gives its levels in (the suffix of its first column, e.g. ``g``)
    units: str = ""


def read_hazard(path: str | Path, *, im: str) -> HazardCurve:
    """Read and check a hazard curve for the IM ``im``.

    Raises
    ------
    HazardError
        For a missing file, a header that is not ``<im>_<unit>,annual_rate`` for this IM and a
        known unit, a value that is not a positive number, levels not increasing or rates not
        decreasing; each names the file, the line and the value.
    """
    path = Path(path)
    kind = IM_KIND.get(im)
    if kind is None:
        raise HazardError(f"{path}: a hazard curve for IM {im!r} is not supported; supported: {sorted(IM_KIND)}")
    try:
        text = path.read_text(encoding="utf-8-sig")
    except OSError as exc:
        raise HazardError(f"{path}: cannot read the hazard curve ({exc.strerror or exc})") from exc
    lines = [(k, ln) for k, ln in enumerate(text.splitlines(), 1) if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        raise HazardError(f"{path}: empty hazard curve; expected a header '{im}_<unit>,annual_rate' and rows")
    head_no, head = lines[0]
    cols = [c.strip().lower() for c in next(csv.reader([head]))]
    units = UNITS[kind]
    expected = f"'{im}_<unit>,annual_rate' with <unit> one of {sorted(units)}"
    if len(cols) < 2 or cols[1] != "annual_rate" or not cols[0].startswith(im + "_") or \
            cols[0][len(im) + 1:] not in units:
        raise HazardError(f"{path}, line {head_no}: header {head.strip()!r}; expected {expected}")
    factor = units[cols[0][len(im) + 1:]]
    levels: list[float] = []
    rates: list[float] = []
    for no, line in lines[1:]:
        row = next(csv.reader([line]))
        if len(row) < 2:
            raise HazardError(f"{path}, line {no}: {line.strip()!r}; expected two values: level,annual_rate")
        for name, value in zip(cols[:2], row[:2]):
            try:
                v = float(value)
            except ValueError:
                raise HazardError(f"{path}, line {no}: {name} = {value.strip()!r} is not a number") from None
            if not (math.isfinite(v) and v > 0):
                raise HazardError(f"{path}, line {no}: {name} = {value.strip()!r}; expected a positive number")
        lv, rt = float(row[0]) * factor, float(row[1])
        if levels and lv <= levels[-1]:
            raise HazardError(f"{path}, line {no}: {cols[0]} = {row[0].strip()} does not increase; the levels "
                              "must increase down the file")
        if rates and rt >= rates[-1]:
            raise HazardError(f"{path}, line {no}: annual_rate = {row[1].strip()} does not decrease; rates of "
                              "exceedance must decrease as the level increases")
        levels.append(lv)
        rates.append(rt)
    if len(levels) < 2:
        raise HazardError(f"{path}: {len(levels)} point(s); a hazard curve needs at least 2")
    comments = [ln.strip().lstrip("#").strip() for ln in text.splitlines()[:head_no - 1]
                if ln.lstrip().startswith("#")]
    title = " ".join(c for c in comments if c)
    return HazardCurve(im, np.array(levels), np.array(rates), str(path), title=title,
                       synthetic="synthetic" in title.lower(), units=cols[0][len(im) + 1:])


def annual_rate(curve: HazardCurve, theta: float, beta: float) -> float:
    """Mean annual rate of overturning for a lognormal fragility (theta [SI], beta) [1/yr]."""
    return float(np.sum(integrand_segments(curve, theta, beta)[2]))


def integrand_segments(curve: HazardCurve, theta: float, beta: float
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The integrand P(C | im) |d lambda / d im| on the Gauss points of every segment.

    Returns
    -------
    im : ndarray
        IM values of the Gauss points [SI].
    density : ndarray
        P(C | im) |d lambda / d im| there [1/yr per IM unit].
    contribution : ndarray
        Each segment's integral, then the tail term [1/yr] (their sum is the rate).
    """
    x, w = GAUSS
    lv, rt = np.log(curve.levels), np.log(curve.rates)
    ims, dens, parts = [], [], []
    for k in range(len(lv) - 1):
        s = -(rt[k + 1] - rt[k]) / (lv[k + 1] - lv[k])               # log-log slope of the segment
        u = 0.5 * (lv[k + 1] - lv[k]) * x + 0.5 * (lv[k + 1] + lv[k])
        im = np.exp(u)
        lam = np.exp(rt[k] - s * (u - lv[k]))
        f = fragility_curve(im, theta, beta) * s * lam                # per unit ln(im)
        parts.append(0.5 * (lv[k + 1] - lv[k]) * float(np.sum(w * f)))
        ims.append(im)
        dens.append(f / im)
    parts.append(float(fragility_curve(np.array([curve.levels[-1]]), theta, beta)[0]) * float(curve.rates[-1]))
    return np.concatenate(ims), np.concatenate(dens), np.array(parts)


def probability_in(rate_per_year: float, years: float = 50.0) -> float:
    """Poisson probability of at least one overturning in ``years`` [-]."""
    return float(1.0 - math.exp(-rate_per_year * years)) if np.isfinite(rate_per_year) else math.nan
