"""A stack in a vertical plane rocking as one on a base corner of its lowest block, one joint shut and either
sticking or sliding, every other joint shut and sticking: an event-driven model of a joint that slips while its stack
rocks (compiled). The blocks below the slipping joint are the lower part (0), those above it the upper part (1), each
rigid (:mod:`.slide_rock_parts`; two blocks: each part one block).

Coordinates: the stack's rotation phi (clockwise positive: a positive rotation tips it towards +x) on the lowest
block's base corner ``pivot`` (+1: the +x corner, b_0 from its base centre), and the upper part's offset u, its base
centre from the centre of the lower's top face along that face [m]. With the field per unit mass f = (-a_h, -(g +
a_v)), its components along the lower's base and its normal f_e = -a_h cos phi + (g + a_v) sin phi and f_n = -a_h sin
phi - (g + a_v) cos phi; the lower's centre of mass at (x_0 - pivot b_0, h_0) from the pivot in its frame, its top
face's centre at x_t from its base centre and the joint at height t_0; the upper's centre of mass x_1 along the joint
and h_1 above it from its base centre; r = x_t + u + x_1 - pivot b_0 and H = t_0 + h_1 the upper's centre from the
pivot, and A = m_0 ((x_0 - pivot b_0)^2 + h_0^2) + I_0 + I_1 + m_1 (r^2 + H^2) (I_k about each part's centre of mass),
Lagrange's equations, the joint's friction F_t on the upper part along the face a generalized force, are

    A phi'' + m_1 H u'' = Q - 2 m_1 r u' phi',       Q = m_0 (h_0 f_e - (x_0 - pivot b_0) f_n) + m_1 (H f_e - r f_n),
    m_1 H phi'' + m_1 u'' = m_1 f_e + m_1 r phi'^2 + F_t,
    N = m_1 (-phi'' r - phi'^2 H - 2 phi' u' - f_n),

N the joint's normal force on the upper part. **Sliding** (u' != 0): F_t = -mu_1 N sign(u') (Coulomb), the two
equations solved for phi'' and u''. **Sticking**: u' = u'' = 0, the stack one rigid body (the two-block model's mode
with its joint shut, :mod:`.two_block`), F_t what the second equation asks. The joint's centre of pressure is
x_p = x_1 - (I_1 phi'' + h_1 F_t) / N from the upper base's centre (the upper part's moment balance about its centre
of mass); the ground's reaction is R = m_0 C_0'' + m_1 C_1'' - (m_0 + m_1) f, C_k the parts' centres of mass.

The model holds while the stack turns on its pivot (pivot phi > 0), the joint presses (N > 0) with its centre of
pressure strictly inside the overlap of the two faces, the ground presses within its friction (R_z > 0, |R_x| <= mu_0
R_z), and each other joint carries what the blocks above it ask of it shut and sticking
(:func:`~.slide_rock_parts.inner`). Events, each located on the step's length to :data:`~.stepping.EVENT_TIME_TOL_S`: a
sticking joint slips where |F_t| passes mu_1 N, towards the side its friction opposes; a sliding joint stops where u'
reaches 0 (the Illinois method on u'), and sticks there where |F_t| <= mu_1 N, else slides back; the stack lands on its
other corner where phi reaches 0 (the Illinois method on phi), by the impact law of :func:`landing`; it falls where
|phi| reaches pi / 2. A run ends where the model no longer holds, in the state just before the event: a sticking stack
whose joint (or another) opens, or whose landing leaves the law, is handed back to the exact model
(:mod:`.two_block_run` or :mod:`.n_block_run`, whose impacts and modes go on from there), a sliding one, one whose other
joint would slip, or one the ground no longer holds, to the stack's contact model (:mod:`.stack_contact`). Steps are the
Dormand & Prince (1980) pair's with the two-block run's error control, never crossing a sample.

References
----------
Dormand, J. R. & Prince, P. J. (1980). A family of embedded Runge-Kutta formulae. J. Comput. Appl. Math. 6(1),
19-26.
Goldstein, H., Poole, C. & Safko, J. (2002). Classical Mechanics, 3rd ed., chapter 1 (Lagrange's equations with
non-conservative generalized forces). Addison-Wesley.
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. Bulletin of the
Seismological Society of America 53(2), 403-417.
Moreau, J. J. (1988). Unilateral contact and dry friction in finite freedom dynamics. In Nonsmooth Mechanics and
Applications, CISM Courses and Lectures 302, 1-82. Springer.
Psycharis, I. N. (1990). Dynamic behaviour of rocking two-block assemblies. Earthquake Engineering & Structural
Dynamics 19(4), 555-575.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..compiled import jit
from ..constants import G
from ..rocking.codes import STATUS_GROUND_FLIGHT
from ..rocking.numerics.rk import DOPRI54, next_step, rejected_step, rk_step
from .n_block import MAX_BODIES, NBlock
from .slide_rock_parts import (
    INNER_HOLDS,
    INNER_OPENS,
    inner,
    inner_landing,
    parts_of,
    rocking_scales,
)
from .stack_pose import SlideRockState
from .stepping import (
    ATOL,
    EVENT_TIME_TOL_S,
    FIRST_STEP_FRACTION,
    HALF_PI,
    MAX_STEP_P,
    REST_RATIO,
    RTOL,
    TAIL_S,
    caps,
    ground_on,
    impact_root,
    piece_at,
)

#: How a run ends: handed back to the two-block model, to the stack's contact model; the stack fell; a cap; at the
#: instant it was asked to stop at
END_EXACT, END_CONTACT, END_FALLS, END_CAP, END_STOPPED = 0, 1, 2, 3, 4
#: Events (:func:`_event`): none, a fall, a landing on the other corner, a sliding joint stopping, a sticking joint
#: slipping, the joint opening (or no longer pressed), the ground no longer holding the pivot
_NONE, _FALL, _IMPACT, _STOP, _SLIPS, _OPENS, _GROUND = 0, 1, 2, 3, 4, 5, 6
#: ... a shut joint of a taller stack's parts slipping (:mod:`.slide_rock_parts`; one opening is :data:`_OPENS`)
_INNER_SLIPS = 7
#: A joint sticking (its slip's sign otherwise); a still joint that can neither stick nor slide its way
STUCK, NEITHER = 0, 2
#: A run going on past an event (:func:`_at_event`)
_GO_ON = -1


class Forces(NamedTuple):
    """The accelerations and the contact forces in a state: phi'' [rad s-2], u'' [m s-2], the joint's normal and
    friction force on the upper block N, F_t [N], its centre of pressure x_p [m], the ground's reaction R_x, R_z
    [N]; the field per unit mass along the lower's base and normal to it f_e, f_n [m s-2]."""

    ddphi: float
    ddu: float
    normal: float
    friction: float
    x_p: float
    rx: float
    rz: float
    fe: float
    fn: float


