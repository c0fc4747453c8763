"""Compiled planar rocking of a body whose two sides differ (a scanned rock or statue): the equation of motion,
the impact rule and the free motion after the record of :mod:`.asymmetric`, on the rocking kernel's Runge-Kutta
step (:mod:`.dopri`), ground pieces and tie rules.

**Equation of motion** on pivot side ``s`` (+1: tilting toward +x), per unit mass, with ``R_s`` the
pivot-to-G distance, ``alpha_s`` the angle of G above the pivot, ``I_s = I_G + R_s^2`` and ``p_s^2 = g R_s / I_s``
(Housner 1963, with the vertical as in Yim, Chopra & Penzien 1980)::

    theta'' = -p_s^2 [(1 + a_v / g) sin(s alpha_s - theta) + (a_h / g) cos(s alpha_s - theta)]

which is :func:`.dopri.rocking_accel` with the side's own ``p_s`` and ``alpha_s``. **Uplift** from rest toward
side s at the exact crossing of ``-s a_h = (g + a_v) tan(alpha_s)`` on the ground's linear piece. **Impact** at
theta = 0 from side s to -s: ``omega+ = r_s omega-`` with ``r_s = (I_G + z_G^2 - b_s b_-s) / (I_G + z_G^2 +
b_-s^2)`` (angular momentum about the new pivot conserved: Housner's argument for unequal pivots; Housner's
``1 - 3/2 sin^2 alpha`` for a rectangle), times a declared factor. A rebound slower than ``rest_ratio``
p_min alpha_min rests; the event cap and tie rule 6 of :mod:`.rules` apply as in :mod:`.kernel`.

**After the record** the free motion is decided by its energy, ``E = I_s omega^2 / 2 + g R_s cos(alpha_s -
|theta|)`` per unit mass, impact by impact in closed form: it overturns where E reaches a side's barrier
``g R_s`` on a swing toward it, and stands once E is below ``g min(R_+, R_-)`` (impacts never add energy,
``(A - b_1 b_2)^2 <= (A + b_1^2)(A + b_2^2)``; a declared restitution is capped to keep it so,
:func:`two_sided_block`). The impacts taken after the record are counted.

Not modelled (flagged in ``status``, never a silent "stands"): the ground falling faster than gravity
(``ground_flight``: the scene stops there, no verdict), the pivot lifting off (``liftoff``) and the pivot's
friction demand (``friction_max``, recorded while |theta| < alpha_s, as the rocking kernel does).

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. BSSA 53(2), 403-417.
Yim, C.-S., Chopra, A. K. & Penzien, J. (1980). Rocking response of rigid blocks to earthquakes. Earthquake
Engineering & Structural Dynamics 8(6), 565-587.
Dormand, J. R. & Prince, P. J. (1980). A family of embedded Runge-Kutta formulae. J. Comput. Appl. Math. 6(1),
19-26.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...compiled import jit, jit_inline, state_factory
from ...constants import G
from ..codes import (
    OVERTURNED,
    REST,
    ROCK,
    STATUS_CHATTER,
    STATUS_GROUND_FLIGHT,
    STATUS_LIFTOFF,
    STATUS_STEP_CAP,
    STATUS_TAIL_CAP,
    STATUS_TIE_HOLD,
)
from ..numerics.dopri import dopri_step, fill_hermite, hermite_peak, locate_impact, pivot_demand
from ..numerics.ground import flight_fraction
from ..planar.kernel import (
    FIRST_STEP_FRACTION,
    MAX_STEPS_FIXED,
    MAX_STEPS_PER_SAMPLE,
    MIN_STEP_AFTER_IMPACT_P,
    MIN_STEP_S,
    TINY,
    UPLIFT_STEP_FRACTION,
    _impact_fraction,
    _next_step,
    _piece,
    reject,
    step_error,
)
from ..rules import MAX_EVENTS_AT_ONE_INSTANT, events_at_instant_compiled, min_advance_compiled
from ..structures import StepControl
from .two_sided_body import TwoSided

HALF_PI = 0.5 * math.pi
#: Impacts of the free motion after the record taken in closed form before it is given up (``tail_cap``)
MAX_TAIL_IMPACTS = 100000


class TwoSidedBlock(NamedTuple):
    """A two-sided body as the compiled kernel takes it (a numba namedtuple; built by :func:`two_sided_block`).

    Attributes
    ----------
    alpha_plus, alpha_minus : float
        Angle of G above each pivot, from the vertical [rad].
    R_plus, R_minus : float
        Pivot-to-G distance on each side [m].
    p2_plus, p2_minus : float
        g R_s / I_s on each side [rad2 s-2].
    ratio_plus, ratio_minus : float
        omega+ / omega- at an impact that leaves that side, the declared factor included [-].
    z_g : float
        Height of G above the base [m].
    g : float
        Gravity [m s-2].
    """

    alpha_plus: float
    alpha_minus: float
    R_plus: float
    R_minus: float
    p2_plus: float
    p2_minus: float
    ratio_plus: float
    ratio_minus: float
    z_g: float
    g: float


def two_sided_block(body: TwoSided, *, restitution_factor: float = 1.0, g_ms2: float = G) -> TwoSidedBlock:
    """The kernel's :class:`TwoSidedBlock` of a :class:`~.asymmetric.TwoSided` body (``restitution_factor``
    scales both sides' impact ratios [-]). Each scaled ratio is capped so that no impact gains speed (ratio <= 1)
    or energy (I_new ratio^2 <= I_old): the energy decision after the record rests on the energy never growing;
    the impact rule's own ratios satisfy both."""
    (ap, rp, ip), (am, rm, im) = body.side(1.0), body.side(-1.0)
    cap_plus, cap_minus = min(1.0, math.sqrt(ip / im)), min(1.0, math.sqrt(im / ip))
    return TwoSidedBlock(alpha_plus=ap, alpha_minus=am, R_plus=rp, R_minus=rm, p2_plus=g_ms2 * rp / ip,
                         p2_minus=g_ms2 * rm / im,
                         ratio_plus=min(body.impact_ratio(1.0) * restitution_factor, cap_plus),
                         ratio_minus=min(body.impact_ratio(-1.0) * restitution_factor, cap_minus),
                         z_g=body.com_height_m, g=g_ms2)


