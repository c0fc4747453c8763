"""A planar rigid block on a moving base with every contact mode: rest, slide, rock, slide-rock, free flight.

Pure rocking (:mod:`.kernel`) is the right model while the pivot sticks and the block stays on its base.
Where it stops (the friction demand exceeds mu, the block's own motion lifts its pivot, or the ground
falls faster than gravity), this model continues from the state it stopped in. It is compiled with numba
when installed, as :mod:`.kernel`.

Model (Shenton & Jones 1991; Zhang & Makris 2001). A rectangular block of half-width b, half-height h,
unit mass and centroidal inertia J = R^2 / 3 moves in its rocking plane, in the frame of the ground
(the ground's acceleration a_h, a_v enters as the inertial force -a_h and the apparent gravity
G = g + a_v). Its state is the centre of mass (x, y), the rotation theta (positive tipping towards +x,
as in :mod:`.kernel`) and their rates (u, v, w). A base corner c (+1 at +x, -1 at -x) sits at
(x + r_x, y + r_y) with r_x = c b cos(theta) - h sin(theta), r_y = -c b sin(theta) - h cos(theta).

Modes and their equations (per unit mass):

* **rest**: nothing moves.
* **slide** (flat on the base, slipping in direction sigma): x'' = -a_h - sigma mu G
  (Shenton & Jones 1991). A block with mu > tan(alpha) cannot slide flat: the friction at its base
  tips it, and it slide-rocks about its leading corner instead.
* **rock** about corner c (the pivot sticks): theta'' = -p^2 [(G/g) sin(c alpha - theta) + (a_h/g)
  cos(c alpha - theta)] (Housner 1963; Yim, Chopra & Penzien 1980 for G).
* **slide-rock** about corner c, the corner slipping in direction sigma: the normal force
  N = (G + r_y w^2) / (1 + r_x (r_x + sigma mu r_y) / J), friction -sigma mu N,
  J theta'' = -N (r_x + sigma mu r_y), x'' = -a_h - sigma mu N, y'' = -G + N
  (Zhang & Makris 2001, the slide-rock mode; here from the corner's contact constraint y_c'' = 0).
* **free flight**: x'' = -a_h, y'' = -G, theta'' = 0.

Transitions: rest -> rock or slide where |a_h| > min(tan alpha, mu) G; rock -> slide-rock where the pivot's
friction demand |f_x| / f_z exceeds mu (Zhang & Makris 2001, eqs. 16-20), in the direction that opposes
the required force; slide-rock -> rock where the corner's slip velocity reaches 0 and sticking needs no
more than mu (else the slip reverses); any contact mode -> free flight where the normal force reaches 0;
slide -> rest where the slip velocity reaches 0 and |a_h| <= mu G. At rock onset from rest the mode is
slide-rock when the onset already needs more than mu (Shenton 1996; Zhang & Makris 2001, eq. 7).

Impact law (a corner meets the base: theta reaching 0 while rocking, or a corner landing from flight).
The impact is instantaneous at that corner (Housner 1963): the corner does not rebound (its normal
velocity is 0 after the impact) and the other corner is released; the tangential impulse P_t sticks the
corner when it needs no more than mu times the normal impulse P_n, else the corner slips with
P_t = -sigma mu P_n (Coulomb's law for impulses, as in Shenton & Jones 1991). For a sticking impact at
theta = 0 this conserves the angular momentum about the corner and gives Housner's ratio
w+ / w- = 1 - 1.5 sin^2(alpha) (tested). The rotation rate after the impact is then multiplied by
e / e_Housner, so that a sticking rocking impact has exactly the block's restitution e, as in pure
rocking. A rebound slower than ``rest_ratio * p * alpha`` at theta = 0 ends in rest (or flat sliding).

Integration: the classical fourth-order Runge-Kutta method on steps that never cross a sample (the
ground is linear between samples), of at most dt / STEPS_PER_SAMPLE and MAX_STEP_P / p; events are
located by bisection on the step length. After the record, the ground is still: the motion is followed
until the block rests, overturns, or rocks on a sticking pivot, whose fate the energy of free rocking
decides as in :mod:`.kernel`.

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. BSSA 53(2), 403-417.
Yim, C.-S., Chopra, A. K. & Penzien, J. (1980). Rocking response of rigid blocks to earthquakes.
Earthquake Eng. Struct. Dyn. 8(6), 565-587.
Shenton, H. W. & Jones, N. P. (1991). Base excitation of rigid bodies. I: Formulation.
J. Eng. Mech. 117(10), 2286-2306.
Shenton, H. W. (1996). Criteria for initiation of slide, rock, and slide-rock rigid-body modes.
J. Eng. Mech. 122(7), 690-693.
Zhang, J. & Makris, N. (2001). Rocking response of free-standing blocks under cycloidal pulses.
J. Eng. Mech. 127(5), 473-483.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..compiled import jit, jit_inline, state_factory
from .codes import (  # noqa: F401  (read by the hand-off and the planner as contact.*)
    FLIGHT,
    MODE_FLIGHT,
    MODE_ROCK,
    MODE_SLIDE,
    MODE_SLIDE_ROCK,
    OVERTURNED,
    REST,
    ROCK,
    SLIDE,
    SLIDE_ROCK,
    STATUS_ENDED,
    STATUS_EVENT_CAP,
    STATUS_GROUND_FLIGHT,
    STATUS_LIFTOFF,
    STATUS_PAINLEVE,
    STATUS_STALLED,
    STATUS_STEP_CAP,
    STATUS_TAIL_CAP,
    STATUS_TIE_HOLD,
)
from .dopri import HISTORY_TIME_TOL_S
from .ground import exceed_fraction, flight_fraction
from .kernel import HALF_PI, SAMPLE_INDEX_TOL, TINY, free_outcome
from .rules import MAX_EVENTS_AT_ONE_INSTANT, events_at_instant_compiled, rocks_compiled
from .structures import ContactBlock, ContactOutcome, ContactState, GroundPiece

__all__ = ["ContactBlock", "ContactOutcome", "ContactState", "contact_block_of", "move", "impact", "accelerations",
           "corner_offsets", "housner_restitution"]

# modes, mode bits and status bits: the simulator's one vocabulary (codes.py)

# Step and event control, named once
STEPS_PER_SAMPLE = 2          # Runge-Kutta steps per sample interval, at least
MAX_STEP_P = 0.02             # largest step as a fraction of 1/p
BISECTIONS = 48               # bisections locating an event inside a step
MAX_EVENTS = 20000            # cap on transitions and impacts
MAX_TAIL_PERIODS = 200.0      # motion followed after the record, in units of 2 pi / p
PAINLEVE_MIN = 1e-6           # a slide-rock normal-force denominator below this is inconsistent
FLAT_ANGLE_ALPHA = 1e-9       # |theta| below this fraction of alpha counts as flat
MAX_STEPS_PER_SAMPLE = 1000   # step budget: step attempts per sample of the record (with the tail's steps), plus
MAX_STEPS_FIXED = 100000      # ... this many; the cap ends the scene (STATUS_STEP_CAP)


@jit
def contact_block_of(p, alpha, e, R, mu, g, rest_ratio) -> ContactBlock:
    """The contact model's block, with its derived half-width, half-height and inertia computed once."""
    return ContactBlock(p=p, alpha=alpha, e=e, R=R, mu=mu, g=g, rest_ratio=rest_ratio, b=R * math.sin(alpha),
                        h=R * math.cos(alpha), J=R * R / 3.0)


