"""Compiled planar rocking of a scanned body that rolls on its convex hull (:mod:`pipeline.shapes.hull`).

**Equation of motion** on pivot k, at (u_k, z_k) from G at rest (R_k its distance from G, alpha_k = atan2(u_k, -z_k)
the angle of G above it from the vertical, signed), per unit mass, with I_k = I_G + R_k^2 (Housner 1963, each pivot
its own inverted pendulum)::

    theta'' = -(g R_k / I_k) [(1 + a_v / g) sin(alpha_k - theta) + (a_h / g) cos(alpha_k - theta)]

(the vertical a_v, up positive, as in Yim, Chopra & Penzien 1980) valid while theta lies in the pivot's interval
of the chain. **Uplift** from rest on the base edge toward the side
whose pivot the ground's push turns the body about; a body resting on another edge of its outline (a tilted rest)
leaves it the same way. **Pivot changes**: where theta reaches a bound, the next vertex touches. On the base edge
(theta = 0, the body landing on what it stands on) the impact conserves angular momentum about the new pivot,
``omega+ = omega- (I_G + r_new . r_old) / (I_G + R_new^2)`` (Housner's argument, his 1 - 3/2 sin^2 alpha for a
rectangle), times a declared factor. Elsewhere the vertices are the scan's facets of one curved surface over which
the body rolls: the change keeps the kinetic energy (``omega+ = omega- sqrt(I_old / I_new)``), as rolling on the
curve the facets approximate would. A landing slower than :data:`REST_RATIO` times sqrt(g / k) (k the radius of
gyration about G: the body's own rate, so that the rule keeps similitude) rests the body on its base; so does
a slow change elsewhere where the new pivot turns the body back while the old one pushes it on (it sits on the
edge between them, a tilted rest).

**Integration**: classical Runge-Kutta of order 4 on :data:`SUBSTEPS` steps per sample, the record linear between
its samples; a step that crosses a bound is cut at it by bisection (:data:`BISECTIONS`). The free motion after the
record is followed for :data:`TAIL_S` more seconds. The body overturns when its tilt reaches 90 degrees (the end of
its chain). Every loop advances or counts against a cap: :data:`MAX_EVENTS_PER_STEP` pivot changes in one step end
the scene with ``STATUS_EVENT_CAP`` and no verdict.

Not modelled (never a silent "stands"): the ground falling faster than gravity (g + a_v <= 0: the scene stops
there with ``STATUS_GROUND_FLIGHT`` and no verdict), sliding and the pivot lifting off (the friction demand at the
pivot is recorded, and a normal force reaching 0 sets ``STATUS_LIFTOFF``: flags, the verdict is kept), motion out
of the plane.

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. BSSA 53(2), 403-417.
Yim, C.-S., Chopra, A. K. & Penzien, J. (1980). Rocking response of rigid blocks to earthquakes. Earthquake
Engineering & Structural Dynamics 8(6), 565-587.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...compiled import jit, jit_inline, jit_lean
from ...constants import G
from ...shapes.hull import HullChain
from ..codes import STATUS_EVENT_CAP, STATUS_GROUND_FLIGHT, STATUS_LIFTOFF
from ..numerics.rk import RK4, rk_step

#: Runge-Kutta steps per sample of the record
SUBSTEPS = 4
#: Halvings that place a pivot change within a step (2^-30 of the step)
BISECTIONS = 30
#: Pivot changes within one step before the scene is ended without a verdict (``STATUS_EVENT_CAP``)
MAX_EVENTS_PER_STEP = 200
#: A rebound slower than this fraction of sqrt(g / k) (k: the radius of gyration about G) rests the body on the edge
#: it landed on [-]
REST_RATIO = 1e-4
#: The free motion after the record is followed this long [s]
TAIL_S = 10.0


class RollingOutcome(NamedTuple):
    """What :func:`roll_on_hull` returns.

    Attributes
    ----------
    overturned : bool
    verdict : int
        1 overturns, 0 stands, -1 no verdict (a cap was met: ``status``).
    theta_max : float
        Largest |tilt| [rad].
    theta_max_plus, theta_max_minus : float
        Largest tilt toward the + side and toward the - side (magnitudes) [rad].
    n_impacts : int
        Landings on the base edge.
    n_pivot_changes : int
        Every change of pivot, landings included.
    t_overturn : float
        When the tilt reached 90 degrees [s from the record's start] (NaN: it did not).
    friction_demand : float
        The largest |f_x| / f_z at the pivot while its gravity moment restores the body (G not past it), at the
        ends of the steps: the friction coefficient rolling without slip needs (0: it never moved) [-].
    status : int
        ``pipeline.rocking.codes`` flags (0: none).
    """

    overturned: bool
    verdict: int
    theta_max: float
    theta_max_plus: float
    theta_max_minus: float
    n_impacts: int
    n_pivot_changes: int
    t_overturn: float
    friction_demand: float
    status: int


@jit
def _accel(theta, u, z, inertia, ah, gv):
    """theta'' on the pivot at (u, z) from G at rest (see the module), ``gv`` = g + a_v [rad s-2]."""
    c, s = math.cos(theta), math.sin(theta)
    rx = -(u * c + z * s)                      # G from the pivot, horizontal and up
    rz = u * s - z * c
    return (gv * rx - ah * rz) / (inertia + rx * rx + rz * rz)


@jit
def _contact_force(theta, omega, u, z, inertia, ah, gv):
    """(f_x, f_z, r_x): the ground's force on the body at the pivot per unit mass [m s-2] (Newton's law for G, whose
    acceleration relative to the ground is theta'' (r_z, -r_x) - omega^2 (r_x, r_z) on the pivot), and G's horizontal
    offset from the pivot r_x [m]."""
    c, s = math.cos(theta), math.sin(theta)
    rx = -(u * c + z * s)
    rz = u * s - z * c
    acc = (gv * rx - ah * rz) / (inertia + rx * rx + rz * rz)
    return acc * rz - omega * omega * rx + ah, -acc * rx - omega * omega * rz + gv, rx


@jit
def _contact(theta, omega, u, z, inertia, ah, gv, demand, status):
    """(demand, status) updated with the contact at the pivot (u, z) while G has not passed it: the largest
    |f_x| / f_z, and ``STATUS_LIFTOFF`` where f_z <= 0."""
    fx, fz, rx = _contact_force(theta, omega, u, z, inertia, ah, gv)
    if rx * u >= 0.0:                                   # G past the pivot: it falls, nothing to hold
        return demand, status
    if fz <= 0.0:
        return demand, status | STATUS_LIFTOFF
    return max(demand, abs(fx) / fz), status


@jit_inline
def _rolling(t, y, args):
    """f of (theta, omega) on the pivot at (u, z) at ``t`` [s] into a step of length h, the ground going linearly
    from a0 to a1 and g + a_v from v0 to v1 over it (``args``: u, z, inertia, a0, a1, v0, v1, h)."""
    u, z, inertia, a0, a1, v0, v1, h = args
    frac = t / h if h > 0.0 else 0.0
    theta, omega = y
    return (omega, _accel(theta, u, z, inertia, a0 + (a1 - a0) * frac, v0 + (v1 - v0) * frac)), 0.0


@jit
def _rk4(theta, omega, u, z, inertia, a0, a1, v0, v1, h):
    """One classical Runge-Kutta step (:func:`~..numerics.rk.rk_step` with :data:`~..numerics.rk.RK4`) of length
    h [s], the ground going linearly from a0 to a1 and g + a_v from v0 to v1 [m s-2]; returns (theta, omega)."""
    args = (u, z, inertia, a0, a1, v0, v1, h)
    y = (theta, omega)
    f, _ = _rolling(0.0, y, args)
    return rk_step(_rolling, args, 0.0, y, f, h, RK4).y


@jit
def _change_ratio(theta, u0, z0, u1, z1, inertia, landing, factor):
    """omega+ / omega- where the pivot moves from (u0, z0) to (u1, z1) at tilt theta (see the module)."""
    c, s = math.cos(theta), math.sin(theta)
    r0x, r0z = -(u0 * c + z0 * s), u0 * s - z0 * c
    r1x, r1z = -(u1 * c + z1 * s), u1 * s - z1 * c
    i0, i1 = inertia + r0x * r0x + r0z * r0z, inertia + r1x * r1x + r1z * r1z
    if landing:
        return min((inertia + r1x * r0x + r1z * r0z) / i1 * factor, 1.0, math.sqrt(i0 / i1))
    return math.sqrt(i0 / i1)


@jit
def _held(theta, u0, z0, u1, z1, inertia, ah, gv, direction):
    """Whether a slow body at the bound between two pivots sits on the edge between them: the new pivot turns it
    back and the old one pushes it on (moving in ``direction``, +-1)."""
    return (_accel(theta, u1, z1, inertia, ah, gv) * direction < 0.0
            and _accel(theta, u0, z0, inertia, ah, gv) * direction > 0.0)


@jit
def _ground(ah, av, i, n, g):
    """The horizontal and g + a_v at sample i (zero motion after the record)."""
    if i >= n:
        return 0.0, g
    return ah[i], g + (av[i] if len(av) else 0.0)


@jit_lean
def _roll(ah, av, dt, pivots, bounds, rest, inertia, g, factor, theta_out):
    n, npiv = len(ah), len(pivots)
    steps = n - 1 + int(TAIL_S / dt)
    h = dt / SUBSTEPS
    rest_omega = REST_RATIO * math.sqrt(g / math.sqrt(inertia))
    theta, omega, k, edge = 0.0, 0.0, -1, rest          # k: the pivot (-1: resting on edge ``edge``)
    hi_max, lo_max, impacts, changes = 0.0, 0.0, 0, 0
    demand, status = 0.0, 0
    for i in range(steps):
        a0, v0 = _ground(ah, av, i, n, g)
        a1, v1 = _ground(ah, av, i + 1, n, g)
        if v0 <= 0.0 or v1 <= 0.0:                      # the ground falls faster than gravity
            return RollingOutcome(False, -1, max(hi_max, lo_max), hi_max, lo_max, impacts, changes,
                                  math.nan, demand, status | STATUS_GROUND_FLIGHT)
        for j in range(SUBSTEPS):
            aa, va = a0 + (a1 - a0) * j / SUBSTEPS, v0 + (v1 - v0) * j / SUBSTEPS
            ab, vb = a0 + (a1 - a0) * (j + 1) / SUBSTEPS, v0 + (v1 - v0) * (j + 1) / SUBSTEPS
            if k < 0:
                theta = bounds[edge]
                if edge < npiv and _accel(theta, pivots[edge, 0], pivots[edge, 1], inertia, aa, va) > 0.0:
                    k = edge
                elif edge > 0 and _accel(theta, pivots[edge - 1, 0], pivots[edge - 1, 1], inertia, aa, va) < 0.0:
                    k = edge - 1
                else:
                    continue
                omega = 0.0
            left, events = h, 0
            while left > 0.0:
                u, z = pivots[k, 0], pivots[k, 1]
                lo, hi = bounds[k], bounds[k + 1]
                f_start = 1.0 - left / h
                a_s, v_s = aa + (ab - aa) * f_start, va + (vb - va) * f_start
                th1, om1 = _rk4(theta, omega, u, z, inertia, a_s, ab, v_s, vb, left)
                if lo <= th1 <= hi:
                    theta, omega = th1, om1
                    demand, status = _contact(theta, omega, u, z, inertia, ab, vb, demand, status)
                    break
                f0, f1 = 0.0, 1.0                          # the bound's crossing, by bisection
                for _ in range(BISECTIONS):
                    fm = 0.5 * (f0 + f1)
                    tm, _om = _rk4(theta, omega, u, z, inertia, a_s, a_s + (ab - a_s) * fm, v_s,
                                   v_s + (vb - v_s) * fm, left * fm)
                    if tm > hi or tm < lo:
                        f1 = fm
                    else:
                        f0 = fm
                _th, omega = _rk4(theta, omega, u, z, inertia, a_s, a_s + (ab - a_s) * f1, v_s,
                                  v_s + (vb - v_s) * f1, left * f1)
                a_at, v_at = a_s + (ab - a_s) * f1, v_s + (vb - v_s) * f1
                left -= left * f1
                edge = k + 1 if th1 > hi else k
                nk = k + 1 if th1 > hi else k - 1
                theta = bounds[edge]
                if nk < 0 or nk >= npiv:                   # past 90 degrees
                    hi_max, lo_max = (0.5 * math.pi, lo_max) if nk >= npiv else (hi_max, 0.5 * math.pi)
                    return RollingOutcome(True, 1, 0.5 * math.pi, hi_max, lo_max, impacts, changes,
                                          i * dt + j * h + (h - left), demand, status)
                landing = edge == rest
                omega *= _change_ratio(theta, u, z, pivots[nk, 0], pivots[nk, 1], inertia, landing, factor)
                impacts += int(landing)
                changes += 1
                events += 1
                if abs(omega) < rest_omega and (landing or _held(theta, u, z, pivots[nk, 0], pivots[nk, 1],
                                                                  inertia, a_at, v_at, 1.0 if th1 > hi else -1.0)):
                    k, omega = -1, 0.0
                    break
                k = nk
                if events >= MAX_EVENTS_PER_STEP:
                    return RollingOutcome(False, -1, max(hi_max, lo_max), hi_max, lo_max, impacts, changes,
                                          math.nan, demand, status | STATUS_EVENT_CAP)
            hi_max, lo_max = max(hi_max, theta), max(lo_max, -theta)
        if len(theta_out) and i + 1 < n:
            theta_out[i + 1] = theta
        if i >= n and k < 0 and edge == rest:
            break
    return RollingOutcome(False, 0, max(hi_max, lo_max), hi_max, lo_max, impacts, changes, math.nan, demand, status)


def landing_ratio(chain: HullChain, *, onto_plus: bool) -> float:
    """omega+ / omega- of the impact rule (angular momentum about the new pivot, no declared factor) where the body,
    rocking on one end of its base edge, lands on it and turns about the other end (``onto_plus``: onto the + end)
    [-]. A rectangle's is Housner's 1 - 3/2 sin^2 alpha on either side."""
    u0, z0 = chain.pivots_m[chain.rest - 1 if onto_plus else chain.rest]
    u1, z1 = chain.pivots_m[chain.rest if onto_plus else chain.rest - 1]
    return float((chain.inertia_m2 + u0 * u1 + z0 * z1) / (chain.inertia_m2 + u1 * u1 + z1 * z1))


def roll_on_hull(ah_ms2: np.ndarray, dt_s: float, chain: HullChain, *, av_ms2: np.ndarray | None = None,
                 restitution_factor: float = 1.0, g_ms2: float = G, theta_out: np.ndarray | None = None
                 ) -> RollingOutcome:
    """Roll the body of ``chain`` under a ground acceleration along its plane's + direction.

    Parameters
    ----------
    ah_ms2 : ndarray
        Horizontal ground acceleration [m s-2].
    dt_s : float
        Its sampling interval [s].
    chain : HullChain
        The body's pivots in the plane (:func:`pipeline.shapes.hull.hull_chain`).
    av_ms2 : ndarray, optional
        Vertical ground acceleration, up positive, on the same samples [m s-2].
    restitution_factor : float
        A declared factor on the landing impact's ratio (capped so that no impact gains speed or energy) [-].
    g_ms2 : float
        Gravity [m s-2].
    theta_out : ndarray, optional
        Filled with the tilt at each sample of the record [rad] (its length: the record's), up to where the scene
        ends (overturned, or stopped without a verdict); the samples after that keep what they held.
    """
    ah = np.ascontiguousarray(ah_ms2, dtype=float)
    av = np.zeros(0) if av_ms2 is None else np.ascontiguousarray(av_ms2, dtype=float)
    out = np.zeros(0) if theta_out is None else theta_out
    return _roll(ah, av, float(dt_s), np.ascontiguousarray(chain.pivots_m), np.ascontiguousarray(chain.bounds_rad),
                 int(chain.rest), float(chain.inertia_m2), float(g_ms2), float(restitution_factor), out)
