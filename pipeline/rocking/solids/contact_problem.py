"""One time step's frictional contact problem of a rigid body (per unit mass): the contact impulses that satisfy
Signorini's condition and Coulomb's law at every contact at once (compiled).

The body's velocity before the contacts act is (v, w); a contact at arm r from G has the velocity
u = v + w x r, and an impulse P at arm r_d changes the velocity at arm r_c by W_cd P with the Delassus block
W_cd = 1 - [r_c]x I^-1 [r_d]x. Coulomb's law in De Saxce's form: with the modified velocity
u~ = u + mu |u_t| n, each impulse P lies in the friction cone K (``|P_t| <= mu P_n``) and -u~ in its normal
cone, which is the fixed point P = proj_K(P - rho u~) for any rho > 0 (De Saxce & Feng 1998). The normal velocity
is measured against Newton's target: ``-e_n`` times its value before the step.

Solved by projected Gauss-Seidel over the contacts (Jean 1999), each contact by one step of the fixed point with
rho below the inverse of its block's largest eigenvalue, until no impulse changes by more than
:data:`SWEEP_TOL` times the step's weight impulse in a whole sweep (converged), or :data:`MAX_SWEEPS` (flagged).
The sweeps converge slowly where the contacts are coupled: a slender body on an edge (two contacts, the
Delassus matrix's nonzero eigenvalues 0.04-12 for a 0.5 x 0.5 x 3 m statue) took 380 sweeps a step on average
over the 144 scenes of ``benchmarks/contact3d_peer.py``. Where at
most :data:`NEWTON_MAX_CONTACTS` touch, the sweeps therefore start from a semismooth Newton solve of the fixed
point of all the contacts together (Alart & Curnier 1991 solve the same kind of nonsmooth system by Newton's
method; here the natural map of De Saxce's law, with its generalized Jacobian, Levenberg-Marquardt's damping for
the rank-deficient W and a backtracking line search on its squared norm). The Newton solve only gives the
sweeps a starting point: convergence is still the sweeps' own criterion, so a step is accepted exactly as
without it. Where the pivot passes from one contact to a neighbour close by (a cylinder's rim points 2.5 cm
apart: their Delassus matrix's smallest nonzero eigenvalue 1.4e-3 against 11.5), Newton from the last step's
impulses stalls at a minimum of its squared norm that loads the wrong contact, and the sweeps converge only after
thousands; Newton then starts again with the step's weight impulse on each contact alone, and with no impulse
(:func:`solve_contacts`): of 9 such steps of at most four contacts captured on two bundled records
(docs/validation.md), one of those starts converged each of the 6 with two contacts (in one iteration and one
sweep) and 2 of the 3 with four. Where more contacts touch than Newton takes (a cylinder's base on up to 32 rim
points, as rocking starts or the body lands), the sweeps alone crept for tens of thousands; after their first
rounds Newton solves the 1, 2, 3 and then 4 contacts farthest toward the side the body's free horizontal velocity
points to, the others without impulse, then the 1-4 that approach the ground fastest, and the sweeps go on from
each (:func:`_side_starts`). A cylinder barely tilted touches on 5-15 nearly collinear points of one rim arc; with
Newton on at most four contacts and the first ranking alone, 53 of 88 capped steps captured on five records
converged; with the second ranking 64, and with Newton on up to eight contacts together 79
(docs/validation.md).

References
----------
Alart, P. & Curnier, A. (1991). A mixed formulation for frictional contact problems prone to Newton like
solution methods. Computer Methods in Applied Mechanics and Engineering 92(3), 353-375.
De Saxce, G. & Feng, Z.-Q. (1998). The bipotential method: a constructive approach to design the complete contact
law with friction and improved numerical algorithms. Mathematical and Computer Modelling 28(4-8), 225-245.
Jean, M. (1999). The non-smooth contact dynamics method. Computer Methods in Applied Mechanics and Engineering
177(3-4), 235-257.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...compiled import jit_inline, jit_lean

#: Gauss-Seidel sweeps: converged when no impulse changes by more than this fraction of the step's weight
#: impulse (g h per unit mass) [-], or flagged at the cap.
SWEEP_TOL = 1e-8
MAX_SWEEPS = 2000
#: The Newton start: tried where at most this many contacts touch (its Jacobian is 3 n square) ...
NEWTON_MAX_CONTACTS = 8
#: ... for at most this many iterations, ended sooner once the natural map is below NEWTON_TOL times SWEEP_TOL
#: times the weight impulse, or where the line search finds no decrease in LINE_SEARCH_HALVINGS halvings.
NEWTON_ITERATIONS = 10
NEWTON_TOL = 0.1
LINE_SEARCH_HALVINGS = 8
#: Where Newton stalls (at a kink of the cone's projection), the sweeps take SWEEPS_PER_ROUND and Newton starts
#: again from where they got, for NEWTON_ROUNDS - 1 rounds; then once from the weight on each contact alone and
#: once from no impulse (more contacts than Newton takes: as many sweeps instead); then on the first 1, 2, ...
#: SIDE_CONTACTS contacts of two rankings alone; the last round's sweeps go on to MAX_SWEEPS in all.
NEWTON_ROUNDS = 4
SWEEPS_PER_ROUND = 25
SIDE_CONTACTS = 4
#: Levenberg-Marquardt damping: this fraction of the largest diagonal of J^T J [-].
LM_DAMPING = 1e-12
#: ... raised by this factor where a step finds no decrease, up to LM_DAMPING_MAX (then Newton stops).
LM_DAMPING_RAISE = 1e4
LM_DAMPING_MAX = 1e-1


class Workspace(NamedTuple):
    """The arrays a step's contact problem works in, made once per run (m = 3 min(n, NEWTON_MAX_CONTACTS)) for up to
    n contacts."""

    big: np.ndarray         # (m, m) the Delassus matrix
    jac: np.ndarray         # (m, m) the natural map's Jacobian
    normal: np.ndarray      # (m, m) J^T J + lambda 1, then its Cholesky factor
    q: np.ndarray           # (m,) the contacts' velocities before any impulse
    pv: np.ndarray          # (m,) the impulses
    f: np.ndarray           # (m,) the natural map at pv
    trial: np.ndarray       # (m,) the line search's impulses
    f_trial: np.ndarray     # (m,) the natural map there
    step: np.ndarray        # (m,) the Newton step
    cone: np.ndarray        # (3, 3) the cone projection's derivative
    block: np.ndarray       # (3, 3) I^-1 [r]x
    rho: np.ndarray         # (n,) the sweeps' step per contact
    held: np.ndarray        # (n, 3) the impulses the sweeps got to, kept while Newton tries other starts
    score: np.ndarray       # (n,) the contacts' scores a Newton start on some of them ranks
    side: np.ndarray        # (k,) int: the contacts a Newton start on some of them takes (k <= SIDE_CONTACTS)
    side_arms: np.ndarray   # (k, 3) their arms
    side_before: np.ndarray     # (k,) their normal velocities before the step
    side_p: np.ndarray      # (k, 3) their impulses
    side_rho: np.ndarray    # (k,) their steps
    free: np.ndarray        # (6,) the body's velocity and rate before any contact impulse


def workspace(n: int) -> Workspace:
    """A :class:`Workspace` for up to ``n`` contacts: the Newton start's matrices and vectors for the
    :data:`NEWTON_MAX_CONTACTS` it takes at most (a scan's hull has hundreds of vertices: 3 n square would be
    55 MB a matrix at 875), the sweeps' steps for all ``n``."""
    m = 3 * max(min(n, NEWTON_MAX_CONTACTS), 1)
    k, n = max(min(n, SIDE_CONTACTS), 1), max(n, 1)
    return Workspace(np.empty((m, m)), np.empty((m, m)), np.empty((m, m)), np.empty(m), np.empty(m), np.empty(m),
                     np.empty(m), np.empty(m), np.empty(m), np.empty((3, 3)), np.empty((3, 3)), np.empty(n),
                     np.empty((n, 3)), np.empty(n), np.empty(k, dtype=np.int64), np.empty((k, 3)), np.empty(k),
                     np.empty((k, 3)), np.empty(k), np.empty(6))


