"""The compiled kernel of the 3D cylinder (:mod:`.cylinder3d` states the model, its equations and their sources):
its constants, the equations of motion rolling on the rim (the angular acceleration from
``(I_G + |r|^2 1 - r r^T) omega' = -omega x I_G omega - r x (omega x r') + r x g_eff`` and the Euler angles'
accelerations), the Dormand-Prince step through :func:`~..numerics.rk.rk_step`, the landing's impulse about the new
contact point, and the energy measures the settle rule reads.

State: ``y = (theta, phi, psi, theta', phi', psi')``, the Euler angles of the tilt, its azimuth and the spin, and
their rates.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from ...compiled import array_as_tuple, jit, jit_inline, store
from ..numerics.rk import DOPRI54, rk_step
from .vec3 import cross as _cross
from .vec3 import effective_gravity, error_norm
from .vec3 import solve_sym3 as _solve_sym3

STATE_SIZE = 6                  # the Euler angles and their rates
LAND_THETA_ALPHA = 1e-9         # theta (fraction of alpha) at which the base is taken to land flat, or starts


class Params(NamedTuple):
    """A cylinder's constants, derived once for the compiled kernel (per unit mass)."""

    a: float            # radius [m]
    h: float            # half-height [m]
    i1: float           # transverse moment of inertia about G [m2]
    i3: float           # axial moment of inertia [m2]
    alpha: float        # slenderness atan(a / h) [rad]
    p: float            # frequency parameter sqrt(g R / (I_G + R^2)) [rad s-1]
    scale: float        # the declared restitution over Housner's [-]
    mu: float           # friction [-]
    land: float         # the tilt taken as landed [rad]
    atol_angle: float   # absolute tolerance on angles [rad]
    atol_rate: float    # ... on rates [rad s-1]
    rtol: float         # relative tolerance [-]


@jit
def inertia_about(e3x, e3y, e3z, rx, ry, rz, i1, i3):
    """The symmetric inertia about a point at ``-r`` from G, per unit mass: I_G + |r|^2 1 - r r^T, with
    I_G = i1 1 + (i3 - i1) e3 e3^T (axisymmetric)."""
    d = i3 - i1
    rr = rx * rx + ry * ry + rz * rz
    return (i1 + d * e3x * e3x + rr - rx * rx, d * e3x * e3y - rx * ry, d * e3x * e3z - rx * rz,
            i1 + d * e3y * e3y + rr - ry * ry, d * e3y * e3z - ry * rz, i1 + d * e3z * e3z + rr - rz * rz)


@jit
def frame(th, ph, a, h):
    """Axis e3, line of nodes e_n and r = G - P (and its partial derivatives in theta and phi)."""
    st, ct, sp, cp = math.sin(th), math.cos(th), math.sin(ph), math.cos(ph)
    lever = h * st - a * ct                  # = R sin(theta - alpha): G's horizontal offset from P
    up = h * ct + a * st                     # = R cos(theta - alpha): G's height
    return st, ct, sp, cp, lever, up


