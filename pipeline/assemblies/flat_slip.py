"""A stack whose joints stay shut while they slip: every block level, each joint sticking or sliding (a chain of
Coulomb sliders on a moving ground), its events located in closed form between the ground's samples (compiled).

Block k (k = 0 the bottom, mass m_k) moves along the ground only: u_k is its displacement in the ground's frame. Joint
j is block j's base on what it stands on (the ground for j = 0); F_j is the horizontal force across it on the part
above, N_j = (m_j + ... + m_{n-1}) (g + a_v) its normal force. Per block (d'Alembert, in the ground's frame)

    m_k (u_k'' + a_h) = F_k - F_{k+1},      F_n = 0,

and per joint Coulomb's law on its slip rate w_j = u_j' - u_{j-1}' (u_{-1} = 0):

    w_j = 0 and |F_j| <= mu_j N_j (stick),      or      F_j = -sgn(w_j) mu_j N_j (slip),

mu_j the friction at block j's base. The blocks between two slipping joints move as one. For a given set of
slipping joints the accelerations and the sticking joints' forces are linear in the ground's accelerations, so on
a linear piece of the ground each slip rate is a quadratic in time and each sticking force a line: a slip that
stops, or a sticking force that reaches mu_j N_j, is the root of a quadratic or of a line, located exactly. There
the joints' modes are chosen again, as the ones whose sticking forces stay inside their limits and whose new slips
move the way their friction opposes, just after the instant. The normal forces do not depend on the accelerations
and the mass matrix is positive definite, so these accelerations are the unique minimiser of a convex problem
(Moreau 1988): the chosen modes are the chain's motion, to the rounding allowances :data:`FORCE_TOL` and
:data:`ACC_TOL` on a limit.

The model holds while every joint stays shut: the resultant of the normal force at each joint, from the blocks
above it in their motion, lies inside the joint's support (the overlap of the block's base with what it stands on),
checked at every sample and event with a bound on its excursion in between, and while the ground does not fall
faster than gravity. Where either fails, where the modes cannot be chosen, or at a cap, the run stops unfinished
(:data:`UNFINISHED`) and the caller follows the episode from its start with the stack's contact model
(:mod:`.stack_contact`). A run ends :data:`STUCK` where every joint sticks, at least one instant after its start,
and the exact model (:mod:`.n_block_run`) goes on from rest with the blocks where they slid to.

References
----------
Moreau, J. J. (1988). Unilateral contact and dry friction in finite freedom dynamics. In Nonsmooth Mechanics and
Applications, CISM Courses and Lectures 302, 1-82. Springer.
Shenton, H. W. (1996). Criteria for initiation of slide, rock, and slide-rock rigid-body modes. Journal of
Engineering Mechanics 122(7), 690-693 (a level block stays level while its normal force's resultant is inside its
base).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..compiled import jit
from ..constants import G
from ..rocking.planar.sliding import first_stop
from .n_block import MAX_BODIES, NBlock
from .stepping import TAIL_S, ground_on, ground_series, piece_at

# Event control, named once
MAX_EVENTS = 100_000         # events (slips that stop or start) per run; the cap ends it unfinished [-]
MAX_AT_INSTANT = 16          # events at one instant without time advancing; beyond, the run ends unfinished [-]
FORCE_TOL = 1e-9             # a sticking force within this fraction of mu N of its limit is at the limit [-]
ACC_TOL = 1e-9               # a slip's acceleration within this fraction of g is none [-]
MODES = 3                    # a joint's modes: stick, slip towards +x, slip towards -x

#: How a run ended
STUCK = 0                    # every joint sticks: the exact model goes on
UNFINISHED = 1               # a joint would open, the ground falls faster than gravity, or a cap: not followed here


class FlatSlipOutcome(NamedTuple):
    """What :func:`simulate_flat_slip` returns.

    Attributes
    ----------
    end : int
        :data:`STUCK` or :data:`UNFINISHED`
    t_end_s : float
        where the run stopped [s]
    offsets_m : tuple of float
        each block's base centre from the centre of the top of the block under it there [m] (block 0: 0)
    base_shift_m : float
        block 0's slip along the ground over the run [m]
    peak_slide_m : tuple of float
        each joint's largest |slip| from where the run started, or from where it stood before the slips ``slid_m``
        given to the run [m]
    events : int
        slips that stopped or started
    """

    end: int
    t_end_s: float
    offsets_m: tuple
    base_shift_m: float
    peak_slide_m: tuple
    events: int


@jit
def _solve(nb, mu, mode, ah, gv, above, acc, force):
    """Each block's acceleration ``acc`` [m s-2] (ground frame) and each joint's force ``force`` [N] on the part
    above it, for the joints' ``mode`` (0 stick, +1 / -1 the slip's direction) under the ground's a_h and
    g + a_v ``gv`` [m s-2]; ``above``: the mass above each joint [kg]."""
    f_top = 0.0                                    # F_{hi + 1}: the force on the cluster from the block above it
    k = nb.n - 1
    while k >= 0:
        lo, mass = k, nb.m[k]
        while lo > 0 and mode[lo] == 0:            # a sticking joint joins its block to the one below
            lo -= 1
            mass += nb.m[lo]
        if mode[lo] == 0:                          # down to a sticking ground: the cluster does not move
            a = 0.0
        else:
            a = (-mode[lo] * mu[lo] * gv * above[lo] - f_top) / mass - ah
        f = f_top
        for j in range(k, lo - 1, -1):
            acc[j] = a
            f += nb.m[j] * (a + ah)
            force[j] = f
        if mode[lo] != 0:
            force[lo] = -mode[lo] * mu[lo] * gv * above[lo]
        f_top = force[lo]
        k = lo - 1


@jit
def _rate(acc, j):
    """Joint j's slip acceleration [m s-2]."""
    return acc[j] - (acc[j - 1] if j > 0 else 0.0)