@jit_inline
def apply_impulse(v, w, inv_i, px, py, pz, rx, ry, rz):
    """Add an impulse P (per unit mass) at r from G to the body's velocity v and rate w."""
    v[0] += px
    v[1] += py
    v[2] += pz
    mx, my, mz = ry * pz - rz * py, rz * px - rx * pz, rx * py - ry * px
    for i in range(3):
        w[i] += inv_i[i, 0] * mx + inv_i[i, 1] * my + inv_i[i, 2] * mz


@jit_inline
def _cross_inv(inv_i, rx, ry, rz, out):
    """I^-1 [r]x into ``out`` (3 x 3)."""
    for i in range(3):
        out[i, 0] = inv_i[i, 1] * rz - inv_i[i, 2] * ry
        out[i, 1] = inv_i[i, 2] * rx - inv_i[i, 0] * rz
        out[i, 2] = inv_i[i, 0] * ry - inv_i[i, 1] * rx


@jit_inline
def delassus(inv_i, arms, n_c, out, a):
    """The Delassus matrix W of the first ``n_c`` contacts into ``out`` (3 n_c square): the velocity at contact c
    per unit impulse at contact d, W_cd = 1 - [r_c]x I^-1 [r_d]x (``a``: room for I^-1 [r_d]x)."""
    for d in range(n_c):
        _cross_inv(inv_i, arms[d, 0], arms[d, 1], arms[d, 2], a)
        for c in range(n_c):
            rx, ry, rz = arms[c, 0], arms[c, 1], arms[c, 2]
            for j in range(3):                                  # [r_c]x times column j of a
                out[3 * c, 3 * d + j] = -(ry * a[2, j] - rz * a[1, j])
                out[3 * c + 1, 3 * d + j] = -(rz * a[0, j] - rx * a[2, j])
                out[3 * c + 2, 3 * d + j] = -(rx * a[1, j] - ry * a[0, j])
            for i in range(3):                                  # every block: the impulse moves G too
                out[3 * c + i, 3 * d + i] += 1.0


