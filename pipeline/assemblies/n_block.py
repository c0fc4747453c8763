"""A stack of n rigid blocks (n = 1 .. :data:`MAX_BODIES`) in a vertical plane, rocking without sliding: the
equations of motion, the impact at a joint and the test for a joint's lift-off.

Block k (k = 0 the bottom) rocks on a corner of the overlap of its base with the top of block k - 1 (block 0: with
the ground). The state is the joints' relative rotations psi_k = phi_k - phi_{k-1} [rad] (phi_k the block's absolute
rotation, phi_{-1} = 0), clockwise positive (a positive rotation tips a block towards +x), and their rates. Each
joint is shut (psi_k held at 0) or open on the corner its rotation tips it over (+1 or -1). In a mode the motion is

    S^T M(q) S z'' = S^T f(q, q', a_h, a_v),      q'' = S z'',      q = (phi_0 .. phi_{n-1}),
    M = sum_k m_k J_k^T J_k + diag(I_0 .. I_{n-1}),
    f = - sum_k m_k J_k^T (kappa_k + (a_h, g + a_v)),

with J_k = dC_k/dq the Jacobian of block k's centre of mass C_k, kappa_k = (dJ_k/dt) q' its acceleration at
constant rates (Kane's equations; Kane & Levinson 1985), I_k the block's moment of inertia about its centre and
(a_h, a_v) the ground's acceleration [m s-2]. z are the open joints' psi, and S maps them to q: phi_k is the sum of
the open joints' psi_j for j <= k. The centre of block k is

    C_k = P_k + R(phi_k) a_k,      P_{k+1} = P_k + R(phi_k) L_k,

P_k the corner joint k turns about, a_k the lever from it to the block's centre and L_k the lever to the corner of
joint k + 1, both in the block's frame, R(phi) a clockwise rotation: dC_k/dphi_j = R'(phi_j) L_j for j < k and
R'(phi_k) a_k for j = k.

At an impact a joint's rotation reaches 0 and its corner changes; every other joint keeps its state. The impulses
act only at the contacts the new mode holds, so they do no work on its free directions (for one block, the
conservation of the angular momentum about the new corner of Housner 1963):

    S_+^T V_+^T B (V_+ S_+ z'_+ - V_- q'_-) = 0,

V being the map from q' to the blocks' velocities (the centres' and the rotation rates) with the corners before (-)
and after (+), B the blocks' masses and moments of inertia: the kinetic energy is B-orthogonally projected, never
gained. A shut joint opens on the corner s where releasing it (every other joint as it is) would accelerate its
rotation towards s. For n = 2 these are the equations of :mod:`.two_block` (Psycharis 1990's modes), which the tests
compare; for n = 1, Housner's (1963).

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. Bulletin of the
Seismological Society of America 53(2), 403-417.
Kane, T. R. & Levinson, D. A. (1985). Dynamics: Theory and Applications. McGraw-Hill.
Psycharis, I. N. (1990). Dynamic behaviour of rocking two-block assemblies. Earthquake Engineering & Structural
Dynamics 19(4), 555-575.
Spanos, P. D., Roussis, P. C. & Politis, N. P. A. (2001). Dynamic analysis of stacked rigid blocks. Soil Dynamics
and Earthquake Engineering 21(7), 559-578.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..compiled import jit_lean
from ..constants import G
from ..errors import BlockParameterError
from .stack import interfaces, placements

#: The most blocks a stack may hold (the state is a tuple of 2 x MAX_BODIES floats, unused joints held at 0)
MAX_BODIES = 5
#: The state's length: each joint's rotation, then each joint's rate
STATE = 2 * MAX_BODIES
#: A joint held shut (its rotation 0); an open joint is its corner, +1 or -1.
SHUT = 0


class NBlock(NamedTuple):
    """n blocks, one on the other (a numba namedtuple; tuples of :data:`MAX_BODIES`, zeros beyond n). Lengths [m]
    in each block's frame at rest, its origin at the centre of its base.

    Attributes
    ----------
    n : int
        the blocks
    b, h, m, i : tuple of float
        each block's half-width [m], half-height [m], mass [kg] and moment of inertia about its centre [kg m2]
    lo, hi : tuple of float
        joint k's support, the overlap of block k's base with what it stands on, in block k's frame [m]
    off : tuple of float
        block k's base centre from the centre of the top of block k - 1 [m] (block 0: 0)
    """

    n: int
    b: tuple
    h: tuple
    m: tuple
    i: tuple
    lo: tuple
    hi: tuple
    off: tuple


def _padded(values) -> tuple:
    return tuple(float(v) for v in values) + (0.0,) * (MAX_BODIES - len(values))


def n_block(bodies, *, label: str = "stack") -> NBlock:
    """The :class:`NBlock` of stacked rectangular bodies (uniform, centre of mass at the centre), bottom first.

    Raises
    ------
    BlockParameterError
        a size or mass not positive, the stack cannot stand at rest (:func:`.stack.interfaces`), or more than
        :data:`MAX_BODIES` bodies.
    """
    bodies = tuple(bodies)
    faces = interfaces(bodies, label=label)
    if len(bodies) > MAX_BODIES:
        raise BlockParameterError(f"{label}: {len(bodies)} bodies; the stack model takes at most {MAX_BODIES}")
    centres, _ = placements(bodies)
    b = [0.5 * x.width_m for x in bodies]
    h = [0.5 * x.height_m for x in bodies]
    return NBlock(len(bodies), _padded(b), _padded(h), _padded([x.mass_kg for x in bodies]),
                  _padded([x.mass_kg * (bk * bk + hk * hk) / 3.0 for x, bk, hk in zip(bodies, b, h)]),
                  _padded([f.left_m - c for f, c in zip(faces, centres)]),
                  _padded([f.right_m - c for f, c in zip(faces, centres)]),
                  _padded([0.0] + [x.offset_m for x in bodies[1:]]))


def tipping_angles(nb: NBlock) -> tuple[tuple[float, float], ...]:
    """Each joint's tipping angle at rest on its + and - corner [rad]: the part above it rocking as one until its
    centre of mass is over the corner."""
    out = []
    for k in range(nb.n):
        xg, zg = part_centre(nb, k)
        out.append((math.atan2(nb.hi[k] - xg, zg), math.atan2(xg - nb.lo[k], zg)))
    return tuple(out)


def part_centre(nb: NBlock, k: int) -> tuple[float, float]:
    """The centre of mass of the part above joint k (blocks k .. n - 1) at rest, in block k's frame (origin: its
    base's centre) [m]."""
    part = _centres_at_rest(nb, k)
    mass = sum(nb.m[j] for j in range(k, nb.n))
    return (sum(nb.m[j] * c[0] for j, c in zip(range(k, nb.n), part)) / mass,
            sum(nb.m[j] * c[1] for j, c in zip(range(k, nb.n), part)) / mass)


