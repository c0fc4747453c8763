"""Planar rocking of a body whose two sides differ: a scanned rock or statue with pivots at different distances
from its centre of mass (:mod:`pipeline.shapes.scan` gives them). An event-driven reference solver on scipy's
``solve_ivp``, as :mod:`.reference` is for the rectangle: not compiled, not yet in the screening (the compiled
model, its tie rules, the contact model's hand-off and the sampled kernels are the next step).

**Equation of motion** on side ``s`` (+1: turning about the pivot toward +x, theta > 0; -1: about the other),
per unit mass, with ``R_s`` the pivot-to-G distance, ``alpha_s`` the angle of G above it, ``I_s = I_G + R_s^2``
and ``p_s^2 = g R_s / I_s`` (Housner 1963; with the vertical, Yim, Chopra & Penzien 1980)::

    theta'' = -p_s^2 [(1 + a_v / g) sin(s alpha_s - theta) + (a_x / g) cos(s alpha_s - theta)]

A rectangle (``alpha_+ = alpha_-``, ``R_+ = R_-``) is Housner's block. **Uplift** from rest toward side s where
``-s a_x > (g + a_v) tan(alpha_s)``. **Impact** at theta = 0, the pivot changing from side s to -s: the
angular momentum about the new pivot is conserved (Housner's argument, about unequal pivots): with ``b_s`` the
pivots' horizontal distances from G and ``z_G`` its height,

    omega+ = omega- (I_G + z_G^2 - b_s b_-s) / (I_G + z_G^2 + b_-s^2)

which is Housner's ``1 - 3/2 sin^2(alpha)`` for a rectangle, and never gains energy ((A - b_1 b_2)^2 <= (A + b_1^2)
(A + b_2^2)). A declared restitution scales it (``restitution_factor``). A rebound slower than ``rest_ratio`` x
p alpha rests. After the record the free motion is followed until the kinetic energy at an impact is below the
lower of the two sides' barriers ``g (R_s - z_G)`` (it cannot overturn then: impacts never add energy) or it
overturns (``|theta| = pi/2``). Sliding and lift-off of the base are not checked (pure rocking).

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. BSSA 53(2), 403-417.
Yim, C.-S., Chopra, A. K. & Penzien, J. (1980). Rocking response of rigid blocks to earthquakes. Earthquake
Engineering & Structural Dynamics 8(6), 565-587.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy.integrate import solve_ivp

from ...constants import G
from ..scanned.two_sided_body import TwoSided
from .reference import segment_events

#: Impacts after the record before the free motion is given up, flagged
MAX_TAIL_IMPACTS = 10000


class AsymmetricOutcome(NamedTuple):
    """What :func:`rock_two_sided` returns.

    Attributes
    ----------
    overturned : bool
    t_overturn_s : float
        NaN when it stands.
    theta_max_plus, theta_max_minus : float
        Largest tilt toward each side [rad].
    n_impacts : int
    undecided : bool
        The free motion after the record was still going after :data:`MAX_TAIL_IMPACTS` impacts (no verdict).
    """

    overturned: bool
    t_overturn_s: float
    theta_max_plus: float
    theta_max_minus: float
    n_impacts: int
    undecided: bool


def _next_uplift(t, lifts, ah, av, tan_a, dt_s, g_ms2):
    """(the first instant from ``t`` at which the ground lifts the body, the side it tilts toward), or None: the
    crossing located between the samples, where the ground is linear."""
    k0 = int(math.floor(t / dt_s + 1e-9))
    idx = np.flatnonzero(lifts[k0:])
    if idx.size == 0:
        return None
    k = k0 + int(idx[0])
    s = 1.0 if ah[k] < 0 else -1.0
    t_up = max(k * dt_s, t)
    if k > 0 and k * dt_s > t:
        f0 = -s * ah[k - 1] - (g_ms2 + av[k - 1]) * tan_a[s]
        f1 = -s * ah[k] - (g_ms2 + av[k]) * tan_a[s]
        if f0 <= 0.0 < f1:
            t_up = max((k - 1 + (-f0 / (f1 - f0))) * dt_s, t)
    return t_up, s


def _swing_peak(omega, side, com_height_m, g_ms2):
    """The peak tilt of a free swing from the flat position at ``omega`` on a side (alpha, R, I) [rad]: where the
    kinetic energy has raised G by I omega^2 / (2 g)."""
    alpha, r, inertia = side
    c = (0.5 * inertia * omega * omega + g_ms2 * com_height_m) / (g_ms2 * r)
    return alpha - math.acos(min(1.0, c))


def rock_two_sided(ah, dt_s: float, body: TwoSided, *, av=None, g_ms2: float = G, restitution_factor: float = 1.0,
                   rtol: float = 1e-8, atol_alpha: float = 1e-10, rest_ratio: float = 1e-6,
                   tail_s: float = 600.0) -> AsymmetricOutcome:
    """Rock a two-sided body under a sampled ground motion (see the module).

    Parameters
    ----------
    ah : array_like
        Horizontal ground acceleration along +x [m s-2] at t = k dt.
    dt_s : float
        Sampling interval [s].
    body : TwoSided
    av : array_like, optional
        Vertical ground acceleration, up positive [m s-2].
    restitution_factor : float
        Scales the impact ratio [-].
    tail_s : float
        Longest free motion followed after the record [s] (then undecided).
    """
    ah = np.asarray(ah, dtype=float)
    av = np.zeros(ah.size) if av is None else np.asarray(av, dtype=float)
    if np.any(g_ms2 + av <= 0.0):
        raise ValueError("g + a_v <= 0 somewhere: free flight, outside the rocking model")
    times = np.arange(ah.size) * dt_s
    t_rec = float(times[-1])
    geo = {s: body.side(s) for s in (1.0, -1.0)}
    tan_a = {s: math.tan(geo[s][0]) for s in (1.0, -1.0)}
    alpha_min = min(geo[1.0][0], geo[-1.0][0])
    # where a sample lifts the body toward each side
    lifts = (-ah > (g_ms2 + av) * tan_a[1.0]) | (ah > (g_ms2 + av) * tan_a[-1.0])

    def rhs(t, y, s):
        alpha, _r, inertia = geo[s]
        p2 = g_ms2 * _r / inertia
        phi = s * alpha - y[0]
        a = float(np.interp(t, times, ah, right=0.0))
        gv = 1.0 + float(np.interp(t, times, av, right=0.0)) / g_ms2
        return [y[1], -p2 * (gv * math.sin(phi) + a / g_ms2 * math.cos(phi))]

    peak = {1.0: 0.0, -1.0: 0.0}
    t, n_imp = 0.0, 0
    barrier = min(g_ms2 * (geo[s][1] - body.com_height_m) for s in (1.0, -1.0))
    while t < t_rec:
        up = _next_uplift(t, lifts, ah, av, tan_a, dt_s, g_ms2)
        if up is None:
            break
        t, s = up
        y = np.array([0.0, 0.0])
        tail_impacts = 0
        while True:
            alpha, r, inertia = geo[s]
            p = math.sqrt(g_ms2 * r / inertia)
            sol = solve_ivp(rhs, (t, t_rec + tail_s), y, method="DOP853", rtol=rtol, atol=atol_alpha * alpha_min,
                            events=segment_events(s), max_step=dt_s, args=(s,))
            seg = np.concatenate([sol.y[0], sol.y_events[2][:, 0]]) if sol.t_events[2].size else sol.y[0]
            peak[1.0] = max(peak[1.0], float(np.max(seg)))
            peak[-1.0] = max(peak[-1.0], float(np.max(-seg)))
            if sol.t_events[1].size:
                return AsymmetricOutcome(True, float(sol.t_events[1][0]), peak[1.0], peak[-1.0], n_imp, False)
            if not sol.t_events[0].size:
                return AsymmetricOutcome(False, math.nan, peak[1.0], peak[-1.0], n_imp, True)
            t = float(sol.t_events[0][0])
            om = float(sol.y_events[0][0][1]) * body.impact_ratio(s) * restitution_factor
            n_imp += 1
            s = -s
            if abs(om) < rest_ratio * p * alpha:
                t = max(t, (math.floor(t / dt_s) + 1) * dt_s) if t < t_rec else t
                break
            if t >= t_rec:
                if 0.5 * geo[s][2] * om * om < barrier:          # cannot overturn any more: the last swing's peak
                    peak[s] = max(peak[s], _swing_peak(om, geo[s], body.com_height_m, g_ms2))
                    return AsymmetricOutcome(False, math.nan, peak[1.0], peak[-1.0], n_imp, False)
                tail_impacts += 1
                if tail_impacts > MAX_TAIL_IMPACTS:
                    return AsymmetricOutcome(False, math.nan, peak[1.0], peak[-1.0], n_imp, True)
            y = np.array([0.0, om])
    return AsymmetricOutcome(False, math.nan, peak[1.0], peak[-1.0], n_imp, False)