@jit
def corner_offsets(theta, c, b, h):
    """Offset (r_x, r_y) of base corner ``c`` from the centre of mass at rotation ``theta`` [m]."""
    ct, st = math.cos(theta), math.sin(theta)
    return c * b * ct - h * st, -c * b * st - h * ct


@jit
def accelerations(mode, c, sigma, theta, w, a, G, blk):
    """(x'', y'', theta'', N, F_x) of the mode at a state: accelerations [m s-2, rad s-2] and the contact
    force per unit mass, normal and tangential [m s-2] (the module's equations)."""
    alpha, g, mu = blk.alpha, blk.g, blk.mu
    b, h = blk.b, blk.h
    J = blk.J
    if mode == FLIGHT:
        return -a, -G, 0.0, 0.0, 0.0
    if mode == SLIDE:
        return -a - sigma * mu * G, 0.0, 0.0, G, -sigma * mu * G
    if mode == REST or mode == OVERTURNED:
        return 0.0, 0.0, 0.0, G, a
    rx, ry = corner_offsets(theta, c, b, h)
    if mode == ROCK:
        phi = alpha * c - theta
        aw = -blk.p * blk.p * ((G / g) * math.sin(phi) + (a / g) * math.cos(phi))
        ax = rx * w * w - ry * aw
        ay = rx * aw + ry * w * w
        return ax, ay, aw, ay + G, ax + a
    den = 1.0 + rx * (rx + sigma * mu * ry) / J
    N = (G + ry * w * w) / max(den, PAINLEVE_MIN)
    aw = -N * (rx + sigma * mu * ry) / J
    return -a - sigma * mu * N, -G + N, aw, N, -sigma * mu * N