def _centres_at_rest(nb: NBlock, k: int) -> list[tuple[float, float]]:
    """The centres of blocks k .. n - 1 at rest in block k's frame (origin: its base's centre) [m]."""
    out, x, z = [], 0.0, 0.0
    for j in range(k, nb.n):
        if j > k:
            x += nb.off[j]
            z += 2.0 * nb.h[j - 1]
        out.append((x, z + nb.h[j]))
    return out


class Scales(NamedTuple):
    """Each joint's rocking scales at rest on its + corner, the part above it rocking as one: alpha [rad] and p
    [rad s-1]; they set the tolerances and the rest thresholds."""

    alpha: tuple
    p: tuple


def scales(nb: NBlock) -> Scales:
    """The :class:`Scales` of ``nb``."""
    alphas, ps = [], []
    for k in range(nb.n):
        part = _centres_at_rest(nb, k)
        mass = sum(nb.m[j] for j in range(k, nb.n))
        xg, zg = part_centre(nb, k)
        corner = nb.hi[k]
        i_o = sum(nb.i[j] + nb.m[j] * ((c[0] - corner) ** 2 + c[1] ** 2) for j, c in zip(range(k, nb.n), part))
        r = math.hypot(corner - xg, zg)
        alphas.append(math.atan2(corner - xg, zg))
        ps.append(math.sqrt(mass * G * r / i_o))
    return Scales(tuple(alphas), tuple(ps))