@jit_inline
def onto_cone(px, py, pz, mu):
    """The Euclidean projection of an impulse onto the friction cone |P_t| <= mu P_n."""
    t = math.sqrt(px * px + py * py)
    if t <= mu * pz:
        return px, py, pz
    if mu * t <= -pz:                                           # inside the polar cone: nothing
        return 0.0, 0.0, 0.0
    n = (mu * t + pz) / (1.0 + mu * mu)
    return mu * n * px / t, mu * n * py / t, n


@jit_inline
def _cone_derivative(zx, zy, zz, mu, out):
    """The derivative of :func:`onto_cone` at z into ``out`` (3 x 3; on a boundary between its pieces, the
    piece's whose formula :func:`onto_cone` uses)."""
    t = math.sqrt(zx * zx + zy * zy)
    out[:, :] = 0.0
    if t <= mu * zz:
        for i in range(3):
            out[i, i] = 1.0
        return
    if mu * t <= -zz:
        return
    k = 1.0 / (1.0 + mu * mu)
    s = (mu * t + zz) * k
    tx, ty = zx / t, zy / t
    tt = ((tx * tx, tx * ty), (ty * tx, ty * ty))
    for i in range(2):
        for j in range(2):
            out[i, j] = mu * (mu * k * tt[i][j] + s / t * ((1.0 if i == j else 0.0) - tt[i][j]))
    out[0, 2], out[1, 2] = mu * k * tx, mu * k * ty
    out[2, 0], out[2, 1] = mu * k * tx, mu * k * ty
    out[2, 2] = k