@jit
def _rk4(mode, c, sigma, x, y, th, u, v, w, t, hh, t0, a0, sa, v0, sv, blk):
    """One classical Runge-Kutta step of length ``hh`` from t; the ground is a0 + sa (t - t0), G likewise."""
    g = blk.g
    ax1, ay1, aw1, _n, _f = accelerations(mode, c, sigma, th, w, a0 + sa * (t - t0), g + v0 + sv * (t - t0), blk)
    tm = t + 0.5 * hh
    am, gm = a0 + sa * (tm - t0), g + v0 + sv * (tm - t0)
    u2, v2, w2 = u + 0.5 * hh * ax1, v + 0.5 * hh * ay1, w + 0.5 * hh * aw1
    ax2, ay2, aw2, _n, _f = accelerations(mode, c, sigma, th + 0.5 * hh * w, w2, am, gm, blk)
    u3, v3, w3 = u + 0.5 * hh * ax2, v + 0.5 * hh * ay2, w + 0.5 * hh * aw2
    ax3, ay3, aw3, _n, _f = accelerations(mode, c, sigma, th + 0.5 * hh * w2, w3, am, gm, blk)
    u4, v4, w4 = u + hh * ax3, v + hh * ay3, w + hh * aw3
    te = t + hh
    ax4, ay4, aw4, _n, _f = accelerations(mode, c, sigma, th + hh * w3, w4, a0 + sa * (te - t0),
                                          g + v0 + sv * (te - t0), blk)
    x1 = x + hh / 6.0 * (u + 2.0 * u2 + 2.0 * u3 + u4)
    y1 = y + hh / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4)
    th1 = th + hh / 6.0 * (w + 2.0 * w2 + 2.0 * w3 + w4)
    u1 = u + hh / 6.0 * (ax1 + 2.0 * ax2 + 2.0 * ax3 + ax4)
    v1 = v + hh / 6.0 * (ay1 + 2.0 * ay2 + 2.0 * ay3 + ay4)
    w1 = w + hh / 6.0 * (aw1 + 2.0 * aw2 + 2.0 * aw3 + aw4)
    return x1, y1, th1, u1, v1, w1


@jit
def _contact_kept(force):
    """Event indicator of a contact force (apparent gravity or normal force): negative where it is <= 0, so that
    contact is lost where the force reaches 0 exactly (tie rule 3 of :mod:`.rules`)."""
    return force if force > 0.0 else -1.0


@jit
def _event(mode, c, sigma, x, y, th, u, v, w, a, G, blk):
    """Event function of the mode: negative once an event has happened (impact, lift-off, slip change,
    the lowest corner below the base in flight); the smallest of the mode's indicators."""
    b, h = blk.b, blk.h
    if mode == FLIGHT:
        return y + h + min(corner_offsets(th, 1.0, b, h)[1], corner_offsets(th, -1.0, b, h)[1])
    if mode == SLIDE:
        return min(sigma * u, _contact_kept(G))
    _ax, _ay, _aw, N, F = accelerations(mode, c, sigma, th, w, a, G, blk)
    ev = min(c * th, _contact_kept(N))
    if mode == ROCK:
        ev = min(ev, blk.mu * N - abs(F))
    else:
        rx, ry = corner_offsets(th, c, b, h)
        ev = min(ev, sigma * (u + ry * w))
    return ev


@jit
def housner_restitution(alpha):
    """Housner's angular-velocity ratio of a sticking rocking impact of a rectangular block,
    1 - 1.5 sin^2(alpha) [-] (Housner 1963)."""
    return 1.0 - 1.5 * math.sin(alpha) ** 2


@jit
def impact(k, th, u, v, w, blk):
    """Velocities just after corner ``k`` meets the base, and whether it sticks (the module's impact law).

    Returns (u, v, w, sticks); the velocities are returned unchanged with ``sticks`` False when the
    corner is not approaching the base.
    """
    b, h = blk.b, blk.h
    J = blk.J
    mu = blk.mu
    rx, ry = corner_offsets(th, k, b, h)
    vt, vn = u + ry * w, v - rx * w
    if vn >= 0.0:
        return u, v, w, False
    m11, m12, m22 = 1.0 + ry * ry / J, -rx * ry / J, 1.0 + rx * rx / J
    det = m11 * m22 - m12 * m12
    pt = (-vt * m22 + vn * m12) / det
    pn = (-vn * m11 + vt * m12) / det
    sticks = pn > 0.0 and abs(pt) <= mu * pn
    if not sticks:
        sig = 1.0 if vt > 0.0 else (-1.0 if vt < 0.0 else (-1.0 if pt > 0.0 else 1.0))
        pn = -vn / max(1.0 + rx * (rx + sig * mu * ry) / J, PAINLEVE_MIN)
        pt = -sig * mu * pn
    w1 = w + (ry * pt - rx * pn) / J
    eh = housner_restitution(blk.alpha)
    if eh > 0.0:
        w1 = w1 * blk.e / eh
    if sticks:
        return -ry * w1, rx * w1, w1, True
    return u + pt, rx * w1, w1, False


