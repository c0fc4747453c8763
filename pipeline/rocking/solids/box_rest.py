"""The 3D box at rest (:mod:`.box3d` states the model): when the ground first lifts it about one of its base edges
or slides it, and the sample intervals over which it does neither. Each edge's lift excess is linear in time
between two samples (the ground is linear there), so its first positive instant is exact; the slip excess
|a_h| - mu (g + a_z) is convex there, so a sample interval whose ends are quiet is quiet throughout.
"""

from __future__ import annotations

import math

from ...compiled import jit
from .box_kernel import EVENT_BISECTIONS, flatten

# The outward normal of edge j in the body's axes (edge 0 at +y, 1 at -x, 2 at -y, 3 at +x)
_NORMAL_X = (0.0, -1.0, 0.0, 1.0)
_NORMAL_Y = (1.0, 0.0, -1.0, 0.0)


@jit
def _accel_at(s, t0, dt, grd, i):
    """The ground's acceleration (a_x, a_y, a_z) at ``s`` in sample interval ``i`` (from ``t0``) [m s-2]."""
    f = (s - t0) / dt
    return (grd.ax[i] + f * (grd.ax[i + 1] - grd.ax[i]), grd.ay[i] + f * (grd.ay[i + 1] - grd.ay[i]),
            grd.az[i] + f * (grd.az[i + 1] - grd.az[i]))


@jit
def _tipping(s, t0, dt, grd, i, c, sn, j, prm):
    """-a.n - (g + a_z) b / h for edge j at time ``s`` [m s-2]: positive where the ground lifts the box about
    it (the ground linear between samples; n the edge's outward normal, b the half-dimension across it)."""
    ax, ay, az = _accel_at(s, t0, dt, grd, i)
    a_n = (c * ax + sn * ay) * _NORMAL_X[j] + (-sn * ax + c * ay) * _NORMAL_Y[j]
    b = prm.by if j % 2 == 0 else prm.bx
    return -a_n - (grd.g + az) * b / prm.hz


@jit
def _slip_excess(s, t0, grd, i, mu):
    """|a_h| - mu (g + a_z) at ``s`` [m s-2]: positive where friction cannot hold the box at rest."""
    ax, ay, az = _accel_at(s, t0, grd.dt, grd, i)
    return math.hypot(ax, ay) - mu * (grd.g + az)


@jit
def slides_at_rest(t, i, grd, prm):
    """The first instant in [t, the next sample] at which the box at rest would slide, or -1. The excess is
    convex in time (the norm of a linear path less a linear threshold): <= 0 throughout when it is at both ends;
    the exact boundary |a_h| = mu (g + a_z) holds."""
    t0 = i * grd.dt
    t1 = t0 + grd.dt
    if _slip_excess(t, t0, grd, i, prm.mu) > 0.0:
        return t
    if _slip_excess(t1, t0, grd, i, prm.mu) <= 0.0:
        return -1.0
    lo, hi = t, t1
    for _ in range(EVENT_BISECTIONS):
        m = 0.5 * (lo + hi)
        if _slip_excess(m, t0, grd, i, prm.mu) > 0.0:
            hi = m
        else:
            lo = m
    return hi


@jit
def quiet(i, grd, ratio):
    """Whether sample ``i`` is quiet: |a_h| <= (g + a_z) min(tan alpha_min, mu), where the box at rest neither lifts
    about any edge (whose threshold is at least tan alpha_min) nor slides. Quiet at both ends of an interval means
    quiet throughout (the excess is convex in time between samples)."""
    return math.hypot(grd.ax[i], grd.ay[i]) <= (grd.g + grd.az[i]) * ratio


@jit
def lift_off(t, i, grd, prm, y):
    """At rest over sample interval ``i`` from ``t``: the instant and the edge about which the ground first lifts
    the box (the state then set turning about it), or (-1, -1) when it stays at rest. Each edge's excess is
    linear in time inside the interval, so its first positive instant is exact."""
    psi = flatten(y)
    c, sn = math.cos(psi), math.sin(psi)
    t0 = i * grd.dt
    t1 = t0 + grd.dt
    best_t, best_j, best_f = -1.0, -1, 0.0
    for j in range(4):
        f0 = _tipping(t, t0, grd.dt, grd, i, c, sn, j, prm)
        f1 = _tipping(t1, t0, grd.dt, grd, i, c, sn, j, prm)
        if f0 > 0.0:
            s = t
        elif f1 > 0.0:
            s = t + (t1 - t) * (-f0) / (f1 - f0)
        else:
            continue
        if best_j < 0 or s < best_t or (s == best_t and f1 > best_f):
            best_t, best_j, best_f = s, j, f1
    if best_j >= 0:
        y[4], y[5], y[6] = 0.0, 0.0, 0.0
    return best_t, best_j
