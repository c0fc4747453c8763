"""Where the 3D contact model (:mod:`.contact3d`) starts: standing at rest, or from a moving state an exact model
hands over (:mod:`.contact_scene`): its time, orientation, rate and the non-slipping point it turns about, with what
came before (its largest tilt and its history).

The kernel places the body with its lowest vertex on the ground and that point where it stood, and gives G the
velocity of a rigid turn about it. The motion does not depend on where G stands horizontally (the ground is a plane),
only ``slide_max_m`` does: it is G's place from where it stood as long as the pivot has not moved since rest (a box
that has turned about one corner or edge only), and otherwise counts G from a pivot taken where it stood (a box that
twisted on a corner, or a cylinder that rolled on its rim, has moved its contact). A start between two steps of the
kernel takes the rest of that step first.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...compiled import jit_inline
from .attitude import headed, rotation, rotation_matrix
from .contact_pose import along, lowest


class Start(NamedTuple):
    """A moving state to start from instead of rest: where an exact model hands its scene over (:mod:`.contact_scene`).

    Attributes
    ----------
    t_s : float
        When [s] (from the record's first sample).
    q : ndarray, shape (4,)
        The orientation of the body's principal axes (unit quaternion (w, x, y, z), body to the ground's frame).
    rate_rad_s : ndarray, shape (3,)
        Its angular velocity in the ground's frame [rad s-1].
    pivot_m : ndarray, shape (3,)
        A point of the body on the ground that does not slip, in its principal axes from G [m]: the velocity of G is
        the rate times the arm from it; the body is placed with its lowest vertex on the ground and this point
        where it stood.
    tilt_max_rad, lean_at_peak_rad : float
        The largest tilt before [rad] and where it leant then (an azimuth from x toward y [rad]).
    tilt_rad, lean_rad : ndarray or None
        The tilt and lean at the samples up to ``t_s`` (for a history; the rest ignored).
    """

    t_s: float
    q: np.ndarray
    rate_rad_s: np.ndarray
    pivot_m: np.ndarray
    tilt_max_rad: float = 0.0
    lean_at_peak_rad: float = math.nan
    tilt_rad: np.ndarray | None = None
    lean_rad: np.ndarray | None = None


class Begin(NamedTuple):
    """How the kernel starts: at rest (``k`` -1) or in step ``k`` with the fraction ``lo`` of it past, from the
    orientation ``q``, rate ``w`` and non-slipping ``pivot`` of a :class:`Start`, its ``tilt`` then, the largest tilt
    and lean before, and the time ``t`` [s]."""

    k: int
    lo: float
    q: np.ndarray
    w: np.ndarray
    pivot: np.ndarray
    tilt: float
    tilt_max: float
    lean_peak: float
    t: float


def begin(start: Start | None, h: float, dt: float, up: np.ndarray, hist: np.ndarray) -> Begin:
    """The kernel's :class:`Begin` of ``start`` (None: at rest) on steps of ``h`` [s] (``up``: the body axis that
    points up as it stands), and the history's samples (of ``dt`` [s]) up to it filled in ``hist``."""
    if start is None:
        hist[:1] = (0.0, math.nan)
        return Begin(-1, 0.0, np.array([1.0, 0.0, 0.0, 0.0]), np.zeros(3), np.zeros(3), 0.0, 0.0, math.nan, 0.0)
    q = np.asarray(start.q, dtype=float) / np.linalg.norm(start.q)
    k = int(math.floor(start.t_s / h))
    lo = start.t_s / h - k
    k, lo = (k + 1, 0.0) if lo > 1.0 - 1e-9 else (k, lo)
    upright = rotation_matrix(q)
    tilt = math.acos(min(1.0, max(-1.0, float(upright[2] @ up))))
    if hist.shape[0]:
        last = min(int(math.floor(start.t_s / dt + 1e-9)), hist.shape[0] - 1)
        for col, series in enumerate((start.tilt_rad, start.lean_rad)):
            if series is not None:
                hist[:last + 1, col] = np.asarray(series, dtype=float)[:last + 1]
    return Begin(k, lo, q, np.asarray(start.rate_rad_s, dtype=float), np.asarray(start.pivot_m, dtype=float), tilt,
                  max(float(start.tilt_max_rad), tilt), float(start.lean_at_peak_rad), float(start.t_s))


@jit_inline
def place(room, vertices, z0, yaw, pose, start):
    """Where the kernel's run starts (``start``: :func:`begin`'s), into ``room``'s arrays (:mod:`.contact3d`): the
    body standing still on its base at ``yaw`` [rad], G at height ``z0``, or (``start.k`` >= 0) turned to
    ``start.q`` at the rate ``start.w`` about its non-slipping ``start.pivot`` with its lowest vertex on the ground
    and that point where it stood; no impulse yet: its place, orientation, velocity and rate (its rotation into
    ``room.r``)."""
    room.contact[0][:, :] = 0.0
    x, q, v, w, r = room.x, room.q, room.v, room.w, room.r
    x[0], x[1], x[2] = 0.0, 0.0, z0
    headed(yaw, pose.q_rest, q)
    v[:] = 0.0
    w[:] = 0.0
    if start.k < 0:
        rotation(q, r)                                  # as it stands: a flat step reads its heading from r
        return x, q, v, w
    rotation(q, r)                                      # where the pivot stood
    p0, p1 = along(r, start.pivot, 0), along(r, start.pivot, 1)
    for i in range(4):
        q[i] = start.q[i]
    for i in range(3):
        w[i] = start.w[i]
    rotation(q, r)
    a0, a1, a2 = along(r, start.pivot, 0), along(r, start.pivot, 1), along(r, start.pivot, 2)
    x[0], x[1], x[2] = p0 - a0, p1 - a1, -lowest(vertices, r)
    v[0], v[1], v[2] = a1 * w[2] - a2 * w[1], a2 * w[0] - a0 * w[2], a0 * w[1] - a1 * w[0]   # (R pivot) x w
    return x, q, v, w
