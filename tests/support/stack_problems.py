"""One step's contact problems of stacks (:mod:`pipeline.assemblies.stack_contact`), for the tests of its solvers:
a stack's blocks placed by an n-block state (each joint shut, or turning on a corner), moved by given rates, gravity
and the ground's push applied over one step, and the contacts found at that configuration."""

from __future__ import annotations

import numpy as np
from stack_flights import RHO, STACKS

from pipeline.assemblies import stack_contact as sc
from pipeline.assemblies.n_block import MAX_BODIES, n_block
from pipeline.assemblies.stack import StackBody
from pipeline.assemblies.stack_pose import bodies_of, state_of

G = 9.80665
STEP_S = 2.5e-4


def problem(family: str, psi: tuple, rates: tuple, push: tuple, mu_ground: float, mu_joint: float, a_h: float,
            kept: np.ndarray | None = None):
    """The contact problem of one step of the stack ``family`` (:data:`stack_flights.STACKS`) from the n-block state
    (``psi`` [rad], ``rates`` [rad s-1] per joint), each block's velocity then changed by ``push`` (3 per block:
    [m s-1, m s-1, rad s-1]) and the step's gravity and ground ``a_h`` [m s-2]: (bodies, count, work) with the
    Delassus matrix and free velocities made, and the slots' impulses of the step before ``kept`` (None: none)."""
    boxes = STACKS[family]
    blocks = [StackBody(w, h, RHO * w * h, mu_ground if k == 0 else mu_joint) for k, (w, h) in enumerate(boxes)]
    nb = n_block(blocks)
    y = tuple(psi) + (0.0,) * (MAX_BODIES - nb.n) + tuple(rates) + (0.0,) * (MAX_BODIES - nb.n)
    q, v = state_of(nb, y)
    v = v + np.asarray(push, dtype=float).reshape(nb.n, 3).T
    bd = bodies_of(nb, [b.mu for b in blocks])
    wk = sc.work()
    for k in range(nb.n):
        wk.inv[0, k], wk.inv[1, k], wk.inv[2, k] = 1.0 / bd.m[k], 1.0 / bd.m[k], 1.0 / bd.i[k]
    q = q + 0.5 * STEP_S * v
    v[0] -= STEP_S * a_h
    v[1] -= STEP_S * G
    count = sc._contacts(bd, nb.n, q, wk)
    if count:
        sc._delassus(bd, count, wk)
        sc._relative(count, v, wk)
    if kept is not None:
        wk.kept[:kept.size] = kept
    return bd, count, wk


def velocities(count: int, wk) -> np.ndarray:
    """U = W P + q of the impulses in ``wk.p`` (per contact: normal, tangent) [m s-1]."""
    m = 2 * count
    return wk.w[:m, :m] @ wk.p[:m] + wk.rhs[:m]


def friction(bd, count: int, wk) -> np.ndarray:
    """Each contact's friction: its upper body's [-]."""
    return np.array([bd.mu[wk.body[i, 0]] for i in range(count)])