@jit_lean
def _natural_map(big, q, pv, rho, mu, n_c, f, jac, dp, with_jacobian):
    """De Saxce's natural map F(P) = P - proj_K(P - rho u~(P)) of every contact (u = W P + q) into ``f``, and with
    ``with_jacobian`` its generalized Jacobian into ``jac`` (``dp``: room for the cone's derivative); the sum of
    its squares."""
    m = 3 * n_c
    total = 0.0
    for c in range(n_c):
        u0, u1, u2 = q[3 * c], q[3 * c + 1], q[3 * c + 2]
        for j in range(m):
            u0 += big[3 * c, j] * pv[j]
            u1 += big[3 * c + 1, j] * pv[j]
            u2 += big[3 * c + 2, j] * pv[j]
        ut = math.sqrt(u0 * u0 + u1 * u1)
        r = rho[c]
        zx, zy, zz = pv[3 * c] - r * u0, pv[3 * c + 1] - r * u1, pv[3 * c + 2] - r * (u2 + mu * ut)
        nx, ny, nz = onto_cone(zx, zy, zz, mu)
        f[3 * c], f[3 * c + 1], f[3 * c + 2] = pv[3 * c] - nx, pv[3 * c + 1] - ny, pv[3 * c + 2] - nz
        total += f[3 * c] ** 2 + f[3 * c + 1] ** 2 + f[3 * c + 2] ** 2
        if not with_jacobian:
            continue
        _cone_derivative(zx, zy, zz, mu, dp)
        sx, sy = (mu * u0 / ut, mu * u1 / ut) if ut > 0.0 else (0.0, 0.0)
        for j in range(m):
            b0, b1, b2 = big[3 * c, j], big[3 * c + 1, j], big[3 * c + 2, j]
            d0 = (1.0 if j == 3 * c else 0.0) - r * b0          # dz / dP_j
            d1 = (1.0 if j == 3 * c + 1 else 0.0) - r * b1
            d2 = (1.0 if j == 3 * c + 2 else 0.0) - r * (b2 + sx * b0 + sy * b1)
            for i in range(3):
                jac[3 * c + i, j] = (1.0 if j == 3 * c + i else 0.0) - (dp[i, 0] * d0 + dp[i, 1] * d1 + dp[i, 2] * d2)
    return total


@jit_lean
def _damped_step(jac, f, m, a, step, damping):
    """The Levenberg-Marquardt step: (J^T J + lambda 1) step = -J^T f with lambda ``damping`` times the largest
    diagonal of J^T J, by Cholesky (``a``: room for the matrix)."""
    top = 0.0
    for i in range(m):
        for j in range(i, m):
            s = 0.0
            for k in range(m):
                s += jac[k, i] * jac[k, j]
            a[i, j] = a[j, i] = s
        top = max(top, a[i, i])
        s = 0.0
        for k in range(m):
            s -= jac[k, i] * f[k]
        step[i] = s
    for i in range(m):
        a[i, i] += damping * top + 1e-300
    for j in range(m):                                          # a = L L^T, L in the lower triangle
        s = a[j, j]
        for k in range(j):
            s -= a[j, k] * a[j, k]
        a[j, j] = math.sqrt(max(s, 1e-300))
        for i in range(j + 1, m):
            s = a[i, j]
            for k in range(j):
                s -= a[i, k] * a[j, k]
            a[i, j] = s / a[j, j]
    for i in range(m):                                          # L y = b, then L^T x = y
        s = step[i]
        for k in range(i):
            s -= a[i, k] * step[k]
        step[i] = s / a[i, i]
    for i in range(m - 1, -1, -1):
        s = step[i]
        for k in range(i + 1, m):
            s -= a[k, i] * step[k]
        step[i] = s / a[i, i]


