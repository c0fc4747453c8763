"""Two rigid blocks in a vertical plane, one on the other, rocking without sliding: the equations of motion, the
impact at a joint and the test for a joint's lift-off.

The lower block (1) rocks on a corner of its base on the ground, the upper block (2) on a corner of the overlap of
its base with the lower block's top. The coordinates are the blocks' absolute rotations q = (phi_1, phi_2) [rad],
clockwise positive (a positive rotation tips a block towards +x). Each joint is shut (its rotation held: phi_1 = 0
on the ground, psi = phi_2 - phi_1 = 0 between the blocks) or open on the corner its rotation tips it over
(``pivot`` +1 or -1). In a mode the motion is

    S^T M(q) S z'' = S^T f(q, q', a_h, a_v),      q'' = S z'',
    M = sum_k m_k J_k^T J_k + diag(I_1, I_2),
    f = - sum_k m_k J_k^T (kappa_k + (a_h, g + a_v)),

with J_k = dC_k/dq the Jacobian of block k's centre of mass C_k, kappa_k = (dJ_k/dt) q' its acceleration at
constant rates (Kane's equations: d'Alembert's principle projected on the rates q'; Kane & Levinson 1985), I_k the
block's moment of inertia about its centre, (a_h, a_v) the ground's acceleration [m s-2] and S the mode's free
directions (both joints open: the identity; the ground joint shut: (0, 1); the blocks' joint shut: (1, 1)). For one
block it is Housner's (1963) equation.

At an impact the joint's rotation reaches 0 and its corner changes; every other joint keeps its state. The impulses
act only at the contacts the new mode holds, so they do no work on its free directions (for one block, the
conservation of the angular momentum about the new corner of Housner 1963; the same principle for two blocks):

    S^T V_+^T B (V_+ S z'_+ - V_- q'_-) = 0,

V being the map from q' to the blocks' velocities (the centres' and the rotation rates) with the corners before (-)
and after (+), B = diag(m_1, m_1, I_1, m_2, m_2, I_2). The kinetic energy is B-orthogonally projected: never gained.
A shut joint opens on the corner s where releasing it (every other joint as it is) would accelerate its rotation
towards s (Housner's lift-off condition for one block). The joints' modes, each block on a corner of the one below,
are those of Psycharis (1990); neither joint slides.

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. Bulletin of the
Seismological Society of America 53(2), 403-417.
Kane, T. R. & Levinson, D. A. (1985). Dynamics: Theory and Applications. McGraw-Hill.
Psycharis, I. N. (1990). Dynamic behaviour of rocking two-block assemblies. Earthquake Engineering & Structural
Dynamics 19(4), 555-575.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from ..compiled import jit
from ..constants import G
from .stack import StackBody, interfaces

#: A joint held shut (its rotation 0); an open joint is its corner, +1 or -1.
SHUT = 0


class TwoBlock(NamedTuple):
    """Two blocks, one on the other (a numba namedtuple). Lengths [m] in each block's frame at rest: the lower's
    origin at the centre of its base, the upper's at the centre of its own base.

    Attributes
    ----------
    b1, h1, m1, i1 : float
        the lower block's half-width [m], half-height [m], mass [kg] and moment of inertia about its centre [kg m2]
    b2, h2, m2, i2 : float
        the same for the upper block
    offset : float
        the upper base's centre from the centre of the lower's top [m]
    left, right : float
        the joint's support, the overlap of the two faces, in the lower's frame [m]
    """

    b1: float
    h1: float
    m1: float
    i1: float
    b2: float
    h2: float
    m2: float
    i2: float
    offset: float
    left: float
    right: float


class Motion(NamedTuple):
    """The state of the two blocks: rotations [rad] and rates [rad s-1]."""

    phi1: float
    phi2: float
    w1: float
    w2: float


def two_block(lower: StackBody, upper: StackBody, *, label: str = "two blocks") -> TwoBlock:
    """The :class:`TwoBlock` of two stacked rectangular bodies (uniform, centre of mass at the centre).

    Raises
    ------
    BlockParameterError
        a size or mass not positive, or the pair cannot stand at rest (:func:`.stack.interfaces`).
    """
    joint = interfaces([lower, upper], label=label)[1]
    b1, h1, b2, h2 = lower.width_m / 2, lower.height_m / 2, upper.width_m / 2, upper.height_m / 2
    return TwoBlock(b1, h1, lower.mass_kg, lower.mass_kg * (b1 * b1 + h1 * h1) / 3.0,
                    b2, h2, upper.mass_kg, upper.mass_kg * (b2 * b2 + h2 * h2) / 3.0,
                    upper.offset_m, joint.left_m - lower.offset_m, joint.right_m - lower.offset_m)


def centre_of_mass(tb: TwoBlock) -> tuple[float, float]:
    """The pair's centre of mass at rest (x, z) [m], in the lower block's frame (origin: its base's centre)."""
    m = tb.m1 + tb.m2
    return tb.m2 * tb.offset / m, (tb.m1 * tb.h1 + tb.m2 * (2.0 * tb.h1 + tb.h2)) / m


def tipping_angles(tb: TwoBlock) -> tuple[tuple[float, float], tuple[float, float]]:
    """Each joint's tipping angle at rest on its + and - corner [rad]: the part above it rocking as one until its
    centre of mass is over the corner (the ground joint: both blocks; the blocks' joint: the upper)."""
    xg, zg = centre_of_mass(tb)
    ground = (math.atan2(tb.b1 - xg, zg), math.atan2(tb.b1 + xg, zg))
    joint = (math.atan2(tb.right - tb.offset, tb.h2), math.atan2(tb.offset - tb.left, tb.h2))
    return ground, joint


@jit
def _rot(phi, x, z):
    """R(phi) (x, z): a clockwise rotation by phi."""
    c, s = math.cos(phi), math.sin(phi)
    return c * x + s * z, -s * x + c * z


@jit
def _rot_d(phi, x, z):
    """dR/dphi (x, z)."""
    c, s = math.cos(phi), math.sin(phi)
    return -s * x + c * z, -c * x - s * z


@jit
def levers(tb, s1, s2):
    """The levers in the blocks' frames for the corners ``s1`` (ground) and ``s2`` (joint): the lower's centre and
    the joint's corner from the ground's corner, the upper's centre from the joint's corner [m]."""
    o1 = s1 * tb.b1
    px = tb.right if s2 > 0 else tb.left
    return (-o1, tb.h1), (px - o1, 2.0 * tb.h1), (tb.offset - px, tb.h2)


@jit
def pivots(j1, j2):
    """The corners a joint state stands for (a shut joint: +1, its kinematics being the same on either corner)."""
    return (1.0 if j1 >= 0 else -1.0), (1.0 if j2 >= 0 else -1.0)


@jit
def centres(tb, phi1, phi2, s1, s2):
    """The centres of mass (x1, z1, x2, z2) [m] in the ground's frame (origin: the lower base's centre at rest)."""
    a1, g1, a2 = levers(tb, s1, s2)
    o1 = s1 * tb.b1
    x1, z1 = _rot(phi1, a1[0], a1[1])
    xg, zg = _rot(phi1, g1[0], g1[1])
    x2, z2 = _rot(phi2, a2[0], a2[1])
    return o1 + x1, z1, o1 + xg + x2, zg + z2


@jit
def _jacobians(tb, phi1, phi2, s1, s2):
    """Columns of J_1 (its second column is zero) and J_2: (u1, g1, u2) with dC_1 = u1 dphi_1,
    dC_2 = g1 dphi_1 + u2 dphi_2."""
    a1, g1, a2 = levers(tb, s1, s2)
    return _rot_d(phi1, a1[0], a1[1]), _rot_d(phi1, g1[0], g1[1]), _rot_d(phi2, a2[0], a2[1])


@jit
def equations(tb, y, s1, s2, ah, av):
    """M and f at the state ``y`` (a :class:`Motion`) on the corners ``s1``, ``s2``: (m11, m12, m22, f1, f2)."""
    a1, g1, a2 = levers(tb, s1, s2)
    u1, v1, u2 = _jacobians(tb, y.phi1, y.phi2, s1, s2)
    r1 = _rot(y.phi1, a1[0], a1[1])
    rg = _rot(y.phi1, g1[0], g1[1])
    r2 = _rot(y.phi2, a2[0], a2[1])
    w1s, w2s = y.w1 * y.w1, y.w2 * y.w2
    gv = G + av
    # kappa_k + (a_h, g + a_v): d2R/dphi2 = -R
    k1x, k1z = -r1[0] * w1s + ah, -r1[1] * w1s + gv
    k2x, k2z = -rg[0] * w1s - r2[0] * w2s + ah, -rg[1] * w1s - r2[1] * w2s + gv
    m11 = tb.m1 * (a1[0] * a1[0] + a1[1] * a1[1]) + tb.i1 + tb.m2 * (g1[0] * g1[0] + g1[1] * g1[1])
    m12 = tb.m2 * (v1[0] * u2[0] + v1[1] * u2[1])
    m22 = tb.m2 * (a2[0] * a2[0] + a2[1] * a2[1]) + tb.i2
    f1 = -tb.m1 * (u1[0] * k1x + u1[1] * k1z) - tb.m2 * (v1[0] * k2x + v1[1] * k2z)
    f2 = -tb.m2 * (u2[0] * k2x + u2[1] * k2z)
    return m11, m12, m22, f1, f2


@jit
def accelerations(tb, y, j1, j2, ah, av):
    """(phi_1'', phi_2'') [rad s-2] in the mode of the joints ``j1`` (ground) and ``j2`` (between the blocks)."""
    s1, s2 = pivots(j1, j2)
    m11, m12, m22, f1, f2 = equations(tb, y, s1, s2, ah, av)
    if j1 != SHUT and j2 != SHUT:
        det = m11 * m22 - m12 * m12
        return (m22 * f1 - m12 * f2) / det, (m11 * f2 - m12 * f1) / det
    if j1 != SHUT:                                  # the blocks' joint shut: S = (1, 1)
        z = (f1 + f2) / (m11 + 2.0 * m12 + m22)
        return z, z
    if j2 != SHUT:                                  # the ground joint shut: S = (0, 1)
        return 0.0, f2 / m22
    return 0.0, 0.0


@jit
def demands(tb, y, j1, j2, ah, av):
    """The friction demand |F_t| / F_n at the ground joint and at the blocks' joint [-] in the mode (j1, j2) at the
    state ``y``: F the contact force that joint carries, sum m_k (C_k'' + (a_h, g + a_v)) over the blocks above it
    (Newton's second law of the part above, in the ground's accelerating frame), F_t and F_n its components along
    and across the face below (the ground's; the lower block's top, turned by phi_1). inf where F_n <= 0 (the face
    would pull)."""
    s1, s2 = pivots(j1, j2)
    d1, d2 = accelerations(tb, y, j1, j2, ah, av)
    a1, g1, a2 = levers(tb, s1, s2)
    u1, v1, u2 = _jacobians(tb, y.phi1, y.phi2, s1, s2)
    r1 = _rot(y.phi1, a1[0], a1[1])
    rg = _rot(y.phi1, g1[0], g1[1])
    r2 = _rot(y.phi2, a2[0], a2[1])
    w1s, w2s, gv = y.w1 * y.w1, y.w2 * y.w2, G + av
    f2x = tb.m2 * (v1[0] * d1 + u2[0] * d2 - rg[0] * w1s - r2[0] * w2s + ah)
    f2z = tb.m2 * (v1[1] * d1 + u2[1] * d2 - rg[1] * w1s - r2[1] * w2s + gv)
    fgx = f2x + tb.m1 * (u1[0] * d1 - r1[0] * w1s + ah)
    fgz = f2z + tb.m1 * (u1[1] * d1 - r1[1] * w1s + gv)
    c, s = math.cos(y.phi1), math.sin(y.phi1)
    ft, fn = c * f2x - s * f2z, s * f2x + c * f2z
    return (abs(fgx) / fgz if fgz > 0.0 else math.inf), (abs(ft) / fn if fn > 0.0 else math.inf)


@jit
def opening(tb, y, j1, j2, ah, av):
    """The shut joint that opens and its corner: (joint 1 or 2, corner) where releasing it on that corner (the other
    joint as it is) accelerates its rotation towards the corner (of several, the one accelerated most); (0, 0) where
    none opens."""
    best, joint, corner = 0.0, 0, 0
    for s in (1, -1):
        if j1 == SHUT:
            d1, d2 = accelerations(tb, y, s, j2, ah, av)
            if s * d1 > best:
                best, joint, corner = s * d1, 1, s
        if j2 == SHUT:
            d1, d2 = accelerations(tb, y, j1, s, ah, av)
            if s * (d2 - d1) > best:
                best, joint, corner = s * (d2 - d1), 2, s
    return joint, corner


@jit
def _velocity_map(tb, phi1, phi2, s1, s2):
    """V: the columns dV/dphi_1' and dV/dphi_2' of the blocks' velocities (v1x, v1z, w1, v2x, v2z, w2)."""
    u1, v1, u2 = _jacobians(tb, phi1, phi2, s1, s2)
    return (u1[0], u1[1], 1.0, v1[0], v1[1], 0.0), (0.0, 0.0, 0.0, u2[0], u2[1], 1.0)


@jit
def _b_product(tb, a, b):
    """a^T B b for two velocity vectors of the blocks."""
    return (tb.m1 * (a[0] * b[0] + a[1] * b[1]) + tb.i1 * a[2] * b[2]
            + tb.m2 * (a[3] * b[3] + a[4] * b[4]) + tb.i2 * a[5] * b[5])


@jit
def projected_rates(tb, y, before, after):
    """The rates (phi_1', phi_2') after an impulse at the contacts of the mode ``after`` = (j1, j2), from the rates of
    ``y`` in the mode ``before`` (the impact law of the module: B-orthogonal projection on the new mode's free
    directions). Also a shut joint's plastic stop (``after`` shuts it)."""
    sb1, sb2 = pivots(before[0], before[1])
    sa1, sa2 = pivots(after[0], after[1])
    cb1, cb2 = _velocity_map(tb, y.phi1, y.phi2, sb1, sb2)
    vel = (cb1[0] * y.w1 + cb2[0] * y.w2, cb1[1] * y.w1 + cb2[1] * y.w2, cb1[2] * y.w1 + cb2[2] * y.w2,
           cb1[3] * y.w1 + cb2[3] * y.w2, cb1[4] * y.w1 + cb2[4] * y.w2, cb1[5] * y.w1 + cb2[5] * y.w2)
    ca1, ca2 = _velocity_map(tb, y.phi1, y.phi2, sa1, sa2)
    j1, j2 = after
    if j1 != SHUT and j2 != SHUT:
        a11, a12, a22 = _b_product(tb, ca1, ca1), _b_product(tb, ca1, ca2), _b_product(tb, ca2, ca2)
        r1, r2 = _b_product(tb, ca1, vel), _b_product(tb, ca2, vel)
        det = a11 * a22 - a12 * a12
        return (a22 * r1 - a12 * r2) / det, (a11 * r2 - a12 * r1) / det
    if j1 != SHUT:
        col = (ca1[0] + ca2[0], ca1[1] + ca2[1], ca1[2] + ca2[2], ca1[3] + ca2[3], ca1[4] + ca2[4],
               ca1[5] + ca2[5])
        z = _b_product(tb, col, vel) / _b_product(tb, col, col)
        return z, z
    if j2 != SHUT:
        return 0.0, _b_product(tb, ca2, vel) / _b_product(tb, ca2, ca2)
    return 0.0, 0.0


@jit
def kinetic_energy(tb, y, j1, j2):
    """The blocks' kinetic energy [J] in the mode (j1, j2)."""
    s1, s2 = pivots(j1, j2)
    m11, m12, m22, _, _ = equations(tb, y, s1, s2, 0.0, 0.0)
    return 0.5 * (m11 * y.w1 * y.w1 + 2.0 * m12 * y.w1 * y.w2 + m22 * y.w2 * y.w2)


@jit
def potential_energy(tb, y, j1, j2):
    """The blocks' potential energy in gravity above rest [J]."""
    s1, s2 = pivots(j1, j2)
    _, z1, _, z2 = centres(tb, y.phi1, y.phi2, s1, s2)
    return G * (tb.m1 * (z1 - tb.h1) + tb.m2 * (z2 - 2.0 * tb.h1 - tb.h2))
