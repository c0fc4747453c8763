"""The compiled kernel of the 3D box (:mod:`.box3d` states the model, its equations and their sources): the
equations of motion on a corner and on an edge, the Dormand-Prince step, the transitions (lift at rest, a corner
lifting off an edge, a corner landing, a flat landing) and the run over a record.

State: ``y = (q0, q1, q2, q3, omega_x, omega_y, omega_z)``, the unit quaternion (body to world) and the angular
velocity in the world's axes. Mode: ``REST`` (flat), ``EDGE`` (on edge ``pivot``: corners ``pivot`` and
``pivot + 1``) or ``CORNER`` (on corner ``pivot``).
"""

from __future__ import annotations

import math
from typing import NamedTuple

from ...compiled import array_as_tuple, jit, jit_inline, store
from ..numerics.rk import DOPRI54, rk_step
from .vec3 import cross, effective_gravity, error_norm, shifted, solve3, solve_sym3

REST, CORNER, EDGE, TWIST_NEXT, TWIST_PREV = -1, 0, 1, 2, 3
STATE_SIZE = 7                  # the quaternion and the angular velocity

# Step limits and events, named once (the step-size factors: ..numerics.rk)
MAX_STEPS_PER_SAMPLE = 2000     # steps allowed per record sample before the run ends, flagged
LAND_THETA_ALPHA = 1e-9         # a base corner within this x alpha x the base's smaller side lands [-]
REST_RATE = 1e-6                # a rebound slower than this x p alpha [rad s-1] ends the motion
EVENT_BISECTIONS = 60           # bisections locating a landing inside a step



class BoxParams(NamedTuple):
    """A box's constants, derived once (per unit mass)."""

    bx: float           # half-width [m]
    by: float           # half-depth [m]
    hz: float           # half-height [m]
    ix: float           # principal moments of inertia about G [m2]
    iy: float
    iz: float
    alpha: float        # the smaller slenderness [rad]
    p: float            # frequency parameter of the plane of the width [rad s-1]
    scale: float        # the declared restitution over Housner's [-]
    mu: float           # friction [-]
    land_m: float       # a corner this high has landed [m]
    atol_angle: float
    atol_rate: float
    rtol: float


class BoxRun(NamedTuple):
    """The kernel's outcome (:class:`.box3d.BoxOutcome` is the user's)."""

    overturned: bool
    t_overturn: float
    tilt_max: float
    azimuth_max: float
    flag: int
    impacts: int
    corner_s: float
    demand: float
    held: int
    steps: int          # Runge-Kutta steps tried (accepted and rejected) and transitions
    holds: int          # cascades of flat landings held at rest to the next sample
    mode: int           # the contact where the run ended (REST, CORNER, EDGE, ...)
    pivot: int          # its corner or edge


@jit
def _params(g, bx, by, hz, mu, scale, rtol, atol_alpha):
    """The box's :class:`BoxParams` (half sizes [m], friction, the restitution's scale, the tolerances)."""
    alpha = min(math.atan2(bx, hz), math.atan2(by, hz))
    r_w = math.hypot(bx, hz)
    p = math.sqrt(0.75 * g / r_w)
    land = LAND_THETA_ALPHA * alpha
    return BoxParams(bx, by, hz, (by * by + hz * hz) / 3.0, (bx * bx + hz * hz) / 3.0, (bx * bx + by * by) / 3.0,
                     alpha, p, scale, mu, land * 2.0 * min(bx, by), atol_alpha * alpha,
                     atol_alpha * alpha * p, rtol)


@jit
def corner(k, prm):
    """Base corner ``k`` (0-3, counter-clockwise from (+b_x, +b_y)) in the body's axes [m]."""
    k = k % 4
    return (prm.bx if k == 0 or k == 3 else -prm.bx), (prm.by if k < 2 else -prm.by), -prm.hz


@jit
def rotation(y):
    """The rotation matrix of the (normalised) quaternion ``y[0:4]``, row by row."""
    n = math.sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3])
    q0, q1, q2, q3 = y[0] / n, y[1] / n, y[2] / n, y[3] / n
    return (1 - 2 * (q2 * q2 + q3 * q3), 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2),
            2 * (q1 * q2 + q0 * q3), 1 - 2 * (q1 * q1 + q3 * q3), 2 * (q2 * q3 - q0 * q1),
            2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), 1 - 2 * (q1 * q1 + q2 * q2))


@jit
def _apply(m, x, y, z):
    """The rotation ``m`` (nine entries, row by row) applied to (x, y, z)."""
    return (m[0] * x + m[1] * y + m[2] * z, m[3] * x + m[4] * y + m[5] * z, m[6] * x + m[7] * y + m[8] * z)


