"""The time history of two stacked blocks rocking under a record (the equations of :mod:`.two_block`).

The ground is linear between samples. From rest the first joint to open does so at the exact crossing of its
lift-off condition on that piece (at rest the condition is linear in the ground's acceleration). While a joint is
open the motion is stepped by the Dormand & Prince (1980) pair with error control, steps never crossing a sample;
an event inside a step (a joint's rotation reaching 0: an impact; a shut joint's lift-off; a fall) is located on the
step's length to :data:`EVENT_TIME_TOL_S`, an impact by the Illinois method started at the root of the step's
Hermite cubic, any other event by bisection. An impact whose rebound is slower than :data:`REST_RATIO` p alpha shuts
the joint (a plastic stop). A block falls when its rotation, or the upper block's rotation on the lower, reaches
pi/2. After the record the free motion is followed until both joints are shut or a block falls, for at most
:data:`TAIL_S`.

The model holds while neither joint slides and no block leaves its support in flight; within its tolerances it
solves the equations of :mod:`.two_block` (against an independent solution: docs/validation.md, "Assemblies").

References
----------
Dormand, J. R. & Prince, P. J. (1980). A family of embedded Runge-Kutta formulae. J. Comput. Appl. Math. 6(1),
19-26.
Dowell, M. & Jarratt, P. (1971). A modified regula falsi method for computing the root of an equation. BIT 11(2),
168-174.
Psycharis, I. N. (1990). Dynamic behaviour of rocking two-block assemblies. Earthquake Engineering & Structural
Dynamics 19(4), 555-575.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..compiled import jit
from ..constants import G
from ..errors import ParameterError
from ..rocking.codes import STATUS_FRICTION, STATUS_GROUND_FLIGHT
from ..rocking.numerics.rk import DOPRI54, next_step, rejected_step, rk_step
from .stepping import (
    ATOL,
    EVENT_TIME_TOL_S,
    FIRST_STEP_FRACTION,
    HALF_PI,
    MAX_STEP_P,
    REST_HOLDS,
    REST_OPENS,
    REST_RATIO,
    REST_SLIPS,
    RTOL,
    TAIL_S,
    caps,
    first_crossing,
    ground_on,
    ground_series,
    impact_root,
    piece_at,
    rest_choice,
    slip_at_rest,
)
from .two_block import (
    SHUT,
    Motion,
    TwoBlock,
    accelerations,
    centre_of_mass,
    demands,
    opening,
    projected_rates,
    tipping_angles,
)

#: What falls: nothing, the upper block (off the lower one), the whole stack (the lower block on the ground).
FALLS_NONE, FALLS_TOP, FALLS_STACK = 0, 1, 2
#: Bits of :attr:`TwoBlockOutcome.modes`: the joints that opened (on the ground, between the blocks), and both at once.
OPENED_GROUND, OPENED_JOINT, OPENED_BOTH = 1, 2, 4


class TwoBlockOutcome(NamedTuple):
    """A run's result.

    Attributes
    ----------
    falls : int
        :data:`FALLS_NONE`, :data:`FALLS_TOP` or :data:`FALLS_STACK`
    t_fall_s : float
        when [s] (NaN when nothing falls)
    peak_phi1_rad, peak_phi2_rad, peak_psi_rad : float
        the largest |phi_1|, |phi_2| and |phi_2 - phi_1| at the steps' ends [rad]
    impacts, liftoffs : int
        impacts at either joint; openings of a shut joint
    modes : int
        bits :data:`OPENED_GROUND`, :data:`OPENED_JOINT`, :data:`OPENED_BOTH`
    status : int
        :class:`~pipeline.rocking.codes.Status` bits: ground_flight (g + a_v reached 0: not followed), step_cap,
        event_cap, tail_cap (the run ended there without a verdict unless a block had fallen), friction (it ended
        where a joint's demand passed the friction it was given)
    final : Motion
        the state where the run ended
    demand_ground, demand_joint : float
        the largest friction demand |F_t| / F_n at the ground joint and at the blocks' joint [-], at rest (at the
        samples) and in motion (at the steps' ends and events), to the run's end or first fall; inf where a face
        would pull
    t_end_s : float
        where the run ended [s]: the fall, the start of the ground's piece that falls faster than gravity, a cap, a
        slip (at rest, at its instant; in motion, at the start of the step at whose end a joint's demand passes its
        friction), or rest after the record
    """

    falls: int
    t_fall_s: float
    peak_phi1_rad: float
    peak_phi2_rad: float
    peak_psi_rad: float
    impacts: int
    liftoffs: int
    modes: int
    status: int
    final: Motion
    demand_ground: float = 0.0
    demand_joint: float = 0.0
    t_end_s: float = math.nan


class Scales(NamedTuple):
    """Each joint's rocking scales at rest on its + corner: the part above it rocking as one (alpha [rad], p [rad
    s-1]); they set the tolerances and the rest threshold."""

    alpha1: float
    p1: float
    alpha2: float
    p2: float


def scales(tb: TwoBlock) -> Scales:
    """The :class:`Scales` of ``tb``."""
    xg, zg = centre_of_mass(tb)
    (alpha1, _), (alpha2, _) = tipping_angles(tb)
    r1 = math.hypot(tb.b1 - xg, zg)
    i_o1 = (tb.i1 + tb.m1 * (tb.b1 ** 2 + tb.h1 ** 2)
            + tb.i2 + tb.m2 * ((tb.b1 - tb.offset) ** 2 + (2 * tb.h1 + tb.h2) ** 2))
    r2 = math.hypot(tb.right - tb.offset, tb.h2)
    i_o2 = tb.i2 + tb.m2 * r2 * r2
    return Scales(alpha1, math.sqrt((tb.m1 + tb.m2) * G * r1 / i_o1), alpha2, math.sqrt(tb.m2 * G * r2 / i_o2))


class Peaks(NamedTuple):
    """The largest |phi_1|, |phi_2| and |phi_2 - phi_1| so far [rad], and the largest friction demand at the ground
    joint and at the blocks' joint [-] (:func:`.two_block.demands`)."""

    phi1: float
    phi2: float
    psi: float
    demand1: float
    demand2: float


