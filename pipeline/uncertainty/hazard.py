"""A site's hazard curve and the mean annual rate of overturning.

The curve is read by :mod:`.hazard_files` (OpenQuake CSV, USGS JSON, a plain CSV). Accepted units of a
plain CSV (converted to SI):

* accelerations (pga, sa, ap): ``g``, ``ms2`` (m s-2), ``cms2`` or ``gal`` (cm s-2);
* velocities (pgv): ``ms`` (m s-1), ``cms`` (cm s-1);
* Arias intensity (arias): ``ms`` (m s-1).

Rate of overturning (Cornell & Krawinkler 2000; Baker 2015, eq. 1):
lambda_C = integral P(C | im) |d lambda / d im| d im, with the curve interpolated log-log
between its points (lambda = lambda_k (im / im_k)^-s_k on each segment, integrated by 32-point
Gauss-Legendre in ln im; a flat segment, s_k = 0, adds nothing), nothing below the first point, and
P(C | im_max) lambda(im_max) for the tail above the last. The probability in t years (Poisson):
1 - exp(-lambda_C t).

References
----------
Cornell, C. A. & Krawinkler, H. (2000). Progress and challenges in seismic performance
assessment. PEER Center News 3(2). Baker (2015), Earthquake Spectra 31(1), eq. 1.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from enum import Enum

import numpy as np
from scipy.special import ndtr

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


class Component(Enum):
    """How an IM combines the two horizontal components (Boore 2010)."""

    rotd100 = "rotd100"      # the largest over all horizontal directions (the peak of the horizontal vector for PGA)
    rotd50 = "rotd50"        # the median over all horizontal directions
    geomean = "geomean"      # the geometric mean of the two recorded components
    larger = "larger"        # the larger of the two recorded components


@dataclass(frozen=True)
class HazardCurve:
    """IM levels [SI] and their annual rates of exceedance [1/yr], with what the file says it is."""

    im: str
    levels: np.ndarray
    rates: np.ndarray
    path: str
    #: the file's own title (a plain CSV's comment lines before the header, joined; a description otherwise)
    title: str = ""
    #: True when the file labels itself synthetic (the word appears in its comments): not a real site's hazard
    synthetic: bool = False
    #: the unit the file gives its levels in (e.g. ``g``)
    units: str = ""
    #: the horizontal component definition of the curve (None: the file does not say)
    component: Component | None = None
    #: True when the file or the user states ``component``; False when it is the format's usual one
    component_stated: bool = False
    #: Sa's period [s] (NaN for other IMs, or a plain CSV that does not give it)
    period_s: float = math.nan
    #: the site of a file of several (OpenQuake)
    site: str = ""
    #: ``openquake``, ``usgs`` or ``csv``
    source_format: str = "csv"
    #: what was done to the numbers (probabilities converted, saturated levels dropped, the curve ended at 0)
    notes: tuple = ()
    #: True when the file's rates reach 0 after the last level kept: nothing exceeds the levels above it
    ended_at_zero: bool = False
    #: an OpenQuake file's years of its probabilities (NaN for annual rates)
    investigation_time_yr: float = math.nan
    #: an OpenQuake file's site as written: (custom_site_id or "", lon, lat, depth)
    site_row: tuple = ()

    def with_component(self, component: Component, *, stated: bool) -> "HazardCurve":
        """The same curve with its component definition given."""
        return dataclasses.replace(self, component=component, component_stated=stated)


#: Curves whose integration weights are held in memory at once by :func:`annual_rates` (about 13 kB each on 50
#: levels).
CURVES_AT_ONCE = 1000


def annual_rate(curve: HazardCurve, theta: float, beta: float) -> float:
    """Mean annual rate of overturning for a lognormal fragility (theta [SI], beta) [1/yr]."""
    return float(annual_rates([curve], [theta], [beta])[0, 0])


def annual_rates(curves, theta, beta) -> np.ndarray:
    """The rate of :func:`annual_rate` for every curve (rows) and every (theta [SI], beta) (columns) [1/yr]: many
    fragility draws on many branches of a logic tree at once. The fragility is evaluated once per set of levels the
    curves share, and at most :data:`CURVES_AT_ONCE` curves' weights are held at once."""
    theta, beta = np.atleast_1d(np.asarray(theta, dtype=float)), np.atleast_1d(np.asarray(beta, dtype=float))
    out = np.empty((len(curves), theta.size))
    groups: dict[bytes, list[int]] = {}
    for b, c in enumerate(curves):
        groups.setdefault(np.asarray(c.levels, dtype=float).tobytes(), []).append(b)
    for members in groups.values():
        u, _, _ = _nodes(curves[members[0]])
        p = fragility_curves(np.append(u.ravel(), math.log(curves[members[0]].levels[-1])), theta, beta)
        for k in range(0, len(members), CURVES_AT_ONCE):
            chunk = members[k:k + CURVES_AT_ONCE]
            out[chunk] = (p @ np.stack([_weights(curves[b]) for b in chunk], axis=1)).T
    return out


