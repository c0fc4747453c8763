"""The pose of a stack's blocks for its contact model (:mod:`.stack_contact`): each block's centre and rotation in
the ground's frame, from the n-block model's state (:mod:`.n_block`) and back, and the stack of where its blocks slid
to.

Block k's centre (x_k, z_k) and rotation phi_k (clockwise positive: a positive rotation tips it towards +x, as in
:mod:`.n_block`), a point (r_x, r_z) of it in its frame at C_k + R(phi_k) r, R(phi) r = (c r_x + s r_z, -s r_x +
c r_z); the ground's frame has its origin at the centre of block 0's base at rest.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..compiled import jit_lean
from .n_block import MAX_BODIES, NBlock, part_centre


class Bodies(NamedTuple):
    """The blocks of a run (tuples of :data:`MAX_BODIES`): half-width, half-height [m], mass [kg], moment of inertia
    about the centre [kg m2], friction at the base [-]."""

    n: int
    b: tuple
    h: tuple
    m: tuple
    i: tuple
    mu: tuple


@jit_lean
def corner_point(q, k, rx, rz):
    """Block k's point at (rx, rz) from its centre in its frame, in the ground's frame."""
    c, s = math.cos(q[2, k]), math.sin(q[2, k])
    return q[0, k] + c * rx + s * rz, q[1, k] - s * rx + c * rz


@jit_lean
def local_point(q, k, px, pz):
    """The point (px, pz) in block k's frame (origin its centre)."""
    c, s = math.cos(q[2, k]), math.sin(q[2, k])
    dx, dz = px - q[0, k], pz - q[1, k]
    return c * dx - s * dz, s * dx + c * dz


@jit_lean
def rotations(q, n, cs):
    """Each of the ``n`` blocks' cos and sin of its rotation into ``cs`` (2, n), for :func:`point_at` and
    :func:`point_in` (the step's configuration's trigonometry once)."""
    for k in range(n):
        cs[0, k], cs[1, k] = math.cos(q[2, k]), math.sin(q[2, k])


@jit_lean
def point_at(q, cs, k, rx, rz):
    """:func:`corner_point` with block k's cos and sin from :func:`rotations`."""
    c, s = cs[0, k], cs[1, k]
    return q[0, k] + c * rx + s * rz, q[1, k] - s * rx + c * rz


@jit_lean
def point_in(q, cs, k, px, pz):
    """:func:`local_point` with block k's cos and sin from :func:`rotations`."""
    c, s = cs[0, k], cs[1, k]
    dx, dz = px - q[0, k], pz - q[1, k]
    return c * dx - s * dz, s * dx + c * dz


@jit_lean
def tilt(q, k):
    """Block k's rotation on what it stands on [rad]."""
    return q[2, k] - (q[2, k - 1] if k > 0 else 0.0)


@jit_lean
def base_offset(bd, q, k):
    """Block k's base centre from the centre of the top of block k - 1, in its frame [m]."""
    px, pz = corner_point(q, k, 0.0, -bd.h[k])
    lx, _ = local_point(q, k - 1, px, pz)
    return lx


def bodies_of(nb: NBlock, mu) -> Bodies:
    """The :class:`Bodies` of the stack ``nb`` with each block's friction at its base ``mu`` [-]."""
    pad = (0.0,) * (MAX_BODIES - nb.n)
    return Bodies(nb.n, nb.b, nb.h, nb.m, nb.i, tuple(float(x) for x in mu[:nb.n]) + pad)


def state_of(nb: NBlock, y) -> tuple[np.ndarray, np.ndarray]:
    """The blocks' centres and rotations q (3, n) and their rates v (3, n) in the ground's frame (its origin the
    centre of block 0's base at rest) from the n-block model's state ``y`` (:mod:`.n_block`: each joint's psi, then
    its rate; an open joint turns about its corner on the side of its rotation, or of its rate at psi = 0)."""
    n = nb.n
    q, v = np.zeros((3, n)), np.zeros((3, n))
    px, pz = 0.0, 0.0                                     # joint k's corner in the ground's frame
    vx, vz = 0.0, 0.0                                     # its velocity
    phi, rate = 0.0, 0.0
    for k in range(n):
        psi, psid = float(y[k]), float(y[MAX_BODIES + k])
        corner = nb.hi[k] if (psi > 0.0 or (psi == 0.0 and psid >= 0.0)) else nb.lo[k]
        phi, rate = phi + psi, rate + psid
        c, s = math.cos(phi), math.sin(phi)
        if k == 0:
            px, pz = corner, 0.0
        ax, az = -corner, nb.h[k]                        # from the corner to the centre, in the block's frame
        q[0, k], q[1, k], q[2, k] = px + c * ax + s * az, pz - s * ax + c * az, phi
        v[0, k], v[1, k], v[2, k] = vx + rate * (-s * ax + c * az), vz + rate * (-c * ax - s * az), rate
        if k + 1 < n:
            nxt = nb.hi[k + 1] if (float(y[k + 1]) > 0.0 or (float(y[k + 1]) == 0.0
                                                              and float(y[MAX_BODIES + k + 1]) >= 0.0)) \
                else nb.lo[k + 1]
            lx, lz = nxt + nb.off[k + 1] - corner, 2.0 * nb.h[k]
            px, pz = px + c * lx + s * lz, pz - s * lx + c * lz
            vx, vz = vx + rate * (-s * lx + c * lz), vz + rate * (-c * lx - s * lz)
    return q, v


class SlideRockState(NamedTuple):
    """Where the slide-rock model (:mod:`.slide_rock`) starts: the stack's rotation phi [rad] on a corner of block 0
    (the side of its sign), the sliding joint's offset u [m] and their rates phi' [rad s-1] and u' [m s-1] (0: the
    joint sticks), and that joint (1 .. n - 1)."""

    phi: float
    u: float
    dphi: float
    du: float
    joint: int = 1