@jit
def _peaks(tb, peaks, y, j1, j2, piece, t, sc):
    """``peaks`` with the state ``y`` (phi_1, phi_2, rates) in the mode (j1, j2) at ``t`` on the ground's piece, and
    the state's demands at both joints; the demands only inside the joints' smaller tipping angles at rest
    (``sc[2]``, ``sc[3]``; 0 beyond): beyond, a body is falling, its demand no longer bearing on whether it falls
    (the rocking kernel's is likewise followed no further)."""
    ah, av = ground_on(piece, t)
    d1, d2 = 0.0, 0.0
    if abs(y[0]) < sc[2] and abs(y[1] - y[0]) < sc[3]:
        d1, d2 = demands(tb, _motion(y), j1, j2, ah, av)
    return Peaks(max(peaks.phi1, abs(y[0])), max(peaks.phi2, abs(y[1])), max(peaks.psi, abs(y[1] - y[0])),
                 max(peaks.demand1, d1), max(peaks.demand2, d2)), d1, d2


@jit
def _rest_demand(peaks, piece):
    """``peaks`` with the demand of the stack at rest, |a_h| / (g + a_v) at both joints, at the piece's ends (linear
    between them: the largest ratio is at an end)."""
    d = max(abs(piece.a0) / (G + piece.v0), abs(piece.a1) / (G + piece.v1))
    return Peaks(peaks.phi1, peaks.phi2, peaks.psi, max(peaks.demand1, d), max(peaks.demand2, d))


@jit
def _motion(y):
    """The integrator's state tuple (phi_1, phi_2, rates) as a :class:`.two_block.Motion`."""
    return Motion(y[0], y[1], y[2], y[3])


