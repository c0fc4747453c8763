"""A solid cylinder rocking and rolling on the rim of its base (wobbling) under both horizontal components of the
ground and the vertical: the 3D model of a round column, vase, tank or drum.

The cylinder (radius ``a``, half-height ``h``: its centre of mass G is ``h`` above the base's centre on the axis
``e3``) stands on a rigid ground that moves with acceleration ``(a_x, a_y, a_z)``. Its orientation is given by
the Euler angles ``phi`` (the azimuth of the tilt: the axis leans toward ``phi``, measured from x toward y),
``theta`` (the tilt of the axis from the vertical) and ``psi`` (the spin), ``R = R_z(phi) R_y(theta) R_z(psi)``.

**Rocking and rolling on the rim** (``theta > 0``). The base touches the ground at the lowest point P of its rim,
on the side the axis leans toward. The rim rolls without slipping (P has no velocity relative to the ground), so
the cylinder has three degrees of freedom (theta, phi, psi); the horizontal position of G follows. With
``r = G - P`` (a function of theta and phi alone)::

    r = ((h sin theta - a cos theta) cos phi, (h sin theta - a cos theta) sin phi, h cos theta + a sin theta)

the height of G is ``R cos(theta - alpha)`` (``R^2 = a^2 + h^2``, ``tan alpha = a / h``), as in the planar model.
Newton's and Euler's equations per unit mass, in the ground's (translating) frame where gravity is
``g_eff = (-a_x, -a_y, -g - a_z)``, with the contact force ``F`` eliminated through the no-slip condition
``v_G = omega x r`` (so ``a_G = omega' x r + omega x r'``), give the angular acceleration::

    (I_G + |r|^2 1 - r r^T) omega' = -omega x I_G omega - r x (omega x r') + r x g_eff

and the Euler angles' accelerations from ``omega = phi' e_z + theta' e_n + psi' e3`` (``e_n``: the line of nodes).
These are the equations of a rolling disk (Goldstein, Poole & Safko 2002, section 4.9; O'Reilly 1996) with the
centre of mass off the disk's plane, as derived for rocking cylinders by Koh & Mustafa (1990) and Vassiliou et
al. (2017). The contact force ``F = a_G - g_eff`` is checked on every accepted step: the scene is flagged when
the base would lift off the ground (``F_z <= 0``: free flight) or slide (``|F_h| > mu F_z``).

**Landing.** When theta returns to zero the base lands flat and rocks on the opposite side of its rim: the
impact conserves the angular momentum about the new contact point (the impulse acts there; Housner 1963 for the
planar block), so ``J' omega+ = I_G omega- + r' x (omega- x r)``. In the plane this gives the cylinder's
Housner coefficient ``e = (I_G + h^2 - a^2) / (I_G + h^2 + a^2)``; a declared restitution scales the tilting
part of ``omega+`` by its ratio to that value. A rebound slower than :data:`REST_RATE` (a fraction of
``p alpha``) ends the motion: the cylinder rests until the ground lifts it again. So does a tilt that stayed
below :data:`SETTLE_TILT_ALPHA` x alpha through a whole sample interval over which the ground could not lift the
cylinder from rest (set at rest at the interval's end; counted in ``holds``, guard tie_hold): at such a tilt the
rim's contact runs round ever faster (Euler's disk), which costs steps and decides nothing.

**Rest and uplift.** At rest, the cylinder lifts on the side opposite the ground's horizontal acceleration when
``|a_h| > (g + a_z) tan alpha``, the same in every direction (it is axisymmetric).

**Overturning** is ``theta >= pi / 2`` while the ground moves (the cylinder lies on its side), as in the planar
kernel.

**Where the model stops.** Sliding or lift-off of the base is not followed in 3D: before the cylinder tilts past
alpha, the run stops there and the scene has no verdict. Past alpha, with the tilt still growing (the centre of mass
beyond the contact, falling), the run goes on with the rim held on the ground (``held``): an overturning reached so
is kept, flagged; if the cylinder comes back below alpha, or stands at the end, the scene has no verdict. So a
held continuation can only confirm a fall that was under way, never make a cylinder stand.

The equations are integrated by the Dormand-Prince 5(4) pair with error control on all six states; no step
crosses a sample of the record (the ground acceleration is linear between samples). A cap on the steps
(:data:`MAX_STEPS_PER_SAMPLE`) ends a run that does not advance, with the scene flagged.

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. BSSA 53(2), 403-417.
Koh, A.-S. & Mustafa, G. (1990). Free rocking of cylindrical structures. J. Eng. Mech. 116(1), 35-54.
O'Reilly, O. M. (1996). The dynamics of rolling disks and sliding disks. Nonlinear Dynamics 10, 287-305.
Goldstein, H., Poole, C. & Safko, J. (2002). Classical Mechanics, 3rd ed., Addison Wesley.
Srinivasan, M. & Ruina, A. (2008). Rocking and rolling: a can that appears to rock might actually roll.
Phys. Rev. E 78, 066609.
Vassiliou, M. F., Burger, S., Egger, M., Bachmann, J. A., Broccardo, M. & Stojadinovic, B. (2017). The
three-dimensional behavior of inverted pendulum cylindrical structures during earthquakes. Earthquake Eng.
Struct. Dyn. 46(14), 2261-2280.
Dormand, J. R. & Prince, P. J. (1980). A family of embedded Runge-Kutta formulae. J. Comput. Appl. Math. 6(1),
19-26.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...compiled import copy_into, fill_with, jit, jit_inline, jit_lean, store
from ..geometry import cylinder_p_e
from ..numerics.rk import next_step, rejected_step
from .convex_body import ConvexBody, cylinder_body
from .cylinder_kernel import (
    STATE_SIZE,
    derivatives,
    dopri_step,
    error_over_tolerance,
    kinetic,
    landing,
    params_of,
    rise,
)
from .handoff3d import CylinderHandoff, CylinderState
from .vec3 import FLAG_FLIGHT as FLAG_FLIGHT  # the flags, re-exported: callers read them here
from .vec3 import (
    FLAG_NONE,
    FLAG_STEPS,
    Ground,
    effective_gravity,
    final_flag,
    first_below,
    friction_demand,
    ground_components,
    keep_first,
)
from .vec3 import FLAG_SLIDE as FLAG_SLIDE
from .vec3 import contact_flag as _contact_flag
from .vec3 import hermite as _hermite

HALF_PI = 0.5 * math.pi

# Step limits and events, named once (the step-size factors: ..numerics.rk)
MAX_STEPS_PER_SAMPLE = 2000     # steps allowed per record sample before the run ends, flagged
REST_RATE = 1e-6                # a rebound slower than this x p alpha [rad s-1] ends the motion
EVENT_BISECTIONS = 60           # bisections locating a landing inside a step
SETTLE_TILT_ALPHA = 1e-3        # a tilt below this x alpha through a whole quiet sample interval is set at rest


class Cylinder(NamedTuple):
    """A solid cylinder (per unit mass).

    Attributes
    ----------
    radius_m : float
        radius of the base a [m]
    half_height_m : float
        half the height h (the centre of mass's height above the base) [m]
    mu : float
        friction coefficient [-]
    restitution : float
        coefficient of restitution of the tilting rate at a landing [-] (Housner's value: :func:`housner_e`)
    """

    radius_m: float
    half_height_m: float
    mu: float
    restitution: float

    def convex(self) -> ConvexBody:
        """The contact model's body of this cylinder: points of its two rims (plastic contacts, which give
        Housner's rule at a pivot)."""
        return cylinder_body(2.0 * self.radius_m, 2.0 * self.half_height_m, mu=self.mu)


class WobbleOutcome(NamedTuple):
    """What a 3D cylinder run gives.

    Attributes
    ----------
    overturned : bool
    t_overturn_s : float
        when theta reached pi/2 [s] (NaN when standing)
    theta_max_rad : float
        the peak tilt [rad]
    azimuth_max_deg : float
        the azimuth the axis leaned toward at the peak tilt [deg, from x toward y]
    flag : int
        FLAG_NONE, FLAG_FLIGHT (the base would leave the ground), FLAG_SLIDE (friction exceeded) or FLAG_STEPS
    impacts : int
        landings counted
    theta : ndarray
        tilt at the record's samples [rad]
    azimuth : ndarray
        the azimuth of the tilt at the samples [rad]
    end : CylinderState
        where the run ended
    friction_demand : float
        the peak |F_h| / F_z at the rim while it rocked [-]
    held : int
        FLAG_SLIDE or FLAG_FLIGHT where the base would have slid or lifted off while the cylinder fell past alpha,
        and the run went on with the rim held (its overturning kept, see the module); FLAG_NONE otherwise
    holds : int
        sample intervals at whose end a tilt below :data:`SETTLE_TILT_ALPHA` x alpha was set at rest
    handoff : CylinderHandoff or None
        the last state the model certified before the base would first slide or lift off (the start of that step);
        None where it never would
    """

    overturned: bool
    t_overturn_s: float
    theta_max_rad: float
    azimuth_max_deg: float
    flag: int
    impacts: int
    theta: np.ndarray
    azimuth: np.ndarray
    end: CylinderState
    friction_demand: float
    held: int
    holds: int = 0
    handoff: CylinderHandoff | None = None


def cylinder_from_corner(R_m: float, alpha: float, *, mu: float, restitution: float) -> Cylinder:
    """The :class:`Cylinder` of radius R sin(alpha) and half-height R cos(alpha) (a sampled block's terms)."""
    return Cylinder(radius_m=R_m * math.sin(alpha), half_height_m=R_m * math.cos(alpha), mu=mu,
                    restitution=restitution)


def housner_e(radius_m: float, half_height_m: float) -> float:
    """Housner's coefficient of restitution of a solid cylinder rocking in a plane
    (:func:`~.geometry.cylinder_p_e`) [-]."""
    return float(cylinder_p_e(radius_m, half_height_m)[1])


def planar_inertia(radius_m: float, half_height_m: float) -> float:
    """The moment of inertia about a rim point for rocking in a plane, per unit mass ``I_G + R^2`` [m2]."""
    a, h = radius_m, half_height_m
    return a * a / 4.0 + h * h / 3.0 + a * a + h * h


@jit
def _lift_off(t, i, grd, prm, y):
    """At rest over sample interval ``i`` from ``t``: the instant the ground lifts the cylinder (the state then
    set tilting toward the inertial force), or -1 when it stays at rest."""
    t0 = i * grd.dt
    start = _uplift(t, t0 + grd.dt, t0, grd.dt, grd.ax[i], grd.ax[i + 1], grd.ay[i], grd.ay[i + 1], grd.az[i],
                    grd.az[i + 1], grd.g, prm.a / prm.h)
    if start >= 0.0:
        gx, gy, _ = effective_gravity(start, i, grd)
        fill_with(y, 0.0)
        y[0], y[1] = 2.0 * prm.land, math.atan2(gy, gx)
    return start


@jit
def _land_inside(t, hh, i, grd, prm, y, k, y_new, err, theta_out, azimuth_out):
    """The base lands flat inside the step from ``t``: the landing located on the step's cubic, the state
    advanced to it (exact Runge-Kutta step) and the impact applied; returns the time, and whether the rebound is
    too slow to go on (rest)."""
    x = first_below(y[0], k[0, 0], y_new[0], k[1, 0], hh, prm.land)
    hl = max(x * hh, 1e-15 * grd.dt)
    dopri_step(t, y, hl, i, grd, prm, k, y_new, err)
    _fill(theta_out, azimuth_out, grd.dt, t, hl, y, k, y_new, grd.ax.shape[0])
    copy_into(y, y_new)
    rate = landing(y, prm.a, prm.h, prm.i1, prm.i3, prm.scale)
    y[0] = prm.land
    rests = rate < REST_RATE * prm.p * prm.alpha
    if rests:
        y[0], y[3], y[4], y[5] = 0.0, 0.0, 0.0, 0.0
    return t + hl, rests


@jit
def _flag_certified(force, mu, held, cert, t, y):
    """The contact flag of the step from (t, y); at the first that flags before any hold, (t, y) into ``cert``."""
    flag = _contact_flag(force, mu)
    if flag != FLAG_NONE and held == FLAG_NONE:
        keep_first(cert, t, y)
    return flag


@jit_inline
def _resting_interval(t, i, dt, grd, prm, y, theta_out, azimuth_out):
    """At rest over sample interval ``i`` from ``t``: the instant the ground lifts the cylinder (:func:`_lift_off`,
    the state then set rocking), or the interval's end at rest (recorded). Returns the time and whether it rocks."""
    start = _lift_off(t, i, grd, prm, y)
    if start < 0.0:
        theta_out[i + 1], azimuth_out[i + 1] = 0.0, y[1]
        return (i + 1) * dt, False
    return start, True


@jit_inline
def _held_past_alpha(flag, held, theta, theta_rate, alpha):
    """The step's flag and the flag held: a flag raised while the cylinder falls past alpha is held (the rim held,
    see the module) until it comes back below alpha, where the held flag stands."""
    if held != FLAG_NONE:
        return (held if theta < alpha else FLAG_NONE), held
    if flag != FLAG_NONE and theta > alpha and theta_rate > 0.0:
        return FLAG_NONE, flag
    return flag, held


@jit_inline
def _settled(t, i, dt, interval_peak, settle, y, grd, prm, theta_out):
    """At the end of sample interval ``i``, a tilt that stayed small through it set at rest (:func:`_settles`);
    whether it was."""
    if abs(t - (i + 1) * dt) <= 1e-12 * dt and _settles(interval_peak, settle, y, i, grd, prm):
        fill_with(y, 0.0)
        theta_out[i + 1] = 0.0
        return True
    return False


@jit_inline
def _start_state(y0, land):
    """The state to start from and whether it rocks: ``y0``, set at rest where its tilt is below ``land``."""
    y = y0.copy()
    rocking = y[0] > land
    if not rocking:
        fill_with(y, 0.0)
    return y, rocking


@jit
def wobble(ax, ay, az, dt, g, a, h, mu, scale, rtol, atol_alpha, y0, theta_out, azimuth_out, y_end, settle, cert):
    """Run a cylinder (radius ``a``, half-height ``h`` [m], friction ``mu``, its restitution over Housner's
    ``scale``) on the ground ``ax, ay, az`` [m s-2] sampled at ``dt`` [s] from ``y0`` (zeros: at rest), filling the
    tilt and its azimuth at the samples, the last state in ``y_end`` and in ``cert`` (t, the 6 states) the last
    state certified before the base would first slide or lift off (t NaN: never); returns (overturned, t_overturn,
    theta_max, its azimuth [rad], flag, impacts, the peak |F_h| / F_z while rocking, the flag held past alpha)."""
    prm = params_of(g, a, h, mu, scale, rtol, atol_alpha)
    y, rocking = _start_state(y0, prm.land)
    return _wobble(ax, ay, az, dt, g, a, h, mu, prm, y, rocking, theta_out, azimuth_out, y_end, settle, cert,
                   np.zeros((2, STATE_SIZE)), np.empty(STATE_SIZE), np.empty(STATE_SIZE))


@jit_lean
def _wobble(ax, ay, az, dt, g, a, h, mu, prm, y, rocking, theta_out, azimuth_out, y_end, settle, cert, k, y_new, err):
    """:func:`wobble`'s loop on the parameters (:func:`.cylinder_kernel.params_of`) and arrays it made."""
    grd = Ground(ax, ay, az, dt, g)
    n = ax.shape[0]
    t, t_end, hh_next, steps = 0.0, (n - 1) * dt, dt, 0
    theta_max, az_max, flag, impacts, t_over, demand, held = 0.0, 0.0, FLAG_NONE, 0, math.nan, 0.0, FLAG_NONE
    theta_out[0], azimuth_out[0] = y[0], y[1]
    fresh, holds, interval, interval_peak = True, 0, -1, 0.0
    while t < t_end - 1e-12 * dt and flag == FLAG_NONE and math.isnan(t_over):
        i = min(int(t / dt + 1e-9), n - 2)
        if i != interval:
            interval, interval_peak = i, y[0]
        if not rocking:
            t, rocking = _resting_interval(t, i, dt, grd, prm, y, theta_out, azimuth_out)
            fresh = True
            continue
        steps += 1
        if steps > MAX_STEPS_PER_SAMPLE * n:
            flag = FLAG_STEPS
            break
        if fresh:
            gx, gy, gz = effective_gravity(t, i, grd)
            store(k[0], derivatives(y, gx, gy, gz, a, h, prm.i1, prm.i3)[0])
            fresh = False
        hh = min(hh_next, (i + 1) * dt - t)
        force = dopri_step(t, y, hh, i, grd, prm, k, y_new, err)
        norm = error_over_tolerance(y, y_new, err, prm)
        if not norm <= 1.0:          # rejected (NaN too)
            hh_next = rejected_step(hh, norm)
            continue
        if y_new[0] >= HALF_PI:                                  # overturned (theta rises through pi/2 here)
            x = (HALF_PI - y[0]) / (y_new[0] - y[0])
            t_over, theta_max, az_max = t + x * hh, HALF_PI, y[1] + x * (y_new[1] - y[1])
            break
        if y_new[0] < prm.land:                                  # the base lands flat inside the step
            impacts += 1
            t, rests = _land_inside(t, hh, i, grd, prm, y, k, y_new, err, theta_out, azimuth_out)
            rocking, fresh = not rests, True
            continue
        flag, held = _held_past_alpha(_flag_certified(force, mu, held, cert, t, y), held, y_new[0], y_new[3],
                                      prm.alpha)
        demand = friction_demand(force, demand)
        _fill(theta_out, azimuth_out, dt, t, hh, y, k, y_new, n)
        if y_new[0] > theta_max:
            theta_max, az_max = y_new[0], y_new[1]
        t, hh_next = t + hh, next_step(hh, norm)
        copy_into(y, y_new)
        copy_into(k[0], k[1])
        interval_peak = max(interval_peak, y[0])
        if _settled(t, i, dt, interval_peak, settle, y, grd, prm, theta_out):
            rocking, fresh, holds = False, True, holds + 1
    copy_into(y_end, y)
    flag = final_flag(flag, held, t_over)       # held past alpha, and it did not overturn: no verdict
    return not math.isnan(t_over), t_over, theta_max, az_max, flag, impacts, demand, held, holds


@jit
def _settles(peak, settle, y, i, grd, prm):
    """A tilt that stayed below ``settle`` x alpha (:data:`SETTLE_TILT_ALPHA`) through sample interval ``i``, over
    which the ground could not lift the cylinder from rest (at both ends; the excess is convex in between): rolling on
    the rim at such a tilt (the contact running round the rim ever faster as the tilt falls, as for Euler's disk),
    with less kinetic energy (about the contact) than would raise it to that tilt, is set at rest at the interval's
    end, as the planar kernel's tie rule holds a flat block (measured:
    docs/validation.md)."""
    if peak >= settle * prm.alpha or kinetic(y, prm) > grd.g * rise(settle * prm.alpha, prm):
        return False
    t0, tan_a = i * grd.dt, prm.a / prm.h
    return (_excess(t0, t0, grd.dt, grd.ax[i], grd.ax[i + 1], grd.ay[i], grd.ay[i + 1], grd.az[i], grd.az[i + 1],
                    grd.g, tan_a) <= 0.0
            and _excess(t0 + grd.dt, t0, grd.dt, grd.ax[i], grd.ax[i + 1], grd.ay[i], grd.ay[i + 1], grd.az[i],
                        grd.az[i + 1], grd.g, tan_a) <= 0.0)


@jit
def _excess(s, t0, dt, ax0, ax1, ay0, ay1, az0, az1, g, tan_alpha):
    """|a_h| - (g + a_z) tan alpha at ``s`` [m s-2]: positive where the ground lifts the cylinder."""
    f = (s - t0) / dt
    hx, hy, v = ax0 + f * (ax1 - ax0), ay0 + f * (ay1 - ay0), az0 + f * (az1 - az0)
    return math.hypot(hx, hy) - (g + v) * tan_alpha


@jit
def _uplift(t, t_next, t0, dt, ax0, ax1, ay0, ay1, az0, az1, g, tan_alpha):
    """The first instant in [t, t_next] at which |a_h| > (g + a_z) tan alpha (the ground linear between
    samples), or -1 when none. The excess is convex in time (the norm of a linear path less a linear
    threshold), so it is <= 0 on the whole interval when it is at both ends."""
    if _excess(t, t0, dt, ax0, ax1, ay0, ay1, az0, az1, g, tan_alpha) > 0.0:
        return t
    if _excess(t_next, t0, dt, ax0, ax1, ay0, ay1, az0, az1, g, tan_alpha) <= 0.0:
        return -1.0
    lo, hi = t, t_next
    for _ in range(EVENT_BISECTIONS):
        m = 0.5 * (lo + hi)
        if _excess(m, t0, dt, ax0, ax1, ay0, ay1, az0, az1, g, tan_alpha) > 0.0:
            hi = m
        else:
            lo = m
    return hi


@jit
def _fill(theta_out, azimuth_out, dt, t, hh, y, k, y_new, n):
    """The samples inside (t, t + hh]: theta by the step's Hermite cubic, the azimuth linearly."""
    j = int(t / dt + 1e-9) + 1
    while j < n and j * dt <= t + hh + 1e-12 * dt:
        x = (j * dt - t) / hh
        theta_out[j] = _hermite(y[0], k[0, 0], y_new[0], k[1, 0], hh, x)
        azimuth_out[j] = y[1] + x * (y_new[1] - y[1])
        j += 1


#: Default tolerances of the step control: relative, and absolute as a fraction of alpha (angles) and of
#: p alpha (rates)
RTOL = 1e-8
ATOL_ALPHA = 1e-9


def simulate_cylinder(ax_ms2, ay_ms2, az_ms2, dt_s: float, cylinder: Cylinder, *, g_ms2: float = 9.80665,
                      rtol: float = RTOL, atol_alpha: float = ATOL_ALPHA, start: CylinderState | None = None,
                      settle_tilt_alpha: float = SETTLE_TILT_ALPHA) -> WobbleOutcome:
    """Run a cylinder on two horizontal components and the vertical of a record (the module's model).

    Parameters
    ----------
    ax_ms2, ay_ms2, az_ms2 : array_like
        ground acceleration along x, y (horizontal, y 90 deg counter-clockwise of x seen from above) and up
        [m s-2], one sample each per ``dt_s``; ``az_ms2`` may be None (no vertical)
    dt_s : float
        sampling interval [s]
    cylinder : Cylinder
    g_ms2 : float
        gravity [m s-2]
    rtol, atol_alpha : float
        tolerances of the step control (relative; absolute as a fraction of alpha, and of p alpha for rates)
    start : CylinderState, optional
        the state at the first sample; default at rest
    settle_tilt_alpha : float
        a tilt below this x alpha through a quiet sample interval is set at rest (0: never; what
        ``benchmarks/cylinder_settle.py`` measures)

    Returns
    -------
    WobbleOutcome
        After overturning the tilt reads pi/2; after a flag (flight, sliding, the step cap) NaN.
    """
    ax, ay, az = ground_components(ax_ms2, ay_ms2, az_ms2)
    y0 = np.zeros(6) if start is None else np.array(start, dtype=float)
    theta = np.full(ax.size, np.nan)
    azimuth = np.full(ax.size, np.nan)
    y_end, cert = np.empty(6), np.full(7, np.nan)
    e_h = housner_e(cylinder.radius_m, cylinder.half_height_m)
    over, t_over, th_max, az_max, flag, impacts, demand, held, holds = wobble(
        ax, ay, az, float(dt_s), float(g_ms2), cylinder.radius_m, cylinder.half_height_m, cylinder.mu,
        cylinder.restitution / e_h if e_h > 0.0 else 0.0, float(rtol), float(atol_alpha), y0, theta, azimuth, y_end,
        float(settle_tilt_alpha), cert)
    if over:
        k = int(np.ceil(t_over / dt_s))
        theta[k:], azimuth[k:] = HALF_PI, az_max
    return WobbleOutcome(bool(over), float(t_over), float(th_max), float(np.degrees(az_max) % 360.0), int(flag),
                         int(impacts), theta, azimuth, CylinderState(*(float(v) for v in y_end)), float(demand),
                         int(held), int(holds), _handoff(cert))


def _handoff(cert: np.ndarray) -> CylinderHandoff | None:
    """The kernel's certified state (t, the 6 states) as a :class:`~.handoff3d.CylinderHandoff` (None: t NaN, the
    base never would slide nor lift off)."""
    if not math.isfinite(cert[0]):
        return None
    return CylinderHandoff(float(cert[0]), CylinderState(*(float(v) for v in cert[1:7])))