#: The forces not computed (:func:`_check` before it reaches them)
_NO_FORCES = Forces(*(math.nan,) * 9)


class SlideRockOutcome(NamedTuple):
    """A run's result.

    Attributes
    ----------
    end : int
        :data:`END_EXACT`, :data:`END_CONTACT`, :data:`END_FALLS`, :data:`END_CAP` or :data:`END_STOPPED`
    t_end_s : float
        where the run ended [s] (the fall's instant for a fall)
    state : tuple of float
        (phi [rad], u [m], phi' [rad s-1], u' [m s-1]) there
    pivot : int
        the corner the stack turned on where the run ended (each landing changes it)
    t_fall_s : float
        when the stack fell [s] (NaN: it did not)
    peak_rad : tuple of float
        each joint's largest |rotation| [rad] (the ground's |phi|; the shut joint's 0)
    offsets_m : tuple of float
        each block's base centre from the centre of the top under it where the run ended [m] (block 0: 0)
    peak_slide_m : tuple of float
        each joint's largest |slip| from where it stood before the slips ``slid_m`` given to the run [m]
    base_shift_m : float
        how far block 0's base centre moved along the ground [m]: 0, the pivot holds
    demand_ground : float
        the largest |R_x| / R_z [-] at the steps' ends
    slips : int
        how many times the joint started to slip
    impacts : int
        landings on the other corner followed by the model's impact law (:func:`landing`)
    steps, events : int
        steps tried (located events' trials included) and events
    status : int
        :class:`~pipeline.rocking.codes.Status` bits: ground_flight, step_cap, event_cap, tail_cap
    """

    end: int
    t_end_s: float
    state: tuple
    pivot: int
    t_fall_s: float
    peak_rad: tuple
    offsets_m: tuple
    peak_slide_m: tuple
    base_shift_m: float
    demand_ground: float
    slips: int
    impacts: int
    steps: int
    events: int
    status: int


