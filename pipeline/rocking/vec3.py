"""Small compiled helpers of the 3D models (:mod:`.cylinder3d`, :mod:`.box3d`): cross products, the solution of a
symmetric 3 x 3 system (an inertia about a point), the inertia about a point by the parallel-axis theorem, and the
cubic Hermite interpolant of a step."""

from __future__ import annotations

from ..compiled import jit


@jit
def cross(ax, ay, az, bx, by, bz):
    """a x b, by components."""
    return ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx


@jit
def solve_sym3(m00, m01, m02, m11, m12, m22, b0, b1, b2):
    """x with M x = b for a symmetric 3 x 3 M (Cramer's rule; M is an inertia about a point: positive
    definite)."""
    c00 = m11 * m22 - m12 * m12
    c01 = m02 * m12 - m01 * m22
    c02 = m01 * m12 - m02 * m11
    det = m00 * c00 + m01 * c01 + m02 * c02
    c11 = m00 * m22 - m02 * m02
    c12 = m01 * m02 - m00 * m12
    c22 = m00 * m11 - m01 * m01
    return ((c00 * b0 + c01 * b1 + c02 * b2) / det, (c01 * b0 + c11 * b1 + c12 * b2) / det,
            (c02 * b0 + c12 * b1 + c22 * b2) / det)


@jit
def solve3(a00, a01, a02, a10, a11, a12, a20, a21, a22, b0, b1, b2):
    """x with A x = b for a general 3 x 3 A, row by row (Cramer's rule)."""
    det = a00 * (a11 * a22 - a12 * a21) - a01 * (a10 * a22 - a12 * a20) + a02 * (a10 * a21 - a11 * a20)
    x0 = b0 * (a11 * a22 - a12 * a21) - a01 * (b1 * a22 - a12 * b2) + a02 * (b1 * a21 - a11 * b2)
    x1 = a00 * (b1 * a22 - a12 * b2) - b0 * (a10 * a22 - a12 * a20) + a02 * (a10 * b2 - b1 * a20)
    x2 = a00 * (a11 * b2 - b1 * a21) - a01 * (a10 * b2 - b1 * a20) + b0 * (a10 * a21 - a11 * a20)
    return x0 / det, x1 / det, x2 / det


@jit
def shifted(m00, m01, m02, m11, m12, m22, rx, ry, rz):
    """The inertia about a point at ``-r`` from G, per unit mass: I_G + |r|^2 1 - r r^T (the parallel-axis
    theorem), as its six entries."""
    rr = rx * rx + ry * ry + rz * rz
    return (m00 + rr - rx * rx, m01 - rx * ry, m02 - rx * rz, m11 + rr - ry * ry, m12 - ry * rz, m22 + rr - rz * rz)


@jit
def hermite(y0, f0, y1, f1, hh, x):
    """The cubic through (0, y0) and (hh, y1) with slopes f0 and f1, at the fraction ``x`` of the step."""
    x2, x3 = x * x, x * x * x
    return ((2 * x3 - 3 * x2 + 1) * y0 + (x3 - 2 * x2 + x) * hh * f0 + (-2 * x3 + 3 * x2) * y1
            + (x3 - x2) * hh * f1)