def slide_rock_pose(nb: NBlock, state: tuple, pivot: int, joint: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """The blocks' centres and rotations q (3, n) and their rates v (3, n) of the stack ``nb`` in the slide-rock
    model's ``state`` (:mod:`.slide_rock`: phi [rad], u [m], phi' [rad s-1], u' [m s-1]) turning on block 0's corner
    ``pivot``: the blocks below ``joint`` turning about that corner as one (their joints shut at their offsets), the
    blocks above turning with them and sliding u' along the joint."""
    phi, u, dphi, du = state[:4]
    c, s = math.cos(phi), math.sin(phi)
    n = nb.n
    q, v = np.zeros((3, n)), np.zeros((3, n))
    x, z = -pivot * nb.b[0], 0.0                    # block k's base centre from the pivot, the blocks' frame
    for k in range(n):
        if k > 0:
            x, z = x + (u if k == joint else nb.off[k]), z + 2.0 * nb.h[k - 1]
        cz = z + nb.h[k]
        # a point (x, z) from the pivot is at R(phi) (x, z), moving at phi' R(phi) (z, -x); the slip along R(phi) (1, 0)
        q[:, k] = (pivot * nb.b[0] + c * x + s * cz, -s * x + c * cz, phi)
        slide = du if k >= joint else 0.0
        v[:, k] = (dphi * (c * cz - s * x) + slide * c, dphi * (-s * cz - c * x) - slide * s, dphi)
    return q, v


def slide_rock_state(bd: Bodies, q: np.ndarray, v: np.ndarray, joint: int = 1) -> SlideRockState:
    """A stack turning as one on a corner of block 0, every joint shut and all but ``joint`` sticking: the slide-rock
    model's state (:mod:`.slide_rock`: phi, u, phi', u'), block 0's rotation and rate, the base centre's offset of
    block ``joint`` from the centre of the top under it along that face and its rate there (that base centre's
    velocity less the lower block's at the same point, along the face) [rad, m, rad s-1, m s-1]."""
    phi = float(q[2, 0])
    lower = joint - 1
    px, pz = corner_point(q, joint, 0.0, -bd.h[joint])
    vx1, vz1 = v[0, joint] + v[2, joint] * (pz - q[1, joint]), v[1, joint] - v[2, joint] * (px - q[0, joint])
    vx0, vz0 = v[0, lower] + v[2, lower] * (pz - q[1, lower]), v[1, lower] - v[2, lower] * (px - q[0, lower])
    du = math.cos(phi) * (vx1 - vx0) - math.sin(phi) * (vz1 - vz0)
    return SlideRockState(phi, float(base_offset(bd, q, joint)), float(v[2, 0]), float(du), joint)


def stack_of(nb: NBlock, offsets_m, count: int) -> NBlock:
    """The lowest ``count`` blocks of ``nb`` with each block's base centred ``offsets_m[k]`` [m] from the centre of
    the top of the block under it, each joint's support the overlap of its faces there (empty where they no longer
    overlap: ``hi <= lo``)."""
    b, h = nb.b[:count], nb.h[:count]
    off = (0.0,) + tuple(float(x) for x in offsets_m[1:count])
    lo = [-b[0]] + [max(-b[k], -b[k - 1] - off[k]) for k in range(1, count)]
    hi = [b[0]] + [min(b[k], b[k - 1] - off[k]) for k in range(1, count)]
    pad = (0.0,) * (MAX_BODIES - count)
    return NBlock(count, tuple(b) + pad, tuple(h) + pad, tuple(nb.m[:count]) + pad, tuple(nb.i[:count]) + pad,
                  tuple(lo) + pad, tuple(hi) + pad, off + pad)


def shifted(nb: NBlock, offsets_m, count: int) -> NBlock | None:
    """:func:`stack_of`, or None where a block's base no longer overlaps its support or the part above a joint would
    not stand at rest on it (its centre of mass outside the overlap)."""
    out = stack_of(nb, offsets_m, count)
    for k in range(count):
        if out.hi[k] <= out.lo[k]:
            return None
        xg, _ = part_centre(out, k)
        if not out.lo[k] < xg < out.hi[k]:
            return None
    return out


def handback(bd: Bodies, q: np.ndarray, v: np.ndarray, modes: np.ndarray, count: int) -> tuple[tuple, tuple]:
    """Each block's offset [m] (its base centre from the centre of the top below, as if the joint were shut: a joint
    turning on a corner placed by where that corner meets the other face) and the n-block state of ``modes``."""
    offsets, psi, rate = [0.0] * MAX_BODIES, [0.0] * MAX_BODIES, [0.0] * MAX_BODIES
    for k in range(count):
        side = int(modes[k])
        if side != 0:
            psi[k] = float(tilt(q, k))
            rate[k] = float(v[2, k] - (v[2, k - 1] if k > 0 else 0.0))
        if k == 0:
            continue
        offsets[k] = float(base_offset(bd, q, k))
        if side != 0:
            px, pz = corner_point(q, k, side * bd.b[k], -bd.h[k])          # the upper's corner on the lower's face
            lx, _ = local_point(q, k - 1, px, pz)
            if abs(lx) <= bd.b[k - 1]:
                offsets[k] = float(lx - side * bd.b[k])
            else:                                                       # the lower's corner on the upper's face
                px, pz = corner_point(q, k - 1, side * bd.b[k - 1], bd.h[k - 1])
                ux, _ = local_point(q, k, px, pz)
                offsets[k] = float(side * bd.b[k - 1] - ux)
    return tuple(offsets), tuple(psi) + tuple(rate)
