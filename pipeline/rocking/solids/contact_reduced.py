"""A step's contact problem with many contacts on a face, solved on a few of them and verified on all (compiled).

The problem is :mod:`.contact_problem`'s: the impulses P_c of the contacts c = 1..n with

    v+ = v_free + M^-1 sum_c J_c^T P_c,     P_c in K,   u~_c in K*,   P_c . u~_c = 0

(De Saxce's form of Coulomb's law and Signorini's condition, u~_c = J_c v+ + (mu |u_t,c| + e_n u_c^-) n). A flat
face on the ground touches at every vertex of its polygon: a cylinder's base at 32 rim points, a scan's facet at as
many as its hull has. The body has six velocities, so most of those contacts are redundant, and the sweeps that
solve them all converge slowly (hundreds of sweeps a step measured on a 32-point cylinder sliding flat, one a step
on the same cylinder with 8 rim points).

Where more than :data:`~.contact_problem.NEWTON_MAX_CONTACTS` contacts touch, the step is therefore first solved on
that many of them, the extreme ones in as many horizontal directions about the contacts' centroid (a flat
cylinder's base: eight rim points 45 deg apart), the others without impulse. That solution is a solution of the
whole problem wherever every other contact, with P_c = 0, has u~_c in K*, which for P_c = 0 is u_n,c + e_n u_c^- >= 0:
it does not approach the ground against Newton's target. That is checked at every such contact, to
:data:`VERIFY_TOL` times the step's weight impulse; where it fails, or the reduced solve does not converge, the
whole problem is solved from the step's warm start as before (:func:`~.contact_problem.solve_contacts`). A kept
reduced solution solves the step's whole problem to the same tolerances as a solve of all its contacts (the sweeps'
on the kept contacts, :data:`VERIFY_TOL` on the others); where the problem has several solutions (redundant contacts
share a load in many ways), it is one of them.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...compiled import jit_inline, jit_lean
from .contact_problem import MAX_SWEEPS, NEWTON_MAX_CONTACTS, SWEEP_TOL, Workspace, _reset, solve_contacts, workspace

#: A contact left without impulse may approach the ground by at most this fraction of the step's weight impulse
#: g h [-] (the sweeps' own tolerance on an impulse, SWEEP_TOL) for the reduced solution to stand.
VERIFY_TOL = SWEEP_TOL


#: The horizontal directions k 360 / K deg (K = NEWTON_MAX_CONTACTS) along which the kept contacts are the farthest.
_DIRECTIONS = tuple((math.cos(a), math.sin(a)) for a in (2.0 * math.pi * d / NEWTON_MAX_CONTACTS
                                                          for d in range(NEWTON_MAX_CONTACTS)))


class Solvers(NamedTuple):
    """The arrays a step's contact problem works in, made once per run: the whole problem's
    :class:`~.contact_problem.Workspace` and the reduced problem's contacts (k <= NEWTON_MAX_CONTACTS)."""

    whole: Workspace
    kept: np.ndarray        # (k,) int: the contacts kept
    arms: np.ndarray        # (k, 3) their arms
    before: np.ndarray      # (k,) their normal velocities before the step
    p: np.ndarray           # (k, 3) their impulses
    free: np.ndarray        # (6,) the body's velocity and rate before any contact impulse


def solvers(n: int) -> Solvers:
    """:class:`Solvers` for up to ``n`` contacts."""
    k = NEWTON_MAX_CONTACTS
    return Solvers(workspace(n), np.empty(k, dtype=np.int64), np.empty((k, 3)), np.empty(k), np.empty((k, 3)),
                   np.empty(6))


@jit_lean
def solve_step(v, w, inv_i, arms, n_c, u_before, mu, e_n, scale, p, work):
    """The step's contact impulses (the body's velocity (v, w) before any contact impulse; ``p`` the warm start),
    applied to (v, w) and left in ``p``: where more than NEWTON_MAX_CONTACTS touch, on the extreme ones alone if that
    solves the whole problem (:func:`_holds_without`), else, and with fewer contacts, on all
    (:func:`~.contact_problem.solve_contacts`). The sweeps taken (those of a reduced solve that did not hold
    included), or -1 at the cap."""
    if n_c <= NEWTON_MAX_CONTACTS:
        return solve_contacts(v, w, inv_i, arms, n_c, u_before, mu, e_n, scale, p, work.whole)
    free = work.free
    free[0], free[1], free[2], free[3], free[4], free[5] = v[0], v[1], v[2], w[0], w[1], w[2]
    k = _extremes(arms, n_c, work.kept)
    for j in range(k):
        c = work.kept[j]
        work.arms[j, 0], work.arms[j, 1], work.arms[j, 2] = arms[c, 0], arms[c, 1], arms[c, 2]
        work.before[j] = u_before[c]
        work.p[j, 0], work.p[j, 1], work.p[j, 2] = p[c, 0], p[c, 1], p[c, 2]
    # int(k): one compiled version, not one more for the literal 0 k starts at (pipeline.compiled)
    taken = solve_contacts(v, w, inv_i, work.arms, int(k), work.before, mu, e_n, scale, work.p, work.whole)
    if taken > 0 and _holds_without(v, w, arms, n_c, u_before, e_n, work.kept, k, VERIFY_TOL * scale):
        for c in range(n_c):
            p[c, 0], p[c, 1], p[c, 2] = 0.0, 0.0, 0.0
        for j in range(k):
            c = work.kept[j]
            p[c, 0], p[c, 1], p[c, 2] = work.p[j, 0], work.p[j, 1], work.p[j, 2]
        return taken
    spent = taken if taken > 0 else MAX_SWEEPS
    _reset(v, w, free)
    whole = solve_contacts(v, w, inv_i, arms, n_c, u_before, mu, e_n, scale, p, work.whole)
    return -1 if whole < 0 else spent + whole


@jit_inline
def _extremes(arms, n_c, index):
    """Into ``index``: the contacts farthest along NEWTON_MAX_CONTACTS horizontal directions k 360 / K deg about the
    contacts' centroid, each once (ties: the first); how many."""
    cx, cy = 0.0, 0.0
    for c in range(n_c):
        cx += arms[c, 0]
        cy += arms[c, 1]
    cx, cy = cx / n_c, cy / n_c
    k = 0
    for d in range(NEWTON_MAX_CONTACTS):
        dx, dy = _DIRECTIONS[d]
        best, at = -math.inf, 0
        for c in range(n_c):
            s = (arms[c, 0] - cx) * dx + (arms[c, 1] - cy) * dy
            if s > best:
                best, at = s, c
        known = False
        for j in range(k):
            known = known or index[j] == at
        if not known:
            index[k] = at
            k += 1
    return k


@jit_inline
def _holds_without(v, w, arms, n_c, u_before, e_n, index, k, tol):
    """Whether every contact not among the first ``k`` of ``index``, without impulse, obeys the law at the body's
    velocity (v, w) after the step: u_n + e_n u^- >= -``tol`` (with P = 0, u~ in K* is exactly that)."""
    for c in range(n_c):
        kept = False
        for j in range(k):
            kept = kept or index[j] == c
        if kept:
            continue
        un = v[2] + w[0] * arms[c, 1] - w[1] * arms[c, 0] + (e_n * u_before[c] if u_before[c] < 0.0 else 0.0)
        if un < -tol:
            return False
    return True