@jit
def _limits(nb, mu, gv0, gv1, above, j):
    """Joint j's friction limits mu N at the instant and at the piece's end [N], and the rounding allowance on
    them."""
    cap0, cap1 = mu[j] * gv0 * above[j], mu[j] * gv1 * above[j]
    return cap0, cap1, FORCE_TOL * max(cap0, cap1, nb.m[j] * G)


@jit
def _holds(nb, mu, mode, free, gv0, gv1, above, acc0, force0, acc1, force1):
    """Whether ``mode`` is the chain's just after the instant of ``acc0``, ``force0`` (the same mode's values at the
    piece's end: ``acc1``, ``force1``, linear in between): each sticking joint's force inside its limit (or on it
    and turning inwards), each joint that starts to slip (``free``: its slip rate is 0) accelerating its own way."""
    for j in range(nb.n):
        if mode[j] == 0:
            cap0, cap1, tol = _limits(nb, mu, gv0, gv1, above, j)
            g0 = abs(force0[j]) - cap0
            if g0 > tol:
                return False
            if g0 >= -tol:                          # on its limit: it must not be leaving the cone
                s = 1.0 if force0[j] > 0.0 else -1.0
                if s * force1[j] - cap1 > tol:
                    return False
        elif free[j]:
            r0, r1 = mode[j] * _rate(acc0, j), mode[j] * _rate(acc1, j)
            tol = ACC_TOL * G
            if not (r0 > tol or (r0 >= -tol and r1 > tol)):
                return False
    return True


@jit
def _choose(nb, mu, w, mode, gv0, gv1, ah0, ah1, above, acc0, force0, acc1, force1):
    """The joints' modes at an instant (slip rates ``w``; a joint that slips keeps its direction), into ``mode``
    with their accelerations and forces at the instant and the piece's end; False where none holds."""
    n = nb.n
    free = np.zeros(MAX_BODIES, dtype=np.bool_)
    count = 0
    for j in range(n):
        free[j] = w[j] == 0.0
        if free[j]:
            count += 1
        else:
            mode[j] = 1 if w[j] > 0.0 else -1
    combos = MODES ** count
    for slipping in range(count + 1):              # fewest new slips first
        for code in range(combos):
            c, used = code, 0
            for j in range(n):
                if free[j]:
                    digit = c % MODES
                    c //= MODES
                    mode[j] = 0 if digit == 0 else (1 if digit == 1 else -1)
                    if digit != 0:
                        used += 1
            if used != slipping:
                continue
            _solve(nb, mu, mode, ah0, gv0, above, acc0, force0)
            _solve(nb, mu, mode, ah1, gv1, above, acc1, force1)
            if _holds(nb, mu, mode, free, gv0, gv1, above, acc0, force0, acc1, force1):
                return True
    return False


@jit
def _first_zero(w0, d0, d1, span, s):
    """The first tau in (0, span] where the slip rate w0 + d0 tau + (d1 - d0) tau^2 / (2 span), of sign s at 0 (or 0
    and starting in that direction), reaches 0; math.inf where it does not. A slip under way ends where Coulomb
    sliding's does (:func:`~pipeline.rocking.planar.sliding.first_stop`); one that starts here, by the modes'
    rule (:data:`ACC_TOL`)."""
    qa, qb, qc = s * (d1 - d0) / (2.0 * span), s * d0, s * w0       # s w(tau) = qa tau^2 + qb tau + qc
    if qc < 0.0:
        return 0.0
    if qc == 0.0:                                   # a slip that starts here: its rate grows from 0 its own way
        if qb < -ACC_TOL * G:
            return 0.0
        qb = max(qb, 0.0)                           # its acceleration 0 to rounding, growing (the modes' rule)
        if qb == 0.0 and qa <= 0.0:
            return 0.0
        return -qb / qa if qa < 0.0 and -qb / qa <= span else math.inf
    r = first_stop(w0, d0, (d1 - d0) / span, span, s)      # a slip under way: where its rate first falls to 0
    return r if r >= 0.0 else math.inf