@jit_lean
def newton_start(v, w, inv_i, arms, n_c, u_before, mu, e_n, scale, p, work, rho):
    """Replace the starting impulses ``p`` by Newton's solve of all the contacts' fixed point together (the body's
    velocity (v, w) before any contact impulse; ``work`` a :class:`Workspace`, ``rho`` the contacts' steps); each
    iteration is kept only where it lowers the natural map's squared norm. Returns the iterations taken."""
    m = 3 * n_c
    big, jac, dp = work.big, work.jac, work.cone
    q, pv, f, trial, f_trial, step = work.q, work.pv, work.f, work.trial, work.f_trial, work.step
    delassus(inv_i, arms, n_c, big, work.block)
    for c in range(n_c):
        rx, ry, rz = arms[c, 0], arms[c, 1], arms[c, 2]
        q[3 * c] = v[0] + w[1] * rz - w[2] * ry
        q[3 * c + 1] = v[1] + w[2] * rx - w[0] * rz
        q[3 * c + 2] = v[2] + w[0] * ry - w[1] * rx + (e_n * u_before[c] if u_before[c] < 0.0 else 0.0)
        pv[3 * c], pv[3 * c + 1], pv[3 * c + 2] = p[c, 0], p[c, 1], p[c, 2]
    # bool() and int() below: one compiled version of each callee (pipeline.compiled)
    size = _natural_map(big, q, pv, rho, mu, n_c, f, jac, dp, bool(True))
    goal = (NEWTON_TOL * SWEEP_TOL * scale) ** 2
    taken = 0
    damping = LM_DAMPING
    while taken < NEWTON_ITERATIONS and size > goal:
        taken += 1
        _damped_step(jac, f, m, work.normal, step, damping)
        t, better = 1.0, False
        for _ in range(LINE_SEARCH_HALVINGS):
            for i in range(m):
                trial[i] = pv[i] + t * step[i]
            new = _natural_map(big, q, trial, rho, mu, n_c, f_trial, jac, dp, bool(False))
            if new < size:
                better = True
                break
            t *= 0.5
        if not better:
            if damping >= LM_DAMPING_MAX:
                break
            damping *= LM_DAMPING_RAISE                         # toward steepest descent, the same Jacobian
            continue
        damping = LM_DAMPING
        for i in range(m):
            pv[i] = trial[i]
        size = new
        if size > goal and taken < NEWTON_ITERATIONS:       # the Jacobian only where another iteration needs it
            _natural_map(big, q, pv, rho, mu, n_c, f, jac, dp, bool(True))
    for c in range(n_c):
        p[c, 0], p[c, 1], p[c, 2] = pv[3 * c], pv[3 * c + 1], pv[3 * c + 2]
    return taken


@jit_inline
def _step_sizes(inv_i, arms, n_c, a, block, rho):
    """rho per contact into ``rho``: the inverse of a Gershgorin bound on the largest eigenvalue of its Delassus
    block 1 - [r]x I^-1 [r]x (:func:`delassus` of the contact alone; ``a``, ``block``: room for 3 x 3)."""
    for c in range(n_c):
        delassus(inv_i, arms[c:c + 1], 1, block, a)
        bound = 0.0
        for i in range(3):
            bound = max(bound, abs(block[i, 0]) + abs(block[i, 1]) + abs(block[i, 2]))
        rho[c] = 1.0 / bound


@jit_lean
def sweep_contacts(v, w, inv_i, arms, n_c, u_before, mu, e_n, scale, p, work, most=MAX_SWEEPS):
    """Projected Gauss-Seidel sweeps from the impulses ``p`` (the body's velocity (v, w) before any contact impulse;
    ``work`` a :class:`Workspace` with its ``rho`` set): applied to (v, w) and left in ``p``. The sweeps taken, or
    -1 after ``most`` without converging."""
    rho = work.rho
    for c in range(n_c):
        apply_impulse(v, w, inv_i, p[c, 0], p[c, 1], p[c, 2], arms[c, 0], arms[c, 1], arms[c, 2])
    for sweep in range(most):
        change = 0.0
        for c in range(n_c):
            rx, ry, rz = arms[c, 0], arms[c, 1], arms[c, 2]
            ux = v[0] + w[1] * rz - w[2] * ry
            uy = v[1] + w[2] * rx - w[0] * rz
            uz = v[2] + w[0] * ry - w[1] * rx + (e_n * u_before[c] if u_before[c] < 0.0 else 0.0)
            uz += mu * math.sqrt(ux * ux + uy * uy)
            nx, ny, nz = onto_cone(p[c, 0] - rho[c] * ux, p[c, 1] - rho[c] * uy, p[c, 2] - rho[c] * uz, mu)
            dx, dy, dz = nx - p[c, 0], ny - p[c, 1], nz - p[c, 2]
            apply_impulse(v, w, inv_i, dx, dy, dz, rx, ry, rz)
            p[c, 0], p[c, 1], p[c, 2] = nx, ny, nz
            change = max(change, abs(dx), abs(dy), abs(dz))
        if change <= SWEEP_TOL * scale:
            return sweep + 1
    return -1