class TwoSidedOutcome(NamedTuple):
    """What :func:`rock_two_sided_compiled` returns.

    Attributes
    ----------
    overturned : bool
    t_overturn : float
        [s], the record's end where the free motion after it escapes; NaN when it stands.
    theta_max_plus, theta_max_minus : float
        Largest tilt toward each side [rad].
    n_impacts, n_uplifts : int
    friction_max : float
        Largest friction demand |f_x| / f_z at the pivot while |theta| < alpha_s [-].
    status : int
        :class:`~.codes.Status` bits.
    """

    overturned: bool
    t_overturn: float
    theta_max_plus: float
    theta_max_minus: float
    n_impacts: int
    n_uplifts: int
    friction_max: float
    status: int


#: The kernel's state while it integrates a scene, changed in place by the step functions (as in :mod:`.kernel`)
PROGRESS = np.dtype([
    ("t", np.float64), ("theta", np.float64), ("omega", np.float64), ("pivot", np.float64), ("mode", np.int64),
    ("h", np.float64), ("peak_plus", np.float64), ("peak_minus", np.float64), ("t_overturn", np.float64),
    ("friction_max", np.float64), ("n_impacts", np.int64), ("n_uplifts", np.int64), ("n_events", np.int64),
    ("n_steps", np.int64), ("status", np.int64), ("t_event", np.float64), ("n_same", np.int64),
    ("out_k", np.int64), ("overturned", np.bool_),
])
new_progress = state_factory(PROGRESS)


class Limits(NamedTuple):
    """The step control of one scene, derived once (the stiffer side sets the steps, the slenderer the
    tolerances)."""

    t_rec: float
    atol_theta: float
    atol_omega: float
    h_max: float
    rest_omega: float
    max_steps: int
    tan_plus: float
    tan_minus: float


@jit
def side_of(b, s):
    """(alpha [rad], R [m], p^2 [rad2 s-2], impact ratio leaving it [-]) of side ``s``."""
    if s > 0.0:
        return b.alpha_plus, b.R_plus, b.p2_plus, b.ratio_plus
    return b.alpha_minus, b.R_minus, b.p2_minus, b.ratio_minus


