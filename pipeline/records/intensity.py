"""Intensity measures of a record: PGA, PGV, PGV/PGA, Arias intensity, Sa(T), per horizontal component definition.

By default horizontal measures are taken on the horizontal *vector* where the record has two
components (the largest over every orientation, as the screening's ``pga``): PGA and PGV are the
vector peaks, Sa(T) is omega^2 times the peak of the vector displacement of an isotropic oscillator
(RotD100). :func:`peak_by_component` and :func:`spectral_acceleration` also give the other definitions
hazard models and loss tools use (Boore 2010): RotD50, the median over the directions 0-179 deg (every
degree) of the peak of the motion projected on each; the geometric mean and the larger of the two
recorded components' peaks. A single horizontal gives its own peak for every definition. The Arias
intensity sums both components. Scaling a record by f scales PGA, PGV and Sa by f and the Arias
intensity by f^2.

Sa is computed exactly for ground acceleration linear between samples: the oscillator's
state is advanced by the matrix exponential of the augmented system (state, input, input
slope), so no time step is introduced (the same exactness as Nigam & Jennings 1969).

References
----------
Arias, A. (1970). A measure of earthquake intensity. In Seismic Design for Nuclear Power
Plants, MIT Press, 438-483: I_a = pi / (2 g) integral a^2 dt.
Nigam, N. C. & Jennings, P. C. (1969). Calculation of response spectra from strong-motion
earthquake records. BSSA 59(2), 909-922.
Boore, D. M. (2010). Orientation-independent, nongeometric-mean measures of seismic
intensity from two horizontal components of motion. BSSA 100(4), 1830-1835 (RotD100).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.linalg import expm

from ..compiled import jit
from ..constants import G

#: Directions of the RotD measures, every degree in [0, 180) [deg] (Boore 2010 uses 1-degree steps).
ROTD_ANGLES_DEG = np.arange(180.0)

#: Every IM the tool computes: (SI unit, how it grows with a factor f on the record: the exponent of f). pga, pgv,
#: pgv_pga, sa and arias are the record's; ap, tp and velocity_ratio are its pulse's, along each block.
IMS = {"pga": ("m s-2", 1), "pgv": ("m s-1", 1), "pgv_pga": ("s", 0), "sa": ("m s-2", 1), "arias": ("m s-1", 2),
       "ap": ("m s-2", 1), "tp": ("s", 0), "velocity_ratio": ("1", 1)}
#: Long names of the IMs.
IM_NAMES = {"pga": "peak ground acceleration (horizontal vector)", "pgv": "peak ground velocity (horizontal vector)",
            "pgv_pga": "PGV / PGA", "sa": "Sa(2 pi / p, 5 %), horizontal vector (RotD100), at the block's period",
            "arias": "Arias intensity (both horizontals)", "ap": "pulse peak acceleration a_p along the block",
            "tp": "pulse lobe duration t_p along the block",
            "velocity_ratio": "the paper's pulse measure |dv| / v_crit (Eqs. 4-5)"}
#: IMs measured under a horizontal component definition.
COMPONENT_IMS = ("pga", "pgv", "sa")
#: IMs a record can be scaled to (those that grow with the factor).
SCALABLE = tuple(k for k, (_, power) in IMS.items() if power > 0)
#: How an SI unit is written in column names and file labels.
SI_LABEL = {"m s-2": "ms2", "m s-1": "ms", "s": "s", "1": "1"}

#: Damping ratio of the response spectrum [-].
DAMPING = 0.05


def oscillator_matrices(period_s: float, dt_s: float, damping: float = DAMPING) -> tuple[np.ndarray, ...]:
    """Exact one-step matrices of a linear oscillator under input linear between samples.

    State x = (u, u') of u'' + 2 zeta w u' + w^2 u = -a(t); with r the input slope over the step,
    x_{k+1} = Phi x_k + Gamma1 a_k + Gamma2 r_k (from the exponential of the augmented system).
    """
    w = 2.0 * math.pi / period_s
    m = np.zeros((4, 4))
    m[0, 1] = 1.0
    m[1, 0], m[1, 1], m[1, 2] = -w * w, -2.0 * damping * w, -1.0
    m[2, 3] = 1.0
    e = expm(m * dt_s)
    return e[:2, :2].copy(), e[:2, 2].copy(), e[:2, 3].copy()


@jit
def _peak_displacement(h1, h2, dt, phi, g1, g2):
    """Peak of |(u1, u2)| of the oscillator under both horizontals (h2 empty: one component)."""
    two = h2.size == h1.size
    u1 = v1 = u2 = v2 = 0.0
    peak = 0.0
    for k in range(h1.size - 1):
        r = (h1[k + 1] - h1[k]) / dt
        nu = phi[0, 0] * u1 + phi[0, 1] * v1 + g1[0] * h1[k] + g2[0] * r
        v1 = phi[1, 0] * u1 + phi[1, 1] * v1 + g1[1] * h1[k] + g2[1] * r
        u1 = nu
        d = u1 * u1
        if two:
            r = (h2[k + 1] - h2[k]) / dt
            nu = phi[0, 0] * u2 + phi[0, 1] * v2 + g1[0] * h2[k] + g2[0] * r
            v2 = phi[1, 0] * u2 + phi[1, 1] * v2 + g1[1] * h2[k] + g2[1] * r
            u2 = nu
            d += u2 * u2
        if d > peak:
            peak = d
    return math.sqrt(peak)


def peak_by_component(horizontal: np.ndarray, component: str = "rotd100") -> float:
    """Peak of one or two horizontal series under a component definition (the module's list).

    Parameters
    ----------
    horizontal : ndarray, shape (n_h, npts)
        One or two horizontals (acceleration, velocity or oscillator displacement), the second 90 deg from
        the first.
    component : {"rotd100", "rotd50", "geomean", "larger"}
        The definition.
    """
    h = np.atleast_2d(np.asarray(horizontal, dtype=float))
    if h.shape[0] == 1:
        return float(np.max(np.abs(h[0])))
    if component == "rotd100":
        return float(np.max(np.hypot(h[0], h[1])))
    if component == "rotd50":
        theta = np.radians(ROTD_ANGLES_DEG)
        peaks = np.max(np.abs(np.cos(theta)[:, None] * h[0][None, :] + np.sin(theta)[:, None] * h[1][None, :]),
                       axis=1)
        return float(np.median(peaks))
    p1, p2 = float(np.max(np.abs(h[0]))), float(np.max(np.abs(h[1])))
    if component == "geomean":
        return math.sqrt(p1 * p2)
    if component == "larger":
        return max(p1, p2)
    raise ValueError(f"component {component!r}: expected rotd100, rotd50, geomean or larger")


@jit
def _displacements(h, dt, phi, g1, g2):
    """Displacement history of the oscillator under one horizontal [m]."""
    u = np.zeros(h.size)
    u1 = v1 = 0.0
    for k in range(h.size - 1):
        r = (h[k + 1] - h[k]) / dt
        nu = phi[0, 0] * u1 + phi[0, 1] * v1 + g1[0] * h[k] + g2[0] * r
        v1 = phi[1, 0] * u1 + phi[1, 1] * v1 + g1[1] * h[k] + g2[1] * r
        u1 = nu
        u[k + 1] = u1
    return u


def spectral_acceleration(horizontal_ms2: np.ndarray, dt_s: float, period_s: float, *,
                          damping: float = DAMPING, component: str = "rotd100") -> float:
    """Pseudo-spectral acceleration Sa(T) = w^2 max |u| under a component definition [m s-2] (default the
    horizontal vector, RotD100; the others from the two oscillators' displacement histories).

    Parameters
    ----------
    horizontal_ms2 : ndarray, shape (n_h, npts)
        One or two horizontals [m s-2].
    dt_s : float
        Sampling interval [s].
    period_s : float
        Oscillator period [s], > 0.
    damping : float
        Damping ratio [-].
    component : {"rotd100", "rotd50", "geomean", "larger"}
        The horizontal component definition (:func:`peak_by_component`).
    """
    h = np.atleast_2d(np.asarray(horizontal_ms2, dtype=float))
    phi, g1, g2 = oscillator_matrices(period_s, dt_s, damping)
    w = 2.0 * math.pi / period_s
    if component != "rotd100":
        u = np.array([_displacements(np.ascontiguousarray(c), float(dt_s), phi, g1, g2) for c in h])
        return w * w * peak_by_component(u, component)
    h2 = np.ascontiguousarray(h[1]) if h.shape[0] > 1 else np.zeros(0)
    return w * w * float(_peak_displacement(np.ascontiguousarray(h[0]), h2, float(dt_s), phi, g1, g2))


def arias_intensity(horizontal_ms2: np.ndarray, dt_s: float, *, g_ms2: float = G) -> float:
    """Arias intensity pi / (2 g) integral a^2 dt, summed over the horizontals [m s-1]."""
    h = np.atleast_2d(np.asarray(horizontal_ms2, dtype=float))
    return float(math.pi / (2.0 * g_ms2) * sum(np.trapezoid(c * c, dx=dt_s) for c in h))


def scale_factors(im_values: np.ndarray, levels: np.ndarray, im: str) -> np.ndarray:
    """Factor on the record that brings its IM to each level, shape (levels, blocks); NaN where the IM is
    zero or undefined (the record cannot be scaled). An IM that grows as f^k is brought to a level L by
    f = (L / IM)^(1/k) (:data:`IMS`)."""
    power = IMS[im][1]
    x = np.asarray(im_values, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        f = (np.asarray(levels, dtype=float)[:, None] / x[None, :]) ** (1.0 / power)
    return np.where(np.isfinite(f) & (f > 0), f, np.nan)


def display_unit(im: str) -> tuple[str, float]:
    """The unit an IM's levels are shown in when the user gave none: (label, factor to SI): g for accelerations,
    cm/s (``cms``) for velocities, else the SI unit."""
    unit = IMS[im][0]
    if unit == "m s-2":
        return "g", G
    if unit == "m s-1":
        return "cms", 0.01
    return SI_LABEL[unit], 1.0


def record_measures(rec, periods_s: np.ndarray, *, component: str = "rotd100", g_ms2: float = G
                    ) -> dict[str, np.ndarray]:
    """A record's own IMs, one value per period of ``periods_s`` [s] (one per block): PGA and PGV under the
    horizontal ``component`` definition (RotD100: the vector peaks, as the screening's ``pga`` and ``pgv``),
    PGV / PGA, Sa(T) at each period and the Arias intensity (SI units, :data:`IMS`)."""
    periods = np.asarray(periods_s, dtype=float)
    n = periods.size
    if component == "rotd100":
        pga, pgv = rec.pga_ms2(), rec.pgv_ms()
    else:
        pga = peak_by_component(rec.horizontal_ms2, component)
        pgv = peak_by_component(rec.velocity_ms, component)
    sa_of = {T: spectral_acceleration(rec.horizontal_ms2, rec.dt_s, float(T), component=component)
             for T in np.unique(periods)}
    return {"pga": np.full(n, pga), "pgv": np.full(n, pgv), "pgv_pga": np.full(n, pgv / pga if pga > 0 else np.nan),
            "sa": np.array([sa_of[T] for T in periods]),
            "arias": np.full(n, arias_intensity(rec.horizontal_ms2, rec.dt_s, g_ms2=g_ms2))}
