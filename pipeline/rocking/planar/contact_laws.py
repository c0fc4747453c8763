"""The laws of the general contact model: a planar rigid block's equations of motion in each contact mode,
its events, the transitions between modes and the impact law (:mod:`.contact` integrates them).

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
import sys

from ...compiled import jit, jit_inline
from ..codes import (
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
)
from ..numerics.rk import RK4, rk_step
from ..rules import rocks_compiled
from .kernel import free_outcome

PAINLEVE_MIN = 1e-6           # a slide-rock normal-force denominator below this is inconsistent
FLAT_ANGLE_ALPHA = 1e-9       # |theta| below this fraction of alpha counts as flat
FORCE_TIE = sys.float_info.min  # a contact force of exactly 0 gives this negative event indicator [m s-2]


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


@jit_inline
def _motion(t, state, args):
    """f of the state (x, y, theta, u, v, w) in the mode (``args``: mode, corner, slip sign, the ground piece's
    t0, a0, sa, v0, sv, the block) at ``t``; the contact force per unit mass (N, F_x) kept."""
    mode, c, sigma, t0, a0, sa, v0, sv, blk = args
    _x, _y, th, u, v, w = state
    ax, ay, aw, n, f = accelerations(mode, c, sigma, th, w, a0 + sa * (t - t0), blk.g + v0 + sv * (t - t0), blk)
    return (u, v, w, ax, ay, aw), (n, f)


@jit
def _rk4(mode, c, sigma, x, y, th, u, v, w, t, hh, t0, a0, sa, v0, sv, blk):
    """One classical Runge-Kutta step (:func:`~..numerics.rk.rk_step` with :data:`~..numerics.rk.RK4`) of length
    ``hh`` from t; the ground is a0 + sa (t - t0), G likewise. Returns the state (x, y, theta, u, v, w) at its end."""
    args = (mode, c, sigma, t0, a0, sa, v0, sv, blk)
    state = (x, y, th, u, v, w)
    f, _ = _motion(t, state, args)
    return rk_step(_motion, args, t, state, f, hh, RK4).y


@jit
def _contact_kept(force):
    """Event indicator of a contact force (apparent gravity or normal force): negative where it is <= 0, so that
    contact is lost where the force reaches 0 exactly (tie rule 3 of :mod:`.rules`); the force itself elsewhere
    (:data:`FORCE_TIE` below 0 at 0), so that, but for that step of one smallest double at 0, it is continuous
    through its root, as the event's location by interpolation wants it."""
    return force if force > 0.0 else min(force, -FORCE_TIE)


@jit
def _event_branches(mode, c, sigma, x, y, th, u, v, w, a, G, blk):
    """The mode's event indicators, each negative once its event has happened (inf where the mode has fewer than
    three): in flight each corner's height above the base; sliding the slip rate along its sign and the apparent
    gravity; rocking or slide-rocking the tilt toward the pivot and the normal force, then the friction margin
    mu N - |F| (rocking) or the pivot's slip rate along its sign (slide-rocking). Each is smooth in the state where
    their smallest (:func:`event_value`) has a kink."""
    b, h = blk.b, blk.h
    if mode == FLIGHT:
        base = y + h
        return base + corner_offsets(th, 1.0, b, h)[1], base + corner_offsets(th, -1.0, b, h)[1], math.inf
    if mode == SLIDE:
        return sigma * u, _contact_kept(G), math.inf
    _ax, _ay, _aw, N, F = accelerations(mode, c, sigma, th, w, a, G, blk)
    if mode == ROCK:
        return c * th, _contact_kept(N), blk.mu * N - abs(F)
    _rx, ry = corner_offsets(th, c, b, h)
    return c * th, _contact_kept(N), sigma * (u + ry * w)


@jit_inline
def event_value(branches):
    """The event function of a state, from its indicators (:func:`_event_branches`): negative once an event has
    happened (impact, lift-off, slip change, the lowest corner below the base in flight); their smallest."""
    return min(min(branches[0], branches[1]), branches[2])


@jit_inline
def _smallest(branches):
    """Which indicator of a triple (:func:`_event_branches`) is the smallest: the one negative where the event
    function is."""
    e0, e1, e2 = branches
    if e0 <= e1 and e0 <= e2:
        return 0
    return 1 if e1 <= e2 else 2


@jit_inline
def _branch(branches, k):
    """Indicator ``k`` of a triple of :func:`_event_branches`."""
    return branches[0] if k == 0 else (branches[1] if k == 1 else branches[2])


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
    """The contact_modes bit of a contact mode (0: none)."""
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


@jit
def state_verdict(mode, th, w, blk):
    """The verdict of a scene ended early (a cap, tie rule 6) from the state it reached: (overturns, peak
    |theta| still to come [rad]). A block on a corner (rock, slide-rock, flight) is judged by the energy of its
    free rocking from there (:func:`.kernel.free_outcome`: as if the ground stopped); a flat one stands."""
    if (mode == ROCK or mode == SLIDE_ROCK or mode == FLIGHT) and th != 0.0:
        over, peak, _extra = free_outcome(th, w, blk.p * blk.p, blk.alpha, blk.e, bool(False))
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