@jit
def _turned(c, s, x, z):
    """(x, z) of the blocks' frame in the ground's, the blocks turned by phi (cos c, sin s)."""
    return c * x + s * z, -s * x + c * z


@jit
def forces(sr, pivot, slip, y, ah, av):
    """The :class:`Forces` of the state y = (phi, u, phi', u') turning on ``pivot``, the joint sliding the way ``slip``
    says (:data:`STUCK`: sticking), under the ground (a_h, a_v) [m s-2] (the module's equations)."""
    phi, u, dphi, du = y[0], y[1], y[2], y[3]
    c, s = math.cos(phi), math.sin(phi)
    gv = G + av
    fe, fn = -ah * c + gv * s, -ah * s - gv * c
    rx0, big_h, r = sr.x0 - pivot * sr.b0, sr.top0 + sr.h1, sr.xt0 + u + sr.x1 - pivot * sr.b0
    a = sr.m0 * (rx0 * rx0 + sr.h0 * sr.h0) + sr.i0 + sr.i1 + sr.m1 * (r * r + big_h * big_h)
    q = sr.m0 * (sr.h0 * fe - rx0 * fn) + sr.m1 * (big_h * fe - r * fn)
    w2 = dphi * dphi
    if slip == STUCK:
        ddphi, ddu = q / a, 0.0
    else:                                           # F_t = -mu_1 slip N, N itself linear in phi''
        k = sr.mu1 * slip
        l21, l22 = sr.m1 * (big_h - k * r), sr.m1
        r1 = q - 2.0 * sr.m1 * r * du * dphi
        r2 = sr.m1 * fe + sr.m1 * r * w2 + k * sr.m1 * (w2 * big_h + 2.0 * dphi * du + fn)
        det = a * l22 - sr.m1 * big_h * l21
        ddphi, ddu = (r1 * l22 - sr.m1 * big_h * r2) / det, (a * r2 - l21 * r1) / det
    normal = sr.m1 * (-ddphi * r - w2 * big_h - 2.0 * dphi * du - fn)
    friction = sr.m1 * (big_h * ddphi + ddu - r * w2 - fe)
    x_p = sr.x1 - (sr.i1 * ddphi + sr.h1 * friction) / normal if normal > 0.0 else math.nan
    # the centres' accelerations: C_0 = T(x_0 - pivot b_0, h_0), C_1 = T(r, H) from the pivot, u' along T(1, 0)
    a0x, a0z = _turned(c, s, sr.h0, -rx0)
    b0x, b0z = _turned(c, s, -rx0, -sr.h0)
    a1x, a1z = _turned(c, s, big_h, -r)
    b1x, b1z = _turned(c, s, r, big_h)
    nx, nz = _turned(c, s, 0.0, 1.0)
    ex, ez = _turned(c, s, 1.0, 0.0)
    acc0x, acc0z = ddphi * a0x + w2 * b0x, ddphi * a0z + w2 * b0z
    acc1x = ddphi * a1x - w2 * b1x - 2.0 * dphi * du * nx + ddu * ex
    acc1z = ddphi * a1z - w2 * b1z - 2.0 * dphi * du * nz + ddu * ez
    m = sr.m0 + sr.m1
    rx = sr.m0 * acc0x + sr.m1 * acc1x + m * ah
    rz = sr.m0 * acc0z + sr.m1 * acc1z + m * gv
    return Forces(ddphi, ddu, normal, friction, x_p, rx, rz, fe, fn)


