"""The stack's contact problem of one step (:mod:`.stack_contact`) solved directly, by its contacts' modes.

Each contact i has its impulse P_i = (P_n, P_t) and its relative velocity after the step U_i = (U_n, U_t), with

    U = W P + q,      0 <= P_n  _|_  U_n >= 0,      |P_t| <= mu P_n,  U_t = 0 where |P_t| < mu P_n,  else P_t U_t < 0,

W the Delassus matrix and q the free relative velocities. Given each contact's mode (free: P = 0; sticking: U_n = U_t
= 0; sliding towards s = +-1: U_n = 0 and P_t = -s mu P_n), the impulses solve a linear system of at most two
equations a contact, here by Gaussian elimination with partial pivoting. The modes are guessed from the impulses of
the step before (a stack mostly keeps its contacts' modes from one 0.25 ms step to the next: 94 % of the steps of two
drums whose joint slips were solved so at the first guess or after a mend, in one measurement); where the solution
breaks a condition, the contacts that break it change mode (a free one that approaches sticks, a pressed one pulled
stops touching, a sticking one beyond its cone slides the way its friction is pushed, a sliding one that turns back
sticks) and the system is solved again, at most :data:`TRIES` times. The sticking ends of one face (a shut face:
both ends on its line, so that their tangential rows are one, and how they share its friction is not determined)
have one tangential unknown, shared by the ends in proportion to their normal impulses: each end is then inside its
cone exactly where the face's total is inside the face's. A solution is kept only where every contact's law holds
to the caller's tolerance (:data:`~.stack_contact.SWEEP_TOL_MS`, the change at which the Gauss-Seidel sweeps stop;
impulses measured as the velocity they give their own contact, ``W_ii P``); else, where the system is singular, or
after :data:`TRIES` solves, the caller solves the step by the sweeps.

Where the stack's contacts keep their modes this is one solve a step instead of the sweeps' approach to that
tolerance on contacts coupled through the blocks (docs/validation.md measures both).

References
----------
Moreau, J. J. (1988). Unilateral contact and dry friction in finite freedom dynamics. In Nonsmooth Mechanics and
Applications, CISM Courses and Lectures 302, 1-82. Springer.
Pfeiffer, F. & Glocker, C. (1996). Multibody Dynamics with Unilateral Contacts. Wiley (the contact problem by the
contacts' modes, an active set of linear systems).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..compiled import jit_lean

#: Linear solves at most per step before the sweeps take the step [-].
TRIES = 4
#: A pivot below this fraction of the largest diagonal of W marks the system singular [-].
SINGULAR = 1e-10

#: A contact's mode: no impulse; sticking; sliding towards +t (friction -mu P_n); sliding towards -t.
FREE, STICK, SLIDE_POS, SLIDE_NEG = 0, 1, 2, 3
#: What a check of the laws found (:func:`_check_and_switch`).
KEPT, SWITCHED, GIVE_UP = 0, 1, 2


class DirectWork(NamedTuple):
    """Scratch of :func:`solve_direct`, made once per run for up to ``c`` contacts: the system's matrix and right-hand
    side, each contact's mode, its unknowns' columns, its friction and the sticking contact whose tangential
    impulse it shares (-1: none)."""

    a: np.ndarray
    x: np.ndarray
    mode: np.ndarray
    col: np.ndarray
    mu: np.ndarray
    share: np.ndarray


def direct_work(c: int) -> DirectWork:
    """A :class:`DirectWork` for ``c`` contacts."""
    return DirectWork(np.zeros((2 * c, 2 * c + 1)), np.zeros(2 * c), np.zeros(c, dtype=np.int64),
                      np.zeros(c, dtype=np.int64), np.zeros(c),
                      np.zeros(c, dtype=np.int64))


@jit_lean
def _guess(count, rhs, kept, slot, mu, dw):
    """Each contact's mode from its slot's impulse of the step before (none: sticking where it approaches)."""
    for i in range(count):
        pn, pt = kept[2 * slot[i]], kept[2 * slot[i] + 1]
        if pn <= 0.0:
            dw.mode[i] = STICK if rhs[2 * i] < 0.0 else FREE
        elif abs(pt) < mu[i] * pn:
            dw.mode[i] = STICK
        else:
            dw.mode[i] = SLIDE_POS if pt < 0.0 else SLIDE_NEG


@jit_lean
def _eliminate(a, x, m, scale):
    """Solve the m x m system a[:m, :m] x = a[:m, m] in place; False where a pivot is below SINGULAR * scale."""
    for k in range(m):
        best, piv = k, abs(a[k, k])
        for r in range(k + 1, m):
            if abs(a[r, k]) > piv:
                best, piv = r, abs(a[r, k])
        if piv <= SINGULAR * scale:
            return False
        if best != k:
            for c in range(k, m + 1):
                a[k, c], a[best, c] = a[best, c], a[k, c]
        for r in range(k + 1, m):
            f = a[r, k] / a[k, k]
            if f != 0.0:
                for c in range(k, m + 1):
                    a[r, c] -= f * a[k, c]
    for k in range(m - 1, -1, -1):
        acc = a[k, m]
        for c in range(k + 1, m):
            acc -= a[k, c] * x[c]
        x[k] = acc / a[k, k]
    return True


@jit_lean
def _shares(count, body, dw):
    """Each sticking contact's partner: the first sticking contact before it between the same two bodies (the other
    end of a shut face, whose tangential row is its own: both ends on the face's line), or -1."""
    for i in range(count):
        dw.share[i] = -1
        if dw.mode[i] != STICK:
            continue
        for j in range(i):
            if dw.mode[j] == STICK and dw.share[j] < 0 and body[j, 0] == body[i, 0] and body[j, 1] == body[i, 1]:
                dw.share[i] = j
                break


