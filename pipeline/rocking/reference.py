"""A second, independent rocking solver on scipy's ``solve_ivp`` (event-driven).

Used as the reference the compiled kernel is benchmarked and tested against
(``benchmarks/bench_rocking.py``, ``tests/test_rocking_reference.py``). It
follows the same event-driven formulation (Housner 1963) with scipy's machinery: one
``solve_ivp`` call (DOP853) per smooth segment between events, the ground
acceleration interpolated linearly (``max_step`` = the sampling interval so
that no step spans more than one kink), terminal events for the impact
(direction chosen by the pivot side, so the root at a segment's start is not
seen again) and for |theta| = pi/2, and a NumPy search for the next uplift
from rest. The free motion after the record is decided by its energy.

Not meant for production: it is 2-3 orders of magnitude slower.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

from ..constants import G

#: Rounding allowance when t / dt falls on a sample [-] (the reference keeps its own: it shares no code with the
#: kernels it checks)
SAMPLE_INDEX_TOL = 1e-9


def rock_reference(ah, dt, *, p, alpha, e, g=G, rtol=1e-8, atol=1e-10, rest_ratio=1e-6, linear=False, av=None):
    """Rocking of a block under a sampled ground motion (horizontal, and optionally vertical).

    With ``av`` (vertical acceleration, up positive [m s-2]) gravity becomes g + a_v(t) in the
    equation of motion and in the uplift threshold (Yim et al. 1980). A record that reaches
    g + a_v <= 0 is refused: the contact model does not hold there.

    Returns
    -------
    dict
        ``overturned``, ``theta_max`` (max |theta| / alpha), ``n_impacts``.
    """
    ah = np.asarray(ah, dtype=float)
    n = ah.size
    av = np.zeros(n) if av is None else np.asarray(av, dtype=float)
    if np.any(g + av <= 0.0):
        raise ValueError("g + a_v <= 0 somewhere: free flight, outside the rocking model")
    t_rec = (n - 1) * dt
    times = np.arange(n) * dt
    thr = alpha if linear else math.tan(alpha)
    p2 = p * p

    def ground(t):
        return float(np.interp(t, times, ah, right=0.0))

    def vertical(t):
        return float(np.interp(t, times, av, right=0.0))

    def rhs(t, y, s):
        phi = alpha * s - y[0]
        a = ground(t)
        gv = 1.0 + vertical(t) / g
        if linear:
            return [y[1], -p2 * (gv * phi + a / g)]
        return [y[1], -p2 * (gv * math.sin(phi) + a / g * math.cos(phi))]

    t, theta_max, n_imp = 0.0, 0.0, 0
    excess = np.abs(ah) - (g + av) * thr          # > 0 where a sample lifts the block
    while t < t_rec:
        # at rest: next sample interval in which |a| crosses (g + a_v) thr, by linear interpolation
        if abs(ground(t)) > (g + vertical(t)) * thr:
            t_up = t
        else:
            k0 = int(math.floor(t / dt + SAMPLE_INDEX_TOL)) + 1
            idx = np.flatnonzero(excess[k0:] > 0)
            if idx.size == 0:
                break
            k = k0 + int(idx[0])
            sig = 1.0 if ah[k] > 0 else -1.0
            f0 = sig * ah[k - 1] - (g + av[k - 1]) * thr
            f1 = sig * ah[k] - (g + av[k]) * thr
            t_up = max((k - 1) * dt + (-f0 / (f1 - f0)) * dt, t)
        s = -1.0 if ground(t_up) > 0 else 1.0
        y = np.array([0.0, 0.0])
        t = t_up
        while True:
            def impact(tt, yy, _s):
                return yy[0]
            impact.terminal = True                   # type: ignore[attr-defined]  # solve_ivp's event protocol
            impact.direction = -1.0 if s > 0 else 1.0  # type: ignore[attr-defined]

            def fall(tt, yy, _s):
                return abs(yy[0]) - math.pi / 2
            fall.terminal = True                     # type: ignore[attr-defined]
            fall.direction = 1.0                     # type: ignore[attr-defined]
            def turn(tt, yy, _s):
                return yy[1]
            sol = solve_ivp(rhs, (t, t_rec), y, method="DOP853", rtol=rtol, atol=atol * alpha,
                            events=(impact, fall, turn), max_step=dt, args=(s,))
            theta_max = max(theta_max, float(np.max(np.abs(sol.y[0]))))
            if sol.t_events[2].size:
                theta_max = max(theta_max, float(np.max(np.abs(sol.y_events[2][:, 0]))))
            if sol.t_events[1].size:
                return {"overturned": True, "theta_max": math.pi / 2 / alpha, "n_impacts": n_imp}
            if sol.t_events[0].size:
                t = float(sol.t_events[0][0])
                om = float(sol.y_events[0][0][1]) * e
                n_imp += 1
                s = -s
                if abs(om) < rest_ratio * p * alpha:
                    break
                y = np.array([0.0, om])
                continue
            # record over while rocking: energy of the free motion
            th, om = float(sol.y[0, -1]), float(sol.y[1, -1])
            if linear:
                E, top, piv = 0.5 * om * om - 0.5 * p2 * (abs(th) - alpha) ** 2, 0.0, -0.5 * p2 * alpha ** 2
            else:
                E, top, piv = 0.5 * om * om + p2 * math.cos(alpha - abs(th)), p2, p2 * math.cos(alpha)
            outward = th * om > 0
            if abs(th) >= alpha and (outward or E <= top):
                return {"overturned": True, "theta_max": math.pi / 2 / alpha, "n_impacts": n_imp}
            if not outward:
                E = piv + e * e * (E - piv)
                n_tail = 1
            else:
                n_tail = 0
            if E >= top:
                return {"overturned": True, "theta_max": math.pi / 2 / alpha, "n_impacts": n_imp + n_tail}
            peak = alpha - (math.sqrt(max(-2 * E / p2, 0.0)) if linear else math.acos(min(E / p2, 1.0)))
            return {"overturned": False, "theta_max": max(theta_max, peak) / alpha, "n_impacts": n_imp}
    return {"overturned": False, "theta_max": theta_max / alpha, "n_impacts": n_imp}
