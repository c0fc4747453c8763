"""The attitude of a rigid body in the 3D contact model (:mod:`.contact3d`), compiled: unit quaternions (w, x, y, z),
their rotation matrices, a turn at a constant rate, the inverse inertia in the world's frame and the energy per unit
mass.
"""

from __future__ import annotations

import math

import numpy as np

from ...compiled import jit_inline


@jit_inline
def rotation(q, r):
    """The rotation matrix of the unit quaternion q = (w, x, y, z) into ``r``."""
    w, x, y, z = q[0], q[1], q[2], q[3]
    r[0, 0], r[0, 1], r[0, 2] = 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)
    r[1, 0], r[1, 1], r[1, 2] = 2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)
    r[2, 0], r[2, 1], r[2, 2] = 2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)


def rotation_matrix(q) -> np.ndarray:
    """The rotation matrix of the unit quaternion q = (w, x, y, z), a new array (for callers in Python)."""
    r = np.empty((3, 3))
    rotation(np.asarray(q, dtype=float), r)
    return r


@jit_inline
def headed(heading, q_rest, out):
    """The standing orientation ``q_rest`` turned by ``heading`` [rad] about the vertical, into ``out``."""
    c, s = math.cos(heading / 2.0), math.sin(heading / 2.0)
    out[0] = c * q_rest[0] - s * q_rest[3]
    out[1] = c * q_rest[1] - s * q_rest[2]
    out[2] = c * q_rest[2] + s * q_rest[1]
    out[3] = c * q_rest[3] + s * q_rest[0]


@jit_inline
def turned(q, wx, wy, wz, t, out):
    """q turned by the world-frame rate (wx, wy, wz) over ``t`` (the exact rotation of a constant rate) into
    ``out`` (not q)."""
    ang = math.sqrt(wx * wx + wy * wy + wz * wz) * t
    if ang == 0.0:
        out[0], out[1], out[2], out[3] = q[0], q[1], q[2], q[3]
        return
    s = math.sin(ang / 2.0) / (ang / t)
    dw, dx, dy, dz = math.cos(ang / 2.0), wx * s, wy * s, wz * s
    o0 = dw * q[0] - dx * q[1] - dy * q[2] - dz * q[3]
    o1 = dw * q[1] + dx * q[0] + dy * q[3] - dz * q[2]
    o2 = dw * q[2] - dx * q[3] + dy * q[0] + dz * q[1]
    o3 = dw * q[3] + dx * q[2] - dy * q[1] + dz * q[0]
    norm = math.sqrt(o0 * o0 + o1 * o1 + o2 * o2 + o3 * o3)
    out[0], out[1], out[2], out[3] = o0 / norm, o1 / norm, o2 / norm, o3 / norm


@jit_inline
def world_inverse_inertia(r, inertia, out):
    """R diag(1 / I) R^T: the inverse inertia in the world frame, into ``out``."""
    for i in range(3):
        for j in range(3):
            s = 0.0
            for k in range(3):
                s += r[i, k] * r[j, k] / inertia[k]
            out[i, j] = s


@jit_inline
def energy(v, w, r, inertia, z_g, g):
    """Kinetic and potential energy per unit mass in the ground's frame (the ground still) [J kg-1]."""
    e = 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) + g * z_g
    for k in range(3):
        wk = r[0, k] * w[0] + r[1, k] * w[1] + r[2, k] * w[2]      # the rate in the body's axes
        e += 0.5 * inertia[k] * wk * wk
    return e