@jit
def _limits(b, control, n, dt):
    p_max = math.sqrt(max(b.p2_plus, b.p2_minus))
    p_min = math.sqrt(min(b.p2_plus, b.p2_minus))
    a_min = min(b.alpha_plus, b.alpha_minus)
    return Limits(t_rec=(n - 1) * dt, atol_theta=control.atol * a_min, atol_omega=control.atol * a_min * p_max,
                  h_max=control.max_step_p / p_max, rest_omega=control.rest_ratio * p_min * a_min,
                  max_steps=MAX_STEPS_PER_SAMPLE * n + MAX_STEPS_FIXED, tan_plus=math.tan(b.alpha_plus),
                  tan_minus=math.tan(b.alpha_minus))


@jit_inline
def _lift_fraction(a0, a1, v0, v1, g, lim):
    """(first fraction x in [0, 1] of a linear piece where the ground lifts the body, the side it tilts to), or
    (-1, 0): toward +x where -a_h > (g + a_v) tan(alpha_+), toward -x where a_h > (g + a_v) tan(alpha_-)."""
    best, side = -1.0, 0.0
    for s in (1.0, -1.0):
        thr = lim.tan_plus if s > 0.0 else lim.tan_minus
        l0 = -s * a0 - (g + v0) * thr
        l1 = -s * a1 - (g + v1) * thr
        x = -1.0
        if l0 > 0.0:
            x = 0.0
        elif l1 > 0.0:
            x = -l0 / (l1 - l0)
        if x >= 0.0 and (best < 0.0 or x < best):
            best, side = x, s
    return best, side


@jit_inline
def _from_rest(ah, av, has_v, dt, pc, b, lim, progress, theta_out):
    """Advance a body at rest to its uplift, the loss of contact or the piece's end; False where the scene ends."""
    pr = progress[0]
    t, t0, t1 = pr.t, pc.t0, pc.t1
    if pc.k >= ah.shape[0] - 1:
        pr.t = lim.t_rec
        return False
    aa0, vv0 = pc.a0 + pc.sa * (t - t0), pc.v0 + pc.sv * (t - t0)
    aa1, vv1 = pc.a0 + pc.sa * (t1 - t0), pc.v0 + pc.sv * (t1 - t0)
    xf = flight_fraction(vv0, vv1, b.g) if has_v else -1.0
    x, side = _lift_fraction(aa0, aa1, vv0, vv1, b.g, lim)
    if xf >= 0.0 and (x < 0.0 or x >= xf):
        pr.t = t + xf * (t1 - t)
        pr.status |= STATUS_GROUND_FLIGHT
        return False
    if x >= 0.0:
        t_up = t + x * (t1 - t)
        pr.n_same = events_at_instant_compiled(t_up, pr.t_event, pr.n_same)
        pr.t_event = t_up
        if pr.n_same > MAX_EVENTS_AT_ONE_INSTANT:     # tie rule 6: held at rest to the next sample
            pr.status |= STATUS_TIE_HOLD
            pr.n_same = 0
            x = -1.0
    if x < 0.0:
        pr.t = t1
    else:
        pr.t = t + x * (t1 - t)
        pr.pivot, pr.theta, pr.omega, pr.mode = side, 0.0, 0.0, ROCK
        pr.n_uplifts += 1
        pr.n_events += 1
        pr.h = min(lim.h_max, dt) * UPLIFT_STEP_FRACTION
    while pr.out_k < theta_out.shape[0] and pr.out_k * dt <= pr.t:
        theta_out[pr.out_k] = 0.0
        pr.out_k += 1
    return True


@jit_inline
def _note_peak(progress, value):
    pr = progress[0]
    if pr.pivot > 0.0:
        pr.peak_plus = max(pr.peak_plus, value)
    else:
        pr.peak_minus = max(pr.peak_minus, value)