@jit
def _rhs(t, y, args):
    """The state's derivative (a tuple) in the mode ``args`` = (tb, j1, j2, piece)."""
    tb, j1, j2, piece = args
    ah, av = ground_on(piece, t)
    d1, d2 = accelerations(tb, _motion(y), j1, j2, ah, av)
    return (y[2], y[3], d1, d2), 0.0


class RestLift(NamedTuple):
    """At rest, the lift-off condition of each joint on each corner, s x its rotation's acceleration were it
    released, is a_h ch + (g + a_v) cg (linear: at rest M is constant and f linear in the ground); the four
    candidates in the order (ground, +1), (ground, -1), (joint, +1), (joint, -1) [s-2 m-1 per m s-2]."""

    ch: tuple
    cg: tuple


@jit
def _lift(tb, cand):
    """Candidate ``cand``'s lift-off condition at rest (:class:`RestLift`'s order): (ch, cg), s x the rotation's
    acceleration of the joint released on corner s under a unit a_h, and under a unit g + a_v."""
    rest = Motion(0.0, 0.0, 0.0, 0.0)
    s = 1 if cand % 2 == 0 else -1
    j1, j2 = (s, SHUT) if cand < 2 else (SHUT, s)
    d1h, d2h = accelerations(tb, rest, j1, j2, 1.0, -G)
    d1g, d2g = accelerations(tb, rest, j1, j2, 0.0, 1.0 - G)
    if cand < 2:
        return s * d1h, s * d1g
    return s * (d2h - d1h), s * (d2g - d1g)


@jit
def rest_lift(tb):
    """The :class:`RestLift` of ``tb``, from the accelerations at rest under a unit horizontal and a unit g + a_v."""
    c0, c1, c2, c3 = _lift(tb, 0), _lift(tb, 1), _lift(tb, 2), _lift(tb, 3)
    return RestLift((c0[0], c1[0], c2[0], c3[0]), (c0[1], c1[1], c2[1], c3[1]))


@jit
def _opening_at_rest(lift, piece, t):
    """The first instant in [t, piece's end] where a joint of the resting stack opens: (t_open, joint, corner), or
    (NaN, 0, 0) (:func:`.stepping.first_crossing` on the :class:`RestLift`'s four conditions)."""
    t_open, cand = first_crossing(lift.ch, lift.cg, 4, piece, t)
    if cand < 0:
        return math.nan, 0, 0
    return t_open, (1 if cand < 2 else 2), (1 if cand % 2 == 0 else -1)


@jit
def _event(tb, y, j1, j2, piece, t):
    """The event the state ``y`` at ``t`` is past: 3 a fall, 1 / 2 an impact at the ground / between the blocks, 4 a
    shut joint lifting off; 0 none."""
    psi = y[1] - y[0]
    if abs(y[0]) >= HALF_PI or abs(y[1]) >= HALF_PI or abs(psi) >= HALF_PI:
        return 3
    if j1 != SHUT and j1 * y[0] <= 0.0:
        return 1
    if j2 != SHUT and j2 * psi <= 0.0:
        return 2
    if j1 == SHUT or j2 == SHUT:
        ah, av = ground_on(piece, t)
        joint, _ = opening(tb, _motion(y), j1, j2, ah, av)
        if joint != 0:
            return 4
    return 0


@jit
def _error_norm(err, y_old, y_new, sc):
    """The step's error over the tolerance (max norm): rotations against sc[0] alpha, rates against sc[1] p alpha
    (``sc``: the run's scales, also the joints' smaller tipping angles, sc[2] and sc[3])."""
    worst = 0.0
    for q in range(4):
        base = sc[0] if q < 2 else sc[1]
        tol = ATOL * base + RTOL * max(abs(y_old[q]), abs(y_new[q]))
        worst = max(worst, abs(err[q]) / tol)
    return worst


@jit
def _keep(hist, t, t1, dt, y):
    """Where ``t`` [s] is the piece's end ``t1`` (a sample), the rotations phi_1 and psi = phi_2 - phi_1 [rad] there
    into ``hist`` (2 x n; 2 x 0: no history kept)."""
    k = int(t / dt + 0.5)
    if t == t1 and hist.shape[1] > 0 and 0 <= k < hist.shape[1]:
        hist[0, k] = y[0]
        hist[1, k] = y[1] - y[0]