@jit
def _first_limit(f0, f1, cap0, cap1, span, tol):
    """The first tau in [0, span] where the line F (f0 to f1) reaches +-cap (cap0 to cap1), and passes it by more
    than ``tol`` [N] at the piece's end; math.inf where not."""
    best = math.inf
    for s in (1.0, -1.0):
        g0, g1 = s * f0 - cap0, s * f1 - cap1
        if g1 > tol and g1 > g0:
            best = min(best, span * max(-g0, 0.0) / (g1 - g0))
    return best


@jit
def _support(nb, x, j):
    """Joint j's support along the ground, (lo, hi) [m]: block j's base over what it stands on."""
    lo, hi = x[j] - nb.b[j], x[j] + nb.b[j]
    if j > 0:
        lo, hi = max(lo, x[j - 1] - nb.b[j - 1]), min(hi, x[j - 1] + nb.b[j - 1])
    return lo, hi


@jit
def _margin(nb, x, acc, ah, gv, above, base):
    """The least, over the joints and their two ends, of N (distance of the normal force's resultant inside the
    support) [N m]: the blocks above the joint in their motion (accelerations ``acc``) under the ground (a_h,
    g + a_v = ``gv``); ``base``: each block's base height [m]."""
    worst = math.inf
    for j in range(nb.n):
        moment = 0.0                                # N_j e_j: the resultant's moment about x = 0 at the joint
        for k in range(j, nb.n):
            moment += nb.m[k] * (gv * x[k] - (acc[k] + ah) * (base[k] + nb.h[k] - base[j]))
        lo, hi = _support(nb, x, j)
        normal = gv * above[j]
        worst = min(worst, moment - normal * lo, normal * hi - moment)
    return worst


@jit
def _excursion(nb, v, acc0, acc1, gv0, gv1, sv, tau, total):
    """A bound on how far :func:`_margin` strays from its chord over a step of ``tau`` [s]: its terms are linear in
    time but for g + a_v times a position, whose second derivative is at most 2 |a_v'| |u'| + (g + a_v) |u''|;
    ``total``: the stack's mass [kg]."""
    curv = 0.0
    gmax = max(gv0, gv1)
    for k in range(nb.n):
        amax = max(abs(acc0[k]), abs(acc1[k]))
        curv = max(curv, 2.0 * abs(sv) * (abs(v[k]) + amax * tau) + gmax * amax)
    return 2.0 * total * curv * tau * tau / 8.0      # the resultant's moment and the support's, each at most this