@jit_inline
def _impact(hh, x, dt, pc, b, control, lim, progress, theta_out):
    """The impact inside an accepted step: located, omega times the side's ratio, the pivot switched; a slow
    rebound, the event cap or tie rule 6 ends in rest."""
    pr = progress[0]
    t, th, om, s = pr.t, pr.theta, pr.omega, pr.pivot
    alpha, _r, p2, ratio = side_of(b, s)
    # bool(False): the rocking kernel's version of the step (pipeline.compiled)
    hs, ths, oms = locate_impact(t, th, om, hh, x, pc, s, p2, alpha, b.g, bool(False))
    peak = max(abs(th), abs(ths))
    if s * om > 0.0 and s * oms < 0.0:
        peak = max(peak, hermite_peak(th, om, ths, oms, hs))
    _note_peak(progress, peak)
    t = t + hs
    pr.out_k = fill_hermite(theta_out, pr.out_k, dt, t - hs, hs, th, om, ths, oms, t)
    pr.n_impacts += 1
    pr.n_events += 1
    pr.t, pr.theta, pr.omega, pr.pivot = t, 0.0, ratio * oms, -s
    pr.n_same = events_at_instant_compiled(t, pr.t_event, pr.n_same)
    pr.t_event = t
    if abs(pr.omega) < lim.rest_omega or pr.n_events >= control.max_events:
        if pr.n_events >= control.max_events:
            pr.status |= STATUS_CHATTER
        pr.omega, pr.mode = 0.0, REST
    if pr.n_same > MAX_EVENTS_AT_ONE_INSTANT:
        pr.status |= STATUS_TIE_HOLD
        pr.n_same = 0
        pr.omega, pr.mode, pr.t = 0.0, REST, pc.t1
    pr.h = max(hh, MIN_STEP_AFTER_IMPACT_P / math.sqrt(p2))


@jit_inline
def _rocking_step(has_v, dt, pc, b, control, lim, progress, theta_out):
    """One adaptive step with its events; False where the scene ends (overturned, contact lost, step cap)."""
    pr = progress[0]
    pr.n_steps += 1
    if pr.n_steps > lim.max_steps:
        pr.status |= STATUS_STEP_CAP
        return False
    t, th, om, s = pr.t, pr.theta, pr.omega, pr.pivot
    alpha, r, p2, _ratio = side_of(b, s)
    min_step = max(MIN_STEP_S, min_advance_compiled(t))
    hh = min(pr.h, lim.h_max, pc.t1 - t)
    if hh <= min_step:
        hh = pc.t1 - t
    th1, om1, et, eo, acc1, sin1, cos1 = dopri_step(t, th, om, hh, pc, s, p2, alpha, b.g, bool(False))
    err = step_error(th, om, th1, om1, et, eo, lim, control.rtol)
    if err > 1.0 and hh > min_step:
        reject(hh, err, min_step, progress)
        return True
    if has_v and b.g + pc.v0 + pc.sv * (t + hh - pc.t0) <= 0.0:
        pr.status |= STATUS_GROUND_FLIGHT
        return False
    x = _impact_fraction(th, om, th1, om1, hh, s)
    if x >= 0.0:
        _impact(hh, x, dt, pc, b, control, lim, progress, theta_out)
        return True
    if abs(th1) >= HALF_PI:
        pr.t_overturn = t + (HALF_PI - abs(th)) / max(abs(th1) - abs(th), TINY) * hh
        pr.overturned, pr.mode, pr.t = True, OVERTURNED, pr.t_overturn
        _note_peak(progress, HALF_PI)
        return False
    if abs(th1) < alpha:
        te = t + hh
        demand, lifted = pivot_demand(sin1, cos1, om1, acc1, r, pc.a0 + pc.sa * (te - pc.t0),
                                      pc.v0 + pc.sv * (te - pc.t0), b.g)
        if lifted:
            pr.status |= STATUS_LIFTOFF
        else:
            pr.friction_max = max(pr.friction_max, demand)
    peak = max(abs(th), abs(th1))
    if om * om1 < 0.0:
        peak = max(peak, hermite_peak(th, om, th1, om1, hh))
    _note_peak(progress, peak)
    pr.out_k = fill_hermite(theta_out, pr.out_k, dt, t, hh, th, om, th1, om1, t + hh)
    pr.t, pr.theta, pr.omega = t + hh, th1, om1
    pr.h = _next_step(hh, err, dt, lim.h_max)
    return True


@jit
def _energy(b, s, th, om):
    """(E, the side's barrier g R_s, I_s) per unit mass on side ``s`` at (theta, omega)."""
    alpha, r, p2, _ratio = side_of(b, s)
    inertia = b.g * r / p2
    return 0.5 * inertia * om * om + b.g * r * math.cos(alpha - abs(th)), b.g * r, inertia


