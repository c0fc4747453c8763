"""An independent reference for two stacked blocks in a vertical plane rocking on a base corner of the lower block
while the upper block slides on the lower's top face, its joint shut: the equations of motion by Lagrange's method in
the stack's rotation phi and the upper block's offset u along the face, solved by scipy's ``solve_ivp``; and the same
accelerations by Newton-Euler, the contact forces unknowns of a linear system (a second derivation of the first).

Coordinates: phi clockwise positive (a positive rotation tips the stack towards +x), the pivot the lower block's base
corner on side ``pivot`` (+1: +x) at the origin, u the upper block's base centre from the centre of the lower's top
face along that face. With the field f = (-a_h, -(g + a_v)) per unit mass, its components along the face and its
normal f_e = -a_h cos(phi) + (g + a_v) sin(phi), f_n = -a_h sin(phi) - (g + a_v) cos(phi), r1x = -pivot b0 + u,
H = 2 h0 + h1 and A = m0 (b0^2 + h0^2) + I0 + I1 + m1 (r1x^2 + H^2):

    A phi'' + m1 H u'' + 2 m1 r1x u' phi' = m0 (h0 f_e + pivot b0 f_n) + m1 (H f_e - r1x f_n)
    m1 H phi'' + m1 u'' - m1 r1x phi'^2 = m1 f_e + F_t,      F_t = -mu N sign(u'),
    N = m1 (-phi'' r1x - phi'^2 H - 2 phi' u' - f_n)

(N the joint's normal force, F_t its friction on the upper block along the face). The joint's centre of pressure is
x_p = -(I1 phi'' + h1 F_t) / N from the upper block's base centre along the face.

References
----------
Goldstein, H., Poole, C. & Safko, J. (2002). Classical Mechanics, 3rd ed., chapter 1 (Lagrange's equations with
non-conservative generalized forces). Addison-Wesley.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy.integrate import solve_ivp

G = 9.80665


class SlideRock(NamedTuple):
    """Two blocks: the lower's half sizes and mass, the upper's, the joint's friction and the floor's [m, kg, -]."""

    b0: float
    h0: float
    m0: float
    b1: float
    h1: float
    m1: float
    mu_joint: float
    mu_floor: float


def accelerations(s: SlideRock, pivot: float, slip: float, phi, dphi, u, du, ah, av) -> tuple[float, float, float]:
    """phi'' [rad s-2], u'' [m s-2] and the joint's normal force N [N] by the module's equations (``slip`` the sign
    of u')."""
    i0, i1 = s.m0 * (s.b0 ** 2 + s.h0 ** 2) / 3.0, s.m1 * (s.b1 ** 2 + s.h1 ** 2) / 3.0
    c, sn = math.cos(phi), math.sin(phi)
    fe, fn = -ah * c + (G + av) * sn, -ah * sn - (G + av) * c
    big_h, r1x = 2.0 * s.h0 + s.h1, -pivot * s.b0 + u
    a = s.m0 * (s.b0 ** 2 + s.h0 ** 2) + i0 + i1 + s.m1 * (r1x ** 2 + big_h ** 2)
    q_phi = s.m0 * (s.h0 * fe + pivot * s.b0 * fn) + s.m1 * (big_h * fe - r1x * fn)
    k = s.mu_joint * slip
    lhs = np.array([[a, s.m1 * big_h], [s.m1 * (big_h - k * r1x), s.m1]])
    rhs = np.array([q_phi - 2.0 * s.m1 * r1x * du * dphi,
                    s.m1 * fe + s.m1 * r1x * dphi ** 2 + k * s.m1 * (dphi ** 2 * big_h + 2.0 * dphi * du + fn)])
    ddphi, ddu = np.linalg.solve(lhs, rhs)
    return float(ddphi), float(ddu), float(s.m1 * (-ddphi * r1x - dphi ** 2 * big_h - 2.0 * dphi * du - fn))


def _turned(phi: float, x: float, z: float) -> np.ndarray:
    """A vector of the blocks' frame (x, z) in the ground's, turned by phi (clockwise positive)."""
    c, s = math.cos(phi), math.sin(phi)
    return np.array([c * x + s * z, -s * x + c * z])


def newton_euler(s: SlideRock, pivot: float, slip: float, phi, dphi, u, du, ah, av) -> tuple[float, float, float]:
    """phi'', u'' and N by Newton-Euler: each block's linear and angular momentum balance, the ground's reaction,
    the joint's normal force and couple and u'' unknowns, the pivot fixed, the blocks turning together and the upper
    block's centre where u puts it."""
    x = _newton_euler(s, pivot, slip, phi, dphi, u, du, ah, av)
    return float(x[2]), float(x[10]), float(x[8])


def newton_euler_forces(s: SlideRock, pivot: float, slip: float, phi, dphi, u, du, ah, av) -> tuple:
    """The contact forces of :func:`newton_euler`: the ground's reaction (R_x, R_z) [N] and the joint's centre of
    pressure from the upper base's centre along the face [m] (its couple on the upper block C = -N x_p: the normal
    force's moment about the base centre)."""
    x = _newton_euler(s, pivot, slip, phi, dphi, u, du, ah, av)
    return float(x[6]), float(x[7]), float(-x[9] / x[8])


def _newton_euler(s: SlideRock, pivot: float, slip: float, phi, dphi, u, du, ah, av) -> np.ndarray:
    """The unknowns of :func:`newton_euler`'s linear system, solved."""
    i0, i1 = s.m0 * (s.b0 ** 2 + s.h0 ** 2) / 3.0, s.m1 * (s.b1 ** 2 + s.h1 ** 2) / 3.0
    f = np.array([-ah, -(G + av)])
    g0 = _turned(phi, -pivot * s.b0, s.h0)
    d_pivot, d_b0 = -g0, _turned(phi, u, s.h0)
    g1 = g0 + _turned(phi, u, s.h0 + s.h1)
    d_b1 = g0 + d_b0 - g1
    e, n = _turned(phi, 1.0, 0.0), _turned(phi, 0.0, 1.0)
    joint = n - s.mu_joint * slip * e                  # the joint's force on the upper block per unit N

    def torque(force, arm):                            # clockwise positive
        return force[0] * arm[1] - force[1] * arm[0]

    # unknowns: a0 (2), alpha0, a1 (2), alpha1, the ground's reaction (2), N, the joint's couple, u''
    m, b = np.zeros((11, 11)), np.zeros(11)
    for k in range(2):
        m[k, k], m[k, 6 + k], m[k, 8], b[k] = s.m0, -1.0, joint[k], s.m0 * f[k]
        m[3 + k, 3 + k], m[3 + k, 8], b[3 + k] = s.m1, -joint[k], s.m1 * f[k]
    m[2, 2], m[2, 6], m[2, 7], m[2, 8], m[2, 9] = i0, -d_pivot[1], d_pivot[0], torque(joint, d_b0), 1.0
    m[5, 5], m[5, 8], m[5, 9] = i1, -torque(joint, d_b1), -1.0
    m[6, 0], m[6, 2], b[6] = 1.0, d_pivot[1], dphi ** 2 * d_pivot[0]
    m[7, 1], m[7, 2], b[7] = 1.0, -d_pivot[0], dphi ** 2 * d_pivot[1]
    m[8, 5], m[8, 2] = 1.0, -1.0
    t1, t2 = _turned(phi, s.h0 + s.h1, -u), _turned(phi, u, s.h0 + s.h1)
    for k in range(2):
        m[9 + k, 3 + k], m[9 + k, k], m[9 + k, 2], m[9 + k, 10] = 1.0, -1.0, -t1[k], -e[k]
        b[9 + k] = -dphi ** 2 * t2[k] - 2.0 * dphi * du * n[k]
    return np.linalg.solve(m, b)


class Trajectory(NamedTuple):
    """The reference's motion to ``t_end_s`` and whether its assumptions held throughout (``holds``: the stack kept
    turning on its pivot, the upper block sliding one way, the joint pressed with its centre of pressure on the
    overlap of the two faces, the floor's reaction pressing and within its friction)."""

    phi_rad: float
    u_m: float
    holds: bool


def slide_rock(s: SlideRock, ah_ms2: float, t_end_s: float, *, pivot: float, slip: float,
               av_ms2: float = 0.0, y0: tuple = (0.0, 0.0, 0.0, 0.0)) -> Trajectory:
    """The stack from ``y0`` = (phi, phi', u, u') (rest by default) under a constant ground acceleration
    (``ah_ms2``, ``av_ms2``), turning on its ``pivot`` corner with the upper block sliding the way ``slip`` says, by
    the equations integrated to ``t_end_s``."""

    def rhs(_t, y):
        ddphi, ddu, _ = accelerations(s, pivot, slip, y[0], y[1], y[2], y[3], ah_ms2, av_ms2)
        return [y[1], ddphi, y[3], ddu]

    sol = solve_ivp(rhs, (0.0, t_end_s), list(y0), rtol=1e-11, atol=1e-13, dense_output=True)
    holds = True
    for t in np.linspace(0.0, t_end_s, 2001)[1:]:
        phi, dphi, u, du = sol.sol(t)
        ddphi, ddu, normal = accelerations(s, pivot, slip, phi, dphi, u, du, ah_ms2, av_ms2)
        f_t = -s.mu_joint * normal * slip
        i1 = s.m1 * (s.b1 ** 2 + s.h1 ** 2) / 3.0
        x_p = -(i1 * ddphi + s.h1 * f_t) / normal if normal > 0.0 else math.nan
        lo, hi = max(-s.b1, -s.b0 - u), min(s.b1, s.b0 - u)
        a0 = ddphi * _turned(phi, s.h0, pivot * s.b0) + dphi ** 2 * _turned(phi, pivot * s.b0, -s.h0)
        r1x, big_h = -pivot * s.b0 + u, 2.0 * s.h0 + s.h1
        a1 = (ddphi * _turned(phi, big_h, -r1x) - dphi ** 2 * _turned(phi, r1x, big_h)
              - 2.0 * dphi * du * _turned(phi, 0.0, 1.0) + ddu * _turned(phi, 1.0, 0.0))
        reaction = s.m0 * a0 + s.m1 * a1 - (s.m0 + s.m1) * np.array([-ah_ms2, -(G + av_ms2)])
        holds &= bool(pivot * phi > 0.0 and slip * du > 0.0 and normal > 0.0 and lo < x_p < hi
                      and reaction[1] > 0.0 and abs(reaction[0]) <= s.mu_floor * reaction[1])
    phi, _, u, _ = sol.y[:, -1]
    return Trajectory(float(phi), float(u), holds)
