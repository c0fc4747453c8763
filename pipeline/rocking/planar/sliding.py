"""Coulomb stick-slip of a block on a moving base, integrated exactly per sample (compiled with numba when
installed, as :mod:`.kernel`).

References
----------
Shenton, H. W. & Jones, N. P. (1991). Base excitation of rigid bodies. I: Formulation. J. Eng. Mech. 117(10),
2286-2306 (the sliding mode and its Coulomb law).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...compiled import jit, jit_inline, jit_lean, state_factory
from ..numerics.ground import exceed_fraction, flight_fraction
from .kernel import TINY

#: Slip starts and stops located in one sample interval, at most (the slip velocity is quadratic in time there,
#: so a physical interval holds a handful; the cap ends the interval's search, counted in ``capped``)
MAX_STOPS_PER_SAMPLE = 64
#: A root of the slip velocity this close to the start of a slip [s] is the slip's own start, not its end
STOP_ROOT_TOL_S = 1e-15


class SlideOutcome(NamedTuple):
    """What :func:`slide` returns.

    Attributes
    ----------
    u_max_m, u_end_m : float
        Peak |u| and final u, the block's displacement relative to the ground [m].
    n_slips : int
        Slip episodes (a slip that reverses at once counts again).
    t_slip_s : float
        Time slipping [s].
    t_flight_s : float
        Time the ground's g + a_v reached 0 [s] (NaN: never; the integration stops there).
    capped_samples : int
        Samples whose search for slip starts and stops reached :data:`MAX_STOPS_PER_SAMPLE`.
    """

    u_max_m: float
    u_end_m: float
    n_slips: int
    t_slip_s: float
    t_flight_s: float
    capped_samples: int


#: The slip state carried from sample to sample, changed in place by :func:`_slide_sample`
SLIP = np.dtype([
    ("u", np.float64),           # displacement relative to the ground [m]
    ("v", np.float64),           # its rate [m s-1]
    ("slipping", np.bool_),
    ("d", np.float64),           # slip direction, sign(u') [-]
    ("u_max", np.float64),       # peak |u| [m]
    ("n_slips", np.int64),
    ("t_slip", np.float64),      # time slipping [s]
])
new_slip_state = state_factory(SLIP)


@jit
def slide(ah, av, dt, mu, g):
    """Coulomb stick-slip of a block on a moving base, integrated exactly per sample.

    Relative displacement u (block minus ground): while slipping in direction
    d = sign(u'), u'' = -a_h - d mu (g + a_v); sticking while
    |a_h| <= mu (g + a_v). The ground acceleration is linear between samples,
    so u' is quadratic and u cubic in time, and slip ends at the exact root of u'.

    Progress: every pass of the inner loop advances within the sample or counts against
    :data:`MAX_STOPS_PER_SAMPLE`; a sample that reaches the cap is counted in ``capped_samples`` and the slip
    state is carried to the next sample unchanged (never met on the bundled records).

    Returns
    -------
    SlideOutcome
    """
    return _slide(ah, av, dt, mu, g, new_slip_state())


@jit_lean
def _slide(ah, av, dt, mu, g, state):
    """:func:`slide`'s loop on the slip state it made."""
    n = ah.shape[0]
    has_v = av.shape[0] == n
    t_flight = math.nan
    capped = 0
    for k in range(n - 1):
        v0 = av[k] if has_v else 0.0
        v1 = av[k + 1] if has_v else 0.0
        if g + v0 <= 0.0 or g + v1 <= 0.0:
            # the ground falls faster than gravity: no normal force, no friction, and the Coulomb
            # model holds no further (the caller reports the scene as free flight)
            t_flight = (k + flight_fraction(v0, v1, g)) * dt
            break
        if not _slide_sample(ah[k], ah[k + 1], v0, v1, dt, mu, g, state):
            capped += 1
    st = state[0]
    return SlideOutcome(u_max_m=st.u_max, u_end_m=st.u, n_slips=st.n_slips, t_slip_s=st.t_slip, t_flight_s=t_flight,
                        capped_samples=capped)


@jit_inline
def _slide_sample(a0, a1, v0, v1, dt, mu, g, state):
    """One sample interval of stick-slip, the ground linear from (a0, v0) to (a1, v1) [m s-2]: slip starts
    where |a_h| exceeds mu (g + a_v) and stops at the root of u'. Returns False where the search met
    :data:`MAX_STOPS_PER_SAMPLE` (the state is carried on as it is)."""
    st = state[0]
    x = 0.0                                   # position in the sample, in [0, dt]
    guard = 0
    ka = (a1 - a0) / dt
    kv = (v1 - v0) / dt
    while x < dt:
        guard += 1
        if guard > MAX_STOPS_PER_SAMPLE:
            return False
        ax = a0 + ka * x
        vx = v0 + kv * x
        if not st.slipping:
            f = exceed_fraction(ax, a0 + ka * dt, vx, v1, g, mu)
            if f < 0.0:
                return True
            x = x + f * (dt - x)
            ax = a0 + ka * x
            if ax == 0.0:                     # no horizontal force: nothing to slip (g + a_v > 0 here)
                return True
            st.d = -1.0 if ax > 0.0 else 1.0  # friction opposes the relative motion, u'' = -a_h - d mu N
            st.slipping = True
            st.n_slips += 1
            st.v = 0.0
            continue
        # slipping: v(tau) = v + c0 tau + c1 tau^2 / 2, tau from x
        c0 = -ax - st.d * mu * (g + vx)
        c1 = -ka - st.d * mu * kv
        rem = dt - x
        tau = first_stop(st.v, c0, c1, rem, st.d)
        if tau < 0.0:
            st.u = st.u + st.v * rem + c0 * rem * rem / 2 + c1 * rem ** 3 / 6
            st.v = st.v + c0 * rem + c1 * rem * rem / 2
            st.t_slip += rem
            st.u_max = max(st.u_max, abs(st.u))
            return True
        st.u = st.u + st.v * tau + c0 * tau * tau / 2 + c1 * tau ** 3 / 6
        st.v = 0.0
        st.t_slip += tau
        st.u_max = max(st.u_max, abs(st.u))
        x = x + tau
        ax = a0 + ka * x
        vx = v0 + kv * x
        if abs(ax) > mu * (g + vx):
            st.d = -1.0 if ax > 0.0 else 1.0  # slips back the other way at once
            st.n_slips += 1
        else:
            st.slipping = False
    return True


@jit
def first_stop(v, c0, c1, rem, d):
    """First tau in [0, rem] where d * v(tau) falls to 0, v(tau) = v + c0 tau + c1 tau^2 / 2; -1 if none.

    d * v starts at 0 (a slip starting, ``v`` exactly 0) or above it (a slip under way, or, by a rounding, a
    few ulps either side of 0). A slip starting does not end within :data:`STOP_ROOT_TOL_S` of tau = 0: its
    start was located where the demand crosses the threshold, and a rounding there may make d * v fall for an
    instant. A slip under way ends at any root where d * v falls, however near: one that a rounding left
    running (d * v a few ulps from 0 while the demand no longer carries it) stops at once.
    """
    A = 0.5 * c1 * d
    B = c0 * d
    C = v * d
    under_way = C != 0.0
    if C < 0.0 and (B < 0.0 or B == 0.0 and A < 0.0):
        return 0.0                                        # a rounding past 0 already, and falling
    best = -1.0
    if abs(A) < TINY:
        if B < 0.0:
            r = -C / B
            if (r > STOP_ROOT_TOL_S or under_way and r >= 0.0) and r <= rem:
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
        if r >= 0.0 and r <= rem and (best < 0.0 or r < best):
            slope = 2 * A * r + B                        # a crossing downward (d * v falling) or a touch
            if r > STOP_ROOT_TOL_S and slope <= 0.0 or under_way and slope < 0.0:
                best = r
    return best