class Work(NamedTuple):
    """Scratch arrays of a run (made once by :func:`work`, so that no step makes an array): the rotations and rates,
    two sets of rotated levers, the mass matrices, the forces and the reduced system."""

    phi: np.ndarray
    w: np.ndarray
    kin: np.ndarray
    kin2: np.ndarray
    mm: np.ndarray
    cross: np.ndarray
    f: np.ndarray
    bias: np.ndarray
    smap: np.ndarray
    a: np.ndarray
    r: np.ndarray
    qdd: np.ndarray
    rel: np.ndarray
    d: np.ndarray
    #: the inputs (y, js, a_h, a_v) of the accelerations now held (:func:`accelerations`); NaN first: none
    key: np.ndarray


#: The length of :attr:`Work.key`
KEY = 3 * MAX_BODIES + 2


def work() -> Work:
    """A :class:`Work` for any stack of up to :data:`MAX_BODIES` blocks."""
    nb_, sq = MAX_BODIES, (MAX_BODIES, MAX_BODIES)
    return Work(np.zeros(nb_), np.zeros(nb_), np.zeros((8, nb_)), np.zeros((8, nb_)), np.zeros(sq), np.zeros(sq),
                np.zeros(nb_), np.zeros((2, nb_)), np.zeros(sq), np.zeros(sq), np.zeros(nb_), np.zeros(nb_),
                np.zeros(nb_), np.zeros(nb_), np.full(KEY, np.nan))


@jit_lean
def _pivot(nb, js, k):
    """Joint k's corner in block k's frame [m]: its own when open, + when shut (the same kinematics either way)."""
    return nb.lo[k] if js[k] < 0 else nb.hi[k]


@jit_lean
def absolute(y, n, wk):
    """The blocks' absolute rotations and rates into ``wk.phi``, ``wk.w`` from the state ``y`` (the joints' psi and
    their rates)."""
    acc, rate = 0.0, 0.0
    for k in range(n):
        acc += y[k]
        rate += y[MAX_BODIES + k]
        wk.phi[k], wk.w[k] = acc, rate


@jit_lean
def kinematics(nb, phi, js, kin):
    """The levers rotated to ``phi`` on the corners of ``js`` into ``kin``, rows: R a_k (x, z), R' a_k, R L_k, R' L_k,
    a_k being block k's lever from its corner to its centre and L_k to the corner of the joint above [m]."""
    for k in range(nb.n):
        px = _pivot(nb, js, k)
        ax, az = -px, nb.h[k]
        lx, lz = 0.0, 0.0
        if k + 1 < nb.n:
            lx, lz = _pivot(nb, js, k + 1) + nb.off[k + 1] - px, 2.0 * nb.h[k]
        c, s = math.cos(phi[k]), math.sin(phi[k])
        kin[0, k], kin[1, k] = c * ax + s * az, -s * ax + c * az
        kin[2, k], kin[3, k] = -s * ax + c * az, -c * ax - s * az
        kin[4, k], kin[5, k] = c * lx + s * lz, -s * lx + c * lz
        kin[6, k], kin[7, k] = -s * lx + c * lz, -c * lx - s * lz


@jit_lean
def _column(kin, k, j, row):
    """dC_k/dphi_j, component ``row`` (0 x, 1 z)."""
    if j < k:
        return kin[6 + row, j]
    if j == k:
        return kin[2 + row, k]
    return 0.0


