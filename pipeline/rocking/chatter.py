"""The end of an impact cascade (chatter) of a rocking block, one flight at a time in closed form.

A rocking block coming to rest strikes the ground again and again, each rebound ``e`` times the last, so the
impacts accumulate in a finite time (Housner 1963; in impact oscillators this is chattering, Budd & Dux 1994).
The kernel ends the cascade where a rebound falls below ``rest_ratio * p * alpha`` (1e-6 by default). Stepping
each small flight by Runge-Kutta steps and locating each impact by Newton iterations on them costs about ten
steps an impact, for a hundred impacts and more per cascade.

Near theta = 0 the equation of motion on pivot side ``s`` (Makris & Roussos 2000, eqs. 1-3 and 8-9, with
g -> g + a_v after Yim et al. 1980) reads, for u = s theta,

    u'' = -G(t) + K(t) u + O(u^2),
    G = p^2 [(1 + a_v/g) S + s (a_h/g) C],   K = p^2 [(1 + a_v/g) C - s (a_h/g) S]

(S, C = sin alpha, cos alpha; alpha, 1 for the linearised model). G is linear in time on a linear piece of the
ground, so without the term in u a flight that leaves theta = 0 at speed w is the cubic
u(tau) = w tau - G0 tau^2 / 2 - G1 tau^3 / 6: its return time is the root of a quadratic and its return speed
follows (:func:`flight`). The term in u is at most |K| u <= K_max w^2 / (2 G_min), with
K_max = p^2 [(1 + a_v/g) C + (|a_h|/g) S]; a flight is taken in closed form only where that is at most the
kernel's relative tolerance ``rtol`` times G_min (the O(u^2) term is smaller still), where it ends inside the
ground piece, where G stays positive (the ground lifts neither corner), where the ground does not fall faster
than gravity, and where the pivot's friction demand at both ends of the flight stays at or below the block's
``stop_mu`` (the kernel checks it at the ends of its steps). Otherwise the kernel steps on from the last impact,
exactly as without this module.

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

from ..compiled import jit, jit_inline
from .codes import REST, STATUS_CHATTER
from .dopri import HISTORY_TIME_TOL_S, pivot_demand
from .rules import min_advance_compiled


class Flight(NamedTuple):
    """One flight of a cascade from theta = 0 back to theta = 0 on one pivot (a numba namedtuple)."""

    tau: float       # its duration [s]; -1 where no return is found
    w_return: float  # the speed it comes back with [rad s-1]
    u_peak: float    # its largest |theta| [rad]


NO_FLIGHT = Flight(tau=-1.0, w_return=0.0, u_peak=0.0)


class Ground(NamedTuple):
    """What one flight needs of the ground at an instant, on one pivot (a numba namedtuple)."""

    restoring: float  # G [rad s-2]
    bound: float      # K_max [s-2]
    demand: float     # the pivot's friction demand |f_x| / f_z there [-]
    holds: bool       # the block stays on the ground and on its pivot (f_z > 0, demand <= stop_mu, g + a_v > 0)


@jit
def flight(w, g0, g1):
    """The flight u(tau) = w tau - g0 tau^2 / 2 - g1 tau^3 / 6 from u = 0 at speed ``w`` > 0 under the
    deceleration g0 + g1 tau (``g0`` > 0): its return time, return speed and peak (:data:`NO_FLIGHT` where u
    does not come back)."""
    a, b = g1 / 6.0, 0.5 * g0                 # u / tau = w - b tau - a tau^2 = 0
    disc = b * b + 4.0 * a * w
    if disc < 0.0:
        return NO_FLIGHT
    den = b + math.sqrt(disc)
    if not den > 0.0:
        return NO_FLIGHT
    tau = 2.0 * w / den
    w_ret = 0.5 * g0 * tau + g1 * tau * tau / 3.0   # -u'(tau), with w = g0 tau / 2 + g1 tau^2 / 6
    if not (w_ret > 0.0 and tau > 0.0):
        return NO_FLIGHT
    # the peak where u'(tp) = w - g0 tp - g1 tp^2 / 2 = 0 (a root exists while the deceleration stays positive)
    dp = g0 * g0 + 2.0 * g1 * w
    tp = min(2.0 * w / (g0 + math.sqrt(dp)), tau) if dp >= 0.0 else 0.5 * tau
    u_pk = w * tp - 0.5 * g0 * tp * tp - g1 * tp * tp * tp / 6.0
    return Flight(tau=tau, w_return=w_ret, u_peak=max(u_pk, 0.0))


@jit_inline
def _ground(t, w, s, pc, block, p2, big_s, big_c):
    """The ground of the piece ``pc`` at time t for a flight on pivot s at speed w, at theta = 0."""
    a = pc.a0 + pc.sa * (t - pc.t0)
    v = pc.v0 + pc.sv * (t - pc.t0)
    g = block.g
    g_s = p2 * ((1.0 + v / g) * big_s + s * (a / g) * big_c)
    k_max = p2 * ((1.0 + v / g) * big_c + abs(a) / g * big_s)
    demand, lifted = pivot_demand(0.0, w, -s * g_s, s, block.alpha, block.R, a, v, g)
    holds = g + v > 0.0 and g_s > 0.0 and not lifted and not demand > block.stop_mu
    return Ground(restoring=g_s, bound=k_max, demand=demand, holds=holds)


@jit_inline
def chatter(dt, pc, block, control, rest_omega, p2, progress, theta_out, impacts):
    """Take the flights of a cascade in closed form from the impact the progress record has just taken
    (theta = 0, omega the rebound on the new pivot), while each holds (the module's conditions), to the rest
    rule or the event cap; the record is left at the last impact taken (at rest where the cascade ended), for
    the kernel to go on from. Fills the theta history and the impact log as the kernel does."""
    pr = progress[0]
    t, s, w = pr.t, pr.pivot, abs(pr.omega)
    big_s, big_c = (block.alpha, 1.0) if block.linear else (math.sin(block.alpha), math.cos(block.alpha))
    g1_unit = p2 * ((pc.sv / block.g) * big_s + (pc.sa / block.g) * big_c)   # G's rate on pivot +1 ...
    g1_side = p2 * (pc.sv / block.g) * big_s                                  # ... and its part common to both
    while True:
        start = _ground(t, w, s, pc, block, p2, big_s, big_c)
        if not (start.holds and start.bound * w * w <= 2.0 * control.rtol * start.restoring ** 2):
            return
        g1 = g1_side + s * (g1_unit - g1_side)
        fl = flight(w, start.restoring, g1)
        te = t + fl.tau
        if fl.tau < min_advance_compiled(t) or te > pc.t1:
            return
        end = _ground(te, fl.w_return, s, pc, block, p2, big_s, big_c)
        g_min = min(start.restoring, end.restoring)
        if not (end.holds and max(start.bound, end.bound) * w * w <= 2.0 * control.rtol * g_min * g_min):
            return
        pr.friction_max = max(pr.friction_max, start.demand, end.demand)
        pr.theta_max = max(pr.theta_max, fl.u_peak)
        while pr.out_k < theta_out.shape[0] and pr.out_k * dt <= te + HISTORY_TIME_TOL_S:
            x = max(pr.out_k * dt - t, 0.0)
            theta_out[pr.out_k] = s * max(w * x - 0.5 * start.restoring * x * x - g1 * x * x * x / 6.0, 0.0)
            pr.out_k += 1
        w_after = block.e * fl.w_return                 # Housner: omega ratio e at the impact
        if pr.n_impacts < impacts.shape[0]:
            impacts[pr.n_impacts, 0] = te
            impacts[pr.n_impacts, 1] = -s * fl.w_return
            impacts[pr.n_impacts, 2] = -s * w_after
        pr.n_impacts += 1
        pr.n_events += 1
        pr.t_event, pr.n_same = te, 0
        t, s, w = te, -s, w_after
        pr.t, pr.theta, pr.omega, pr.pivot = t, 0.0, s * w, s
        if w < rest_omega or pr.n_events >= control.max_events:
            if pr.n_events >= control.max_events:
                pr.status |= STATUS_CHATTER
            pr.omega, pr.mode = 0.0, REST
            return