@jit
def _onset(a, G, blk):
    """Mode, corner and slip direction at the start of motion from rest under ground acceleration a and
    apparent gravity G (Shenton 1996): slide when the block cannot tip first, else rock about the corner
    away from a, or slide-rock when rocking would already need more friction than mu."""
    if G <= 0.0:
        return FLIGHT, 1.0, 1.0
    sgn = 1.0 if a > 0.0 else -1.0
    if not rocks_compiled(blk.alpha, blk.mu):       # tie rules 1 and 5 (rules), as the planner
        return SLIDE, 1.0, -sgn
    c = -sgn
    _ax, _ay, _aw, N, F = accelerations(ROCK, c, 1.0, 0.0, 0.0, a, G, blk)
    if N > 0.0 and abs(F) > blk.mu * N:
        return SLIDE_ROCK, c, -1.0 if F > 0.0 else 1.0
    return ROCK, c, 1.0


@jit
def _mode_bit(mode):
    if mode == SLIDE:
        return MODE_SLIDE
    if mode == ROCK:
        return MODE_ROCK
    if mode == SLIDE_ROCK:
        return MODE_SLIDE_ROCK
    if mode == FLIGHT:
        return MODE_FLIGHT
    return 0


@jit
def _constrain(mode, c, x, y, th, u, v, w, xc, blk):
    """The state put back on the mode's constraints: the pivot at ``xc`` on the base in rock, the corner on
    the base in slide-rock (no normal velocity), flat on the base in rest and slide."""
    b, h = blk.b, blk.h
    if mode == REST or mode == SLIDE:
        return x, 0.0, 0.0, (0.0 if mode == REST else u), 0.0, 0.0
    if mode == ROCK or mode == SLIDE_ROCK:
        rx, ry = corner_offsets(th, c, b, h)
        if mode == ROCK:
            return xc - rx, -h - ry, th, -ry * w, rx * w, w
        return x, -h - ry, th, u, rx * w, w
    return x, y, th, u, v, w


@jit
def _slip_point(mode, c, x, th, blk):
    """Horizontal position of the base point whose travel counts as slip in this mode [m]: the contact
    corner in slide-rock, the base's middle otherwise."""
    b, h = blk.b, blk.h
    if mode == SLIDE_ROCK:
        return x + corner_offsets(th, c, b, h)[0]
    return x - h * math.sin(th)


@jit
def _after_impact(k, x, y, th, u, v, w, blk):
    """Mode, corner, slip direction and state after corner ``k`` meets the base (the impact law); a rebound
    too slow at theta = 0 ends flat (rest, or slide when the base still moves)."""
    b, h = blk.b, blk.h
    rest_w = blk.rest_ratio * blk.p * blk.alpha
    flat = abs(th) <= FLAT_ANGLE_ALPHA * blk.alpha
    if flat and abs(w) < rest_w:
        # a flat landing (or a dying rebound): plastic normal impact, Coulomb tangential impulse on the base
        dv = max(-v, 0.0)
        speed = max(abs(u) - blk.mu * dv, 0.0)
        u1 = math.copysign(speed, u) if speed > 0.0 else 0.0
        return (SLIDE if u1 != 0.0 else REST), 1.0, (1.0 if u1 > 0.0 else -1.0), x, 0.0, 0.0, u1, 0.0, 0.0
    u1, v1, w1, sticks = impact(k, th, u, v, w, blk)
    if flat:
        th = 0.0
        if abs(w1) < rest_w or k * w1 <= 0.0:
            return REST, 1.0, 1.0, x, 0.0, 0.0, 0.0, 0.0, 0.0
    rx, ry = corner_offsets(th, k, b, h)
    y = -h - ry
    if sticks:
        return ROCK, k, 1.0, x, y, th, u1, v1, w1
    vt = u1 + ry * w1
    return SLIDE_ROCK, k, (1.0 if vt > 0.0 else -1.0), x, y, th, u1, v1, w1


#: The contact model's state while it follows a scene: one record, changed in place by the step functions and
#: read once at the end into a :class:`ContactOutcome`.
MOTION = np.dtype([
    ("t", np.float64),               # time reached [s]
    ("mode", np.int64),              # codes.Mode
    ("corner", np.float64),          # contact corner c (+1 at +x, -1 at -x)
    ("sigma", np.float64),           # slip direction (+1, -1)
    ("x", np.float64), ("y", np.float64), ("theta", np.float64),   # [m], [m], [rad]
    ("u", np.float64), ("v", np.float64), ("w", np.float64),       # [m s-1], [m s-1], [rad s-1]
    ("xc", np.float64),              # where the sticking pivot is on the base [m]
    ("slip", np.float64),            # net slip of the base [m], and its largest |value|
    ("slip_max", np.float64),
    ("theta_max", np.float64),       # largest |theta| [rad]
    ("t_start", np.float64),         # where the model took over [s] (hand_back waits a sample interval after it)
    ("t_overturn", np.float64),      # [s], NaN while standing
    ("n_impacts", np.int64),
    ("modes", np.int64),             # codes.ContactMode bits of the modes that occurred
    ("status", np.int64),            # codes.Status bits
    ("events", np.int64),            # transitions and impacts (MAX_EVENTS caps them)
    ("n_steps", np.int64),           # Runge-Kutta steps (the step budget caps them)
    ("t_event", np.float64),         # time of the last event [s], and events in a row there (tie rule 6)
    ("n_same", np.int64),
    ("out_k", np.int64),             # the next sample of the theta history to fill
    ("overturned", np.bool_),
])
new_motion = state_factory(MOTION)