@jit_lean
def _unknowns(mode, share):
    """A contact's unknowns: none free, P_n sliding or sharing its face's tangential impulse, else P_n and P_t."""
    if mode == FREE:
        return 0
    return 2 if mode == STICK and share < 0 else 1


@jit_lean
def _solve_modes(count, w, rhs, body, mu, dw, p, scale):
    """The impulses ``p`` of the contacts in their modes ``dw.mode``; False where the system is singular. The
    sticking ends of one face carry its tangential impulse in proportion to their normal ones (each then inside its
    cone exactly where the face's total is inside the face's)."""
    _shares(count, body, dw)
    m = 0
    for i in range(count):
        dw.col[i] = m
        m += _unknowns(dw.mode[i], dw.share[i])
    if m == 0:
        for i in range(2 * count):
            p[i] = 0.0
        return True
    row = 0
    for i in range(count):
        for r in range(_unknowns(dw.mode[i], dw.share[i])):
            eq = 2 * i + r                          # U_n = 0, and U_t = 0 where it sticks
            for j in range(count):
                mj, cj = dw.mode[j], dw.col[j]
                if mj == STICK:
                    dw.a[row, cj] = w[eq, 2 * j]
                    if dw.share[j] < 0:
                        dw.a[row, cj + 1] = w[eq, 2 * j + 1]
                elif mj != FREE:
                    s = 1.0 if mj == SLIDE_POS else -1.0
                    dw.a[row, cj] = w[eq, 2 * j] - s * mu[j] * w[eq, 2 * j + 1]
            dw.a[row, m] = -rhs[eq]
            row += 1
    if not _eliminate(dw.a, dw.x, m, scale):
        return False
    for i in range(count):
        mode, c = dw.mode[i], dw.col[i]
        if mode == FREE:
            p[2 * i], p[2 * i + 1] = 0.0, 0.0
        elif mode == STICK:
            p[2 * i], p[2 * i + 1] = dw.x[c], (dw.x[c + 1] if dw.share[i] < 0 else 0.0)
        else:
            s = 1.0 if mode == SLIDE_POS else -1.0
            p[2 * i], p[2 * i + 1] = dw.x[c], -s * mu[i] * dw.x[c]
    _share_out(count, dw, p)
    return True