@jit
def _run(nb, mu, ah, av, dt, t0, slid):
    """The chain from rest at ``t0`` [s] (the module's rules), each joint having slipped ``slid`` [m] before: (end,
    t, slips, peaks, events)."""
    n = nb.n
    t_rec = (ah.shape[0] - 1) * dt
    tail_end = t_rec + TAIL_S
    above, base = np.zeros(MAX_BODIES), np.zeros(MAX_BODIES)
    for j in range(n - 1, -1, -1):
        above[j] = nb.m[j] + (above[j + 1] if j + 1 < n else 0.0)
    for j in range(1, n):
        base[j] = base[j - 1] + 2.0 * nb.h[j - 1]
    x0 = np.zeros(MAX_BODIES)                       # each base centre at the start, ground frame
    for j in range(1, n):
        x0[j] = x0[j - 1] + nb.off[j]
    slip, w, peak = np.zeros(MAX_BODIES), np.zeros(MAX_BODIES), np.abs(slid)
    x, v = x0.copy(), np.zeros(MAX_BODIES)
    mode = np.zeros(MAX_BODIES, dtype=np.int64)
    acc0, force0, acc1, force1 = np.zeros(MAX_BODIES), np.zeros(MAX_BODIES), np.zeros(MAX_BODIES), np.zeros(MAX_BODIES)
    acc_e = np.zeros(MAX_BODIES)
    t, events, same, choose = t0, 0, 0, True
    while t < tail_end and events < MAX_EVENTS and same <= MAX_AT_INSTANT:
        piece = piece_at(ah, av, dt, t, t_rec, tail_end)
        t1 = piece.t0 + piece.span
        span = t1 - t
        if not span > 0.0:
            return UNFINISHED, t, slip, peak, events
        ah0, av0 = ground_on(piece, t)
        ah1, av1 = ground_on(piece, t1)
        gv0, gv1 = G + av0, G + av1
        if not (gv0 > 0.0 and gv1 > 0.0):
            return UNFINISHED, t, slip, peak, events        # the ground falls faster than gravity: flight
        if choose:
            if not _choose(nb, mu, w, mode, gv0, gv1, ah0, ah1, above, acc0, force0, acc1, force1):
                return UNFINISHED, t, slip, peak, events
            moving = False
            for j in range(n):
                moving = moving or mode[j] != 0
            if not moving:
                return (STUCK if t > t0 else UNFINISHED), t, slip, peak, events
            choose = False
        else:
            _solve(nb, mu, mode, ah0, gv0, above, acc0, force0)
            _solve(nb, mu, mode, ah1, gv1, above, acc1, force1)
        margin0 = _margin(nb, x, acc0, ah0, gv0, above, base)
        tau, which = span, -1                        # the step, and the joint whose event ends it (-1: none)
        for j in range(n):
            if mode[j] != 0:
                r = _first_zero(w[j], _rate(acc0, j), _rate(acc1, j), span, float(mode[j]))
            else:
                cap0, cap1, tol = _limits(nb, mu, gv0, gv1, above, j)
                r = _first_limit(force0[j], force1[j], cap0, cap1, span, tol)
            if r <= tau:
                tau, which = r, j
        frac = tau / span
        for k in range(n):
            acc_e[k] = acc0[k] + (acc1[k] - acc0[k]) * frac
        bound = _excursion(nb, v, acc0, acc_e, gv0, gv0 + (gv1 - gv0) * frac, (av1 - av0) / span, tau,
                           above[0])
        vel = 0.0
        for j in range(n):
            if mode[j] != 0:
                d0, d1 = _rate(acc0, j), _rate(acc1, j)
                slip[j] += w[j] * tau + 0.5 * d0 * tau * tau + (d1 - d0) * tau * tau * tau / (6.0 * span)
                w[j] += d0 * tau + 0.5 * (d1 - d0) * tau * tau / span
                if j == which or mode[j] * w[j] <= 0.0:
                    w[j] = 0.0                      # the slip stopped here
            peak[j] = max(peak[j], abs(slid[j] + slip[j]))
            vel += w[j]
            v[j] = vel
            x[j] = x0[j] + slip[j] + (x[j - 1] - x0[j - 1] if j > 0 else 0.0)
        ah_e, gv_e = ah0 + (ah1 - ah0) * frac, gv0 + (gv1 - gv0) * frac
        if not min(margin0, _margin(nb, x, acc_e, ah_e, gv_e, above, base)) > bound:
            return UNFINISHED, t, slip, peak, events        # a joint may open: the contact model follows it
        t_next = t + tau if frac < 1.0 else t1
        same = same + 1 if t_next <= t else 0
        t = t_next
        if which >= 0:
            events += 1
            choose = True
    return UNFINISHED, t, slip, peak, events


def simulate_flat_slip(nb: NBlock, mu, ah_ms2: np.ndarray, dt_s: float, *, av_ms2: np.ndarray | None = None,
                       t0_s: float = 0.0, slid_m: tuple | None = None) -> FlatSlipOutcome:
    """The stack ``nb`` (friction ``mu`` [-] at each block's base), at rest at ``t0_s`` [s], under the ground
    ``ah_ms2``, ``av_ms2`` [m s-2] (samples ``dt_s`` [s] apart), by the module's model, to where every joint sticks
    again or the model stops holding; ``slid_m``: each joint's slip before the run [m] (block 0's along the ground),
    from which its largest slip is measured (None: 0).

    Raises
    ------
    ParameterError
        a series not finite, the vertical's length not the horizontal's, or ``dt_s`` not positive
    """
    ah, av = ground_series(ah_ms2, av_ms2, dt_s)
    mus = tuple(float(m) for m in mu[:nb.n]) + (0.0,) * (MAX_BODIES - nb.n)
    slid = np.zeros(MAX_BODIES)
    if slid_m is not None:
        slid[:nb.n] = [float(x) for x in slid_m[:nb.n]]
    end, t, slip, peak, events = _run(nb, mus, ah, av, float(dt_s), float(t0_s), slid)
    offsets = (0.0,) + tuple(float(nb.off[k] + slip[k]) for k in range(1, nb.n)) + (0.0,) * (MAX_BODIES - nb.n)
    return FlatSlipOutcome(int(end), float(t), offsets, float(slip[0]), tuple(float(p) for p in peak), int(events))