@jit
def _inertia_g(m, prm):
    """I_G in the world's axes, R diag(i_x, i_y, i_z) R^T, as six entries (xx, xy, xz, yy, yz, zz)."""
    a, b, c = prm.ix, prm.iy, prm.iz
    return (a * m[0] * m[0] + b * m[1] * m[1] + c * m[2] * m[2], a * m[0] * m[3] + b * m[1] * m[4] + c * m[2] * m[5],
            a * m[0] * m[6] + b * m[1] * m[7] + c * m[2] * m[8], a * m[3] * m[3] + b * m[4] * m[4] + c * m[5] * m[5],
            a * m[3] * m[6] + b * m[4] * m[7] + c * m[5] * m[8], a * m[6] * m[6] + b * m[7] * m[7] + c * m[8] * m[8])


@jit
def _sym_apply(s, x, y, z):
    """The symmetric matrix ``s`` (six entries: xx, xy, xz, yy, yz, zz) applied to (x, y, z)."""
    return (s[0] * x + s[1] * y + s[2] * z, s[1] * x + s[3] * y + s[4] * z, s[2] * x + s[4] * y + s[5] * z)


@jit
def lever(m, k, prm):
    """r = G - (corner k) in the world's axes [m]."""
    cx, cy, cz = corner(k, prm)
    rx, ry, rz = _apply(m, cx, cy, cz)
    return -rx, -ry, -rz


@jit
def edge_axis(m, j, prm):
    """The unit direction of edge ``j`` (corner j to corner j + 1) in the world's axes, and its length [m]."""
    ax_, ay_, az_ = corner(j, prm)
    bx_, by_, bz_ = corner(j + 1, prm)
    ux, uy, uz = _apply(m, bx_ - ax_, by_ - ay_, bz_ - az_)
    n = math.sqrt(ux * ux + uy * uy + uz * uz)
    return ux / n, uy / n, uz / n, n


#: The contact forces an accepted step reports (:func:`derivatives`): F_x, F_y, F_z, N_1, N_2, F_2 across the edge
FORCE_SIZE = 6


@jit
def edge_ends_hold(force, mu, ux, uy):
    """Whether friction holds at both corners of an edge (unit horizontal direction ``(ux, uy)``) under ``force``
    (:func:`derivatives`): the forces across the edge are fixed by the yaw couple (corner 2's is ``force[5]``, corner
    1's the rest), those along it only in sum, so both hold where each corner's friction cone leaves room across
    and the two rooms along the edge add up to the force along it. Coulomb's law at each contact point."""
    n1, n2 = force[3], force[4]
    across = -force[0] * uy + force[1] * ux
    along = force[0] * ux + force[1] * uy
    x2 = force[5]
    x1 = across - x2
    r1 = (mu * n1) ** 2 - x1 * x1
    r2 = (mu * n2) ** 2 - x2 * x2
    if r1 < 0.0 or r2 < 0.0:
        return False
    return math.sqrt(r1) + math.sqrt(r2) >= abs(along)


@jit
def derivatives(y, gx, gy, gz, prm, mode, pivot):
    """d/dt of the state on a corner, an edge, or a corner with the edge's other corner sliding (the module's
    equations) under the effective gravity (gx, gy, gz) = (-a_x, -a_y, -g - a_z), as a tuple like ``y``; and the
    contact force per unit mass (F_x, F_y, F_z) and, on an edge, the normal forces at its two corners (N_1 at
    ``pivot``, N_2 at ``pivot + 1``) and the second corner's force across the edge (along e_z x u: the yaw couple of
    the two corners, from the contact's moment about the pivot, ``M_z / L``); with a corner sliding, the pivot's
    force, its normal force and the sliding corner's (and 0)."""
    m = rotation(y)
    rx, ry, rz = lever(m, pivot, prm)
    ig = _inertia_g(m, prm)
    ip = shifted(ig[0], ig[1], ig[2], ig[3], ig[4], ig[5], rx, ry, rz)
    wx, wy, wz = y[4], y[5], y[6]
    lx, ly, lz = _sym_apply(ip, wx, wy, wz)
    gyx, gyy, gyz = cross(wx, wy, wz, lx, ly, lz)
    tx, ty, tz = cross(rx, ry, rz, gx, gy, gz)
    n1, n2 = 0.0, 0.0
    twist = mode == TWIST_NEXT or mode == TWIST_PREV
    if twist:
        # omega = s u + psi' e_z with u along the edge (the sliding corner stays on the ground): the Euler equation
        # with the sliding corner's normal force N (frictionless slide) solved for s'', psi'' and N
        ux, uy, uz, length = edge_axis(m, pivot if mode == TWIST_NEXT else pivot - 1, prm)
        if mode == TWIST_PREV:
            ux, uy, uz = -ux, -uy, -uz
        s, wz_ = wx * ux + wy * uy + wz * uz, wz
        a0x, a0y = -s * wz_ * uy, s * wz_ * ux                     # s psi' (e_z x u)
        b = _sym_apply(ip, a0x, a0y, 0.0)
        c1 = _sym_apply(ip, ux, uy, uz)
        sdd, pdd, n2 = solve3(c1[0], ip[2], -length * uy, c1[1], ip[4], length * ux, c1[2], ip[5], 0.0,
                              tx - gyx - b[0], ty - gyy - b[1], tz - gyz - b[2])
        alx, aly, alz = sdd * ux + a0x, sdd * uy + a0y, sdd * uz + pdd
    elif mode == EDGE:
        ux, uy, uz, length = edge_axis(m, pivot, prm)
        iu = _sym_apply(ip, ux, uy, uz)
        sdd = (ux * tx + uy * ty + uz * tz) / (ux * iu[0] + uy * iu[1] + uz * iu[2])
        alx, aly, alz = sdd * ux, sdd * uy, sdd * uz
    else:
        alx, aly, alz = solve_sym3(ip[0], ip[1], ip[2], ip[3], ip[4], ip[5], tx - gyx, ty - gyy, tz - gyz)
    q0, q1, q2, q3 = y[0], y[1], y[2], y[3]
    cx, cy, cz = cross(wx, wy, wz, q1, q2, q3)
    f = (-0.5 * (wx * q1 + wy * q2 + wz * q3), 0.5 * (q0 * wx + cx), 0.5 * (q0 * wy + cy), 0.5 * (q0 * wz + cz),
         alx, aly, alz)
    vx, vy, vz = cross(wx, wy, wz, rx, ry, rz)
    ax1, ay1, az1 = cross(alx, aly, alz, rx, ry, rz)
    ax2, ay2, az2 = cross(wx, wy, wz, vx, vy, vz)
    fx, fy, fz = ax1 + ax2 - gx, ay1 + ay2 - gy, az1 + az2 - gz
    if twist:
        return f, (fx, fy, fz - n2, fz - n2, n2, 0.0)  # the pivot's force, its normal force, the sliding corner's
    if mode == EDGE:
        mx, my, mz = _sym_apply(ip, alx, aly, alz)
        mx, my, mz = mx + gyx - tx, my + gyy - ty, mz + gyz - tz
        n2 = -(mx * -uy + my * ux) / length          # N_2 = -M_P . (e_z x w) / L
        n1 = fz - n2
        return f, (fx, fy, fz, n1, n2, mz / length)  # F_2 . (e_z x u) = M_P,z / L (the edge on the ground)
    return f, (fx, fy, fz, n1, n2, 0.0)