class MoveLimits(NamedTuple):
    """What the contact model derives from its block, the record and its caps, once per scene.

    Attributes
    ----------
    h_max : float
        Largest step [s].
    t_cap : float
        The motion after the record is followed up to this time [s].
    thr : float
        Motion starts from rest where |a_h| > thr (g + a_v): min(tan(alpha), mu) [-].
    max_steps, max_events : int
        Step budget and event cap of the scene.
    """

    h_max: float
    t_cap: float
    thr: float
    max_steps: int
    max_events: int


@jit
def move(ah, av, dt, blk, start, tail_energy, t_stop=math.inf, hand_back=False, theta_out=None):
    """Follow the block from ``start`` under the ground motion, in whatever modes it takes.

    Parameters
    ----------
    ah, av : ndarray
        Horizontal and vertical ground acceleration at t = k dt [m s-2] (``av`` empty: no vertical).
    dt : float
        Sampling interval [s].
    blk : ContactBlock
        The block.
    start : ContactState
        Where to start (a rest state at t = 0 for a whole simulation; where the pure-rocking kernel
        stopped, to continue it).
    tail_energy : bool
        After the record, decide a block rocking on a sticking pivot by the energy of free rocking
        (:func:`.kernel.free_outcome`) instead of following it.
    t_stop : float
        Stop there, whatever the block is doing [s] (default: follow it to its end).
    hand_back : bool
        Stop where the block is back at rest or rocking on a sticking pivot, at least one sample interval
        after ``start`` (the pure-rocking kernel, whose model holds there and which is cheaper, takes over:
        :mod:`.handoff`).
    theta_out : ndarray, optional
        theta [rad] at the samples k dt from ``start`` on, filled as the block moves (linear within a step, whose
        length is at most half a sample interval); samples not reached are left as they were.

    Returns
    -------
    ContactOutcome
    """
    n = ah.shape[0]
    has_v = av.shape[0] == n
    lim = _limits(blk, n, dt, MAX_STEPS_PER_SAMPLE * n + MAX_STEPS_FIXED, MAX_EVENTS)
    hist = theta_out if theta_out is not None else np.empty(0)
    progress = new_motion()
    _begin(progress, start, dt, blk, hist)
    while progress[0].mode != OVERTURNED and progress[0].t < t_stop and _within_caps(lim, progress):
        pc = _piece(ah, av, has_v, dt, progress[0].t, lim.h_max)
        if pc.k >= n - 1 and (progress[0].mode == REST or progress[0].mode == ROCK and tail_energy):
            _free_rocking(blk, progress)      # after the record, at rest or rocking freely: nothing to follow
            break
        if progress[0].mode == REST:
            if not _from_rest(pc, t_stop, dt, blk, lim, progress, hist):
                break
        elif progress[0].mode != FLIGHT and blk.g + pc.v0 + pc.sv * (progress[0].t - pc.t0) <= 0.0:
            _lose_contact(progress)
        elif not _step(pc, t_stop, hand_back, dt, blk, lim, progress, hist):
            break
    _verdict_if_ended(blk, progress)
    return _outcome(progress)


@jit
def _limits(blk, n, dt, max_steps, max_events):
    """The scene's :class:`MoveLimits` (``n`` samples of interval ``dt`` [s])."""
    return MoveLimits(h_max=min(dt / STEPS_PER_SAMPLE, MAX_STEP_P / blk.p),
                      t_cap=(n - 1) * dt + MAX_TAIL_PERIODS * 2.0 * math.pi / blk.p,
                      thr=min(math.tan(blk.alpha), blk.mu), max_steps=max_steps, max_events=max_events)


@jit
def _begin(progress, start, dt, blk, hist):
    """Set the motion record to the start state."""
    pr = progress[0]
    pr.t, pr.mode, pr.corner, pr.sigma = start.t, start.mode, start.corner, start.sigma
    pr.x, pr.y, pr.theta, pr.u, pr.v, pr.w = start.x, start.y, start.theta, start.u, start.v, start.w
    pr.xc = start.x + corner_offsets(start.theta, start.corner, blk.b, blk.h)[0]
    pr.theta_max = abs(start.theta)
    pr.slip = start.slip
    pr.slip_max = abs(start.slip)
    pr.t_start = start.t
    pr.t_overturn = math.nan
    pr.modes = _mode_bit(start.mode)
    pr.t_event = -math.inf
    pr.out_k = int(math.ceil(start.t / dt - SAMPLE_INDEX_TOL)) if hist.shape[0] > 0 else 0


