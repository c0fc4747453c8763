"""Closed-form overturning thresholds of a rocking block under idealized single pulses.

The second analytic tier, after the paper's energy criterion
(:mod:`pipeline.criteria`): exact solutions of the *linearised* Housner
equation for pulse shapes where one is published. They are used in the
stability charts and as independent truth in the tests.

All amplitudes are in units of ``alpha * g`` and all frequencies relative
to the block's frequency parameter ``p`` (similitude: the result depends
only on these ratios and the pulse shape).

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during
earthquakes. BSSA 53(2), 403-417.
Makris, N. & Roussos, Y. (2000). Rocking response of rigid blocks under
near-source ground motions. Geotechnique 50(3), 243-262.
Zhang, J. & Makris, N. (2001). Rocking response of free-standing blocks
under cycloidal pulses. J. Eng. Mech. 127(5), 473-483.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from .errors import ParameterError

#: Fullness factor beta = dv / (a_p t_p) of the idealized pulse shapes of the
#: reference paper (its Eq. 8 and the text after it). "harmonic" is a train of
#: half-sine lobes: each lobe is a half-sine.
PULSE_BETA = {
    "half-sine": 2.0 / math.pi,
    "harmonic": 2.0 / math.pi,
    "step": 1.0,
    "linear": 0.5,
    "parabolic": 2.0 / 3.0,
}


def pulse_beta(shape: str) -> float:
    """Fullness factor of an idealized pulse shape.

    Raises
    ------
    ParameterError
        For an unknown shape, listing the valid ones.
    """
    try:
        return PULSE_BETA[shape]
    except KeyError:
        raise ParameterError(f"pulse shape {shape!r} is unknown; valid: {sorted(PULSE_BETA)}") from None


def housner_rectangle_duration(nu):
    """Shortest rectangular pulse that overturns a block, as p t1 [-].

    Parameters
    ----------
    nu : float or array_like
        Pulse amplitude over the uplift acceleration, a / (alpha g) [-].

    Returns
    -------
    ndarray
        p t1 = ln(nu / (nu - 1)); ``inf`` where nu <= 1 (no uplift).

    References
    ----------
    Housner (1963) eq. 9, cosh(p t1) = 1 + 1 / (2 nu (nu - 1)), which is the
    same as p t1 = ln(nu / (nu - 1)) and the linear escape condition at t1.
    """
    nu = np.asarray(nu, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.log(nu / (nu - 1.0))
    return np.where(nu > 1.0, out, np.inf)


def housner_rectangle_amplitude(p_t1):
    """Smallest rectangular-pulse amplitude that overturns, as a / (alpha g) [-].

    The inverse of :func:`housner_rectangle_duration`: nu = 1 / (1 - exp(-p t1)).

    Parameters
    ----------
    p_t1 : float or array_like
        Pulse duration times p [-], > 0.
    """
    p_t1 = np.asarray(p_t1, dtype=float)
    return 1.0 / -np.expm1(-p_t1)


def makris_roussos_halfsine(omega_over_p, *, max_iterations: int = 100):
    """Minimum overturning amplitude of a half-sine pulse (linear model).

    Solves ``(w/p) sin(psi) - cos(psi) = exp(-(p/w)(pi - psi))`` for psi in
    (0, pi/2] by Newton's method safeguarded by bisection (vectorized), started
    from a table of roots on a log grid of w/p: a Newton step that leaves the
    current bracket is replaced by the bisection step, so it always converges;
    it stops when no element moves by more than 1e-14 rad (3-4 steps). The minimum amplitude is
    a_p,min / (alpha g) = 1 / sin(psi). The block overturns without impact.

    Parameters
    ----------
    omega_over_p : float or array_like
        Pulse circular frequency over p, w_p / p [-], > 0; the half-sine
        lasts t_p = pi / w_p.
    max_iterations : int
        Upper bound on the steps (pure bisection reaches double precision in 60).

    Returns
    -------
    ndarray
        a_p,min / (alpha g) [-].

    References
    ----------
    Makris & Roussos (2000) eq. 27; Housner's (1963) eqs. 11-12 overstate it
    (see :func:`housner_halfsine`).
    """
    k = np.asarray(omega_over_p, dtype=float)
    if np.any(~(k > 0)):
        raise ParameterError(f"omega_over_p = {k[~(k > 0)].tolist()[:3]}: must be > 0")
    logk, psi_table = _mr_start_table()
    psi0 = np.interp(np.log10(k), logk, psi_table)
    return 1.0 / np.sin(_mr_root(k, psi0, max_iterations))


def _mr_root(k: np.ndarray, psi: np.ndarray, max_iterations: int) -> np.ndarray:
    """Root in (0, pi/2] of M&R eq. 27 from the start ``psi``: Newton inside a bisection bracket."""
    lo = np.zeros_like(k)                  # f(0) = -1 - exp(-pi/k) < 0
    hi = np.full_like(k, np.pi / 2.0)      # f(pi/2) = k - exp(-pi/(2k)) > 0 for every k > 0
    psi = np.array(psi, dtype=float)
    for _ in range(max_iterations):
        tail = np.exp(-(np.pi - psi) / k)
        f = k * np.sin(psi) - np.cos(psi) - tail                   # M&R eq. 27
        neg = f < 0.0
        lo = np.where(neg, psi, lo)
        hi = np.where(neg, hi, psi)
        slope = k * np.cos(psi) + np.sin(psi) - tail / k           # d f / d psi
        with np.errstate(divide="ignore", invalid="ignore"):
            newton = psi - f / slope
        inside = (newton >= lo) & (newton <= hi)          # at the root the step may land on the bracket
        new = np.where(inside, newton, 0.5 * (lo + hi))
        moved = np.max(np.abs(new - psi), initial=0.0)
        psi = new
        if moved <= 1e-14:
            break
    return psi


@lru_cache(maxsize=1)
def _mr_start_table() -> tuple[np.ndarray, np.ndarray]:
    """Roots of M&R eq. 27 on a log grid of w/p (1e-4 to 1e4): start values for Newton."""
    logk = np.linspace(-4.0, 4.0, 321)
    return logk, _mr_root(10.0 ** logk, np.full(logk.size, np.pi / 4.0), 200)


def housner_halfsine(omega_over_p):
    """Housner's (1963) half-sine estimate sqrt(1 + (w/p)^2), in units of alpha g.

    Kept for comparison only: it postulates overturning at the pulse end and
    overstates the amplitude needed (Makris & Roussos 2000).
    """
    k = np.asarray(omega_over_p, dtype=float)
    return np.sqrt(1.0 + k**2)                     # Housner (1963) eqs. 11-12, approximate


def impulse_limit(omega_over_p, beta: float):
    """The impulse (short-pulse) rule in units of alpha g: max(1, w_p / (2 p)) for a half-sine.

    For a pulse of fullness ``beta`` lasting t_p = pi / w_p, the linear
    impulse rule beta t_p a_p >= alpha g / p gives a_p / (alpha g) >=
    w_p / (pi beta p); with uplift the boundary is the larger of that and 1.
    This is the reference paper's Eq. 7 in the frequency domain.
    """
    k = np.asarray(omega_over_p, dtype=float)
    return np.maximum(k / (math.pi * beta), 1.0)