@jit_lean
def _share_out(count, dw, p):
    """A face's tangential impulse, solved on its first sticking end, shared by its ends in proportion to their
    normal impulses."""
    for j in range(count):
        if dw.mode[j] != STICK or dw.share[j] >= 0:
            continue
        normal = p[2 * j]
        for i in range(j + 1, count):
            if dw.share[i] == j:
                normal += p[2 * i]
        if normal <= 0.0 or normal == p[2 * j]:
            continue
        total = p[2 * j + 1]
        p[2 * j + 1] = total * p[2 * j] / normal
        for i in range(j + 1, count):
            if dw.share[i] == j:
                p[2 * i + 1] = total * p[2 * i] / normal


@jit_lean
def _velocity(count, w, rhs, p, eq):
    """U[eq] = (W P + q)[eq]."""
    acc = rhs[eq]
    for j in range(2 * count):
        acc += w[eq, j] * p[j]
    return acc


@jit_lean
def _check_and_switch(count, w, rhs, mu, dw, p, tol):
    """KEPT where every contact keeps its law to ``tol`` [m s-1]; SWITCHED where the breaking contacts' modes were
    changed; GIVE_UP where a sticking end sharing its face's tangential row slips (its row is not its partner's)."""
    ok = KEPT
    for i in range(count):
        mode, wn, wt = dw.mode[i], w[2 * i, 2 * i], w[2 * i + 1, 2 * i + 1]
        if mode == FREE:
            if _velocity(count, w, rhs, p, 2 * i) < -tol:
                dw.mode[i], ok = STICK, SWITCHED
            continue
        pn, pt = p[2 * i], p[2 * i + 1]
        if pn * wn < -tol:
            dw.mode[i], ok = FREE, SWITCHED
        elif mode == STICK:
            if (abs(pt) - mu[i] * pn) * wt > tol:
                dw.mode[i], ok = (SLIDE_POS if pt < 0.0 else SLIDE_NEG), SWITCHED
            elif dw.share[i] >= 0 and abs(_velocity(count, w, rhs, p, 2 * i + 1)) > tol:
                return GIVE_UP                      # its tangential row, dropped from the system, is not its partner's
        else:
            s = 1.0 if mode == SLIDE_POS else -1.0
            if s * _velocity(count, w, rhs, p, 2 * i + 1) < -tol:
                dw.mode[i], ok = STICK, SWITCHED
    return ok


@jit_lean
def solve_direct(count, w, rhs, kept, slot, body, mu_body, dw, p, tol):
    """The step's impulses into ``p`` (pairs (P_n, P_t) per contact) by the contacts' modes, guessed from the slots'
    impulses ``kept`` of the step before; each contact's friction that of its upper body ``body[i, 0]`` in
    ``mu_body``. True where a solution keeps every law to
    ``tol`` [m s-1] (then each P_n >= 0 and |P_t| <= mu P_n exactly: within ``tol`` they are moved onto the bound);
    False: ``p`` holds no solution."""
    mu = dw.mu
    for i in range(count):
        mu[i] = mu_body[body[i, 0]]
    scale = 0.0
    for i in range(2 * count):
        scale = max(scale, w[i, i])
    _guess(count, rhs, kept, slot, mu, dw)
    for _ in range(TRIES):
        if not _solve_modes(count, w, rhs, body, mu, dw, p, scale):
            return False
        verdict = _check_and_switch(count, w, rhs, mu, dw, p, tol)
        if verdict == GIVE_UP:
            return False
        if verdict == KEPT:
            for i in range(count):
                pn = max(p[2 * i], 0.0)
                p[2 * i], p[2 * i + 1] = pn, max(-mu[i] * pn, min(mu[i] * pn, p[2 * i + 1]))
            return True
    return False