@jit_inline
def _within_caps(lim, progress):
    """False, with the cap's status bit set, once the scene meets its tail, event or step cap."""
    pr = progress[0]
    if pr.t >= lim.t_cap:
        pr.status |= STATUS_TAIL_CAP
        return False
    if pr.events >= lim.max_events:
        pr.status |= STATUS_EVENT_CAP
        return False
    if pr.n_steps >= lim.max_steps:
        pr.status |= STATUS_STEP_CAP
        return False
    return True


@jit_inline
def _piece(ah, av, has_v, dt, t, h_max):
    """The ground's linear piece holding t (the next one when t is on its end); after the record, the ground
    is still, over a step of ``h_max``."""
    n = ah.shape[0]
    k = int(t / dt + SAMPLE_INDEX_TOL)
    if k < n - 1:
        t0 = k * dt
        t1 = t0 + dt
        if t1 <= t:
            k += 1
            t0, t1 = k * dt, (k + 1) * dt
    a0 = a1 = v0 = v1 = 0.0
    if k < n - 1:
        a0, a1 = ah[k], ah[k + 1]
        if has_v:
            v0, v1 = av[k], av[k + 1]
    else:
        t0, t1 = t, t + h_max
    return GroundPiece(k=k, t0=t0, t1=t1, a0=a0, a1=a1, v0=v0, v1=v1, sa=(a1 - a0) / (t1 - t0),
                       sv=(v1 - v0) / (t1 - t0))


@jit
def _free_rocking(blk, progress):
    """After the record, a block rocking on a sticking pivot: the energy of free rocking decides
    (:func:`.kernel.free_outcome`)."""
    pr = progress[0]
    if pr.mode != ROCK:
        return
    over, peak, extra = free_outcome(pr.theta, pr.w, blk.p * blk.p, blk.alpha, blk.e, False)
    pr.theta_max = max(pr.theta_max, peak)
    if over:
        pr.overturned, pr.t_overturn, pr.mode = True, pr.t, OVERTURNED
        pr.n_impacts += extra


@jit_inline
def _from_rest(pc, t_stop, dt, blk, lim, progress, hist):
    """Advance a block at rest to the start of motion (its mode by :func:`_onset`), to the loss of contact, or
    to the piece's end. Returns whether the scene goes on."""
    pr = progress[0]
    t, t0, t1, g = pr.t, pc.t0, pc.t1, blk.g
    aa0, vv0 = pc.a0 + pc.sa * (t - t0), pc.v0 + pc.sv * (t - t0)
    xf = flight_fraction(vv0, pc.v1, g)
    xm = exceed_fraction(aa0, pc.a1, vv0, pc.v1, g, lim.thr)
    if xf < 0.0 and xm < 0.0:
        pr.t = min(t1, t_stop)
        pr.out_k = _fill_linear(hist, pr.out_k, dt, pr.t, 0.0, pr.t, 0.0)
        return True
    frac = xf if (xf >= 0.0 and (xm < 0.0 or xf <= xm)) else xm
    if t + frac * (t1 - t) > t_stop:
        pr.t = t_stop
        return False
    t_on = t + frac * (t1 - t)
    pr.n_same = events_at_instant_compiled(t_on, pr.t_event, pr.n_same)
    pr.t_event = t_on
    if pr.n_same > MAX_EVENTS_AT_ONE_INSTANT:
        pr.status |= STATUS_TIE_HOLD             # tie rule 6: held at rest to the next sample
        pr.n_same = 0
        pr.t = min(t1, t_stop)
        return True
    pr.t = t_on
    pr.out_k = _fill_linear(hist, pr.out_k, dt, t_on, 0.0, t_on, 0.0)
    mode, c, sigma = _onset(pc.a0 + pc.sa * (t_on - t0), g + pc.v0 + pc.sv * (t_on - t0), blk)
    pr.mode, pr.corner, pr.sigma = mode, c, sigma
    if mode == FLIGHT:
        pr.status |= STATUS_GROUND_FLIGHT
    pr.modes |= _mode_bit(mode)
    pr.xc = pr.x + corner_offsets(0.0, c, blk.b, blk.h)[0]
    pr.events += 1
    return True


@jit_inline
def _lose_contact(progress):
    """The ground's g + a_v is at 0 at this instant (a sample exactly at -g): contact is lost here (tie rule 3),
    whatever the next step would see."""
    pr = progress[0]
    pr.mode = FLIGHT
    pr.status |= STATUS_GROUND_FLIGHT
    pr.modes |= MODE_FLIGHT
    pr.events += 1