@jit
def _start_modes(y):
    """The joints' states of a start (phi_1, phi_2, rates): each open on the side its rotation (or, at 0, its rate)
    points; shut at 0 and 0."""
    psi, rate = y[1] - y[0], y[3] - y[2]
    j1 = SHUT if y[0] == 0.0 and y[2] == 0.0 else (1 if (y[0] > 0.0 or (y[0] == 0.0 and y[2] > 0.0)) else -1)
    j2 = SHUT if psi == 0.0 and rate == 0.0 else (1 if (psi > 0.0 or (psi == 0.0 and rate > 0.0)) else -1)
    return j1, j2


@jit
def _rest_piece(lift, mu_rest, piece, t):
    """What the resting stack meets first on the piece from t: (REST_SLIPS, the instant, 0, 0) where its demand
    |a_h| / (g + a_v) passes ``mu_rest`` first, (REST_OPENS, the instant, the joint, its corner), or (REST_HOLDS,
    the piece's end, 0, 0)."""
    t_open, joint, corner = _opening_at_rest(lift, piece, t)
    kind, t_next = rest_choice(t_open, joint != 0, slip_at_rest(mu_rest, piece, t), piece.t0 + piece.span)
    return (kind, t_next, joint, corner) if kind == REST_OPENS else (kind, t_next, 0, 0)


@jit
def _run(tb, lift, ah, av, dt, sc, rest1, rest2, h_max, hist, y, t, stop1, stop2):
    """The run of :func:`simulate_two_block` from ``y`` at ``t`` (its scales, rest thresholds, largest step, history
    ``hist`` (:func:`_keep`) and each joint's friction given) [SI units]."""
    t_rec = (ah.shape[0] - 2) * dt + dt           # the last piece's end, as piece_at computes it
    tail_end = t_rec + TAIL_S
    j1, j2 = _start_modes(y)
    h = h_max * FIRST_STEP_FRACTION
    peaks = Peaks(0.0, 0.0, 0.0, 0.0, 0.0)
    impacts, liftoffs, modes, status, events, steps = 0, 0, 0, 0, 0, 0
    falls, t_fall = FALLS_NONE, math.nan
    f, fresh = y, True                            # f must be evaluated before the next step
    while True:
        capped = caps(steps, events, t, tail_end)
        if capped:
            status |= capped
            break
        modes |= _mode_bits(j1, j2)
        piece = piece_at(ah, av, dt, t, t_rec, tail_end)
        if G + piece.v0 <= 0.0 or G + piece.v1 <= 0.0:
            status |= STATUS_GROUND_FLIGHT
            break
        t1 = piece.t0 + piece.span
        if j1 == SHUT and j2 == SHUT:
            if t >= t_rec:
                break                               # at rest after the record: stands
            kind, t_next, joint, corner = _rest_piece(lift, min(stop1, stop2), piece, t)
            peaks = peaks if kind == REST_OPENS else _rest_demand(peaks, piece)
            if kind == REST_SLIPS:
                t, status = t_next, status | STATUS_FRICTION      # a joint slips first: the caller follows it
                break
            if kind == REST_HOLDS:
                events, t = events + (1 if t1 <= t else 0), t1      # no advance (never met): counted
                _keep(hist, t, t1, dt, y)
                continue
            t = t_next
            j1, j2 = (corner, j2) if joint == 1 else (j1, corner)
            liftoffs, events, fresh, h = liftoffs + 1, events + 1, True, h_max * FIRST_STEP_FRACTION
            continue
        if fresh:
            f, fresh = _rhs(t, y, (tb, j1, j2, piece))[0], False
            if _event(tb, y, j1, j2, piece, t) == 4:    # a joint shut by an impact opens at once
                y, j1, j2 = _open(tb, y, j1, j2, piece, t)
                liftoffs, events, fresh = liftoffs + 1, events + 1, True
                continue
        hh = min(h, h_max, t1 - t)
        st = rk_step(_rhs, (tb, j1, j2, piece), t, y, f, hh, DOPRI54)
        steps += 1
        norm = _error_norm(st.err, y, st.y, sc)
        if not norm <= 1.0:
            h = rejected_step(hh, norm)
            continue
        kind = _event(tb, st.y, j1, j2, piece, t + hh)
        if kind == 0:
            t_new = t1 if hh == t1 - t else t + hh
            peaks, d1, d2 = _peaks(tb, peaks, st.y, j1, j2, piece, t_new, sc)
            if d1 > stop1 or d2 > stop2:
                status |= STATUS_FRICTION           # from the step's start the caller follows the slip
                break
            t, y, f = t_new, st.y, st.f
            _keep(hist, t, t1, dt, y)
            h = next_step(hh, norm)
            continue
        hi, y, tries = _locate(tb, y, f, j1, j2, piece, t, hh, st.y, st.f)
        steps += tries
        kind = _event(tb, y, j1, j2, piece, t + hi)
        t += hi
        peaks = _peaks(tb, peaks, y, j1, j2, piece, t, sc)[0]
        events, fresh = events + 1, True
        h = max(hi, h_max * FIRST_STEP_FRACTION)
        if kind == 3:
            falls, t_fall = (FALLS_STACK if abs(y[0]) >= HALF_PI else FALLS_TOP), t
            break
        if kind == 4:
            y, j1, j2 = _open(tb, y, j1, j2, piece, t)
            liftoffs += 1
        else:
            y, j1, j2 = _impact(tb, y, j1, j2, kind, rest1, rest2)
            impacts += 1
    return TwoBlockOutcome(falls, t_fall, peaks.phi1, peaks.phi2, peaks.psi, impacts, liftoffs, modes, status,
                           _motion(y), peaks.demand1, peaks.demand2, t)