@jit
def _rhs(t, y, args):
    """The state's derivative (a tuple) with ``args`` = (sr, pivot, slip, piece)."""
    sr, pivot, slip, piece = args
    ah, av = ground_on(piece, t)
    fo = forces(sr, pivot, slip, y, ah, av)
    return (y[2], y[3], fo.ddphi, fo.ddu), 0.0


@jit
def _check(sr, parts, pivot, slip, y, piece, t):
    """The event the state y at t is past (the module's order: a fall, a landing, a sliding joint's stop, the
    ground, the joint opening, a sticking joint slipping), or :data:`_NONE`; and the state's :class:`Forces` where
    the checks reached them (NaN before: a fall, a landing or a stop is seen without them)."""
    if abs(y[0]) >= HALF_PI:
        return _FALL, _NO_FORCES
    if pivot * y[0] < 0.0 or (y[0] == 0.0 and pivot * y[2] <= 0.0):
        return _IMPACT, _NO_FORCES
    if slip != STUCK and slip * y[3] < 0.0:
        return _STOP, _NO_FORCES
    ah, av = ground_on(piece, t)
    fo = forces(sr, pivot, slip, y, ah, av)
    if not (fo.rz > 0.0 and abs(fo.rx) <= sr.mu0 * fo.rz):
        return _GROUND, fo
    lo, hi = max(-sr.b1, -sr.bt0 - y[1]), min(sr.b1, sr.bt0 - y[1])
    if not (fo.normal > 0.0 and lo < fo.x_p < hi):
        return _OPENS, fo
    if slip == STUCK and abs(fo.friction) > sr.mu1 * fo.normal:
        return _SLIPS, fo
    kind = inner(parts, pivot, y, fo.ddphi, fo.ddu, fo.fe, fo.fn)     # the parts' own joints, shut and sticking
    if kind != INNER_HOLDS:
        return (_OPENS if kind == INNER_OPENS else _INNER_SLIPS), fo
    return _NONE, fo


@jit
def _event(sr, parts, pivot, slip, y, piece, t):
    """:func:`_check`'s event alone."""
    return _check(sr, parts, pivot, slip, y, piece, t)[0]


@jit
def _handed_to(slip, kind):
    """Where a run that stops at the event ``kind`` goes: a sticking stack landing outside the law or opening its
    joint to the two-block model (:data:`END_EXACT`), anything else to the contact model (:data:`END_CONTACT`)."""
    return END_EXACT if slip == STUCK and (kind == _IMPACT or kind == _OPENS) else END_CONTACT


@jit
def _slides_to(sr, pivot, y, ah, av):
    """Where the joint is still (u' = 0): :data:`STUCK` where it holds, else the side it slides to (its friction
    opposing), or :data:`NEITHER` where neither is consistent (a slide whose u'' would not go its way: left to the
    contact model)."""
    stuck = forces(sr, pivot, STUCK, y, ah, av)
    if abs(stuck.friction) <= sr.mu1 * stuck.normal:
        return STUCK
    slip = -1 if stuck.friction > 0.0 else 1
    return slip if slip * forces(sr, pivot, slip, y, ah, av).ddu > 0.0 else NEITHER