@jit_inline
def _event_step(mode, c, sigma, x, y, th, u, v, w, t, hh, pc, blk):
    """The length of a step from t that ends at the mode's first event inside ``hh`` (bisection on the
    step length: the event function is negative at its end)."""
    g, t0 = blk.g, pc.t0
    lo, hi = 0.0, hh
    for _ in range(BISECTIONS):
        mid = 0.5 * (lo + hi)
        xm_, ym_, thm, um, vm, wm = _rk4(mode, c, sigma, x, y, th, u, v, w, t, mid, t0, pc.a0, pc.sa, pc.v0, pc.sv,
                                         blk)
        tm = t + mid
        if _event(mode, c, sigma, xm_, ym_, thm, um, vm, wm, pc.a0 + pc.sa * (tm - t0), g + pc.v0 + pc.sv * (tm - t0),
                  blk) < 0.0:
            hi = mid
        else:
            lo = mid
    return hi


@jit_inline
def _step(pc, t_stop, hand_back, dt, blk, lim, progress, hist):
    """One Runge-Kutta step in the current mode, shortened to its first event: overturning ends the scene; the
    state is put back on the mode's constraints, the slip and the history follow, and an event changes the mode
    (:func:`_after_event`). Returns whether the scene goes on."""
    pr = progress[0]
    t, mode, c, sigma = pr.t, pr.mode, pr.corner, pr.sigma
    x, y, th, u, v, w = pr.x, pr.y, pr.theta, pr.u, pr.v, pr.w
    g, t0 = blk.g, pc.t0
    hh = min(lim.h_max, pc.t1 - t, t_stop - t)
    pr.n_steps += 1
    x1, y1, th1, u1, v1s, w1 = _rk4(mode, c, sigma, x, y, th, u, v, w, t, hh, t0, pc.a0, pc.sa, pc.v0, pc.sv, blk)
    te = t + hh
    ev = _event(mode, c, sigma, x1, y1, th1, u1, v1s, w1, pc.a0 + pc.sa * (te - t0), g + pc.v0 + pc.sv * (te - t0),
                blk)
    if ev < 0.0:
        hh = _event_step(mode, c, sigma, x, y, th, u, v, w, t, hh, pc, blk)
        te = t + hh
        x1, y1, th1, u1, v1s, w1 = _rk4(mode, c, sigma, x, y, th, u, v, w, t, hh, t0, pc.a0, pc.sa, pc.v0, pc.sv, blk)
    if abs(th1) >= HALF_PI:
        frac = (HALF_PI - abs(th)) / max(abs(th1) - abs(th), TINY)
        pr.overturned, pr.t_overturn, pr.mode, pr.theta_max = True, t + frac * hh, OVERTURNED, HALF_PI
        pr.t = pr.t_overturn
        return False
    if mode != ROCK:
        pr.slip += _slip_point(mode, c, x1, th1, blk) - _slip_point(mode, c, x, th, blk)
        pr.slip_max = max(pr.slip_max, abs(pr.slip))
    pr.x, pr.y, pr.theta, pr.u, pr.v, pr.w = _constrain(mode, c, x1, y1, th1, u1, v1s, w1, pr.xc, blk)
    pr.theta_max = max(pr.theta_max, abs(pr.theta))
    pr.out_k = _fill_linear(hist, pr.out_k, dt, t, th, te, pr.theta)
    pr.t = te
    if ev >= 0.0:
        return True
    return _after_event(pc, t_stop, hand_back, dt, blk, progress)


@jit_inline
def _after_event(pc, t_stop, hand_back, dt, blk, progress):
    """The mode after an event at the current state (:func:`_transition`), with tie rule 6 and the hand-back
    to the rocking kernel. Returns whether the scene goes on."""
    pr = progress[0]
    t = pr.t
    pr.events += 1
    pr.n_same = events_at_instant_compiled(t, pr.t_event, pr.n_same)
    pr.t_event = t
    if pr.n_same > MAX_EVENTS_AT_ONE_INSTANT:
        if abs(pr.theta) > FLAT_ANGLE_ALPHA * blk.alpha:
            pr.status |= STATUS_STALLED              # tie rule 6 while not flat: ended, the state's verdict
            return False
        pr.status |= STATUS_TIE_HOLD                 # tie rule 6, flat: held at rest to the next sample
        pr.n_same = 0
        pr.mode, pr.theta, pr.y, pr.u, pr.v, pr.w = REST, 0.0, 0.0, 0.0, 0.0, 0.0
        pr.t = min(pc.t1, t_stop)
        return True
    aa, gg = pc.a0 + pc.sa * (t - pc.t0), blk.g + pc.v0 + pc.sv * (t - pc.t0)
    mode, c, sigma, x, y, th, u, v, w, hit = _transition(pr.mode, pr.corner, pr.sigma, pr.x, pr.y, pr.theta, pr.u,
                                                         pr.v, pr.w, aa, gg, blk)
    pr.mode, pr.corner, pr.sigma = mode, c, sigma
    pr.x, pr.y, pr.theta, pr.u, pr.v, pr.w = x, y, th, u, v, w
    if mode == FLIGHT:
        pr.status |= STATUS_GROUND_FLIGHT if gg <= 0.0 else STATUS_LIFTOFF
    pr.n_impacts += hit
    pr.xc = x + corner_offsets(th, c, blk.b, blk.h)[0]
    pr.modes |= _mode_bit(mode)
    return not (hand_back and (mode == ROCK or mode == REST) and t >= pr.t_start + dt)