@jit_lean
def solve_contacts(v, w, inv_i, arms, n_c, u_before, mu, e_n, scale, p, work):
    """The step's contact impulses (the body's velocity (v, w) before any contact impulse), in the
    :class:`Workspace` ``work``: the sweeps of :func:`sweep_contacts` from the start ``p`` (the previous step's
    impulses at the same vertices), or from Newton's solve where at most :data:`NEWTON_MAX_CONTACTS` touch;
    applied to (v, w) and left in ``p``. The sweeps taken, or -1 at the cap.

    At most :data:`NEWTON_MAX_CONTACTS` contacts: Newton's rounds start from ``p``, then from where the sweeps got
    (:data:`NEWTON_ROUNDS` - 1 rounds of :data:`SWEEPS_PER_ROUND` sweeps), then from the step's weight impulse
    ``scale`` on each contact alone and from no impulse (one round each). More: as many sweeps from ``p`` as those
    first rounds take. Then, either way, Newton on some of the contacts alone (:func:`_side_starts`); the last
    round goes on from where the first rounds got, to :data:`MAX_SWEEPS` in all."""
    _step_sizes(inv_i, arms, n_c, work.block, work.cone, work.rho)
    few = n_c <= NEWTON_MAX_CONTACTS
    free = work.free
    free[0], free[1], free[2], free[3], free[4], free[5] = v[0], v[1], v[2], w[0], w[1], w[2]
    done = (NEWTON_ROUNDS - 1) * SWEEPS_PER_ROUND
    if not few:
        taken = sweep_contacts(v, w, inv_i, arms, n_c, u_before, mu, e_n, scale, p, work, done)
        if taken > 0:
            return taken
    for r in range(NEWTON_ROUNDS - 1 if few else 0):            # Newton again from where the sweeps got
        taken = _round(v, w, inv_i, arms, n_c, u_before, mu, e_n, scale, p, work)
        if taken > 0:
            return r * SWEEPS_PER_ROUND + taken
        _reset(v, w, free)
    _copy(p, work.held, n_c)
    _reset(v, w, free)
    for alone in range(n_c + 1 if few else 0):                  # the weight on one contact (n_c: on none)
        for c in range(n_c):
            p[c, 0], p[c, 1], p[c, 2] = 0.0, 0.0, scale if c == alone else 0.0
        taken = _round(v, w, inv_i, arms, n_c, u_before, mu, e_n, scale, p, work)
        if taken > 0:
            return done + taken
        done += SWEEPS_PER_ROUND
        _reset(v, w, free)
    taken, done = _side_starts(v, w, inv_i, arms, n_c, u_before, mu, e_n, scale, p, work, done)
    if taken > 0:
        return done + taken
    _reset(v, w, free)
    _copy(work.held, p, n_c)
    if few:
        newton_start(v, w, inv_i, arms, n_c, u_before, mu, e_n, scale, p, work, work.rho)
    taken = sweep_contacts(v, w, inv_i, arms, n_c, u_before, mu, e_n, scale, p, work, MAX_SWEEPS - done)
    return done + taken if taken > 0 else -1


@jit_inline
def _reset(v, w, free):
    """(v, w) back to the body's velocity and rate before any contact impulse (``free``, stacked)."""
    v[0], v[1], v[2], w[0], w[1], w[2] = free[0], free[1], free[2], free[3], free[4], free[5]


@jit_inline
def _round(v, w, inv_i, arms, n_c, u_before, mu, e_n, scale, p, work):
    """Newton from ``p``, then :data:`SWEEPS_PER_ROUND` sweeps: the sweeps taken, or -1."""
    newton_start(v, w, inv_i, arms, n_c, u_before, mu, e_n, scale, p, work, work.rho)
    return sweep_contacts(v, w, inv_i, arms, n_c, u_before, mu, e_n, scale, p, work, int(SWEEPS_PER_ROUND))