@jit
def derivatives(y, gx, gy, gz, a, h, i1, i3):
    """d/dt of the state (theta, phi, psi, theta', phi', psi') rolling on the rim, per unit mass, under the
    effective gravity (gx, gy, gz) = (-a_x, -a_y, -g - a_z), as a tuple like ``y``; and the contact force per unit
    mass (F_x, F_y, F_z) = a_G - g_eff."""
    th, ph, tdot, pdot, sdot = y[0], y[1], y[3], y[4], y[5]
    st, ct, sp, cp, lever, up = frame(th, ph, a, h)
    e3x, e3y, e3z = st * cp, st * sp, ct
    enx, eny = -sp, cp
    # omega = phi' e_z + theta' e_n + psi' e3
    wx = tdot * enx + sdot * e3x
    wy = tdot * eny + sdot * e3y
    wz = pdot + sdot * e3z
    rx, ry, rz = lever * cp, lever * sp, up
    # r' = r_theta theta' + r_phi phi'
    drx = up * cp * tdot - lever * sp * pdot
    dry = up * sp * tdot + lever * cp * pdot
    drz = (-h * st + a * ct) * tdot
    # I_G omega, and the gyroscopic term omega x I_G omega
    w3 = wx * e3x + wy * e3y + wz * e3z
    lx, ly, lz = i1 * wx + (i3 - i1) * w3 * e3x, i1 * wy + (i3 - i1) * w3 * e3y, i1 * wz + (i3 - i1) * w3 * e3z
    gyx, gyy, gyz = _cross(wx, wy, wz, lx, ly, lz)
    wrx, wry, wrz = _cross(wx, wy, wz, drx, dry, drz)
    c1x, c1y, c1z = _cross(rx, ry, rz, wrx, wry, wrz)
    c2x, c2y, c2z = _cross(rx, ry, rz, gx, gy, gz)
    m = inertia_about(e3x, e3y, e3z, rx, ry, rz, i1, i3)
    alx, aly, alz = _solve_sym3(m[0], m[1], m[2], m[3], m[4], m[5],
                                -gyx - c1x + c2x, -gyy - c1y + c2y, -gyz - c1z + c2z)
    # omega' = phi'' e_z + theta'' e_n + psi'' e3 + b, b = theta' phi' (e_z x e_n) + psi' (phi' e_z + theta' e_n) x e3
    fx, fy, fz = _cross(tdot * enx, tdot * eny, pdot, e3x, e3y, e3z)
    bx = tdot * pdot * (-cp) + sdot * fx
    by = tdot * pdot * (-sp) + sdot * fy
    bz = sdot * fz
    ux, uy, uz = alx - bx, aly - by, alz - bz
    tdd = ux * enx + uy * eny
    ux, uy = ux - tdd * enx, uy - tdd * eny
    sdd = (ux * cp + uy * sp) / st
    pdd = uz - sdd * ct
    # the contact force per unit mass: a_G - g_eff, a_G = omega' x r + omega x r'
    agx, agy, agz = _cross(alx, aly, alz, rx, ry, rz)
    return (tdot, pdot, sdot, tdd, pdd, sdd), (agx + wrx - gx, agy + wry - gy, agz + wrz - gz)


@jit_inline
def _rhs(t, y, args):
    """f of the rolling cylinder (``args``: sample interval, ground, constants) at ``t``, and the contact force per
    unit mass (:func:`derivatives`)."""
    i, grd, prm = args
    gx, gy, gz = effective_gravity(t, i, grd)
    return derivatives(y, gx, gy, gz, prm.a, prm.h, prm.i1, prm.i3)


@jit
def dopri_step(t, y, hh, i, grd, prm, k, y_new, err):
    """One Dormand-Prince 5(4) step of length ``hh`` from ``(t, y)`` (:func:`~..numerics.rk.rk_step`; ``k[0]``: f
    at the start, FSAL): the 5th-order state in ``y_new``, the embedded error in ``err``, and f at the end in
    ``k[1]``; returns the contact force per unit mass at the end."""
    st = rk_step(_rhs, (i, grd, prm), t, array_as_tuple(y, STATE_SIZE), array_as_tuple(k[0], STATE_SIZE), hh,
                 DOPRI54)
    store(y_new, st.y)
    store(err, st.err)
    store(k[1], st.f)
    return st.kept


