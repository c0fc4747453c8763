"""The end of an impact cascade (chatter) of a rocking block, one flight at a time in closed form.

A rocking block coming to rest strikes the ground again and again, each rebound ``e`` times the last, so the
impacts accumulate in a finite time (Housner 1963; in impact oscillators this is chattering, Budd & Dux 1994).
The kernel ends the cascade where a rebound falls below ``rest_ratio * p * alpha`` (1e-6 by default); a slender
block (e near 1) strikes hundreds of times on the way. Stepping each small flight by Runge-Kutta steps and
locating each impact by Newton iterations on them took a third of the sampled simulations' time on the bundled
records: 21 s of their kernels against 13.5 s with this module (docs/validation.md).

Near theta = 0 the equation of motion on pivot side ``s`` (Makris & Roussos 2000, eqs. 1-3 and 8-9, with
g -> g + a_v after Yim et al. 1980) reads, for u = s theta,

    u'' = -G(t) + K(t) u + (G(t) / 2) u^2 + O(u^3),
    G = p^2 [(1 + a_v/g) S + s (a_h/g) C],   K = p^2 [(1 + a_v/g) C - s (a_h/g) S]

(S, C = sin alpha, cos alpha; the linearised model has G with S, C = alpha, 1, K = p^2 (1 + a_v/g) and nothing
beyond the term in u). On a linear piece of the ground G and K are linear in time. With K held at its value
where a flight starts, the equation u'' = -(G0 + G1 x) + K0 u is solved in closed form (:func:`motion_at`), a
flight that leaves theta = 0 at speed w returns where u = 0 again (:func:`flight`: Newton iterations from the
root of the cubic that K = 0 gives), and the impact follows Housner's rule.

What this drops is K's change over the flight and the u^2 term (the u^3 term is smaller still): at most
(|K'| tau + G_max / 2 u_peak) u_peak, with u_peak <= w^2 / G_min while K u <= G / 2. A flight is taken in closed
form only where that is at most the kernel's relative tolerance ``rtol`` times the smallest G of the flight,
where the flight ends inside the ground piece, where G stays positive (the ground lifts neither corner), where
the ground does not fall faster than gravity, and where the pivot's friction demand at both ends of the flight
stays at or below the block's ``stop_mu`` (the kernel checks it at the ends of its steps). Otherwise the kernel
steps on from the last impact, exactly as without this module.

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. BSSA 53(2), 403-417.
Budd, C. & Dux, F. (1994). Chattering and related behaviour in impact oscillators. Phil. Trans. R. Soc. Lond.
A 347, 365-389.
Makris, N. & Roussos, Y. (2000). Rocking response of rigid blocks under near-source ground motions.
Geotechnique 50(3), 243-262.
Yim, C.-S., Chopra, A. K. & Penzien, J. (1980). Rocking response of rigid blocks to earthquakes. Earthquake
Eng. Struct. Dyn. 8(6), 565-587.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from ...compiled import jit, jit_inline
from ..codes import REST, STATUS_CHATTER
from ..numerics.dopri import HISTORY_TIME_TOL_S, pivot_demand
from ..rules import events_at_instant_compiled, min_advance_compiled

# Closed-form flights, named once
SERIES_BELOW = 0.25           # sinh(y) - y by its Taylor series to y^9 below this |y| (the next term < 1e-16) [-]
NEWTON_ITERATIONS = 20        # Newton iterations at most on a flight's return time
PEAK_ITERATIONS = 2           # Newton iterations on its turning point, from the cubic's (quadratic convergence)
CONCAVE_SHARE = 0.5           # K u stays below this share of G over a flight (u concave: one return) [-]


class Flight(NamedTuple):
    """One flight of a cascade from theta = 0 back to theta = 0 on one pivot (a numba namedtuple)."""

    tau: float       # its duration [s]; -1 where no return is found
    w_return: float  # the speed it comes back with [rad s-1]


NO_FLIGHT = Flight(tau=-1.0, w_return=0.0)


class Ground(NamedTuple):
    """What one flight needs of the ground at an instant, on one pivot (a numba namedtuple)."""

    restoring: float  # G [rad s-2]
    stiffness: float  # K [s-2]
    half_bound: float  # a bound of the O(u^2) term's coefficient, |G| / 2 (0 for the linearised model) [rad-1 s-2]
    demand: float     # the pivot's friction demand |f_x| / f_z there [-]
    holds: bool       # the block stays on the ground and on its pivot (f_z > 0, demand <= stop_mu, g + a_v > 0)


@jit
def _sinh_minus(y):
    """sinh(y) - y without cancellation."""
    if abs(y) < SERIES_BELOW:
        y2 = y * y
        return y * y2 / 6.0 * (1.0 + y2 / 20.0 * (1.0 + y2 / 42.0 * (1.0 + y2 / 72.0)))
    return math.sinh(y) - y


@jit
def motion_at(x, w, g0, g1, k):
    """u and u' at x of u'' = -(g0 + g1 x) + k u from u = 0, u' = w (k >= 0), in closed form:
    u = w sinh(y) / lam - g0 (cosh(y) - 1) / k - g1 (sinh(y) - y) / (k lam), y = lam x, lam = sqrt(k)
    (the cubic w x - g0 x^2 / 2 - g1 x^3 / 6 as k -> 0, which the series keep without cancellation)."""
    lam = math.sqrt(k)
    y = lam * x
    if y == 0.0:
        return w * x - 0.5 * g0 * x * x - g1 * x * x * x / 6.0, w - g0 * x - 0.5 * g1 * x * x
    sm = _sinh_minus(y)
    half = 0.5 * y
    sh_half = half + _sinh_minus(half)
    c1 = 2.0 * sh_half * sh_half                  # cosh(y) - 1
    sh_over = x + sm / lam                        # sinh(y) / lam
    u = w * sh_over - g0 * c1 / k - g1 * sm / (k * lam)
    v = w * (1.0 + c1) - g0 * sh_over - g1 * c1 / k
    return u, v


@jit
def flight(w, g0, g1, k, span):
    """The flight of u'' = -(g0 + g1 x) + k u from u = 0 at speed ``w`` > 0 (``g0`` > 0, ``k`` >= 0): its return
    time and return speed (:data:`NO_FLIGHT` where u does not come back within ``span`` [s]). Newton
    iterations from the return time of the cubic (k = 0), which is earlier (k u >= 0 only slows the fall); u is
    concave where the caller takes the flight, so after the first they approach the root from its right,
    monotonically."""
    a, b = g1 / 6.0, 0.5 * g0                 # the cubic: u / x = w - b x - a x^2 = 0
    disc = b * b + 4.0 * a * w
    if disc < 0.0:
        return NO_FLIGHT
    den = b + math.sqrt(disc)
    if not den > 0.0:
        return NO_FLIGHT
    tau = 2.0 * w / den
    if tau > span:
        return NO_FLIGHT
    u, v = motion_at(tau, w, g0, g1, k)
    for _ in range(NEWTON_ITERATIONS):
        if not v < 0.0:
            return NO_FLIGHT
        step = u / v
        tau -= step
        u, v = motion_at(tau, w, g0, g1, k)
        if abs(step) <= 4.0 * 2.220446049250313e-16 * tau:
            break
    if not (tau > 0.0 and v < 0.0):
        return NO_FLIGHT
    return Flight(tau=tau, w_return=-v)


@jit
def flight_peak(w, g0, g1, k, tau):
    """The largest u of the flight of :func:`flight` (its duration ``tau``): from the cubic's turning point
    (u'(tp) = w - g0 tp - g1 tp^2 / 2 = 0), Newton iterations on u'."""
    dp = g0 * g0 + 2.0 * g1 * w
    tp = min(2.0 * w / (g0 + math.sqrt(dp)), tau) if dp >= 0.0 else 0.5 * tau
    u_pk, v_pk = motion_at(tp, w, g0, g1, k)
    for _ in range(PEAK_ITERATIONS):
        acc = -(g0 + g1 * tp) + k * u_pk            # u'' < 0 where the flight is taken
        if not acc < 0.0:
            break
        tp = min(max(tp - v_pk / acc, 0.0), tau)
        u_pk, v_pk = motion_at(tp, w, g0, g1, k)
    return max(u_pk, 0.0)


@jit_inline
def take_impact(t, om_before, e, rest_omega, max_events, progress, impacts):
    """Housner's impact at time t (theta = 0) as the kernel and the closed-form cascade both take it: omega
    multiplied by e and the pivot switched (Housner 1963), logged in ``impacts`` while it has room, counted
    against the event cap and tie rule 6's count; a rebound slower than ``rest_omega`` or the cap ends in rest."""
    pr = progress[0]
    om_after = e * om_before                                   # omega ratio e, energy ratio e^2
    if pr.n_impacts < impacts.shape[0]:
        impacts[pr.n_impacts, 0] = t
        impacts[pr.n_impacts, 1] = om_before
        impacts[pr.n_impacts, 2] = om_after
    if pr.n_impacts == 0:
        pr.t_first_impact = t
    pr.n_impacts += 1
    pr.n_events += 1
    pr.t, pr.theta, pr.omega, pr.pivot = t, 0.0, om_after, -pr.pivot
    pr.n_same = events_at_instant_compiled(t, pr.t_event, pr.n_same)
    pr.t_event = t
    if abs(om_after) < rest_omega or pr.n_events >= max_events:
        if pr.n_events >= max_events:
            pr.status |= STATUS_CHATTER
        pr.omega, pr.mode = 0.0, REST


@jit_inline
def _ground(t, w, s, pc, block, p2, big_s, big_c, k_side, sin_a, cos_a):
    """The ground of the piece ``pc`` at time t for a flight on pivot s at speed w, at theta = 0 (``big_s``,
    ``big_c``, ``k_side``: S, C and K's S, 0 for the linearised model; ``sin_a``, ``cos_a``: of alpha)."""
    a = pc.a0 + pc.sa * (t - pc.t0)
    v = pc.v0 + pc.sv * (t - pc.t0)
    g = block.g
    g_s = p2 * ((1.0 + v / g) * big_s + s * (a / g) * big_c)
    k_s = p2 * ((1.0 + v / g) * big_c - s * (a / g) * k_side)
    half = 0.0 if block.linear else 0.5 * p2 * ((1.0 + abs(v) / g) * big_s + abs(a) / g * big_c)
    demand, lifted = pivot_demand(s * sin_a, cos_a, w, -s * g_s, block.R, a, v, g)   # phi = alpha s
    holds = g + v > 0.0 and g_s > 0.0 and k_s >= 0.0 and not lifted and not demand > block.stop_mu
    return Ground(restoring=g_s, stiffness=k_s, half_bound=half, demand=demand, holds=holds)


@jit_inline
def chatter(dt, pc, block, control, rest_omega, p2, progress, theta_out, impacts):
    """Take the flights of a cascade in closed form from the impact the progress record has just taken
    (theta = 0, omega the rebound on the new pivot), while each holds (the module's conditions), to the rest
    rule or the event cap; the record is left at the last impact taken (at rest where the cascade ended), for
    the kernel to go on from. Fills the theta history and the impact log as the kernel does."""
    pr = progress[0]
    t, s, w = pr.t, pr.pivot, abs(pr.omega)
    sin_a, cos_a = math.sin(block.alpha), math.cos(block.alpha)
    big_s, big_c = (block.alpha, 1.0) if block.linear else (sin_a, cos_a)
    k_side = 0.0 if block.linear else big_s
    inv_g = 1.0 / block.g
    while True:
        start = _ground(t, w, s, pc, block, p2, big_s, big_c, k_side, sin_a, cos_a)
        if not start.holds:
            return
        g1 = p2 * (pc.sv * inv_g * big_s + s * pc.sa * inv_g * big_c)          # G's rate on the piece
        k1 = p2 * (pc.sv * inv_g * big_c - s * pc.sa * inv_g * k_side)        # K's rate
        fl = flight(w, start.restoring, g1, start.stiffness, pc.t1 - t)
        te = t + fl.tau
        if fl.tau < min_advance_compiled(t) or te > pc.t1:
            return
        end = _ground(te, fl.w_return, s, pc, block, p2, big_s, big_c, k_side, sin_a, cos_a)
        g_min = min(start.restoring, end.restoring)
        u_bound = w * w / g_min                  # the peak, while K u <= G / 2 (checked here)
        # what the closed form drops: K's change over the flight, and the O(u^2) term
        dropped = (abs(k1) * fl.tau + max(start.half_bound, end.half_bound) * u_bound) * u_bound
        if not (end.holds and dropped <= control.rtol * g_min
                and max(start.stiffness, end.stiffness) * u_bound <= CONCAVE_SHARE * g_min):
            return
        pr.friction_max = max(pr.friction_max, start.demand, end.demand)
        if u_bound > pr.theta_max:
            pr.theta_max = max(pr.theta_max, flight_peak(w, start.restoring, g1, start.stiffness, fl.tau))
        while pr.out_k < theta_out.shape[0] and pr.out_k * dt <= te + HISTORY_TIME_TOL_S:
            u_k, _v = motion_at(max(pr.out_k * dt - t, 0.0), w, start.restoring, g1, start.stiffness)
            theta_out[pr.out_k] = s * max(u_k, 0.0)
            pr.out_k += 1
        take_impact(te, -s * fl.w_return, block.e, rest_omega, control.max_events, progress, impacts)
        if pr.mode == REST:
            return
        t, s, w = pr.t, pr.pivot, abs(pr.omega)