def _nodes(curve: HazardCurve) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per segment (rows) and Gauss point (columns): ln im, |d lambda / d ln im| of the log-log segment, and the
    quadrature weight in ln im."""
    x, w = GAUSS
    lv, rt = np.log(curve.levels), np.log(curve.rates)
    half = 0.5 * np.diff(lv)
    s = -np.diff(rt) / np.diff(lv)                                          # each segment's log-log slope
    u = half[:, None] * x[None, :] + (0.5 * (lv[1:] + lv[:-1]))[:, None]
    slope_rate = s[:, None] * np.exp(rt[:-1, None] - s[:, None] * (u - lv[:-1, None]))
    return u, slope_rate, half[:, None] * w[None, :]


def _weights(curve: HazardCurve) -> np.ndarray:
    """The integral's weights at the Gauss points of :func:`_nodes` (raveled), then lambda(im_max), the tail's
    [1/yr]."""
    _, slope_rate, quad = _nodes(curve)
    return np.append((quad * slope_rate).ravel(), curve.rates[-1])


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
    u, slope_rate, quad = _nodes(curve)
    im = np.exp(u)
    f = fragility_curve(im, theta, beta) * slope_rate                       # per unit ln(im)
    parts = np.append(np.sum(quad * f, axis=1),
                      float(fragility_curve(np.array([curve.levels[-1]]), theta, beta)[0]) * float(curve.rates[-1]))
    return im.ravel(), (f / im).ravel(), parts


def fragility_curves(ln_im: np.ndarray, theta: np.ndarray, beta: np.ndarray) -> np.ndarray:
    """:func:`~.fragility.fragility_curve` of many fragilities (rows) at many ln im (columns) [-]: 0 for theta = inf,
    1 for theta = 0."""
    with np.errstate(divide="ignore", invalid="ignore"):
        z = (ln_im[None, :] - np.log(theta)[:, None]) / beta[:, None]
    p = np.where(np.isposinf(theta)[:, None], 0.0, ndtr(z))
    return np.where((theta == 0)[:, None], 1.0, p)


def exceedance_rate(curve: HazardCurve, im: float) -> float:
    """lambda(im), the curve interpolated log-log [1/yr]: the first point's rate below it, the last point's above
    it (an upper bound: the curve says nothing beyond its last point but that the rate is lower)."""
    lv, rt = np.log(curve.levels), np.log(curve.rates)
    return float(np.exp(np.interp(math.log(im), lv, rt, left=rt[0], right=rt[-1])))


def annual_rate_upper(curve: HazardCurve, theta: float, beta: float, top: float) -> float:
    """An upper bound of the rate of overturning for a fragility fitted only up to the level ``top`` [SI]: the
    fragility below ``top`` (0 where nothing overturned: theta = inf), and overturning certain at and above it,
    the conservative reading of levels never tested [1/yr]. Equal to ``lambda(top)`` when nothing overturned.
    """
    return float(annual_rates_upper([curve], theta, beta, top)[0])


def annual_rates_upper(curves, theta: float, beta: float, top: float) -> np.ndarray:
    """:func:`annual_rate_upper` on every curve [1/yr]; NaN where ``top`` is not known (not finite)."""
    if not math.isfinite(top):
        return np.full(len(curves), np.nan)
    lam_top = np.array([exceedance_rate(c, top) for c in curves])
    below = [dataclasses.replace(c, levels=np.append(c.levels[c.levels < top], top),
                                 rates=np.append(c.rates[c.levels < top], lam)) for c, lam in zip(curves, lam_top)]
    tested = np.array([b.levels.size >= 2 for b in below])
    out = lam_top.copy()                                  # nothing tested below the first level: certain above it
    if tested.any():
        rates = annual_rates([b for b, ok in zip(below, tested) if ok], [theta], [beta])[:, 0]
        p_top = float(fragility_curves(np.array([math.log(top)]), np.array([theta]), np.array([beta]))[0, 0])
        out[tested] = rates + (1.0 - p_top) * lam_top[tested]   # the tail at top taken as certain, not P(top)
    return out


def probability_in(rate_per_year: float, years: float = 50.0) -> float:
    """Poisson probability of at least one overturning in ``years`` [-]."""
    return float(1.0 - math.exp(-rate_per_year * years)) if np.isfinite(rate_per_year) else math.nan


@dataclass(frozen=True)
class HazardSet:
    """The hazard curves a fragility run integrates against: one, or Sa at several periods.

    A block is integrated against the curve of the period nearest (in log period) to its own
    Sa period; ``for_block`` says which and how far off it is.
    """

    curves: tuple

    @property
    def path(self) -> str:
        return "; ".join(c.path for c in self.curves)

    @property
    def title(self) -> str:
        return "; ".join(c.title for c in self.curves if c.title)

    @property
    def synthetic(self) -> bool:
        return any(c.synthetic for c in self.curves)

    @property
    def component(self) -> Component | None:
        return self.curves[0].component

    @property
    def units(self) -> str:
        return self.curves[0].units

    @property
    def notes(self) -> tuple:
        return tuple(n for c in self.curves for n in c.notes)

    def for_block(self, period_s: float) -> tuple[HazardCurve, float]:
        """The curve for a block whose Sa period is ``period_s`` [s], and the ratio of the curve's period to it
        (1 for an IM other than Sa, or the only curve)."""
        if len(self.curves) == 1 or not math.isfinite(period_s):
            c = self.curves[0]
            return c, (c.period_s / period_s if math.isfinite(c.period_s) and math.isfinite(period_s) else 1.0)
        gaps = [abs(math.log(c.period_s / period_s)) for c in self.curves]
        c = self.curves[int(np.argmin(gaps))]
        return c, c.period_s / period_s


def hazard_set(curves, *, im: str, fit_component: Component, scale: float | None = None) -> HazardSet:
    """Check hazard curves against a fragility fit and bind them into a :class:`HazardSet`.

    Parameters
    ----------
    curves : sequence of HazardCurve
        One curve, or Sa curves at several periods.
    im : str
        The fit's IM.
    fit_component : Component
        The horizontal component definition the fragility is fitted on.
    scale : float, optional
        The user's conversion from the hazard's component to the fit's: hazard levels are multiplied by it.

    Raises
    ------
    HazardError
        For curves of another IM, several curves for an IM other than Sa, Sa curves without a period or two of
        the same period, and a curve whose component differs from the fit's with no conversion given.
    """
    curves = list(curves)
    for c in curves:
        if c.im != im:
            raise HazardError(f"{c.path}: a {c.im} curve for a fragility on {im}")
    if len(curves) > 1 and im != "sa":
        raise HazardError(f"{len(curves)} hazard curves for {im}: give one (several are for Sa at several periods)")
    if im == "sa":
        missing = [c.path for c in curves if not math.isfinite(c.period_s)]
        if missing:
            raise HazardError(f"{missing[0]}: an Sa curve without its period; name it in the header "
                              "(sa(1.0)_g,annual_rate) or give OpenQuake's or the USGS file as exported")
        periods = [c.period_s for c in curves]
        if len(set(periods)) < len(periods):
            raise HazardError(f"two Sa curves of the same period ({sorted(periods)} s): give one per period")
    out = []
    for c in curves:
        notes = list(c.notes)
        if c.component is None:
            # a curve of unknown definition is not taken as one: RotD100 exceeds RotD50 by a record-dependent factor
            raise HazardError(
                f"{c.path}: the hazard curve does not state its horizontal component definition (RotD50, RotD100, "
                "geometric mean, larger component), and its format has no usual one; state it in the header "
                f"({c.im}_<unit>_rotd50,annual_rate) or with --hazard-component")
        elif c.component != fit_component:
            if scale is None:
                raise HazardError(
                    f"{c.path}: the hazard is {c.component.value}"
                    f"{'' if c.component_stated else ' (the usual definition of its format)'}, "
                    f"the fragility is fitted on "
                    f"{fit_component.value}; fit on the hazard's definition (leave out --im-component), state the "
                    "hazard's definition (--hazard-component) or the conversion (--hazard-scale FACTOR: hazard "
                    f"{c.component.value} x FACTOR = {fit_component.value})")
            notes.append(f"levels converted from {c.component.value} to {fit_component.value} by the stated "
                         f"factor {scale:g}")
            c = dataclasses.replace(c.with_component(fit_component, stated=True), levels=c.levels * scale)
        out.append(dataclasses.replace(c, notes=tuple(notes)))
    return HazardSet(tuple(sorted(out, key=lambda c: c.period_s if math.isfinite(c.period_s) else 0.0)))