class Landing(NamedTuple):
    """An impact's outcome (:func:`landing`): whether the law's assumptions hold (``holds``), the rates after it
    phi' [rad s-1] and u' [m s-1], the joint's state after it (:data:`STUCK` or the slip's sign), and the impulses:
    the joint's normal and friction impulse on the upper block and the ground's at the new corner [N s]."""

    holds: bool
    dphi: float
    du: float
    slip: int
    normal: float
    friction: float
    ground_x: float
    ground_z: float


@jit
def _arms(sr, pivot, u):
    """The upper part's centre of mass from the pivot at phi = 0 and u [m]: its height H, and its offset along the
    base from the corner ``pivot`` (r_-) and from the other (r_+)."""
    along = sr.xt0 + u + sr.x1
    return sr.top0 + sr.h1, along - pivot * sr.b0, along + pivot * sr.b0


@jit
def _landed(sr, pivot, y, dphi, du):
    """The impulses of an impact at phi = 0 from the rates y[2], y[3] on ``pivot`` to (dphi, du) on the other corner:
    (joint normal, joint friction on the upper, ground x, ground z) [N s]: each block's momentum change."""
    u, w, du0 = y[1], y[2], y[3]
    big_h, r_old, r_new = _arms(sr, pivot, u)
    normal = sr.m1 * (r_old * w - r_new * dphi)
    friction = sr.m1 * (big_h * (dphi - w) + du - du0)
    # at phi = 0 the lower's centre moves at phi' (h_0, -(x_0 - pivot b_0)) about its pivot; the upper's at
    # phi' (H, -r) + u' (1, 0)
    gx = sr.m0 * sr.h0 * (dphi - w) + sr.m1 * (big_h * (dphi - w) + du - du0)
    gz = sr.m0 * (-(sr.x0 + pivot * sr.b0) * dphi + (sr.x0 - pivot * sr.b0) * w) + sr.m1 * (-r_new * dphi + r_old * w)
    return normal, friction, gx, gz


@jit
def landing(sr, parts, pivot, y, rest):
    """The stack turning on ``pivot`` lands on its other corner at phi = 0 with the rates y[2], y[3]: a plastic impact
    whose impulses act at the new corner and at the joint, the old corner lifting (Housner 1963), the joint kept shut
    and its impulses within Coulomb's cone, |friction| <= mu_1 normal (Moreau 1988's impact law at the joint). The
    rates after it keep the stack's angular momentum about the new corner,

        A_+ phi'_+ + m_1 H u'_+ = w (m_0 (h_0^2 + x_+ x_-) + I_0 + I_1 + m_1 (H^2 + r_- r_+)) + m_1 H u'_-,

    x_-+ = x_0 -+ pivot b_0 and r_-+ = x_t + u + x_1 -+ pivot b_0 (the parts' centres from the old and the new corner),
    A_+ the module's A on the new corner, and either stick (u'_+ = 0) where the friction that asks is within the cone,
    or slide with the friction at its bound against the slip. :attr:`Landing.holds` where those hold, the joint's
    impulses press with their centre inside the overlap of the faces, the ground's within its friction, every other
    joint carries its impulses shut and sticking (:func:`~.slide_rock_parts.inner_landing`), and the stack rebounds
    on the new corner faster than ``rest`` [rad s-1] (else another model follows the landing)."""
    u, w, du0 = y[1], y[2], y[3]
    big_h, r_old, r_new = _arms(sr, pivot, u)
    x_old, x_new = sr.x0 - pivot * sr.b0, sr.x0 + pivot * sr.b0     # the lower's centre from each corner
    a_new = sr.m0 * (x_new * x_new + sr.h0 * sr.h0) + sr.i0 + sr.i1 + sr.m1 * (r_new * r_new + big_h * big_h)
    ang = (w * (sr.m0 * (sr.h0 * sr.h0 + x_new * x_old) + sr.i0 + sr.i1 + sr.m1 * (big_h * big_h + r_new * r_old))
           + sr.m1 * big_h * du0)
    dphi, du, slip = ang / a_new, 0.0, STUCK
    normal, friction, gx, gz = _landed(sr, pivot, y, dphi, du)
    if not abs(friction) <= sr.mu1 * normal:        # slides: friction = -mu_1 slip normal, normal linear in dphi
        slip = -1 if friction > 0.0 else 1
        k = sr.mu1 * slip
        l21, rhs2 = sr.m1 * (big_h - k * r_new), sr.m1 * (big_h * w + du0) - k * sr.m1 * r_old * w
        det = a_new * sr.m1 - sr.m1 * big_h * l21
        dphi, du = (ang * sr.m1 - sr.m1 * big_h * rhs2) / det, (a_new * rhs2 - l21 * ang) / det
        normal, friction, gx, gz = _landed(sr, pivot, y, dphi, du)
    lo, hi = max(-sr.b1, -sr.bt0 - u), min(sr.b1, sr.bt0 - u)
    x_p = sr.x1 - (sr.i1 * (dphi - w) + sr.h1 * friction) / normal if normal > 0.0 else math.nan
    holds = (normal > 0.0 and lo < x_p < hi and (slip == STUCK or slip * du > 0.0)
             and gz > 0.0 and abs(gx) <= sr.mu0 * gz and -pivot * dphi > rest
             and inner_landing(parts, pivot, u, w, du0, dphi, du))
    return Landing(holds, dphi, du, slip, normal, friction, gx, gz)