@jit
def _after_record(b, lim, progress):
    """The free motion after the record, impact by impact by its energy (see the module)."""
    pr = progress[0]
    if pr.overturned or pr.mode != ROCK:
        return
    s, th, om = pr.pivot, pr.theta, pr.omega
    alpha = side_of(b, s)[0]
    outward = th * om > 0.0 or (th == 0.0 and om * s > 0.0)
    E, top, inertia = _energy(b, s, th, om)
    floor = b.g * min(b.R_plus, b.R_minus)
    if (abs(th) >= alpha and (outward or E <= top)) or (outward and E >= top):
        pr.overturned, pr.t_overturn, pr.mode = True, pr.t, OVERTURNED
        _note_peak(progress, HALF_PI)
        return
    for _ in range(MAX_TAIL_IMPACTS):
        if E < top:
            _note_peak(progress, side_of(b, pr.pivot)[0] - math.acos(min(E / top, 1.0)))
        if E < floor:
            return
        kinetic = E - b.g * b.z_g                   # at theta = 0, where every side's G is at z_G
        ratio = side_of(b, pr.pivot)[3]
        om0 = math.sqrt(max(2.0 * kinetic / inertia, 0.0))
        pr.pivot = -pr.pivot
        pr.n_impacts += 1
        E, top, inertia = _energy(b, pr.pivot, 0.0, ratio * om0)
        if ratio * om0 < lim.rest_omega:
            return
        if E >= top:
            pr.overturned, pr.t_overturn, pr.mode = True, pr.t, OVERTURNED
            _note_peak(progress, HALF_PI)
            return
    pr.status |= STATUS_TAIL_CAP


@jit
def rock_two_sided_compiled(ah, av, dt, b, control, theta_out):
    """Rock a two-sided body from rest under a sampled ground motion (the module says how).

    Parameters
    ----------
    ah, av : ndarray
        Horizontal (along +x) and vertical (up) ground acceleration at t = k dt [m s-2]; ``av`` empty: none.
    dt : float
        Sampling interval [s].
    b : TwoSidedBlock
    control : StepControl
        Tolerances (``rtol``, ``atol`` as fractions of the smaller alpha), ``rest_ratio``, ``max_step_p`` (of
        1 / the larger p) and ``max_events``; ``chatter`` is not read (every flight is stepped).
    theta_out : ndarray
        theta at the samples [rad], filled while the record lasts (empty: none kept).

    Returns
    -------
    TwoSidedOutcome
    """
    n = ah.shape[0]
    has_v = av.shape[0] == n
    lim = _limits(b, control, n, dt)
    progress = new_progress()
    pr = progress[0]
    pr.pivot, pr.mode, pr.t_overturn, pr.t_event = 1.0, REST, math.nan, -math.inf
    pr.h = min(lim.h_max, dt) * FIRST_STEP_FRACTION
    while progress[0].t < lim.t_rec:
        pc = _piece(ah, av, has_v, dt, progress[0].t, lim.t_rec)
        if progress[0].mode == REST:
            if not _from_rest(ah, av, has_v, dt, pc, b, lim, progress, theta_out):
                break
        elif not _rocking_step(has_v, dt, pc, b, control, lim, progress, theta_out):
            break
    if not progress[0].status & (STATUS_GROUND_FLIGHT | STATUS_STEP_CAP):
        _after_record(b, lim, progress)
    pr = progress[0]
    return TwoSidedOutcome(overturned=pr.overturned, t_overturn=pr.t_overturn, theta_max_plus=pr.peak_plus,
                           theta_max_minus=pr.peak_minus, n_impacts=pr.n_impacts, n_uplifts=pr.n_uplifts,
                           friction_max=pr.friction_max, status=pr.status)


def rock_two_sided_fast(ah, dt_s: float, body: TwoSided, *, av=None, restitution_factor: float = 1.0,
                        control: StepControl | None = None, g_ms2: float = G,
                        theta_out: np.ndarray | None = None) -> TwoSidedOutcome:
    """:func:`rock_two_sided_compiled` from Python: ``body`` by its :class:`~.asymmetric.TwoSided` geometry,
    ``av`` None for no vertical, ``control`` None for the simulator's defaults."""
    if control is None:
        from ..settings import SimulationConfig
        from ..simulate import step_control
        control = step_control(SimulationConfig())
    a = np.ascontiguousarray(ah, dtype=float)
    v = np.zeros(0) if av is None else np.ascontiguousarray(av, dtype=float)
    out = np.zeros(0) if theta_out is None else theta_out
    return rock_two_sided_compiled(a, v, float(dt_s), two_sided_block(body, restitution_factor=restitution_factor,
                                                                       g_ms2=g_ms2), control, out)