@jit_lean
def mass_matrix(nb, kin_a, kin_b, out):
    """sum_k m_k J_k^T J_k + diag(I) into ``out``, J on the left from ``kin_a``'s corners and on the right from
    ``kin_b``'s (the same: M; after and before an impact: V_+^T B V_-)."""
    n = nb.n
    for i in range(n):
        for j in range(n):
            acc = nb.i[i] if i == j else 0.0
            for k in range(max(i, j), n):
                acc += nb.m[k] * (_column(kin_a, k, i, 0) * _column(kin_b, k, j, 0)
                                  + _column(kin_a, k, i, 1) * _column(kin_b, k, j, 1))
            out[i, j] = acc


@jit_lean
def _bias(nb, kin, w, ah, av, out):
    """kappa_k + (a_h, g + a_v) for each block (x and z rows) [m s-2] into ``out``."""
    gx, gz = ah, G + av
    for k in range(nb.n):
        w2 = w[k] * w[k]
        out[0, k], out[1, k] = gx - kin[0, k] * w2, gz - kin[1, k] * w2
        gx -= kin[4, k] * w2                    # the blocks above: the lever to the next corner
        gz -= kin[5, k] * w2


@jit_lean
def forces(nb, kin, w, ah, av, wk):
    """f = - sum_k m_k J_k^T (kappa_k + (a_h, g + a_v)) into ``wk.f`` (and the biases into ``wk.bias``)."""
    _bias(nb, kin, w, ah, av, wk.bias)
    for j in range(nb.n):
        acc = 0.0
        for k in range(j, nb.n):
            acc -= nb.m[k] * (_column(kin, k, j, 0) * wk.bias[0, k] + _column(kin, k, j, 1) * wk.bias[1, k])
        wk.f[j] = acc


@jit_lean
def free_map(n, js, s):
    """S, the map from the open joints' rates to the absolute rates q', into the first columns of ``s``; returns
    the open joints."""
    col = 0
    for j in range(n):
        if js[j] != SHUT:
            for k in range(n):
                s[k, col] = 1.0 if k >= j else 0.0
            col += 1
    return col


@jit_lean
def solve(a, r, k):
    """x with a x = r for the leading k x k block of ``a`` (symmetric positive definite: Gaussian elimination
    without pivoting), in place: ``a`` is overwritten and x left in ``r``."""
    for c in range(k):
        for rr in range(c + 1, k):
            factor = a[rr, c] / a[c, c]
            for cc in range(c, k):
                a[rr, cc] -= factor * a[c, cc]
            r[rr] -= factor * r[c]
    for c in range(k - 1, -1, -1):
        acc = r[c]
        for cc in range(c + 1, k):
            acc -= a[c, cc] * r[cc]
        r[c] = acc / a[c, c]


@jit_lean
def _reduced(n, js, mm, rhs, wk):
    """S z with (S^T mm S) z = S^T rhs into ``wk.qdd`` (0 where no joint is open)."""
    s, a, r, out = wk.smap, wk.a, wk.r, wk.qdd
    k = free_map(n, js, s)
    for p in range(k):
        for q in range(k):
            acc = 0.0
            for i in range(n):
                for j in range(n):
                    acc += s[i, p] * mm[i, j] * s[j, q]
            a[p, q] = acc
        acc = 0.0
        for i in range(n):
            acc += s[i, p] * rhs[i]
        r[p] = acc
    solve(a, r, k)
    for i in range(n):
        acc = 0.0
        for p in range(k):
            acc += s[i, p] * r[p]
        out[i] = acc


@jit_lean
def accelerations(nb, y, js, ah, av, wk):
    """The absolute accelerations q'' [rad s-2] in the mode ``js`` at the state ``y`` into ``wk.qdd`` (with the
    rotations, rates, levers and biases they come from); not computed again where ``wk`` holds those of the same
    inputs (a step's last stage, then its events and demands, are at one state)."""
    absolute(y, nb.n, wk)
    if _held(wk.key, y, js, ah, av):
        return
    kinematics(nb, wk.phi, js, wk.kin)
    mass_matrix(nb, wk.kin, wk.kin, wk.mm)
    forces(nb, wk.kin, wk.w, ah, av, wk)
    _reduced(nb.n, js, wk.mm, wk.f, wk)
    for q in range(2 * MAX_BODIES):
        wk.key[q] = y[q]
    for q in range(MAX_BODIES):
        wk.key[2 * MAX_BODIES + q] = js[q]
    wk.key[3 * MAX_BODIES], wk.key[3 * MAX_BODIES + 1] = ah, av