@jit
def _error_norm(err, y_old, y_new, sc):
    """The step's error over the tolerance (max norm): phi against sc[0] alpha, u against sc[2], the rates against
    sc[1] and sc[3]."""
    worst = 0.0
    for q in range(4):
        tol = ATOL * sc[q] + RTOL * max(abs(y_old[q]), abs(y_new[q]))
        worst = max(worst, abs(err[q]) / tol)
    return worst


@jit
def _locate(sr, parts, pivot, slip, y, f, piece, t, hh, y_end, f_end):
    """The event inside the step of ``hh`` [s] from (t, y) that ended at ``y_end``: a landing or a stop alone by the
    Illinois method on phi or u' (:func:`.stepping.impact_root`), else, or where that meets another event first, by
    bisection of the step's length. Returns (lo, y_lo, hi, y_hi, tries): the last length without the event and the
    state there, the first with it and the state there, the steps tried."""
    args = (sr, pivot, slip, piece)
    kind = _event(sr, parts, pivot, slip, y_end, piece, t + hh)
    tries = 0
    if (kind == _IMPACT and pivot * y[0] > 0.0) or (kind == _STOP and slip * y[3] > 0.0):
        weights = (float(pivot), 0.0, 0.0, 0.0) if kind == _IMPACT else (0.0, 0.0, 0.0, float(slip))
        converged, lo, y_lo, hi, y_hi, tries = impact_root(_rhs, args, t, y, f, hh, y_end, f_end, weights)
        if converged and _event(sr, parts, pivot, slip, y_lo, piece, t + lo) == _NONE:
            return lo, y_lo, hi, y_hi, tries
    lo, y_lo, hi, y_hi = 0.0, y, hh, y_end
    while hi - lo > EVENT_TIME_TOL_S:
        mid = 0.5 * (lo + hi)
        trial = rk_step(_rhs, args, t, y, f, mid, DOPRI54).y
        tries += 1
        if _event(sr, parts, pivot, slip, trial, piece, t + mid) != _NONE:
            hi, y_hi = mid, trial
        else:
            lo, y_lo = mid, trial
    return lo, y_lo, hi, y_hi, tries