@jit_inline
def _side_starts(v, w, inv_i, arms, n_c, u_before, mu, e_n, scale, p, work, done):
    """From the body's velocity before any contact impulse (``work.free``): Newton on the first 1, 2, ...
    :data:`SIDE_CONTACTS` contacts farthest toward the side the body's free horizontal velocity points to, the
    others without impulse, and one round of sweeps from each (:func:`_tipping_side`); then the same on as many of
    the contacts that approach the ground fastest. The sweeps taken by the round that converged (or -1) and the
    sweeps ``done`` before it."""
    free = work.free
    for ranking in range(2):
        most = min(n_c, SIDE_CONTACTS) if ranking == 1 or free[0] != 0.0 or free[1] != 0.0 else 1
        _rank(_side_scores(free, arms, n_c, work.score, ranking), n_c, work.side, most)
        for k in range(1, most + 1):
            _reset(v, w, free)
            _tipping_side(v, w, inv_i, arms, n_c, u_before, mu, e_n, scale, p, work, k)
            taken = sweep_contacts(v, w, inv_i, arms, n_c, u_before, mu, e_n, scale, p, work, int(SWEEPS_PER_ROUND))
            if taken > 0:
                return taken, done
            done += SWEEPS_PER_ROUND
    return -1, done


@jit_inline
def _side_scores(free, arms, n_c, score, ranking):
    """Into ``score``, for each contact (the body's free velocity and rate ``free``): ranking 0, how far it lies
    along the free horizontal velocity; ranking 1, how fast it approaches the ground (minus its normal velocity)."""
    for c in range(n_c):
        rx, ry = arms[c, 0], arms[c, 1]
        score[c] = rx * free[0] + ry * free[1] if ranking == 0 else -(free[2] + free[3] * ry - free[4] * rx)
    return score


@jit_inline
def _rank(score, n_c, side, most):
    """Into the first ``most`` of ``side``: the contacts of the highest ``score``, highest first."""
    for j in range(most):
        best, at = -math.inf, 0
        for c in range(n_c):
            if score[c] > best and not _chosen(side, j, c):
                best, at = score[c], c
        side[j] = at


@jit_inline
def _chosen(side, j, c):
    """Contact ``c`` among the first ``j`` of ``side``."""
    for i in range(j):
        if side[i] == c:
            return True
    return False


@jit_inline
def _tipping_side(v, w, inv_i, arms, n_c, u_before, mu, e_n, scale, p, work, k):
    """Into ``p``: Newton's solve of the first ``k`` contacts of ``work.side`` (:func:`_rank`; the body's
    velocity (v, w) before any contact impulse), from the step's weight impulse ``scale`` shared among them; no
    impulse at the others."""
    side, s_arms, s_before, s_p = work.side, work.side_arms, work.side_before, work.side_p
    for j in range(k):
        at = side[j]
        s_arms[j, 0], s_arms[j, 1], s_arms[j, 2] = arms[at, 0], arms[at, 1], arms[at, 2]
        s_before[j] = u_before[at]
        s_p[j, 0], s_p[j, 1], s_p[j, 2] = 0.0, 0.0, scale / k
    _step_sizes(inv_i, s_arms, k, work.block, work.cone, work.side_rho)
    newton_start(v, w, inv_i, s_arms, int(k), s_before, mu, e_n, scale, s_p, work, work.side_rho)
    for c in range(n_c):
        p[c, 0], p[c, 1], p[c, 2] = 0.0, 0.0, 0.0
    for j in range(k):
        p[side[j], 0], p[side[j], 1], p[side[j], 2] = s_p[j, 0], s_p[j, 1], s_p[j, 2]


@jit_inline
def _copy(source, target, n_c):
    """The first ``n_c`` impulses of ``source`` into ``target``."""
    for c in range(n_c):
        target[c, 0], target[c, 1], target[c, 2] = source[c, 0], source[c, 1], source[c, 2]
