"""An independent form of the equations of n stacked rocking blocks, for the tests: Lagrange's equations of the
blocks' energy, the positions as complex numbers built corner by corner, the kinetic energy's mass matrix from the
bodies' velocities, its derivative and the potential's gradient by central differences. It shares with
:mod:`pipeline.assemblies.n_block` only the model's rules (each body turns about a corner of its support on the body
below; a shut joint holds its rotation at 0), not its code.
"""

from __future__ import annotations

import cmath

import numpy as np

G = 9.80665
DIFF = 1e-6


class Stack:
    """Blocks bottom first: half-widths b, half-heights h, masses m, each base's offset from the top's centre below."""

    def __init__(self, b, h, m, off):
        self.b, self.h, self.m, self.off = (np.asarray(v, dtype=float) for v in (b, h, m, off))
        self.n = len(self.b)
        self.inertia = self.m * (self.b ** 2 + self.h ** 2) / 3.0

    def support(self, k):
        """Joint k's support in block k's frame: the overlap of its base with the face below."""
        if k == 0:
            return -self.b[0], self.b[0]
        return max(-self.b[k], -self.b[k - 1] - self.off[k]), min(self.b[k], self.b[k - 1] - self.off[k])


def _corner(stack: Stack, k: int, s: int) -> float:
    lo, hi = stack.support(k)
    return hi if s >= 0 else lo


def centres(stack: Stack, phi, corners_):
    """Each block's centre as x + i z; the ground's origin at block 0's base centre at rest."""
    out = []
    point = complex(_corner(stack, 0, corners_[0]), 0.0)           # the corner block 0 turns about
    for k in range(stack.n):
        spin = cmath.exp(-1j * phi[k])                                # a clockwise rotation of x + i z
        px = _corner(stack, k, corners_[k])
        out.append(point + spin * complex(-px, stack.h[k]))
        if k + 1 < stack.n:
            qx = _corner(stack, k + 1, corners_[k + 1]) + stack.off[k + 1]
            point = point + spin * complex(qx - px, 2.0 * stack.h[k])
    return out


def _absolute(psi):
    return np.cumsum(psi)


def _map(joints):
    """S: the open joints' relative rates to the absolute rates."""
    n = len(joints)
    cols = [j for j in range(n) if joints[j] != 0]
    return np.array([[1.0 if k >= j else 0.0 for j in cols] for k in range(n)]).reshape(n, len(cols))


def _mass(stack: Stack, q, joints):
    """S^T M S from the kinetic energy: the velocities of unit rates by differences of the positions."""
    corners_ = [1 if j >= 0 else -1 for j in joints]
    S = _map(joints)
    cols = []
    for c in range(S.shape[1]):
        plus = centres(stack, q + DIFF * S[:, c], corners_)
        minus = centres(stack, q - DIFF * S[:, c], corners_)
        cols.append(([(p - m) / (2 * DIFF) for p, m in zip(plus, minus)], S[:, c]))
    out = np.zeros((S.shape[1], S.shape[1]))
    for a, (va, wa) in enumerate(cols):
        for b, (vb, wb) in enumerate(cols):
            out[a, b] = sum(stack.m[k] * (va[k].real * vb[k].real + va[k].imag * vb[k].imag)
                            + stack.inertia[k] * wa[k] * wb[k] for k in range(stack.n))
    return out


def _potential(stack: Stack, q, joints, ah, av):
    corners_ = [1 if j >= 0 else -1 for j in joints]
    return sum(stack.m[k] * (ah * c.real + (G + av) * c.imag) for k, c in enumerate(centres(stack, q, corners_)))


def accelerations(stack: Stack, joints, psi, psi_rate, ah, av):
    """q'' (absolute) from Lagrange's equations in the open joints' coordinates."""
    S = _map(joints)
    q = _absolute(psi)
    if S.shape[1] == 0:
        return np.zeros(stack.n)
    z_rate = np.array([psi_rate[j] for j in range(stack.n) if joints[j] != 0])
    m = _mass(stack, q, joints)
    dm = [(_mass(stack, q + DIFF * S[:, c], joints) - _mass(stack, q - DIFF * S[:, c], joints)) / (2 * DIFF)
          for c in range(S.shape[1])]
    dv = np.array([(_potential(stack, q + DIFF * S[:, c], joints, ah, av)
                    - _potential(stack, q - DIFF * S[:, c], joints, ah, av)) / (2 * DIFF) for c in range(S.shape[1])])
    mdot = sum(dm[c] * z_rate[c] for c in range(S.shape[1]))
    dT = np.array([0.5 * z_rate @ dm[c] @ z_rate for c in range(S.shape[1])])
    return S @ np.linalg.solve(m, -mdot @ z_rate + dT - dv)