@jit
def _at_event(sr, parts, pivot, slip, piece, t, lo, y_lo, hi, y_hi, rest):
    """The run at an event located in the step from t between ``lo`` (the state ``y_lo``) and ``hi`` (``y_hi``, past
    it): (how the run ends, or :data:`_GO_ON`; the instant; the state; the pivot; the joint's state). A fall ends
    it at ``hi``; a slip's start or stop changes the joint's state there; a landing within :func:`landing`'s law
    (a rebound above ``rest`` [rad s-1]) turns the stack onto its other corner there; any other event ends the run
    at ``lo``, just before it."""
    kind = _event(sr, parts, pivot, slip, y_hi, piece, t + hi)
    if kind == _FALL:
        return END_FALLS, t + hi, y_hi, pivot, slip
    if kind == _STOP or kind == _SLIPS:             # the joint's state changes at the event's far end
        y = (y_hi[0], y_hi[1], y_hi[2], 0.0)
        ah, av = ground_on(piece, t + hi)
        new = _slides_to(sr, pivot, y, ah, av)
        return (END_CONTACT if new == NEITHER else _GO_ON), t + hi, y, pivot, (slip if new == NEITHER else new)
    if kind == _IMPACT:
        ld = landing(sr, parts, pivot, (0.0, y_hi[1], y_hi[2], y_hi[3]), rest)
        if ld.holds:
            return _GO_ON, t + hi, (0.0, y_hi[1], ld.dphi, ld.du), -pivot, ld.slip
    return _handed_to(slip, kind), t + lo, y_lo, pivot, slip


@jit
def _run(sr, parts, ah, av, dt, y, t, pivot, slip, sc, h_max, origin_u, t_stop):
    """The run of :func:`simulate_slide_rock` from y = (phi, u, phi', u') at t on ``pivot``, the joint's ``slip``
    [SI units]:
    (end, t, y, pivot, slip, t_fall, peak |phi|, peak |u - origin_u|, ground demand, slips, impacts, steps, events,
    status)."""
    t_rec = (ah.shape[0] - 2) * dt + dt             # the last piece's end, as piece_at computes it
    tail_end = t_rec + TAIL_S
    h = h_max * FIRST_STEP_FRACTION
    end, status, t_fall = END_CAP, 0, math.nan
    peak_phi, peak_u, demand = abs(y[0]), abs(y[1] - origin_u), 0.0
    slips, impacts, steps, events = 0, 0, 0, 0
    f, fresh = y, True
    while True:
        capped = caps(steps, events, t, tail_end)
        if capped:
            status |= capped
            break
        if t >= t_stop:
            end = END_STOPPED
            break
        piece = piece_at(ah, av, dt, t, t_rec, tail_end)
        if G + piece.v0 <= 0.0 or G + piece.v1 <= 0.0:
            status, end = status | STATUS_GROUND_FLIGHT, END_CONTACT
            break
        t1 = min(piece.t0 + piece.span, t_stop)
        args = (sr, pivot, slip, piece)
        if fresh:
            kind = _event(sr, parts, pivot, slip, y, piece, t)
            if kind == _SLIPS:                      # a sticking joint past its friction at the start: it slides
                ah0, av0 = ground_on(piece, t)
                new = _slides_to(sr, pivot, y, ah0, av0)
                if new == NEITHER:
                    end = END_CONTACT
                    break
                slip, slips, events = new, slips + 1, events + 1
                continue
            if kind != _NONE:
                end = _handed_to(slip, kind)
                break
            f, fresh = _rhs(t, y, args)[0], False
        hh = min(h, h_max, t1 - t)
        st = rk_step(_rhs, args, t, y, f, hh, DOPRI54)
        steps += 1
        norm = _error_norm(st.err, y, st.y, sc)
        if not norm <= 1.0:
            h = rejected_step(hh, norm)
            continue
        kind, fo = _check(sr, parts, pivot, slip, st.y, piece, t + hh)
        if kind == _NONE:
            t, y, f = (t1 if hh == t1 - t else t + hh), st.y, st.f
            peak_phi, peak_u = max(peak_phi, abs(y[0])), max(peak_u, abs(y[1] - origin_u))
            demand = max(demand, abs(fo.rx) / fo.rz)
            h = next_step(hh, norm)
            continue
        lo, y_lo, hi, y_hi, tries = _locate(sr, parts, pivot, slip, y, f, piece, t, hh, st.y, st.f)
        steps, events, fresh = steps + tries, events + 1, True
        h = max(hi, h_max * FIRST_STEP_FRACTION)
        end, t, y, new_pivot, new_slip = _at_event(sr, parts, pivot, slip, piece, t, lo, y_lo, hi, y_hi,
                                                   REST_RATIO * sc[1])
        slips += 1 if new_slip != STUCK and new_slip != slip and end == _GO_ON else 0
        impacts += 1 if new_pivot != pivot else 0
        pivot, slip = new_pivot, new_slip
        peak_phi, peak_u = max(peak_phi, abs(y[0])), max(peak_u, abs(y[1] - origin_u))
        if end == END_FALLS:
            t_fall = t
        if end != _GO_ON:
            break
    return end, t, y, pivot, slip, t_fall, peak_phi, peak_u, demand, slips, impacts, steps, events, status