@jit_lean
def _held(key, y, js, ah, av):
    """Whether ``key`` holds these inputs."""
    if key[3 * MAX_BODIES] != ah or key[3 * MAX_BODIES + 1] != av:
        return False
    for q in range(MAX_BODIES):
        if key[2 * MAX_BODIES + q] != js[q]:
            return False
    for q in range(2 * MAX_BODIES):
        if key[q] != y[q]:
            return False
    return True


@jit_lean
def relative(qdd, n, wk):
    """psi'' from q'' (each joint's: its block's less the block's below), into ``wk.rel``."""
    below = 0.0
    for k in range(n):
        wk.rel[k] = qdd[k] - below
        below = qdd[k]


@jit_lean
def tuple_set(js, k, value):
    """``js`` (a tuple of :data:`MAX_BODIES` ints) with joint ``k`` set to ``value``."""
    return (value if k == 0 else js[0], value if k == 1 else js[1], value if k == 2 else js[2],
            value if k == 3 else js[3], value if k == 4 else js[4])


@jit_lean
def opening(nb, y, js, ah, av, wk):
    """The shut joint that opens and its corner: (joint, corner) where releasing it on that corner (every other
    joint as it is) accelerates its rotation towards the corner (of several, the one accelerated most); (-1, 0)
    where none opens."""
    best, joint, corner = 0.0, -1, 0
    for k in range(nb.n):
        if js[k] != SHUT:
            continue
        for s in (1, -1):
            accelerations(nb, y, tuple_set(js, k, s), ah, av, wk)
            relative(wk.qdd, nb.n, wk)
            if s * wk.rel[k] > best:
                best, joint, corner = s * wk.rel[k], k, s
    return joint, corner


@jit_lean
def projected_rates(nb, y, before, after, wk):
    """The absolute rates q' after an impulse at the contacts of the mode ``after`` from the rates of ``y`` in the
    mode ``before`` (the module's impact law; also a shut joint's plastic stop where ``after`` shuts it), in
    ``wk.qdd``."""
    wk.key[0] = math.nan                           # the levers and wk.qdd are no longer accelerations'
    absolute(y, nb.n, wk)
    kinematics(nb, wk.phi, before, wk.kin2)
    kinematics(nb, wk.phi, after, wk.kin)
    mass_matrix(nb, wk.kin, wk.kin2, wk.cross)
    mass_matrix(nb, wk.kin, wk.kin, wk.mm)
    for i in range(nb.n):
        acc = 0.0
        for j in range(nb.n):
            acc += wk.cross[i, j] * wk.w[j]
        wk.f[i] = acc
    _reduced(nb.n, after, wk.mm, wk.f, wk)


@jit_lean
def demands(nb, y, js, ah, av, wk):
    """Each joint's friction demand |F_t| / F_n [-] in the mode ``js`` at the state ``y`` into ``wk.d``: F the force
    the joint carries, sum m_j (C_j'' + (a_h, g + a_v)) over the blocks above it (Newton's second law of the part
    above, in the ground's accelerating frame), F_t and F_n its components along and across the face below (the
    ground's; block k - 1's top, turned by phi_{k-1}). inf where F_n <= 0 (the face would pull)."""
    n = nb.n
    accelerations(nb, y, js, ah, av, wk)
    qdd = wk.qdd
    fx, fz = 0.0, 0.0
    for k in range(n - 1, -1, -1):
        cx, cz = wk.bias[0, k], wk.bias[1, k]
        for j in range(k + 1):
            cx += _column(wk.kin, k, j, 0) * qdd[j]
            cz += _column(wk.kin, k, j, 1) * qdd[j]
        fx += nb.m[k] * cx
        fz += nb.m[k] * cz
        turn = wk.phi[k - 1] if k > 0 else 0.0
        c, s = math.cos(turn), math.sin(turn)
        ft, fn = c * fx - s * fz, s * fx + c * fz
        wk.d[k] = abs(ft) / fn if fn > 0.0 else math.inf


