"""Coulomb stick-slip of a block on a moving base, integrated exactly per sample (compiled with numba when
installed, as :mod:`.kernel`).

References
----------
Shenton, H. W. & Jones, N. P. (1991). Base excitation of rigid bodies. I: Formulation. J. Eng. Mech. 117(10),
2286-2306 (the sliding mode and its Coulomb law).
"""

from __future__ import annotations

import math

from ..compiled import jit
from .ground import exceed_fraction, flight_fraction
from .kernel import TINY

#: Slip starts and stops located in one sample interval, at most (the slip velocity is quadratic in time there,
#: so a physical interval holds a handful; the cap ends the interval's search, counted in ``capped``)
MAX_STOPS_PER_SAMPLE = 64


@jit
def slide(ah, av, dt, mu, g):
    """Coulomb stick-slip of a block on a moving base, integrated exactly per sample.

    Relative displacement u (block minus ground): while slipping in direction
    d = sign(u'), u'' = -a_h - d mu (g + a_v); sticking while
    |a_h| <= mu (g + a_v). The ground acceleration is linear between samples,
    so u' is quadratic and u cubic in time, and slip ends at the exact root of u'.

    Progress: every pass of the inner loop advances within the sample or counts against
    :data:`MAX_STOPS_PER_SAMPLE`; a sample that reaches the cap is counted in ``capped`` and the slip state is
    carried to the next sample unchanged (never met on the bundled records).

    Returns
    -------
    tuple
        (peak |u| [m], final u [m], number of slip episodes, time slipping [s],
        time the ground's g + a_v reached 0 [s] (NaN: never; the integration stops there),
        samples whose search reached MAX_STOPS_PER_SAMPLE)
    """
    n = ah.shape[0]
    has_v = av.shape[0] == n
    u, v = 0.0, 0.0
    slipping = False
    d = 0.0
    u_max = 0.0
    n_slips = 0
    t_slip = 0.0
    t_flight = math.nan
    capped = 0
    for k in range(n - 1):
        a0, a1 = ah[k], ah[k + 1]
        v0 = av[k] if has_v else 0.0
        v1 = av[k + 1] if has_v else 0.0
        if g + v0 <= 0.0 or g + v1 <= 0.0:
            # the ground falls faster than gravity: no normal force, no friction, and the Coulomb
            # model holds no further (the caller reports the scene as free flight)
            t_flight = (k + flight_fraction(v0, v1, g)) * dt
            break
        x = 0.0                                   # position in the sample, in [0, dt]
        guard = 0
        while x < dt:
            guard += 1
            if guard > MAX_STOPS_PER_SAMPLE:
                capped += 1
                break
            ka = (a1 - a0) / dt
            kv = (v1 - v0) / dt
            ax = a0 + ka * x
            vx = v0 + kv * x
            if not slipping:
                f = exceed_fraction(ax, a0 + ka * dt, vx, v1, g, mu)
                if f < 0.0:
                    x = dt
                    break
                x = x + f * (dt - x)
                ax = a0 + ka * x
                if ax == 0.0:                     # no horizontal force: nothing to slip (g + a_v > 0 here)
                    x = dt
                    break
                d = -1.0 if ax > 0.0 else 1.0     # friction opposes the relative motion, u'' = -a_h - d mu N
                slipping = True
                n_slips += 1
                v = 0.0
                continue
            # slipping: v(tau) = v + c0 tau + c1 tau^2 / 2, tau from x
            c0 = -ax - d * mu * (g + vx)
            c1 = -ka - d * mu * kv
            rem = dt - x
            tau = _first_stop(v, c0, c1, rem, d)
            if tau < 0.0:
                u = u + v * rem + c0 * rem * rem / 2 + c1 * rem ** 3 / 6
                v = v + c0 * rem + c1 * rem * rem / 2
                t_slip += rem
                u_max = max(u_max, abs(u))
                x = dt
                break
            u = u + v * tau + c0 * tau * tau / 2 + c1 * tau ** 3 / 6
            v = 0.0
            t_slip += tau
            u_max = max(u_max, abs(u))
            x = x + tau
            ax = a0 + ka * x
            vx = v0 + kv * x
            if abs(ax) > mu * (g + vx):
                d = -1.0 if ax > 0.0 else 1.0     # slips back the other way at once
                n_slips += 1
            else:
                slipping = False
    return u_max, u, n_slips, t_slip, t_flight, capped


@jit
def _first_stop(v, c0, c1, rem, d):
    """First tau in (0, rem] where d * v(tau) reaches 0, v(tau) = v + c0 tau + c1 tau^2 / 2; -1 if none."""
    # d * v(tau) starts >= 0 and we look for its first return to 0
    A = 0.5 * c1 * d
    B = c0 * d
    C = v * d
    tiny = 1e-15
    best = -1.0
    if abs(A) < TINY:
        if B < 0.0:
            r = -C / B
            if r > tiny and r <= rem:
                best = r
        return best
    disc = B * B - 4 * A * C
    if disc < 0.0:
        return -1.0
    sq = math.sqrt(disc)
    q = -0.5 * (B + math.copysign(sq, B))
    r1 = q / A
    r2 = C / q if q != 0.0 else r1
    for r in (r1, r2):
        if r > tiny and r <= rem and (best < 0.0 or r < best):
            # must be a crossing downward (d * v decreasing) or a touch
            if 2 * A * r + B <= 0.0:
                best = r
    return best