@jit_inline
def _rhs(t, y, args):
    """f of the box in ``mode`` on ``pivot`` (``args``: sample interval, ground, constants, mode, pivot) at ``t``,
    and the contact forces (:func:`derivatives`)."""
    i, grd, prm, mode, pivot = args
    gx, gy, gz = effective_gravity(t, i, grd)
    return derivatives(y, gx, gy, gz, prm, mode, pivot)


@jit
def dopri_step(t, y, hh, i, grd, prm, mode, pivot, k, y_new, err, force):
    """One Dormand-Prince 5(4) step of ``hh`` from ``(t, y)`` (:func:`~..numerics.rk.rk_step`; ``k[0]``: f at the
    start): the 5th-order state in ``y_new``, the error in ``err``, f at the end in ``k[1]`` and the contact forces
    there in ``force``."""
    st = rk_step(_rhs, (i, grd, prm, mode, pivot), t, array_as_tuple(y, STATE_SIZE), array_as_tuple(k[0], STATE_SIZE),
                 hh, DOPRI54)
    store(y_new, st.y)
    store(err, st.err)
    store(k[1], st.f)
    store(force, st.kept)


@jit
def _error_norm(y, y_new, err, prm):
    """The step's error over the tolerance: the quaternion's four components held to the angles' tolerance."""
    return error_norm(y, y_new, err, 4, prm.atol_angle, prm.atol_rate, prm.rtol)


@jit
def height(m, y, k, pivot, prm):
    """The height of base corner ``k`` above the pivot corner [m], and its rate [m s-1] (``m``: the rotation of
    ``y``)."""
    ax_, ay_, az_ = corner(k, prm)
    bx_, by_, bz_ = corner(pivot, prm)
    dx, dy, dz = _apply(m, ax_ - bx_, ay_ - by_, az_ - bz_)
    vx, vy, vz = cross(y[4], y[5], y[6], dx, dy, dz)
    return dz, vz


@jit
def tilt_of(y):
    """The tilt of the body's axis from the vertical [rad] and the azimuth it leans toward [rad]."""
    n = y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3]
    rzz = 1.0 - 2.0 * (y[1] * y[1] + y[2] * y[2]) / n
    rxz, ryz = 2.0 * (y[1] * y[3] + y[0] * y[2]) / n, 2.0 * (y[2] * y[3] - y[0] * y[1]) / n
    return math.acos(max(-1.0, min(1.0, rzz))), math.atan2(ryz, rxz)


@jit
def flatten(y):
    """The quaternion set to the pure turn about the vertical nearest ``y[0:4]`` (the box flat on its base);
    returns that turn [rad]."""
    m = rotation(y)
    psi = math.atan2(m[3], m[0])
    y[0], y[1], y[2], y[3] = math.cos(0.5 * psi), 0.0, 0.0, math.sin(0.5 * psi)
    return psi
