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

from ..constants import G

#: Directions of the RotD measures, every degree in [0, 180) [deg] (Boore 2010 uses 1-degree steps).
ROTD_ANGLES_DEG = np.arange(180.0)

try:  # the same source runs as Python without numba
    from numba import njit as _njit

    def _jit(f):
        return _njit(cache=True, nogil=True)(f)
except ImportError:  # pragma: no cover
    def _jit(f):
        return f

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


@_jit
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


@_jit
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