@jit_lean
def kinetic_energy(nb, y, js, wk):
    """The blocks' kinetic energy [J] (the mode's corners)."""
    wk.key[0] = math.nan
    absolute(y, nb.n, wk)
    kinematics(nb, wk.phi, js, wk.kin)
    mass_matrix(nb, wk.kin, wk.kin, wk.mm)
    out = 0.0
    for i in range(nb.n):
        for j in range(nb.n):
            out += wk.w[i] * wk.mm[i, j] * wk.w[j]
    return 0.5 * out


@jit_lean
def potential_energy(nb, y, js, wk):
    """The blocks' potential energy in gravity above rest [J]: each centre's height less its height at rest (the sum
    of the heights of the blocks below and its half-height)."""
    wk.key[0] = math.nan
    absolute(y, nb.n, wk)
    kinematics(nb, wk.phi, js, wk.kin)
    out, z, z0 = 0.0, 0.0, 0.0
    for k in range(nb.n):
        out += nb.m[k] * G * ((z + wk.kin[1, k]) - (z0 + nb.h[k]))
        z += wk.kin[5, k]
        z0 += 2.0 * nb.h[k]
    return out


@jit_lean
def may_open(nb, y, js, ah, av, wk):
    """Whether a shut joint would open at the state ``y`` in the mode ``js``: the test of :func:`opening` by one
    solve of the current mode instead of one per shut joint and corner.

    A shut joint k carries the contact moment M_s about each corner s of its support that the part above it needs,
    sum over j >= k of (C_j - P_s) x m_j (C_j'' + (a_h, g + a_v)) + I_j phi_j'' (clockwise, in the ground's
    accelerating frame). Released on corner s, the joint's rotation accelerates by -M_s / (e^T M^-1 e) along it
    (M_s is the multiplier of its constraint, e its direction), so it opens towards s exactly where s M_s < 0: where
    the contact would have to pull (Housner's condition for one block)."""
    accelerations(nb, y, js, ah, av, wk)
    n, pos = nb.n, wk.kin2
    px, pz = 0.0, 0.0                             # the corners from joint 0's, block by block
    for j in range(n):
        pos[0, j], pos[1, j] = px + wk.kin[0, j], pz + wk.kin[1, j]
        bx, bz = wk.bias[0, j], wk.bias[1, j]
        for i in range(j + 1):
            bx += _column(wk.kin, j, i, 0) * wk.qdd[i]
            bz += _column(wk.kin, j, i, 1) * wk.qdd[i]
        pos[2, j], pos[3, j] = nb.m[j] * bx, nb.m[j] * bz
        px += wk.kin[4, j]
        pz += wk.kin[5, j]
    fx, fz, moment = 0.0, 0.0, 0.0                # the part above: its force and moment about the origin
    for k in range(n - 1, -1, -1):
        fx += pos[2, k]
        fz += pos[3, k]
        moment += pos[1, k] * pos[2, k] - pos[0, k] * pos[3, k] + nb.i[k] * wk.qdd[k]
        if js[k] != SHUT:
            continue
        c, s = math.cos(wk.phi[k]), math.sin(wk.phi[k])
        for corner in (1, -1):
            x = nb.hi[k] if corner > 0 else nb.lo[k]
            ox, oz = -x, nb.h[k]                  # the centre from the corner, in the block's frame
            cx = pos[0, k] - (c * ox + s * oz)
            cz = pos[1, k] - (-s * ox + c * oz)
            if corner * (moment - (cz * fx - cx * fz)) < 0.0:
                return True
    return False