@jit
def _verdict_if_ended(blk, progress):
    """A scene ended early by a cap or tie rule 6 takes the verdict of the state it reached."""
    pr = progress[0]
    if pr.status & STATUS_ENDED and not pr.overturned:
        over, peak = state_verdict(pr.mode, pr.theta, pr.w, blk)
        pr.theta_max = max(pr.theta_max, peak)
        if over:
            pr.overturned, pr.t_overturn, pr.mode = True, pr.t, OVERTURNED


@jit
def _outcome(progress):
    """The motion record as the model's :class:`ContactOutcome`."""
    pr = progress[0]
    end = ContactState(t=pr.t, mode=pr.mode, corner=pr.corner, sigma=pr.sigma, x=pr.x, y=pr.y, theta=pr.theta,
                       u=pr.u, v=pr.v, w=pr.w, slip=pr.slip)
    return ContactOutcome(overturned=pr.overturned, t_overturn=pr.t_overturn, theta_max_rad=pr.theta_max,
                          n_impacts=pr.n_impacts, slip_max=pr.slip_max, slip_end=pr.slip, modes=pr.modes,
                          status=pr.status, end=end)


@jit
def _fill_linear(hist, out_k, dt, t0, th0, t1, th1):
    """theta at the samples k dt <= t1 not filled yet, linear between (t0, th0) and (t1, th1); the next sample."""
    while out_k < hist.shape[0] and out_k * dt <= t1 + HISTORY_TIME_TOL_S:
        hist[out_k] = th1 if t1 <= t0 else th0 + (th1 - th0) * (out_k * dt - t0) / (t1 - t0)
        out_k += 1
    return out_k


@jit
def state_verdict(mode, th, w, blk):
    """The verdict of a scene ended early (a cap, tie rule 6) from the state it reached: (overturns, peak
    |theta| still to come [rad]). A block on a corner (rock, slide-rock, flight) is judged by the energy of its
    free rocking from there (:func:`.kernel.free_outcome`: as if the ground stopped); a flat one stands."""
    if (mode == ROCK or mode == SLIDE_ROCK or mode == FLIGHT) and th != 0.0:
        over, peak, _extra = free_outcome(th, w, blk.p * blk.p, blk.alpha, blk.e, False)
        return over, peak
    return False, abs(th)


@jit
def _transition(mode, c, sigma, x, y, th, u, v, w, a, G, blk):
    """The mode after an event of ``mode`` at this state: (mode, corner, sigma, x, y, theta, u, v, w,
    impacts)."""
    b, h = blk.b, blk.h
    if mode == FLIGHT:
        k = 1.0 if corner_offsets(th, 1.0, b, h)[1] < corner_offsets(th, -1.0, b, h)[1] else -1.0
        m, c1, s1, x, y, th, u, v, w = _after_impact(k, x, y, th, u, v, w, blk)
        return m, c1, s1, x, y, th, u, v, w, 1
    if mode == SLIDE:
        if G <= 0.0:
            return FLIGHT, c, sigma, x, y, th, u, v, w, 0
        if abs(a) <= blk.mu * G:
            return REST, c, sigma, x, y, th, 0.0, v, w, 0
        return SLIDE, c, -sigma, x, y, th, 0.0, v, w, 0
    _ax, _ay, _aw, N, F = accelerations(mode, c, sigma, th, w, a, G, blk)
    if c * th <= 0.0:                               # the other corner meets the base
        m, c1, s1, x, y, th, u, v, w = _after_impact(-c, x, y, 0.0, u, v, w, blk)
        return m, c1, s1, x, y, th, u, v, w, 1
    if N <= 0.0:
        return FLIGHT, c, sigma, x, y, th, u, v, w, 0
    if mode == ROCK:                                 # the pivot needs more friction than mu: it slips
        return SLIDE_ROCK, c, (-1.0 if F > 0.0 else 1.0), x, y, th, u, v, w, 0
    # slide-rock: the corner's slip stopped; it sticks when sticking needs no more than mu
    _ax, _ay, _aw, Nr, Fr = accelerations(ROCK, c, 1.0, th, w, a, G, blk)
    if Nr > 0.0 and abs(Fr) <= blk.mu * Nr:
        return ROCK, c, 1.0, x, y, th, u, v, w, 0
    return SLIDE_ROCK, c, -sigma, x, y, th, u, v, w, 0