@jit
def _locate(tb, y, f, j1, j2, piece, t, hh, y_end, f_end):
    """An event inside the step of ``hh`` [s] from (t, y) that ended at ``y_end``: an impact alone at the step's end
    by the Illinois method on the joint's rotation (:func:`.stepping.impact_root`), else, or where that finds
    another event first, the step's length bisected to :data:`EVENT_TIME_TOL_S`. Returns the length reaching the
    event, the state there and the steps tried."""
    kind = _event(tb, y_end, j1, j2, piece, t + hh)
    tries = 0
    if kind == 1 or kind == 2:
        weights = (float(j1), 0.0, 0.0, 0.0) if kind == 1 else (-float(j2), float(j2), 0.0, 0.0)
        converged, lo, y_lo, hi, y_hi, tries = impact_root(_rhs, (tb, j1, j2, piece), t, y, f, hh, y_end, f_end,
                                                              weights)
        if converged and _event(tb, y_lo, j1, j2, piece, t + lo) == 0:
            return hi, y_hi, tries
    lo, hi, y_hi = 0.0, hh, y_end
    while hi - lo > EVENT_TIME_TOL_S:
        mid = 0.5 * (lo + hi)
        trial = rk_step(_rhs, (tb, j1, j2, piece), t, y, f, mid, DOPRI54).y
        tries += 1
        if _event(tb, trial, j1, j2, piece, t + mid) != 0:
            hi, y_hi = mid, trial
        else:
            lo = mid
    return hi, y_hi, tries


@jit
def _mode_bits(j1, j2):
    """The :data:`OPENED_GROUND`, :data:`OPENED_JOINT` and :data:`OPENED_BOTH` bits of the joints' states."""
    bits = (OPENED_GROUND if j1 != SHUT else 0) | (OPENED_JOINT if j2 != SHUT else 0)
    return bits | (OPENED_BOTH if j1 != SHUT and j2 != SHUT else 0)


@jit
def _open(tb, y, j1, j2, piece, t):
    """Open the shut joint whose lift-off condition holds at ``t`` on its corner."""
    ah, av = ground_on(piece, t)
    joint, corner = opening(tb, _motion(y), j1, j2, ah, av)
    if joint == 1:
        return y, corner, j2
    if joint == 2:
        return y, j1, corner
    return y, j1, j2


