"""A stack of rigid blocks in a vertical plane with every contact mode at each interface and on the ground: stick,
slide, rock, lift-off, free flight and landing, by Moreau-Jean time stepping (compiled).

Each block k (k = 0 the bottom) has its centre (x_k, z_k) in the ground's frame, its rotation phi_k (clockwise
positive: a positive rotation tips it towards +x, as in :mod:`.n_block`) and their rates v = (u, w, omega). Over a
step of length h the velocities jump by the contacts' impulses P (Moreau 1988; Jean 1999):

    q_m = q + h/2 v-,      M (v+ - v-) = h f(t_m) + H(q_m)^T P,      q+ = q_m + h/2 v+,

f = -m (a_h, g + a_v, 0) the gravity and the ground's inertial force at the step's middle t_m, M = diag(m, m, I) per
block. A contact is a corner of a block at or below a face it may touch at q_m: block 0's base corners against the
ground; at each joint the upper block's base corners against the lower's top face, and the lower's top corners
against the upper's base (a corner that meets a corner of the other block counted once). Each contact's normal and
tangential relative velocities after the step U = H v+ obey the plastic impact law and Coulomb's friction

    0 <= P_n  _|_  U_n >= 0,      |P_t| <= mu P_n,  U_t = 0 where |P_t| < mu P_n,  else P_t U_t < 0,

mu the friction of the upper face of the contact (the block's own ``mu`` at its base). The impulses are found first
by the contacts' modes (:mod:`.stack_direct`: the modes of the step before, one linear solve, kept only where every
contact's law holds to :data:`SWEEP_TOL_MS`), else by projected Gauss-Seidel over the contacts, each contact's 2 x 2
problem solved by its cases (no contact, stick, or slide either way), started from the impulses of the step before,
to a change of at most :data:`SWEEP_TOL_MS`; a step whose sweeps reach :data:`MAX_SWEEPS` keeps
its last iterate, is counted (:attr:`StackContactOutcome.unconverged`) and flags the run step_cap (its verdict is
kept, the scene flagged: ``simulation_guard``). For one block a plastic impact at a new
sticking corner is, in the limit of short steps, Housner's (1963) (the angular momentum about the new corner kept,
the old one lifting); the tests compare one block's runs with the exact model's, which uses Housner's impact.

A block **falls** where its rotation, or its rotation on the block under it, reaches pi / 2 (:mod:`.n_block`'s
rule), or where its centre has dropped below the top of the block it stood on (it left its support); the blocks
above it fall with it, and the blocks below go on. **Handing back**: once every joint (the ground's included) is,
for :data:`HANDBACK_STEPS` steps in a row, sticking (the friction of its pressed ends together at most
:data:`STICKING` of mu times their P_n together: how the two ends of a shut face share a friction force is not
determined, and the sweeps may leave them opposed) and either shut (both ends of its face pressed, its rotation
below :data:`REST_TILT_RAD` and its rate times the block's half-diagonal below :data:`REST_SPEED`) or turning on
one corner alone, the rotation towards it, on
a ground not falling faster than gravity nor asking a resting stack for more friction than its least, the run stops
(``rested``), so that the exact model (:mod:`.n_block_run`) goes on from that state with the blocks' offsets where
they slid to (:func:`shifted`); a shut joint's rotation is dropped (a velocity-level step stops a landing corner
from sinking further, not from having sunk within its step). With ``rock_slide``, the stack is also handed back
where, for :data:`HANDBACK_STEPS` steps in a row, it turns as one on a sticking corner of block 0, every joint shut
and one of them slipping: the slide-rock model (:mod:`.slide_rock`) goes on from that state. After the record the ground
is still, and the motion is followed for at most :data:`~.stepping.TAIL_S`.

**Long steps** (an option, off by default: ``long_step_s`` of :func:`simulate_stack_contact`). During the record,
where no corner clear of a face could reach it within :data:`IMPACT_SAFETY` long steps at its speed towards it
(:func:`_clear_ahead`) and the hand-back's count of steps is not running, ``m`` of the steps are taken as one
Moreau-Jean step of m h (the ground at its middle, linear between samples, as for every step): ``m`` the largest
divisor of the steps a sampling interval is taken in with m h <= ``long_step_s``, a long step starting only at a
multiple of ``m`` in the interval, so that it never straddles a sample; the 3D contact model's rule
(:mod:`pipeline.rocking.solids.long_steps`, its :data:`~pipeline.rocking.solids.long_steps.IMPACT_SAFETY` and its
divisor). They are not the default: on the 168 slipping-stack scenes of ``benchmarks/stack_steps.py`` every step short
gives the verdicts of every step a quarter as long, and long steps of 0.5-1.25 ms turn one or two of them
(docs/validation.md).

References
----------
Moreau, J. J. (1988). Unilateral contact and dry friction in finite freedom dynamics. In Nonsmooth Mechanics and
Applications, CISM Courses and Lectures 302, 1-82. Springer.
Jean, M. (1999). The non-smooth contact dynamics method. Computer Methods in Applied Mechanics and Engineering
177(3-4), 235-257.
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. Bulletin of the
Seismological Society of America 53(2), 403-417.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..compiled import jit_lean
from ..constants import G
from ..errors import ParameterError
from ..rocking.codes import STATUS_GROUND_FLIGHT, STATUS_STEP_CAP, STATUS_TAIL_CAP
from ..rocking.solids.long_steps import IMPACT_SAFETY, steps_merged
from .n_block import MAX_BODIES, NBlock
from .stack_direct import DirectWork, direct_work, solve_direct
from .stack_pose import (
    SlideRockState,
    base_offset,
    bodies_of,
    corner_point,
    handback,
    point_at,
    point_in,
    rotations,
    slide_rock_state,
    state_of,
    tilt,
)
from .stepping import HALF_PI, TAIL_S, ground_on, piece_at

# Step control, named once
MAX_STEP_S = 2.5e-4          # the longest step [s]: the record's interval in the fewest equal parts of at most this
MAX_SWEEPS = 400             # Gauss-Seidel sweeps per step [-]
SWEEP_TOL_MS = 1e-9          # a sweep that changes no contact's velocity by more than this ends them [m s-1]
REST_SPEED = 1e-5            # a shut joint's rate times the block's half-diagonal below this [m s-1] ...
REST_TILT_RAD = 1e-3         # ... and its rotation below this [rad] (the rotation a landing leaves where one corner
#                              sank further than the other in its step, dropped at the hand-back)
MAX_CONTACT_STEPS = 2_000_000   # steps per run [-]: the cap ends the run without a verdict
HANDBACK_STEPS = 8           # steps in a row in which every joint is shut or turns on a sticking corner: handed back
STICKING = 0.9               # a joint sticks where its pressed ends' friction is at most this share of mu P_n [-]
WITHIN = 1e-9                # a corner within this fraction of the two blocks' sizes of a face (its plane, its end)
#                              counts as on it (their rest positions are sums of rounded lengths)
#: The most contacts: two on the ground, four at each joint
MAX_CONTACTS = 2 + 4 * (MAX_BODIES - 1)
#: What a run's joints make of a step (:func:`_joint_modes`): nothing to hand back; a state of the exact model; the
#: stack rocking as one with one joint slipping (the slide-rock model's)
HANDS_NONE, HANDS_EXACT, HANDS_ROCKING = 0, 1, 2
#: The ground, as the second body of a contact (a contact's slot, which keeps its impulse to the next step: the
#: ground's two corners, then per joint the upper's two corners and the lower's two)
NO_BODY = -1


class StackContactOutcome(NamedTuple):
    """A run's result.

    Attributes
    ----------
    standing : int
        how many blocks still stand at the run's end (the lowest ones)
    t_fall_s : tuple of float
        when each block fell [s] (NaN: it did not)
    peak_rad : tuple of float
        each block's largest |rotation on what it stands on| [rad]
    rested : bool
        the run handed back (the module's rule; without ``hand_back``, at rest after the record); else it stopped at
        the tail's end, a cap, or every block fallen
    t_end_s : float
        where the run stopped [s]
    offsets_m : tuple of float
        each block's base centre from the centre of the top of the block under it, in that block's frame, where
        the run stopped [m] (block 0: 0)
    status : int
        :class:`~pipeline.rocking.codes.Status` bits: ground_flight (the ground fell faster than gravity in the run),
        step_cap (the run reached :data:`MAX_CONTACT_STEPS`, or a step's sweeps :data:`MAX_SWEEPS`), tail_cap
    steps : int
        steps taken
    unconverged : int
        steps whose Gauss-Seidel sweeps reached :data:`MAX_SWEEPS`
    peak_slide_m : tuple of float
        each joint's largest |offset change| from where the run started, or from where it stood before the slips
        ``slid_m`` given to the run [m] (block 0: its base centre's on the ground)
    peak_lift_m : float
        the largest height of block 0's lower base corner above the ground [m] (a flight's)
    handback : tuple of float
        where the run handed back (``rested``): the n-block state of the lowest ``standing`` blocks with the
        offsets ``offsets_m`` (:mod:`.n_block`'s: each joint's psi, then its rate; a shut joint's 0)
    base_shift_m : float
        how far block 0's base centre moved on the ground from the run's start to its end [m]
    rocking : tuple of float
        where the run handed back the stack turning as one with one joint slipping (``rock_slide``): the
        slide-rock model's state (:class:`.stack_pose.SlideRockState`: phi, u, their rates and the slipping joint);
        else None (``handback`` then holds the exact model's state, or rest)
    """

    standing: int
    t_fall_s: tuple
    peak_rad: tuple
    rested: bool
    t_end_s: float
    offsets_m: tuple
    status: int
    steps: int
    unconverged: int
    peak_slide_m: tuple
    peak_lift_m: float
    handback: tuple = (0.0,) * (2 * MAX_BODIES)
    base_shift_m: float = 0.0
    rocking: SlideRockState | None = None


class Work(NamedTuple):
    """Scratch arrays made once per run: the contacts' bodies, Jacobian rows (per contact: normal then tangent,
    each the two bodies' three entries), slots, the Delassus matrix, the free velocities' relative velocities, the
    impulses, the impulses kept per slot between steps, the direct solve's scratch, the blocks' cos and sin of their
    rotations (:func:`~.stack_pose.rotations`) and their inverse masses and moments of inertia (3, n)."""

    body: np.ndarray
    jac: np.ndarray
    slot: np.ndarray
    w: np.ndarray
    rhs: np.ndarray
    p: np.ndarray
    kept: np.ndarray
    kept_next: np.ndarray
    direct: DirectWork
    trig: np.ndarray
    inv: np.ndarray


def work() -> Work:
    """A :class:`Work` for any stack of up to :data:`MAX_BODIES` blocks."""
    c = MAX_CONTACTS
    return Work(np.zeros((c, 2), dtype=np.int64), np.zeros((c, 2, 6)), np.zeros(c, dtype=np.int64),
                np.zeros((2 * c, 2 * c)), np.zeros(2 * c), np.zeros(2 * c), np.zeros(2 * c), np.zeros(2 * c),
                direct_work(c),
                np.zeros((2, MAX_BODIES)), np.zeros((3, MAX_BODIES)))


@jit_lean
def _add(wk, count, a, b, nx, nz, px, pz, q, slot):
    """Contact ``count`` of body a on body b (NO_BODY: the ground) at (px, pz), b's face normal (nx, nz) pointing to
    a: its Jacobian rows (U = J v, a's entries then b's)."""
    tx, tz = nz, -nx
    wk.body[count, 0], wk.body[count, 1], wk.slot[count] = a, b, slot
    for j in range(2):
        ex, ez = (nx, nz) if j == 0 else (tx, tz)
        dx, dz = px - q[0, a], pz - q[1, a]
        wk.jac[count, j, 0], wk.jac[count, j, 1], wk.jac[count, j, 2] = ex, ez, ex * dz - ez * dx
        if b == NO_BODY:
            wk.jac[count, j, 3], wk.jac[count, j, 4], wk.jac[count, j, 5] = 0.0, 0.0, 0.0
        else:
            dx, dz = px - q[0, b], pz - q[1, b]
            wk.jac[count, j, 3], wk.jac[count, j, 4], wk.jac[count, j, 5] = -ex, -ez, -(ex * dz - ez * dx)
    return count + 1


@jit_lean
def _contacts(bd, n, q, wk):
    """The contacts at the configuration q (3, n): their count, their rows in ``wk``."""
    cs = wk.trig
    rotations(q, n, cs)
    count = 0
    for side in range(2):
        s = 2.0 * side - 1.0
        px, pz = point_at(q, cs, 0, s * bd.b[0], -bd.h[0])
        if pz <= WITHIN * bd.h[0]:
            count = _add(wk, count, 0, NO_BODY, 0.0, 1.0, px, pz, q, side)
    for k in range(1, n):
        lo, up = k - 1, k
        tol, gap_tol = WITHIN * (bd.b[lo] + bd.b[up]), WITHIN * (bd.h[lo] + bd.h[up])
        met = 0
        for side in range(2):
            s = 2.0 * side - 1.0
            px, pz = point_at(q, cs, up, s * bd.b[up], -bd.h[up])
            lx, lz = point_in(q, cs, lo, px, pz)
            if lz - bd.h[lo] <= gap_tol and abs(lx) <= bd.b[lo] + tol:
                c, sn = cs[0, lo], cs[1, lo]
                count = _add(wk, count, up, lo, sn, c, px, pz, q, 2 + 4 * (k - 1) + side)
                met |= 1 << side
        for side in range(2):
            if met & (1 << side):
                continue                            # the two corners meet: counted once
            s = 2.0 * side - 1.0
            px, pz = point_at(q, cs, lo, s * bd.b[lo], bd.h[lo])
            ux, uz = point_in(q, cs, up, px, pz)
            if -bd.h[up] - uz <= gap_tol and abs(ux) <= bd.b[up] + tol:
                c, sn = cs[0, up], cs[1, up]
                count = _add(wk, count, up, lo, sn, c, px, pz, q, 4 + 4 * (k - 1) + side)
    return count


@jit_lean
def _delassus(bd, count, wk):
    """W = H M^-1 H^T of the ``count`` contacts."""
    for i in range(count):
        for ri in range(2):
            for j in range(count):
                for rj in range(2):
                    acc = 0.0
                    for ei in range(2):
                        bi = wk.body[i, ei]
                        if bi == NO_BODY:
                            continue
                        for ej in range(2):
                            if wk.body[j, ej] != bi:
                                continue
                            for d in range(3):
                                acc += wk.jac[i, ri, 3 * ei + d] * wk.inv[d, bi] * wk.jac[j, rj, 3 * ej + d]
                    wk.w[2 * i + ri, 2 * j + rj] = acc


@jit_lean
def _relative(count, v, wk):
    """The contacts' relative velocities (normal, tangent) under the velocities v (3, n) into ``wk.rhs``."""
    for i in range(count):
        for r in range(2):
            acc = 0.0
            for e in range(2):
                b = wk.body[i, e]
                if b != NO_BODY:
                    for d in range(3):
                        acc += wk.jac[i, r, 3 * e + d] * v[d, b]
            wk.rhs[2 * i + r] = acc


@jit_lean
def _local_solve(wnn, wnt, wtn, wtt, qn, qt, mu):
    """The impulse (P_n, P_t) of one contact given the rest: U = W P + q, the plastic impact law and Coulomb."""
    if qn >= 0.0:
        return 0.0, 0.0
    det = wnn * wtt - wnt * wtn
    if det > 0.0:
        pn = (-qn * wtt + qt * wnt) / det
        pt = (-qt * wnn + qn * wtn) / det
        if pn >= 0.0 and abs(pt) <= mu * pn:
            return pn, pt
    for k in range(2):
        sgn = 1.0 - 2.0 * k                          # slides towards sgn: friction -sgn mu P_n
        den = wnn - sgn * mu * wnt
        if den > 0.0:
            pn = -qn / den
            pt = -sgn * mu * pn
            ut = wtn * pn + wtt * pt + qt
            if pn >= 0.0 and sgn * ut >= 0.0:
                return pn, pt
    pn = -qn / wnn
    return pn, max(-mu * pn, min(mu * pn, -qt / wtt if wtt > 0.0 else 0.0))


@jit_lean
def _solve(bd, count, wk):
    """The step's impulses into ``wk.p``: by the contacts' modes (:mod:`.stack_direct`), else by projected
    Gauss-Seidel; True where either converged."""
    if solve_direct(count, wk.w, wk.rhs, wk.kept, wk.slot, wk.body, bd.mu, wk.direct, wk.p, SWEEP_TOL_MS):
        return True
    return _sweeps(bd, count, wk)


@jit_lean
def _sweeps(bd, count, wk):
    """The step's impulses into ``wk.p`` by projected Gauss-Seidel from the slots' impulses of the step before; True
    where the sweeps converged."""
    for i in range(count):
        wk.p[2 * i], wk.p[2 * i + 1] = wk.kept[2 * wk.slot[i]], wk.kept[2 * wk.slot[i] + 1]
    for _ in range(MAX_SWEEPS):
        change = 0.0
        for i in range(count):
            qn, qt = wk.rhs[2 * i], wk.rhs[2 * i + 1]
            for j in range(count):
                if j != i:
                    qn += wk.w[2 * i, 2 * j] * wk.p[2 * j] + wk.w[2 * i, 2 * j + 1] * wk.p[2 * j + 1]
                    qt += wk.w[2 * i + 1, 2 * j] * wk.p[2 * j] + wk.w[2 * i + 1, 2 * j + 1] * wk.p[2 * j + 1]
            mu = bd.mu[wk.body[i, 0]]
            pn, pt = _local_solve(wk.w[2 * i, 2 * i], wk.w[2 * i, 2 * i + 1], wk.w[2 * i + 1, 2 * i],
                                  wk.w[2 * i + 1, 2 * i + 1], qn, qt, mu)
            change = max(change, wk.w[2 * i, 2 * i] * abs(pn - wk.p[2 * i]),
                         wk.w[2 * i + 1, 2 * i + 1] * abs(pt - wk.p[2 * i + 1]))
            wk.p[2 * i], wk.p[2 * i + 1] = pn, pt
        if change <= SWEEP_TOL_MS:
            return True
    return False


@jit_lean
def _apply(bd, count, v, wk):
    """v += M^-1 H^T P."""
    for i in range(count):
        for e in range(2):
            b = wk.body[i, e]
            if b == NO_BODY:
                continue
            for d in range(3):
                v[d, b] += wk.inv[d, b] * (wk.jac[i, 0, 3 * e + d] * wk.p[2 * i]
                                           + wk.jac[i, 1, 3 * e + d] * wk.p[2 * i + 1])


@jit_lean
def _fallen(bd, n, q, cs):
    """The lowest block that has fallen (the module's rule), or n (``cs``: the blocks' :func:`~.stack_pose.rotations`
    at q)."""
    for k in range(n):
        if abs(q[2, k]) >= HALF_PI or abs(tilt(q, k)) >= HALF_PI:
            return k
        if k > 0:
            _, lz = point_in(q, cs, k - 1, q[0, k], q[1, k])
            if lz < bd.h[k - 1]:
                return k
    return n


@jit_lean
def _joint_modes(bd, n, q, v, count, wk, modes, rock_slide):
    """Each joint's mode into ``modes`` (0 shut: both ends of its face pressed, the joint still and flat within the
    rest thresholds; +1 or -1: turning on that end's corner alone, the rotation towards it), and what they make:
    :data:`HANDS_EXACT` where each joint sticks (the friction of its pressed ends together within :data:`STICKING`
    of the cone of their normal impulses together); with ``rock_slide``, :data:`HANDS_ROCKING` where the stack turns
    as one on a sticking corner of block 0, every other joint shut and one of them slipping (the slide-rock model's
    state, :mod:`.slide_rock`); else :data:`HANDS_NONE` (a joint flying, slipping otherwise, or pressed on the side it
    turns away from). Returns (what they make, the slipping joint or -1)."""
    ends = modes                                    # first each joint's ends pressed, as bits
    for k in range(n):
        ends[k] = 0
    slipping = -1
    for k in range(n):
        normal, tangent = 0.0, 0.0
        for i in range(count):
            pn, sl = wk.p[2 * i], wk.slot[i]
            joint, side = (0, sl) if sl < 2 else ((sl - 2) // 4 + 1, (sl - 2) % 2)
            if pn <= 0.0 or joint != k:
                continue
            ends[k] |= 1 << side
            normal, tangent = normal + pn, tangent + wk.p[2 * i + 1]
        if abs(tangent) > STICKING * bd.mu[k] * normal:
            if not rock_slide or k == 0 or slipping >= 0:
                return HANDS_NONE, -1
            slipping = k
    for k in range(n):
        bits, turn = ends[k], tilt(q, k)
        rate = v[2, k] - (v[2, k - 1] if k > 0 else 0.0)
        if bits == 3:
            if abs(turn) >= REST_TILT_RAD or abs(rate) * math.hypot(bd.b[k], bd.h[k]) >= REST_SPEED:
                return HANDS_NONE, -1
            modes[k] = 0
        elif bits == 0:
            return HANDS_NONE, -1
        else:
            side = 1 if bits == 2 else -1
            if turn * side <= 0.0:
                return HANDS_NONE, -1
            modes[k] = side
    if slipping < 0:
        return HANDS_EXACT, -1
    if modes[0] == 0:
        return HANDS_NONE, -1
    for k in range(1, n):
        if modes[k] != 0:
            return HANDS_NONE, -1
    return HANDS_ROCKING, slipping


@jit_lean
def _all_shut(modes, n):
    """Every joint shut: the stack at rest."""
    for k in range(n):
        if modes[k] != 0:
            return False
    return True


@jit_lean
def _holds(bd, n, piece, t, at_rest):
    """The ground at t does not fall faster than gravity, nor, where the stack is ``at_rest`` (every joint shut), ask
    its joints for more friction than the least they have (so that the exact model, handed the stack at rest, goes on
    from there; a stack handed back in motion has its joints' demands followed by the exact model)."""
    a_h, a_v = ground_on(piece, t)
    if not at_rest:
        return G + a_v > 0.0
    least = math.inf
    for k in range(n):
        least = min(least, bd.mu[k])
    return G + a_v > 0.0 and abs(a_h) <= least * (G + a_v)


@jit_lean
def _ready(bd, n, piece, t, modes, hand_back):
    """Given the joints' ``modes`` (:func:`_joint_modes`), whether the stack may stop here: the ground :func:`_holds`
    for it, and, without ``hand_back``, it is at rest (every joint shut)."""
    at_rest = _all_shut(modes, n)
    return _holds(bd, n, piece, t, at_rest) and (hand_back or at_rest)


@jit_lean
def _reset(bd, n, wk):
    """No impulse kept from a step before; the blocks' inverse masses and moments of inertia."""
    for i in range(wk.kept.shape[0]):
        wk.kept[i] = 0.0
    for k in range(n):
        wk.inv[0, k], wk.inv[1, k], wk.inv[2, k] = 1.0 / bd.m[k], 1.0 / bd.m[k], 1.0 / bd.i[k]


@jit_lean
def _measure(bd, n, q, cs, peak, slide, origin):
    """At the step's end q: the blocks' rotations into ``cs`` (:func:`~.stack_pose.rotations`), each joint's
    largest rotation and slip into ``peak`` and ``slide`` (slips from ``origin``); returns the height of block 0's
    lower base corner [m]."""
    rotations(q, n, cs)
    _, z_left = point_at(q, cs, 0, -bd.b[0], -bd.h[0])
    _, z_right = point_at(q, cs, 0, bd.b[0], -bd.h[0])
    for k in range(n):
        peak[k] = max(peak[k], abs(tilt(q, k)))
        base_x, base_z = point_at(q, cs, k, 0.0, -bd.h[k])
        if k > 0:
            base_x, _ = point_in(q, cs, k - 1, base_x, base_z)      # base_offset's
        slide[k] = max(slide[k], abs(base_x - origin[k]))
    return min(z_left, z_right)


@jit_lean
def _normal_rate(q, v, a, b, nx, nz, px, pz):
    """The velocity of body a's point (px, pz) relative to body b's (NO_BODY: the ground) along the normal (nx, nz)
    of b's face towards a [m s-1]: a contact's U_n there (:func:`_add`'s normal row times v), negative where they
    approach."""
    dx, dz = px - q[0, a], pz - q[1, a]
    u = nx * v[0, a] + nz * v[1, a] + (nx * dz - nz * dx) * v[2, a]
    if b != NO_BODY:
        dx, dz = px - q[0, b], pz - q[1, b]
        u -= nx * v[0, b] + nz * v[1, b] + (nx * dz - nz * dx) * v[2, b]
    return u


@jit_lean
def _clear_ahead(bd, n, q, v, cs, span_s):
    """Whether no corner clear of a face it may touch (:func:`_contacts`' pairs: block 0's base corners and the
    ground; at each joint the upper block's base corners and the lower's top face, the lower's top corners and the
    upper's base) could reach it within :data:`IMPACT_SAFETY` ``span_s`` [s] at its present speed towards it, at the
    configuration q (3, n) and velocities v (3, n); the blocks' cos and sin into ``cs``. A corner beyond a face's end
    is held to the face's line, as if the face went on."""
    rotations(q, n, cs)
    reach = IMPACT_SAFETY * span_s
    for side in range(2):
        s = 2.0 * side - 1.0
        px, pz = point_at(q, cs, 0, s * bd.b[0], -bd.h[0])
        tol = WITHIN * bd.h[0]
        if pz > tol and pz + reach * min(_normal_rate(q, v, 0, NO_BODY, 0.0, 1.0, px, pz), 0.0) <= tol:
            return False
    for k in range(1, n):
        lo, up = k - 1, k
        tol = WITHIN * (bd.h[lo] + bd.h[up])
        for side in range(2):
            s = 2.0 * side - 1.0
            px, pz = point_at(q, cs, up, s * bd.b[up], -bd.h[up])
            gap = point_in(q, cs, lo, px, pz)[1] - bd.h[lo]
            if gap > tol and gap + reach * min(_normal_rate(q, v, up, lo, cs[1, lo], cs[0, lo], px, pz), 0.0) <= tol:
                return False
            px, pz = point_at(q, cs, lo, s * bd.b[lo], bd.h[lo])
            gap = -bd.h[up] - point_in(q, cs, up, px, pz)[1]
            if gap > tol and gap + reach * min(_normal_rate(q, v, up, lo, cs[1, up], cs[0, up], px, pz), 0.0) <= tol:
                return False
    return True


@jit_lean
def _run(bd, ah, av, dt, t, q, v, hand_back, wk, t_fall, peak, slide, origin, modes, parts, merge, step_s, t_stop,
         rock_slide):
    """The run of :func:`simulate_stack_contact` from (q, v) at t, a sampling interval in ``parts`` steps, ``merge``
    of them taken as one where no contact is ahead (the module's long steps; 1: none), steps of at most ``step_s`` [s]
    after the record; fills t_fall, peak, slide and, where it hands back, the joints' modes (``rock_slide``: also to
    the slide-rock model, :func:`_joint_modes`)."""
    n_samples = ah.shape[0]
    t_rec = (n_samples - 2) * dt + dt
    tail_end = t_rec + TAIL_S
    n = bd.n
    status, steps, unconverged = 0, 0, 0
    rested, lift, ready, hands, slipping = False, 0.0, 0, HANDS_NONE, -1
    _reset(bd, n, wk)
    while n > 0:
        if steps >= MAX_CONTACT_STEPS:
            status |= STATUS_STEP_CAP
            break
        if t >= tail_end * (1.0 - 1e-15):
            status |= STATUS_TAIL_CAP
            break
        if t >= t_stop:
            break
        piece = piece_at(ah, av, dt, t, t_rec, tail_end)
        after = t >= t_rec - 1e-12 * dt
        hh = min(piece.span / parts, step_s) if after else piece.span / parts
        t_end_piece = piece.t0 + piece.span
        if merge > 1 and not after and ready == 0:
            at = int(round((t - piece.t0) / hh))        # the step's place in its sampling interval
            if at % merge == 0 and at + merge <= parts and abs(t - piece.t0 - at * hh) <= 1e-9 * hh and _clear_ahead(
                    bd, n, q, v, wk.trig, merge * hh):
                hh = merge * hh
        if t + hh > t_end_piece:
            hh = t_end_piece - t
        if hh <= 0.0:
            hh = piece.span / parts
        a_h, a_v = ground_on(piece, t + 0.5 * hh)
        if G + a_v <= 0.0:
            status |= STATUS_GROUND_FLIGHT
        # q_m = q + h/2 v-
        for k in range(n):
            for d in range(3):
                q[d, k] += 0.5 * hh * v[d, k]
            v[0, k] -= hh * a_h
            v[1, k] -= hh * (G + a_v)
        count = _contacts(bd, n, q, wk)
        for i in range(wk.kept_next.shape[0]):
            wk.kept_next[i] = 0.0
        if count > 0:
            _delassus(bd, count, wk)
            _relative(count, v, wk)
            if not _solve(bd, count, wk):
                unconverged, status = unconverged + 1, status | STATUS_STEP_CAP
            _apply(bd, count, v, wk)
            for i in range(count):
                wk.kept_next[2 * wk.slot[i]], wk.kept_next[2 * wk.slot[i] + 1] = wk.p[2 * i], wk.p[2 * i + 1]
        for i in range(wk.kept.shape[0]):
            wk.kept[i] = wk.kept_next[i]
        for k in range(n):
            for d in range(3):
                q[d, k] += 0.5 * hh * v[d, k]
        t = t_end_piece if hh == t_end_piece - t else t + hh
        steps += 1
        lift = max(lift, _measure(bd, n, q, wk.trig, peak, slide, origin))
        fell = _fallen(bd, n, q, wk.trig)
        if fell < n:
            for k in range(fell, n):
                t_fall[k] = t
            n = fell
            continue
        hands, slipping = _joint_modes(bd, n, q, v, count, wk, modes, rock_slide and hand_back) if (
            hand_back or t >= t_rec) and count > 0 else (HANDS_NONE, -1)
        if hands != HANDS_NONE and _ready(bd, n, piece, t, modes, hand_back):
            ready += 1
            if ready >= HANDBACK_STEPS:
                rested = True
                break
        else:
            ready = 0
    return n, t, rested, status, steps, unconverged, lift, hands, slipping


def simulate_stack_contact(nb: NBlock, mu, ah_ms2: np.ndarray, dt_s: float, *, av_ms2: np.ndarray | None = None,
                           start: tuple | None = None, t0_s: float = 0.0, hand_back: bool = True,
                           slid_m: tuple | None = None, step_s: float = MAX_STEP_S,
                           long_step_s: float = 0.0, until_s: float = math.inf,
                           pose: tuple | None = None, rock_slide: bool = False) -> StackContactOutcome:
    """The stack ``nb`` (friction ``mu`` [-] at each block's base) under the ground ``ah_ms2``, ``av_ms2`` [m s-2]
    (samples ``dt_s`` [s] apart), from the n-block state ``start`` (None: rest) at ``t0_s`` [s], by the module's
    model. With ``hand_back`` the run hands back where the module's rule says so; without, it stops only at rest
    (every joint shut) after the record. ``slid_m``: each joint's slip before the run [m] (block 0's along the
    ground), from which its largest slip is measured (None: 0, from where the run starts). ``step_s`` [s]: the longest
    step (a sampling interval in the fewest equal steps of at most it); ``long_step_s`` [s]: with long steps (the
    module's option), the longest of the steps taken several as one (0: every step short, the default).
    ``until_s`` [s]: the run stops at the end of the first step that reaches it (its state then in the outcome).
    ``pose``: (q, v), the blocks' centres and rotations (3, n) and their rates (3, n) in the ground's frame
    (:func:`.stack_pose.state_of`'s), the start in place of ``start`` (a state the n-block model does not describe:
    a joint sliding). ``rock_slide``: the stack is also handed back where it turns as one on a sticking corner of
    block 0 with every joint shut and one slipping (:attr:`StackContactOutcome.rocking`)."""
    if not (math.isfinite(step_s) and step_s > 0.0 and math.isfinite(long_step_s) and long_step_s >= 0.0):
        raise ParameterError(f"step_s = {step_s!r}, long_step_s = {long_step_s!r}: expected a positive step and a "
                             "long step of 0 (none) or more [s]")
    ah = np.ascontiguousarray(ah_ms2, dtype=float)
    av = np.zeros(0) if av_ms2 is None else np.ascontiguousarray(av_ms2, dtype=float)
    y = (0.0,) * (2 * MAX_BODIES) if start is None else start
    q, v = state_of(nb, y) if pose is None else (np.array(pose[0], dtype=float), np.array(pose[1], dtype=float))
    bd = bodies_of(nb, mu)
    t_fall, peak, slide = np.full(MAX_BODIES, np.nan), np.zeros(MAX_BODIES), np.zeros(MAX_BODIES)
    base_x, _ = corner_point(q, 0, 0.0, -nb.h[0])               # block 0's base centre on the ground
    off0 = np.array([base_x] + [base_offset(bd, q, k) for k in range(1, nb.n)] + [0.0] * (MAX_BODIES - nb.n))
    for k in range(nb.n):
        peak[k] = abs(q[2, k] - (q[2, k - 1] if k > 0 else 0.0))
    modes = np.zeros(MAX_BODIES, dtype=np.int64)
    parts = max(1, int(math.ceil(dt_s / step_s - 1e-9)))
    origin = off0.copy()                                        # where each joint stood before any slip
    if slid_m is not None:
        origin[:nb.n] -= [float(x) for x in slid_m[:nb.n]]
        slide[:nb.n] = np.abs(off0[:nb.n] - origin[:nb.n])
    merge = steps_merged(parts, float(dt_s) / parts, longest_s=long_step_s)
    count, t_end, rested, status, steps, unconverged, lift, hands, slipping = _run(
        bd, ah, av, float(dt_s), float(t0_s), q, v, bool(hand_back), work(), t_fall, peak, slide, origin, modes,
        parts, merge, float(step_s), float(until_s), bool(rock_slide))
    rocking = rested and hands == HANDS_ROCKING
    offsets, y = handback(bd, q, v, modes if rested and not rocking else np.zeros(MAX_BODIES, dtype=np.int64), count)
    base_end, _ = corner_point(q, 0, 0.0, -nb.h[0])
    return StackContactOutcome(int(count), tuple(float(x) for x in t_fall), tuple(float(x) for x in peak),
                               bool(rested), float(t_end), offsets, int(status), int(steps), int(unconverged),
                               tuple(float(x) for x in slide), float(lift), y, float(base_end - off0[0]),
                               slide_rock_state(bd, q, v, slipping) if rocking else None)

