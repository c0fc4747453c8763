"""A stack of n blocks seen by the slide-rock model (:mod:`.slide_rock`): two rigid parts, the blocks below the
sliding joint and the blocks above it, each part's own joints shut; and the loads those shut joints carry, which
say where the two-part picture stops holding.

The stack turns as one by phi on a base corner of block 0 (``pivot``), and the upper part slides by u along the
sliding joint. In the lower part's frame (x along its base, z normal to it; origin the pivot), block k's centre is
at rho_k = (x_k - pivot b_0, z_k), x_k and z_k from block 0's base centre (an upper block's shifted by u along the
joint). With the field per unit mass f = (f_e, f_n) in that frame (:mod:`.slide_rock`), block k's centre
accelerates at

    a_k = (phi'' z_k - phi'^2 x_k + [u'' ], -phi'' x_k - phi'^2 z_k - [2 phi' u']),

the bracketed terms for the upper part's blocks only (the slip's acceleration and Coriolis' term). The part above
joint k (blocks k .. n - 1) is pushed by the block below with the force F = sum m_i (a_i - f) (Newton's second law
for each block, summed) and its moment about joint k's face centre O_k is

    M = sum (x_i - x_O) m_i (a_i - f)_n - (z_i - z_O) m_i (a_i - f)_e - (sum I_i) phi'',

so that the joint's centre of pressure lies x_p = M / F_n from O_k along the face (Euler's law for the blocks
above it). The joint stays shut and sticking while F_n > 0, |F_e| <= mu_k F_n and x_p lies strictly inside the overlap
of its faces; at joint 0 (the ground) F is the ground's reaction, and at the sliding joint F_e is its friction.
An impact is checked the same way with the blocks' velocity changes in place of a_i - f and of phi''.

References
----------
Goldstein, H., Poole, C. & Safko, J. (2002). Classical Mechanics, 3rd ed., chapter 1 (Newton's and Euler's laws for
a system of particles). Addison-Wesley.
Psycharis, I. N. (1990). Dynamic behaviour of rocking two-block assemblies. Earthquake Engineering & Structural
Dynamics 19(4), 555-575.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..compiled import jit
from ..constants import G
from ..errors import ParameterError
from .exact_run import as_two_block
from .n_block import MAX_BODIES, NBlock
from .two_block_run import scales

#: A shut joint of a part: holding, opening (not pressed, or its centre of pressure outside its faces' overlap),
#: slipping
INNER_HOLDS, INNER_OPENS, INNER_SLIPS = 0, 1, 2


class SlideRock(NamedTuple):
    """The stack's two parts (a numba namedtuple): the blocks below the sliding joint (the lower part, rigid while it
    turns on a corner of its base) and the blocks above it (the upper part), each part's joints shut. The lower's base
    half-width, its centre of mass's height above its base [m], mass [kg] and moment of inertia about its centre of
    mass [kg m2]; the same of the upper (its base half-width, its centre of mass's height above the joint); the
    friction of the ground under the lower and of the joint [-]; the lower's centre of mass and its top face's centre
    from its base centre along its base [m], the joint's height above the lower's base and the top face's half-width
    [m]; the upper's centre of mass from its base centre along the joint [m]. Two blocks: each part is one block."""

    b0: float
    h0: float
    m0: float
    i0: float
    b1: float
    h1: float
    m1: float
    i1: float
    mu0: float
    mu1: float
    x0: float
    top0: float
    xt0: float
    bt0: float
    x1: float


class Parts(NamedTuple):
    """The blocks of the two parts, for the checks of the parts' own joints (a numba namedtuple, apart from
    :class:`SlideRock`, which every step's equations read; its blocks in one array, which a compiled call takes by
    reference): ``table`` (rows :data:`B`, :data:`H`, :data:`M`, :data:`INERTIA`, :data:`OFF`, :data:`PX`, :data:`PZ`,
    :data:`MU`: each block's half-width and half-height [m], mass [kg], moment of inertia about its centre [kg m2],
    base centre from the centre of the top under it [m], base centre from its part's base centre along the bases and
    up [m], friction at its base [-]), the blocks, the sliding joint (the upper part's lowest block), block 0's base
    half-width, the lower part's top face's centre from its base centre and the joint's height [m]."""

    table: np.ndarray
    n: int
    joint: int
    b0: float
    xt0: float
    top0: float


#: The rows of :attr:`Parts.table`
B, H, M, INERTIA, OFF, PX, PZ, MU = range(8)


class _Part(NamedTuple):
    """One part's mass [kg], centre of mass (x, z) from its base centre [m] and moment of inertia about it [kg m2]."""

    m: float
    x: float
    z: float
    i: float


def _part(nb: NBlock, blocks: range, px: list, pz: list) -> _Part:
    """The part of ``blocks`` (its blocks' base centres ``px``, ``pz`` from the part's base centre): one block's own
    values where it is one block, else the sums (the parallel-axis theorem)."""
    if len(blocks) == 1:
        k = blocks[0]
        return _Part(nb.m[k], px[k], pz[k] + nb.h[k], nb.i[k])
    m = sum(nb.m[k] for k in blocks)
    x = sum(nb.m[k] * px[k] for k in blocks) / m
    z = sum(nb.m[k] * (pz[k] + nb.h[k]) for k in blocks) / m
    i = sum(nb.i[k] + nb.m[k] * ((px[k] - x) ** 2 + (pz[k] + nb.h[k] - z) ** 2) for k in blocks)
    return _Part(m, x, z, i)


def _placed(nb: NBlock, joint: int) -> tuple[list, list]:
    """Each block's base centre from its part's base centre (x along the bases, z up) [m]: the lower part's from block
    0's, the upper's from block ``joint``'s (``joint`` = n: the whole stack from block 0's)."""
    px, pz = [0.0] * MAX_BODIES, [0.0] * MAX_BODIES
    for k in range(1, nb.n):
        if k != joint:
            px[k], pz[k] = px[k - 1] + nb.off[k], pz[k - 1] + 2.0 * nb.h[k - 1]
    return px, pz


def parts_of(nb: NBlock, mu, joint: int = 1) -> tuple[SlideRock, Parts]:
    """The :class:`SlideRock` and the :class:`Parts` of the stack ``nb`` (each block's friction at its base ``mu``
    [-]) sliding at ``joint`` (1 .. n - 1), its other joints shut at their offsets ``nb.off`` (the sliding joint's own
    offset is the model's u)."""
    if not 1 <= joint < nb.n:
        raise ParameterError(f"joint = {joint}: expected a joint between two blocks of the stack, 1 to {nb.n - 1}")
    px, pz = _placed(nb, joint)
    lower, upper = _part(nb, range(joint), px, pz), _part(nb, range(joint, nb.n), px, pz)
    top0 = pz[joint - 1] + 2.0 * nb.h[joint - 1]                     # the joint's height above block 0's base
    sr = SlideRock(nb.b[0], lower.z, lower.m, lower.i, nb.b[joint], upper.z, upper.m, upper.i, float(mu[0]),
                   float(mu[joint]), lower.x, top0, px[joint - 1], nb.b[joint - 1], upper.x)
    mus = [float(x) for x in mu[:nb.n]] + [0.0] * (MAX_BODIES - nb.n)
    table = np.array([nb.b, nb.h, nb.m, nb.i, nb.off, px, pz, mus], dtype=float)
    return sr, Parts(table, nb.n, joint, nb.b[0], px[joint - 1], top0)


def rocking_scales(nb: NBlock) -> tuple[float, float, float]:
    """The stack rocking as one, the scales of the run's error control: its angle alpha [rad] and frequency p
    [rad s-1] on a base corner (its centre of mass taken over the base's centre), and its height [m] (two blocks: the
    two-block run's own scales)."""
    height = 2.0 * sum(nb.h[:nb.n])
    if nb.n == 2:
        rocks = scales(as_two_block(nb))
        return rocks.alpha1, rocks.p1, height
    whole = _part(nb, range(nb.n), *_placed(nb, nb.n))
    inertia = whole.i + whole.m * ((whole.x - nb.b[0]) ** 2 + whole.z ** 2)        # about the corner
    return math.atan2(nb.b[0], whole.z), math.sqrt(whole.m * G * math.hypot(nb.b[0], whole.z) / inertia), height


@jit
def base_at(parts, pivot, u, k):
    """Block k's base centre from the pivot in the lower part's frame [m] (the upper part's shifted by ``u``)."""
    x, z = parts.table[PX, k] - pivot * parts.b0, parts.table[PZ, k]
    if k >= parts.joint:
        x, z = x + parts.xt0 + u, z + parts.top0
    return x, z


@jit
def _load(parts, pivot, u, k, turn, spin_sq, shift, slip_e, slip_n, fe, fn):
    """The module's sums above joint k for a motion common to the blocks: each block's centre (x, z) from the pivot
    changes by (turn z - spin_sq x - fe, -turn x - spin_sq z + shift - fn), plus (slip_e, slip_n) for the upper part's
    blocks, and each turns by ``turn``; returns the sums along the face and normal to it and their centre from block
    k's base centre along the face (NaN where the normal sum does not press)."""
    ox, oz = base_at(parts, pivot, u, k)
    s_e, s_n, moment, spin = 0.0, 0.0, 0.0, 0.0
    t = parts.table
    for i in range(k, parts.n):
        cx, cz = base_at(parts, pivot, u, i)
        cz += t[H, i]
        de, dn = turn * cz - spin_sq * cx - fe, -turn * cx - spin_sq * cz + shift - fn
        if i >= parts.joint:
            de, dn = de + slip_e, dn + slip_n
        pe, pn = t[M, i] * de, t[M, i] * dn
        s_e, s_n = s_e + pe, s_n + pn
        moment += (cx - ox) * pn - (cz - oz) * pe
        spin += t[INERTIA, i]
    moment -= spin * turn
    return s_e, s_n, (moment / s_n if s_n > 0.0 else math.nan)


@jit
def joint_load(parts, pivot, y, ddphi, ddu, fe, fn, k):
    """What the blocks above joint k (k .. n - 1) ask of it in the state y = (phi, u, phi', u') with the
    accelerations phi'' [rad s-2] and u'' [m s-2] under the field (f_e, f_n) [m s-2] (the module's sums): the force on
    them along the face and normal to it [N], and its centre of pressure from block k's base centre along the face
    [m] (NaN where the force does not press)."""
    return _load(parts, pivot, y[1], k, ddphi, y[2] * y[2], 0.0, ddu, -2.0 * y[2] * y[3], fe, fn)


@jit
def landing_load(parts, pivot, u, w, du0, dphi, du, k):
    """:func:`joint_load` of an impulse: the blocks above joint k change their velocities from turning at ``w``
    [rad s-1] on ``pivot`` (the upper part sliding at ``du0`` [m s-1]) at phi = 0 to turning at ``dphi`` on the other
    corner, 2 pivot b_0 along the base from the first (sliding at ``du``); the impulse on them along the face and
    normal to it [N s] and its centre from block k's base centre [m]."""
    return _load(parts, pivot, u, k, dphi - w, 0.0, -2.0 * pivot * parts.b0 * dphi, du - du0, 0.0, 0.0, 0.0)


@jit
def _holds(parts, k, f_e, f_n, x_p):
    """How shut joint k carries (f_e, f_n) centred at x_p: :data:`INNER_HOLDS`, :data:`INNER_OPENS` or
    :data:`INNER_SLIPS`."""
    t = parts.table
    off = t[OFF, k]
    lo, hi = max(-t[B, k], -off - t[B, k - 1]), min(t[B, k], -off + t[B, k - 1])
    if not (f_n > 0.0 and lo < x_p < hi):
        return INNER_OPENS
    if abs(f_e) > t[MU, k] * f_n:
        return INNER_SLIPS
    return INNER_HOLDS


@jit
def inner(parts, pivot, y, ddphi, ddu, fe, fn):
    """The first of the parts' own joints (bottom first) that would open or slip in the state y with these
    accelerations and field (:func:`joint_load`): its :data:`INNER_OPENS` or :data:`INNER_SLIPS`, else
    :data:`INNER_HOLDS` (two blocks: no such joint)."""
    for k in range(1, parts.n):
        if k != parts.joint:
            f_e, f_n, x_p = joint_load(parts, pivot, y, ddphi, ddu, fe, fn, k)
            kind = _holds(parts, k, f_e, f_n, x_p)
            if kind != INNER_HOLDS:
                return kind
    return INNER_HOLDS


@jit
def inner_landing(parts, pivot, u, w, du0, dphi, du):
    """Whether every joint of the parts carries a landing's impulses (:func:`landing_load`) shut and sticking."""
    for k in range(1, parts.n):
        if k != parts.joint:
            j_e, j_n, x_p = landing_load(parts, pivot, u, w, du0, dphi, du, k)
            if _holds(parts, k, j_e, j_n, x_p) != INNER_HOLDS:
                return False
    return True