@jit
def _impact(tb, y, j1, j2, joint, rest1, rest2):
    """The impact at ``joint`` (1: the ground, 2: between the blocks): its rotation set to 0, its corner changed,
    the rates projected (:func:`.two_block.projected_rates`); a rebound below the rest threshold shuts it."""
    if joint == 1:
        y = (0.0, 0.0 if j2 == SHUT else y[1], y[2], y[3])
        after = (-j1, j2)
    else:
        y = (y[0], y[0], y[2], y[3])
        after = (j1, -j2)
    w1, w2 = projected_rates(tb, _motion(y), (j1, j2), after)
    y = (y[0], y[1], w1, w2)
    k1, k2 = after
    if joint == 1 and k1 * w1 <= rest1:
        w1, w2 = projected_rates(tb, Motion(y[0], y[1], w1, w2), after, (SHUT, k2))
        return (0.0, y[1], w1, w2), SHUT, k2
    if joint == 2 and k2 * (w2 - w1) <= rest2:
        w1, w2 = projected_rates(tb, Motion(y[0], y[1], w1, w2), after, (k1, SHUT))
        return (y[0], y[0], w1, w2), k1, SHUT
    return y, k1, k2


def simulate_two_block(tb: TwoBlock, ah_ms2: np.ndarray, dt_s: float, *, av_ms2: np.ndarray | None = None,
                       rest_ratio: float = REST_RATIO, history: np.ndarray | None = None,
                       start: Motion | None = None, t0_s: float = 0.0, stop_mu: tuple | None = None) -> TwoBlockOutcome:
    """Two stacked blocks under the ground acceleration ``ah_ms2`` [m s-2] (samples ``dt_s`` [s] apart, the vertical
    ``av_ms2`` [m s-2] when given), from rest at the record's start (or from the state ``start`` at ``t0_s`` [s]) to
    rest or a fall after its end; an impact whose rebound is below ``rest_ratio`` p alpha [-] (each joint's scales,
    :func:`scales`) shuts its joint. ``history``: an array (2, samples) that receives phi_1 and psi = phi_2 - phi_1
    [rad] at each sample the run reaches (left as given after a fall). ``stop_mu``: the friction at the ground joint
    and at the blocks' joint [-]; the run then stops (status ``friction``) where a joint would slip, as
    :func:`.n_block_run.simulate_n_block` does: at rest at the instant the ground's |a_h| / (g + a_v) passes the
    smaller, in motion at the start of the step at whose end a joint's demand passes its own.

    Returns
    -------
    TwoBlockOutcome

    Raises
    ------
    ParameterError
        a series not 1-D, shorter than 2 samples or not finite (naming the first bad sample), the vertical's length
        not the horizontal's, or ``dt_s`` not positive
    """
    ah, av = ground_series(ah_ms2, av_ms2, dt_s)
    s = scales(tb)
    alpha, p = min(s.alpha1, s.alpha2), max(s.p1, s.p2)
    (g1, g2), (k1, k2) = tipping_angles(tb)
    hist = np.zeros((2, 0)) if history is None else history
    if hist.shape not in ((2, 0), (2, ah.shape[0])):
        raise ParameterError(f"history: shape {hist.shape}, expected (2, {ah.shape[0]}), one column a sample")
    stop1, stop2 = (math.inf, math.inf) if stop_mu is None else (float(stop_mu[0]), float(stop_mu[1]))
    y = (0.0, 0.0, 0.0, 0.0) if start is None else tuple(float(v) for v in start)
    return _run(tb, rest_lift(tb), ah, av, float(dt_s), (alpha, p * alpha, min(g1, g2), min(k1, k2)),
                rest_ratio * s.p1 * s.alpha1, rest_ratio * s.p2 * s.alpha2, MAX_STEP_P / p, hist, y, float(t0_s),
                stop1, stop2)