def simulate_slide_rock(nb: NBlock, mu, ah: np.ndarray, av: np.ndarray, dt_s: float, *, start: tuple,
                        t0_s: float, origin_m: float, until_s: float = math.inf, joint: int = 1) -> SlideRockOutcome:
    """The stack ``nb`` (friction ``mu`` [-] at each block's base) rocking as one on a corner of its lowest block, the
    blocks above ``joint`` sliding on it (:mod:`.slide_rock_parts`: each part's own joints shut at their offsets),
    under the ground ``ah``, ``av`` [m s-2] (contiguous float arrays, checked by the caller; ``av`` empty: none),
    samples ``dt_s`` [s] apart, from the state ``start`` = (phi [rad] != 0, its corner the side of its sign; u [m],
    the offset of the sliding joint; phi' [rad s-1]; u' [m s-1], the joint sliding its way, sticking where 0) at
    ``t0_s`` [s]. ``origin_m``: that joint's offset before any slip [m], from which its largest slip is measured.
    ``until_s`` [s]: the run stops there (:data:`END_STOPPED`), its steps ending on it."""
    phi, u0, rate, du0 = (float(x) for x in start[:4])
    pivot = 1 if phi > 0.0 else -1
    slip = STUCK if du0 == 0.0 else (1 if du0 > 0.0 else -1)
    alpha, p, height = rocking_scales(nb)
    sc = (alpha, p * alpha, alpha * height, p * alpha * height)
    end, t, y, pivot, _slip, t_fall, peak_phi, peak_u, demand, slips, impacts, steps, events, status = _run(
        *parts_of(nb, mu, joint), ah, av, float(dt_s), (phi, u0, rate, du0),
        float(t0_s), pivot, slip, sc, MAX_STEP_P / p, float(origin_m), float(until_s))
    offsets = [0.0] + [float(nb.off[k]) for k in range(1, MAX_BODIES)]
    offsets[joint] = float(y[1])
    slides = [0.0] * MAX_BODIES
    slides[joint] = float(peak_u)
    return SlideRockOutcome(int(end), float(t), tuple(float(x) for x in y), pivot, float(t_fall),
                            (float(peak_phi),) + (0.0,) * (MAX_BODIES - 1), tuple(offsets), tuple(slides), 0.0,
                            float(demand), int(slips), int(impacts), int(steps), int(events), int(status))


def rock_start(nb: NBlock, y: tuple) -> SlideRockState:
    """The slide-rock state of the n-block state ``y`` of two blocks whose blocks' joint is shut and sticking (u the
    upper's offset ``nb.off[1]``)."""
    return SlideRockState(float(y[0]), float(nb.off[1]), float(y[MAX_BODIES]), 0.0, 1)


def handback(out: SlideRockOutcome) -> tuple:
    """The n-block state where the run ended (the ground joint's psi and rate; the shut joint's 0)."""
    pad = (0.0,) * (MAX_BODIES - 2)
    return (out.state[0], 0.0) + pad + (out.state[2], 0.0) + pad
