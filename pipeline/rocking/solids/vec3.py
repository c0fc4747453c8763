"""What the 3D models (:mod:`.cylinder3d`, :mod:`.box3d`) share: their flags, the check of the ground components
they take, and small compiled helpers (cross products, the solution of a 3 x 3 system, the inertia about a point by
the parallel-axis theorem, the cubic Hermite interpolant of a step, the contact's flag)."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...compiled import jit, jit_inline


class Ground(NamedTuple):
    """The ground's acceleration [m s-2] at samples ``dt`` [s] apart, for the compiled 3D kernels."""

    ax: np.ndarray
    ay: np.ndarray
    az: np.ndarray
    dt: float
    g: float


@jit
def effective_gravity(t, i, grd):
    """The effective gravity (-a_x, -a_y, -g - a_z) [m s-2] at ``t`` [s] inside sample interval ``i`` of ``grd``
    (the ground linear between samples)."""
    f = (t - i * grd.dt) / grd.dt
    return (-(grd.ax[i] + f * (grd.ax[i + 1] - grd.ax[i])), -(grd.ay[i] + f * (grd.ay[i + 1] - grd.ay[i])),
            -grd.g - (grd.az[i] + f * (grd.az[i + 1] - grd.az[i])))


# Locating a crossing inside a step, named once
CROSSING_PROBES = 16            # a step's cubic is probed at this many points before bisecting
CROSSING_BISECTIONS = 60        # then bisected this many times

# Flags (why a 3D scene is flagged)
FLAG_NONE, FLAG_FLIGHT, FLAG_SLIDE, FLAG_STEPS = 0, 1, 2, 3


def ground_components(ax_ms2, ay_ms2, az_ms2) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The ground's x, y and vertical acceleration as three equal contiguous float series (``az_ms2`` None: zeros).

    Raises
    ------
    ValueError
        Unless they are three equal 1-D series of at least 2 samples.
    """
    ax = np.ascontiguousarray(ax_ms2, dtype=float)
    ay = np.ascontiguousarray(ay_ms2, dtype=float)
    az = np.zeros_like(ax) if az_ms2 is None else np.ascontiguousarray(az_ms2, dtype=float)
    if not (ax.shape == ay.shape == az.shape) or ax.ndim != 1 or ax.size < 2:
        raise ValueError(f"the components hold {ax.shape}, {ay.shape} and {az.shape} samples; expected three "
                         "equal 1-D series of at least 2 samples")
    return ax, ay, az


@jit
def contact_flag(force, mu):
    """FLAG_FLIGHT where the ground would pull the base (F_z <= 0), FLAG_SLIDE where friction cannot hold it
    (|F_h| > mu F_z), else FLAG_NONE; ``force`` the contact force per unit mass."""
    if force[2] <= 0.0:
        return FLAG_FLIGHT
    if math.hypot(force[0], force[1]) > mu * force[2]:
        return FLAG_SLIDE
    return FLAG_NONE


@jit
def keep_first(cert, t, y):
    """(t, y) into ``cert`` unless it holds a state already (t NaN until then): the last state a 3D model certifies
    before its first stop, which the contact model goes on from; whether it was kept now."""
    if not math.isnan(cert[0]):
        return False
    cert[0] = t
    for j in range(y.shape[0]):
        cert[1 + j] = y[j]
    return True


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


@jit
def error_norm(y, y_new, err, n_angles, atol_angle, atol_rate, rtol):
    """The embedded error over the tolerance, the largest over the states (NaN stays NaN: rejected): the first
    ``n_angles`` states are angles (absolute tolerance ``atol_angle``), the rest rates (``atol_rate``)."""
    norm = 0.0
    for j in range(y.shape[0]):
        tol = (atol_angle if j < n_angles else atol_rate) + rtol * max(abs(y[j]), abs(y_new[j]))
        norm = max(norm, abs(err[j]) / tol)
    return norm


@jit
def first_below(y0, f0, y1, f1, hh, level):
    """The fraction of a step where the Hermite cubic of its ends first falls to ``level``: probed at
    :data:`CROSSING_PROBES` points, then bisected (1 where no probe is at or below it)."""
    lo, hi = 0.0, 1.0
    for j in range(1, CROSSING_PROBES + 1):
        if hermite(y0, f0, y1, f1, hh, j / CROSSING_PROBES) <= level:
            lo, hi = (j - 1) / CROSSING_PROBES, j / CROSSING_PROBES
            break
    for _ in range(CROSSING_BISECTIONS):
        mid = 0.5 * (lo + hi)
        if hermite(y0, f0, y1, f1, hh, mid) <= level:
            hi = mid
        else:
            lo = mid
    return hi


@jit_inline
def friction_demand(force, demand):
    """The larger of ``demand`` and the contact force's |F_h| / F_z (``force[0:3]``; none where F_z <= 0) [-]."""
    if force[2] > 0.0:
        return max(demand, math.hypot(force[0], force[1]) / force[2])
    return demand


@jit_inline
def final_flag(flag, held, t_over):
    """A run's flag: a flag held while the body fell past its tipping point stands where it did not overturn
    (no verdict)."""
    return held if held != FLAG_NONE and flag == FLAG_NONE and math.isnan(t_over) else flag
