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
from typing import NamedTuple

import numpy as np
from scipy.integrate import solve_ivp

from ...constants import G

#: Rounding allowance when t / dt falls on a sample [-] (the reference keeps its own: it shares no code with the
#: kernels it checks)
SAMPLE_INDEX_TOL = 1e-9


class ReferenceOutcome(NamedTuple):
    """What :func:`rock_reference` returns.

    Attributes
    ----------
    overturned : bool
    theta_max_ratio : float
        Largest |theta| / alpha [-] (pi / 2 / alpha once overturned), as :class:`~.simulate.RockResult`.
    n_impacts : int
        Impacts, with the one on the way when the free motion after the record overturns after it.
    """

    overturned: bool
    theta_max_ratio: float
    n_impacts: int


class _Ground:
    """The ground motion linear between samples (0 after the record) and the block's equation of motion."""

    def __init__(self, ah, av, dt, *, p, alpha, g, linear):
        self.ah, self.av, self.dt = ah, av, dt
        self.times = np.arange(ah.size) * dt
        self.p2, self.alpha, self.g, self.linear = p * p, alpha, g, linear
        self.thr = alpha if linear else math.tan(alpha)
        self.excess = np.abs(ah) - (g + av) * self.thr          # > 0 where a sample lifts the block

    def horizontal(self, t):
        return float(np.interp(t, self.times, self.ah, right=0.0))

    def vertical(self, t):
        return float(np.interp(t, self.times, self.av, right=0.0))

    def rhs(self, t, y, s):
        """Housner's equation on pivot side s, gravity g + a_v (Yim et al. 1980); linearised when asked."""
        phi = self.alpha * s - y[0]
        a = self.horizontal(t)
        gv = 1.0 + self.vertical(t) / self.g
        if self.linear:
            return [y[1], -self.p2 * (gv * phi + a / self.g)]
        return [y[1], -self.p2 * (gv * math.sin(phi) + a / self.g * math.cos(phi))]

    def next_uplift(self, t):
        """The first instant from t where |a_h| exceeds (g + a_v) thr, linear between samples; None if never."""
        if abs(self.horizontal(t)) > (self.g + self.vertical(t)) * self.thr:
            return t
        k0 = int(math.floor(t / self.dt + SAMPLE_INDEX_TOL)) + 1
        idx = np.flatnonzero(self.excess[k0:] > 0)
        if idx.size == 0:
            return None
        k = k0 + int(idx[0])
        ah, av, g, thr = self.ah, self.av, self.g, self.thr
        sig = 1.0 if ah[k] > 0 else -1.0
        f0 = sig * ah[k - 1] - (g + av[k - 1]) * thr
        f1 = sig * ah[k] - (g + av[k]) * thr
        return max((k - 1) * self.dt + (-f0 / (f1 - f0)) * self.dt, t)


def segment_events(s):
    """solve_ivp's terminal events of a rocking segment on pivot side s: the impact (theta back to 0, the
    direction chosen by s so that the root at the segment's start is not seen again) and overturning
    (|theta| = pi/2); and the turning points (omega = 0), recorded only."""
    def impact(tt, yy, _s):
        return yy[0]
    impact.terminal = True                       # type: ignore[attr-defined]  # solve_ivp's event protocol
    impact.direction = -1.0 if s > 0 else 1.0    # type: ignore[attr-defined]

    def fall(tt, yy, _s):
        return abs(yy[0]) - math.pi / 2
    fall.terminal = True                         # type: ignore[attr-defined]
    fall.direction = 1.0                         # type: ignore[attr-defined]

    def turn(tt, yy, _s):
        return yy[1]
    return impact, fall, turn


def _free_motion(th, om, *, p2, alpha, e, linear):
    """The fate of free rocking from (theta, omega) after the record, by its energy (Housner 1963): (overturns,
    peak |theta| [rad], impacts before it overturns: 0 or 1)."""
    if linear:
        E, top, piv = 0.5 * om * om - 0.5 * p2 * (abs(th) - alpha) ** 2, 0.0, -0.5 * p2 * alpha ** 2
    else:
        E, top, piv = 0.5 * om * om + p2 * math.cos(alpha - abs(th)), p2, p2 * math.cos(alpha)
    outward = th * om > 0
    if abs(th) >= alpha and (outward or E <= top):
        return True, math.pi / 2, 0
    n_tail = 0
    if not outward:
        E = piv + e * e * (E - piv)
        n_tail = 1
    if E >= top:
        return True, math.pi / 2, n_tail
    return False, alpha - (math.sqrt(max(-2 * E / p2, 0.0)) if linear else math.acos(min(E / p2, 1.0))), 0


def rock_reference(ah, dt, *, p, alpha, e, g=G, rtol=1e-8, atol=1e-10, rest_ratio=1e-6, linear=False,
                   av=None) -> ReferenceOutcome:
    """Rocking of a block under a sampled ground motion (horizontal, and optionally vertical).

    With ``av`` (vertical acceleration, up positive [m s-2]) gravity becomes g + a_v(t) in the
    equation of motion and in the uplift threshold (Yim et al. 1980). A record that reaches
    g + a_v <= 0 is refused: the contact model does not hold there.
    """
    ah = np.asarray(ah, dtype=float)
    av = np.zeros(ah.size) if av is None else np.asarray(av, dtype=float)
    if np.any(g + av <= 0.0):
        raise ValueError("g + a_v <= 0 somewhere: free flight, outside the rocking model")
    ground = _Ground(ah, av, dt, p=p, alpha=alpha, g=g, linear=linear)
    t_rec = (ah.size - 1) * dt
    t, theta_max, n_imp = 0.0, 0.0, 0
    while t < t_rec:
        t_up = ground.next_uplift(t)
        if t_up is None:
            break
        s = -1.0 if ground.horizontal(t_up) > 0 else 1.0
        y, t = np.array([0.0, 0.0]), t_up
        while True:                                  # rocking segments between impacts, until rest
            sol = solve_ivp(ground.rhs, (t, t_rec), y, method="DOP853", rtol=rtol, atol=atol * alpha,
                            events=segment_events(s), max_step=dt, args=(s,))
            theta_max = max(theta_max, float(np.max(np.abs(sol.y[0]))))
            if sol.t_events[2].size:
                theta_max = max(theta_max, float(np.max(np.abs(sol.y_events[2][:, 0]))))
            if sol.t_events[1].size:
                return ReferenceOutcome(True, math.pi / 2 / alpha, n_imp)
            if not sol.t_events[0].size:             # the record is over while rocking: the free motion's energy
                over, peak, n_tail = _free_motion(float(sol.y[0, -1]), float(sol.y[1, -1]), p2=p * p, alpha=alpha,
                                                  e=e, linear=linear)
                return ReferenceOutcome(over, max(theta_max, peak) / alpha, n_imp + n_tail)
            t, om = float(sol.t_events[0][0]), float(sol.y_events[0][0][1]) * e
            n_imp += 1
            s = -s
            if abs(om) < rest_ratio * p * alpha:
                break
            y = np.array([0.0, om])
    return ReferenceOutcome(False, theta_max / alpha, n_imp)