@jit
def landing(y, a, h, i1, i3, scale):
    """The impact of a base landing flat (theta ~ 0): angular momentum about the new contact point conserved;
    the new state rocks on the side the rebound tilts toward (the impulse's point found in two passes). Returns
    the rebound's tilting rate [rad s-1]."""
    th, ph, tdot, pdot, sdot = y[0], y[1], y[3], y[4], y[5]
    st, ct, sp, cp, lever, up = frame(th, ph, a, h)
    e3x, e3y, e3z = st * cp, st * sp, ct
    wx, wy, wz = -tdot * sp + sdot * e3x, tdot * cp + sdot * e3y, pdot + sdot * e3z
    rx, ry, rz = lever * cp, lever * sp, up                       # r = G - P before
    w3 = wx * e3x + wy * e3y + wz * e3z
    lx, ly, lz = i1 * wx + (i3 - i1) * w3 * e3x, i1 * wy + (i3 - i1) * w3 * e3y, i1 * wz + (i3 - i1) * w3 * e3z
    vx, vy, vz = _cross(wx, wy, wz, rx, ry, rz)                    # v_G before
    new_ph = ph + math.pi
    nx, ny, nz = 0.0, 0.0, 0.0
    for _ in range(2):
        # the new contact P' on the rim toward new_ph: r' = h e3 - a u(new_ph)
        ux, uy, uz = ct * math.cos(new_ph), ct * math.sin(new_ph), -st
        qx, qy, qz = h * e3x - a * ux, h * e3y - a * uy, h * e3z - a * uz
        hx, hy, hz = _cross(qx, qy, qz, vx, vy, vz)
        m = inertia_about(e3x, e3y, e3z, qx, qy, qz, i1, i3)
        nx, ny, nz = _solve_sym3(m[0], m[1], m[2], m[3], m[4], m[5], lx + hx, ly + hy, lz + hz)
        if nx * nx + ny * ny > 0.0:
            new_ph = math.atan2(-nx * scale, ny * scale)
    nx, ny = nx * scale, ny * scale
    rate = math.sqrt(nx * nx + ny * ny)
    y[5] = nz                                   # the spin about the vertical, all in psi (phi' = 0)
    y[2] = y[1] + y[2] - new_ph                 # R_z(phi + psi) kept at theta ~ 0
    y[1] = new_ph
    y[3] = rate
    y[4] = 0.0
    return rate


@jit
def params_of(g, a, h, mu, scale, rtol, atol_alpha):
    """The cylinder's :class:`Params` (radius and half height [m], friction, the restitution's scale, the
    tolerances)."""
    alpha = math.atan2(a, h)
    big_r = math.hypot(a, h)
    i1 = a * a / 4.0 + h * h / 3.0
    p = math.sqrt(g * big_r / (i1 + big_r * big_r))
    return Params(a, h, i1, a * a / 2.0, alpha, p, scale, mu,
                  LAND_THETA_ALPHA * alpha, atol_alpha * alpha, atol_alpha * alpha * p, rtol)


@jit
def error_over_tolerance(y, y_new, err, prm):
    """The embedded error over the tolerance, the largest over the six states (NaN stays NaN: rejected). The
    azimuth phi is held to the angles' tolerance even near the vertical, where an error in it moves the axis
    little: it persists, and turns the rocking plane once the tilt grows (measured: weighting it by sin(theta)
    let a motion excited in one plane leave it by 16 deg)."""
    return error_norm(y, y_new, err, 3, prm.atol_angle, prm.atol_rate, prm.rtol)


@jit
def rise(theta, prm):
    """How much G rises from flat to the tilt ``theta`` <= alpha [m]: R cos(alpha - theta) - h."""
    return math.hypot(prm.a, prm.h) * math.cos(prm.alpha - theta) - prm.h


@jit
def kinetic(y, prm):
    """The kinetic energy per unit mass of the cylinder rolling on its rim, about the contact point [m2 s-2]:
    omega^T (I_G + |r|^2 1 - r r^T) omega / 2."""
    th, ph, tdot, pdot, sdot = y[0], y[1], y[3], y[4], y[5]
    st, ct, sp, cp, lever, up = frame(th, ph, prm.a, prm.h)
    e3x, e3y, e3z = st * cp, st * sp, ct
    wx, wy, wz = -tdot * sp + sdot * e3x, tdot * cp + sdot * e3y, pdot + sdot * e3z
    m = inertia_about(e3x, e3y, e3z, lever * cp, lever * sp, up, prm.i1, prm.i3)
    return 0.5 * (m[0] * wx * wx + m[3] * wy * wy + m[5] * wz * wz
                  + 2.0 * (m[1] * wx * wy + m[2] * wx * wz + m[4] * wy * wz))
