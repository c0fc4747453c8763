"""The time history of n stacked blocks rocking under a record (the equations of :mod:`.n_block`).

The ground is linear between samples. From rest the first joint to open does so at the exact crossing of its
lift-off condition on that piece (at rest the condition is linear in the ground's acceleration). While a joint is
open the motion is stepped by the Dormand & Prince (1980) pair with error control, steps never crossing a sample; an
event inside a step (a joint's rotation reaching 0: an impact; a shut joint's lift-off; a fall) is located on the
step's length to :data:`EVENT_TIME_TOL_S`, an impact by the Illinois method started at the root of the step's Hermite
cubic, any other event by bisection. An impact whose rebound is slower than :data:`REST_RATIO` p alpha (the joint's
scales) shuts the joint (a plastic stop). Block k falls when its rotation, or its rotation on the block below,
reaches pi/2; the blocks above it fall with it. After the record the free motion is followed until every joint is
shut or a block falls, for at most :data:`TAIL_S`.

The run may start from a moving state (the blocks left standing when those above them fell,
:mod:`.n_block_verdicts`). The model holds while no joint slides and no block leaves its support in flight (its
friction demands are kept, for the caller to flag; given the blocks' friction, the run stops where a joint would
slip, for the caller to follow it with the stack's contact model, :mod:`.stack_contact`); for two blocks it is the
two-block run (:mod:`.two_block_run`), which the tests compare.

References
----------
Dormand, J. R. & Prince, P. J. (1980). A family of embedded Runge-Kutta formulae. J. Comput. Appl. Math. 6(1),
19-26.
Dowell, M. & Jarratt, P. (1971). A modified regula falsi method for computing the root of an equation. BIT 11(2),
168-174.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from ..compiled import filled_like, jit, jit_lean, tuple_with
from ..constants import G
from ..errors import ParameterError
from ..rocking.codes import STATUS_FRICTION, STATUS_GROUND_FLIGHT
from ..rocking.numerics.rk import DOPRI54, next_step, rejected_step, rk_step
from .n_block import (
    MAX_BODIES,
    SHUT,
    NBlock,
    absolute,
    accelerations,
    demands,
    may_open,
    opening,
    part_centre,
    projected_rates,
    relative,
    scales,
    tipping_angles,
    tuple_set,
    work,
)
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

#: Stacks whose run set-up (:func:`_setup`) is kept [-]
SETUPS_KEPT = 64
#: No block falls (:attr:`NBlockOutcome.falls`)
FALLS_NONE = -1
#: The events a state can be past (:func:`_event`)
EV_NONE, EV_IMPACT, EV_FALL, EV_LIFT = 0, 1, 3, 4


class NBlockOutcome(NamedTuple):
    """A run's result.

    Attributes
    ----------
    falls : int
        the lowest block that falls (the blocks above it fall with it), or :data:`FALLS_NONE`
    t_fall_s : float
        when [s] (NaN when nothing falls)
    peak_psi_rad : tuple of float
        each joint's largest |psi_k| at the steps' ends [rad]
    impacts, liftoffs : int
        impacts at any joint; openings of a shut joint
    modes : int
        bit k: joint k opened
    status : int
        :class:`~pipeline.rocking.codes.Status` bits: ground_flight (g + a_v reached 0: not followed), step_cap,
        event_cap, tail_cap (the run ended there without a verdict unless a block had fallen)
    final : tuple of float
        the state where the run ended (:mod:`.n_block`'s)
    demand : tuple of float
        each joint's largest friction demand |F_t| / F_n [-], at rest (at the samples) and in motion (at the steps'
        ends and events, inside the joints' smaller tipping angles), to the run's end or first fall; inf where a face
        would pull
    steps : int
        steps tried, accepted or not, locating events included
    t_end_s : float
        where the run ended [s]: the fall, the start of the ground's piece that falls faster than gravity, a cap, or
        rest after the record
    """

    falls: int
    t_fall_s: float
    peak_psi_rad: tuple
    impacts: int
    liftoffs: int
    modes: int
    status: int
    final: tuple
    demand: tuple
    steps: int = 0
    t_end_s: float = math.nan


class _Tol(NamedTuple):
    """The run's error scales (alpha and p alpha of the stack) and each joint's smaller tipping angle at rest and
    rest threshold [rad, rad s-1]."""

    alpha: float
    rate: float
    tip: tuple
    rest: tuple


@jit_lean
def _rhs(t, y, args):
    """The state's derivative (a tuple) in the mode ``args`` = (nb, js, piece)."""
    nb, js, piece, wk = args
    ah, av = ground_on(piece, t)
    accelerations(nb, y, js, ah, av, wk)
    relative(wk.qdd, nb.n, wk)
    rel = wk.rel
    out = y
    for k in range(MAX_BODIES):
        out = tuple_with(out, k, y[MAX_BODIES + k])
        out = tuple_with(out, MAX_BODIES + k, rel[k])
    return out, 0.0


@jit_lean
def _event(nb, y, js, piece, t, wk):
    """The event the state ``y`` at ``t`` is past, and its joint: a fall (the lowest block falling), an impact, a
    shut joint lifting off; (:data:`EV_NONE`, -1) for none."""
    absolute(y, nb.n, wk)
    for k in range(nb.n):
        if abs(wk.phi[k]) >= HALF_PI or abs(y[k]) >= HALF_PI:
            return EV_FALL, k
    for k in range(nb.n):
        if js[k] != SHUT and js[k] * y[k] <= 0.0:
            return EV_IMPACT, k
    for k in range(nb.n):
        if js[k] == SHUT:
            ah, av = ground_on(piece, t)
            if may_open(nb, y, js, ah, av, wk):             # one solve; which joint opens, only where one does
                joint, _ = opening(nb, y, js, ah, av, wk)
                if joint >= 0:
                    return EV_LIFT, joint
            break
    return EV_NONE, -1


@jit_lean
def _error_norm(err, y_old, y_new, tol):
    """The step's error over the tolerance (max norm): rotations against alpha, rates against p alpha."""
    worst = 0.0
    for q in range(2 * MAX_BODIES):
        base = tol.alpha if q < MAX_BODIES else tol.rate
        bound = ATOL * base + RTOL * max(abs(y_old[q]), abs(y_new[q]))
        worst = max(worst, abs(err[q]) / bound)
    return worst


@jit_lean
def _peaks(nb, peak, demand, y, js, piece, t, tol, wk):
    """Each joint's largest |psi| and friction demand with the state ``y`` at ``t``; the demands only inside the
    joints' smaller tipping angles (beyond, a body is falling, its demand no longer bearing on whether it falls)."""
    for k in range(nb.n):
        peak[k] = max(peak[k], abs(y[k]))
    inside = True
    for k in range(nb.n):
        inside = inside and abs(y[k]) < tol.tip[k]
    if inside:
        ah, av = ground_on(piece, t)
        demands(nb, y, js, ah, av, wk)
        for k in range(nb.n):
            demand[k] = max(demand[k], wk.d[k])


@jit_lean
def _rest_demand(nb, demand, piece):
    """Each joint's demand at rest, |a_h| / (g + a_v), at the piece's ends (linear between them)."""
    d = max(abs(piece.a0) / (G + piece.v0), abs(piece.a1) / (G + piece.v1))
    for k in range(nb.n):
        demand[k] = max(demand[k], d)


@jit_lean
def _open_bits(js, n):
    """Bit k set for each open joint k of the modes ``js``."""
    bits = 0
    for k in range(n):
        if js[k] != SHUT:
            bits |= 1 << k
    return bits


@jit_lean
def _least(values, n):
    """The least of the first n values."""
    out = math.inf
    for k in range(n):
        out = min(out, values[k])
    return out




@jit_lean
def _rest_piece(nb, ch, cg, mu_rest, demand, piece, t):
    """What the resting stack meets first on the piece from t: (REST_SLIPS, the instant, -1, 0), (REST_OPENS, the
    instant, the joint, its corner) or (REST_HOLDS, the piece's end, -1, 0); the piece's demands where it rests or
    slips on it."""
    t_open, joint, corner = _opening_at_rest(ch, cg, nb.n, piece, t)
    kind, t_next = rest_choice(t_open, joint >= 0, slip_at_rest(mu_rest, piece, t), piece.t0 + piece.span)
    if kind != REST_OPENS:
        _rest_demand(nb, demand, piece)
        return kind, t_next, -1, 0
    return kind, t_next, joint, corner


@jit_lean
def _slips(nb, mu, wk):
    """A joint's demand in ``wk.d`` (the last :func:`_peaks`) above its friction ``mu``."""
    for k in range(nb.n):
        if wk.d[k] > mu[k]:
            return True
    return False


@jit_lean
def _opening_at_rest(ch, cg, n, piece, t):
    """The first instant in [t, piece's end] where a joint of the resting stack opens: (t_open, joint, corner), or
    (NaN, -1, 0) (:func:`.stepping.first_crossing` on :func:`rest_lift`'s conditions, rows 2k and 2k + 1 for joint
    k's corners +1 and -1)."""
    t_open, cand = first_crossing(ch, cg, 2 * n, piece, t)
    if cand < 0:
        return math.nan, -1, 0
    return t_open, cand // 2, (1 if cand % 2 == 0 else -1)


def rest_lift(nb: NBlock) -> tuple[np.ndarray, np.ndarray]:
    """At rest, each joint's lift-off condition on each corner as ch a_h + cg (g + a_v) > 0 (rows 2k for corner +1,
    2k + 1 for -1): the statics of the interface, the stack at rest being one rigid body (the part above joint k
    tips about the corner its resultant passes, where a_h / (g + a_v) falls below (x_G - hi) / z_G or rises above
    (x_G - lo) / z_G, (x_G, z_G) its centre of mass over the joint's support [lo, hi]: Housner's bound
    -tan alpha, tan alpha for one block). The sign of s psi_k'' were joint k released on corner s is the sign of
    this condition (tested away from the bound); stated by the statics, a ground held at a bound of
    :func:`.stack.uplift_ratios` does not open the joint (tie rule 2; tested on three stacks), whatever the rounding
    of the equations of motion."""
    ch, cg = np.zeros(2 * nb.n), np.zeros(2 * nb.n)
    for k in range(nb.n):
        xg, zg = part_centre(nb, k)
        ch[2 * k], cg[2 * k] = -1.0, (xg - nb.hi[k]) / zg
        ch[2 * k + 1], cg[2 * k + 1] = 1.0, -(xg - nb.lo[k]) / zg
    return ch, cg


@jit_lean
def _all_shut(js, n):
    for k in range(n):
        if js[k] != SHUT:
            return False
    return True


@jit_lean
def _keep(hist, t, t1, dt, y, n):
    """Where ``t`` [s] is the piece's end ``t1`` (a sample), each joint's psi [rad] there into ``hist`` (n x samples;
    n x 0: no history kept)."""
    k = int(t / dt + 0.5)
    if t == t1 and hist.shape[1] > 0 and 0 <= k < hist.shape[1]:
        for j in range(n):
            hist[j, k] = y[j]


@jit_lean
def _locate(nb, y, f, js, piece, t, hh, y_end, f_end, wk):
    """An event inside the step of ``hh`` [s] from (t, y) that ended at ``y_end``: an impact alone at the step's end
    by the Illinois method on the joint's rotation (:func:`_impact_root`), else, or where that finds another event
    first, the step's length bisected to :data:`EVENT_TIME_TOL_S`. Returns the length reaching the event, the state
    there and the steps tried."""
    kind, joint = _event(nb, y_end, js, piece, t + hh, wk)
    tries = 0
    if kind == EV_IMPACT:
        ok, hi, y_hi, tries = _impact_root(nb, y, f, js, piece, t, hh, y_end, f_end, joint, wk)
        if ok:
            return hi, y_hi, tries
    lo, hi, y_hi = 0.0, hh, y_end
    while hi - lo > EVENT_TIME_TOL_S:
        mid = 0.5 * (lo + hi)
        trial = rk_step(_rhs, (nb, js, piece, wk), t, y, f, mid, DOPRI54).y
        tries += 1
        if _event(nb, trial, js, piece, t + mid, wk)[0] != EV_NONE:
            hi, y_hi = mid, trial
        else:
            lo = mid
    return hi, y_hi, tries


@jit_lean
def _impact_root(nb, y, f, js, piece, t, hh, y_end, f_end, joint, wk):
    """The step's length at which ``joint``'s rotation reaches 0 (:func:`.stepping.impact_root` on its corner times
    its rotation). Returns (ok, the length past the root, the state there, the steps tried); ok is False where the
    bracket's near end is past another event, or the method did not converge (the caller then bisects)."""
    weights = tuple_with(filled_like(0.0, y), joint, float(js[joint]))
    converged, lo, y_lo, hi, y_hi, tries = impact_root(_rhs, (nb, js, piece, wk), t, y, f, hh, y_end, f_end,
                                                              weights)
    ok = converged and _event(nb, y_lo, js, piece, t + lo, wk)[0] == EV_NONE
    return ok, hi, y_hi, tries


@jit_lean
def _with_rates(y, qd, n):
    """``y`` with its rates the joints' relative rates of the absolute rates ``qd``."""
    below = 0.0
    for k in range(n):
        y = tuple_with(y, MAX_BODIES + k, qd[k] - below)
        below = qd[k]
    return y


@jit_lean
def _impact(nb, y, js, joint, tol, wk):
    """The impact at ``joint``: its rotation set to 0, its corner changed, the rates projected
    (:func:`.n_block.projected_rates`); a rebound below its rest threshold shuts it."""
    y = tuple_with(y, joint, 0.0)
    after = tuple_set(js, joint, -js[joint])
    projected_rates(nb, y, js, after, wk)
    y = _with_rates(y, wk.qdd, nb.n)
    if after[joint] * y[MAX_BODIES + joint] <= tol.rest[joint]:
        shut = tuple_set(after, joint, SHUT)
        projected_rates(nb, y, after, shut, wk)
        return _with_rates(y, wk.qdd, nb.n), shut
    return y, after


@jit_lean
def _open(nb, y, js, piece, t, wk):
    """Open the shut joint whose lift-off condition holds at ``t`` on its corner."""
    ah, av = ground_on(piece, t)
    joint, corner = opening(nb, y, js, ah, av, wk)
    return js if joint < 0 else tuple_set(js, joint, corner)


@jit_lean
def _start_modes(y, n):
    """The joints' states of a start: open on the side its rotation (or, at 0, its rate) points; shut at 0 and 0."""
    js = (SHUT, SHUT, SHUT, SHUT, SHUT)
    for k in range(n):
        psi, rate = y[k], y[MAX_BODIES + k]
        if psi != 0.0 or rate != 0.0:
            js = tuple_set(js, k, 1 if (psi > 0.0 or (psi == 0.0 and rate > 0.0)) else -1)
    return js


@jit
def _run(nb, ch, cg, ah, av, dt, tol, h_max, hist, y, t, wk, mu):
    """The run of :func:`simulate_n_block` from the state ``y`` at ``t`` [SI units]."""
    return _run_loop(nb, ch, cg, ah, av, dt, tol, h_max, hist, y, t, wk, mu, np.zeros(MAX_BODIES), np.zeros(MAX_BODIES))


@jit_lean
def _run_loop(nb, ch, cg, ah, av, dt, tol, h_max, hist, y, t, wk, mu, peak, demand):
    """:func:`_run`'s loop on the peaks' and demands' arrays it made."""
    t_rec = (ah.shape[0] - 2) * dt + dt           # the last piece's end, as _piece_at computes it
    tail_end = t_rec + TAIL_S
    js = _start_modes(y, nb.n)
    mu_rest, h = _least(mu, nb.n), h_max * FIRST_STEP_FRACTION
    impacts, liftoffs, modes, status, events, steps = 0, 0, 0, 0, 0, 0
    falls, t_fall = FALLS_NONE, math.nan
    f, fresh = y, True
    while True:
        capped = caps(steps, events, t, tail_end)
        if capped:
            status |= capped
            break
        modes |= _open_bits(js, nb.n)
        piece = piece_at(ah, av, dt, t, t_rec, tail_end)
        if G + piece.v0 <= 0.0 or G + piece.v1 <= 0.0:
            status |= STATUS_GROUND_FLIGHT
            break
        t1 = piece.t0 + piece.span
        if _all_shut(js, nb.n):
            if t >= t_rec:
                break                               # at rest after the record: stands
            kind, t_next, joint, corner = _rest_piece(nb, ch, cg, mu_rest, demand, piece, t)
            if kind == REST_SLIPS:
                t, status = t_next, status | STATUS_FRICTION      # a joint slips first: the caller follows it
                break
            if kind == REST_HOLDS:
                events += 1 if t1 <= t else 0       # no advance (never met): counted, so that the run ends
                t = t1
                _keep(hist, t, t1, dt, y, nb.n)
                continue
            t = t_next
            js = tuple_set(js, joint, corner)
            liftoffs, events, fresh = liftoffs + 1, events + 1, True
            h = h_max * FIRST_STEP_FRACTION
            continue
        if fresh:
            f, fresh = _rhs(t, y, (nb, js, piece, wk))[0], False
            if _event(nb, y, js, piece, t, wk)[0] == EV_LIFT:     # a joint shut by an impact opens at once
                js = _open(nb, y, js, piece, t, wk)
                liftoffs, events, fresh = liftoffs + 1, events + 1, True
                continue
        hh = min(h, h_max, t1 - t)
        st = rk_step(_rhs, (nb, js, piece, wk), t, y, f, hh, DOPRI54)
        steps += 1
        norm = _error_norm(st.err, y, st.y, tol)
        if not norm <= 1.0:
            h = rejected_step(hh, norm)
            continue
        kind, _ = _event(nb, st.y, js, piece, t + hh, wk)
        if kind == EV_NONE:
            t_new = t1 if hh == t1 - t else t + hh
            _peaks(nb, peak, demand, st.y, js, piece, t_new, tol, wk)
            if _slips(nb, mu, wk):
                status |= STATUS_FRICTION                   # from the step's start the caller follows the slip
                break
            t, y, f = t_new, st.y, st.f
            _keep(hist, t, t1, dt, y, nb.n)
            h = next_step(hh, norm)
            continue
        hi, y, tries = _locate(nb, y, f, js, piece, t, hh, st.y, st.f, wk)
        steps += tries
        kind, joint = _event(nb, y, js, piece, t + hi, wk)
        t += hi
        _peaks(nb, peak, demand, y, js, piece, t, tol, wk)
        events, fresh = events + 1, True
        h = max(hi, h_max * FIRST_STEP_FRACTION)
        if kind == EV_FALL:
            falls, t_fall = joint, t
            break
        if kind == EV_LIFT:
            js = _open(nb, y, js, piece, t, wk)
            liftoffs += 1
        elif kind == EV_IMPACT:
            y, js = _impact(nb, y, js, joint, tol, wk)
            impacts += 1
    return NBlockOutcome(falls, t_fall, (peak[0], peak[1], peak[2], peak[3], peak[4]), impacts, liftoffs, modes,
                         status, y, (demand[0], demand[1], demand[2], demand[3], demand[4]), steps, t)


def run_tolerances(nb: NBlock, rest_ratio: float = REST_RATIO) -> tuple[_Tol, float]:
    """The run's :class:`_Tol` and its largest step [s]."""
    sc = scales(nb)
    tips = tipping_angles(nb)
    alpha, p = min(sc.alpha), max(sc.p)
    pad = (math.inf,) * (MAX_BODIES - nb.n)
    tol = _Tol(alpha, p * alpha, tuple(min(t) for t in tips) + pad,
               tuple(rest_ratio * a * q for a, q in zip(sc.alpha, sc.p)) + pad)
    return tol, MAX_STEP_P / p


@lru_cache(maxsize=SETUPS_KEPT)
def _setup(nb: NBlock, rest_ratio: float) -> tuple[_Tol, float, np.ndarray, np.ndarray]:
    """A stack's tolerances, largest step and lift-off conditions (:func:`run_tolerances`, :func:`rest_lift`), made
    once per stack: a stack slipping from rest runs hundreds of short runs (the arrays are only read by the run)."""
    tol, h_max = run_tolerances(nb, rest_ratio)
    ch, cg = rest_lift(nb)
    return tol, h_max, ch, cg


def simulate_n_block(nb: NBlock, ah_ms2: np.ndarray, dt_s: float, *, av_ms2: np.ndarray | None = None,
                     rest_ratio: float = REST_RATIO, history: np.ndarray | None = None,
                     start: tuple | None = None, t0_s: float = 0.0, stop_mu: tuple | None = None) -> NBlockOutcome:
    """The stack ``nb`` under the ground acceleration ``ah_ms2`` [m s-2] (samples ``dt_s`` [s] apart, the vertical
    ``av_ms2`` [m s-2] when given), from rest at the record's start (or from the state ``start`` at ``t0_s`` [s]) to
    rest or a fall after its end; an impact whose rebound is below ``rest_ratio`` p alpha [-] (each joint's scales)
    shuts its joint. ``history``: an array (n, samples) that receives each joint's psi [rad] at each sample the run
    reaches. ``stop_mu``: each block's friction at its base [-]; the run then stops (status ``friction``) where a
    joint would slip: at rest at the instant the ground's |a_h| / (g + a_v) passes the smallest, in motion at the
    start of the step at whose end a joint's demand passes its own (a face that would pull included).

    Raises
    ------
    ParameterError
        a series not 1-D, shorter than 2 samples or not finite (naming the first bad sample), the vertical's length
        not the horizontal's, ``dt_s`` not positive, or ``history`` of the wrong shape
    """
    ah, av = ground_series(ah_ms2, av_ms2, dt_s)
    hist = np.zeros((nb.n, 0)) if history is None else history
    if hist.shape not in ((nb.n, 0), (nb.n, ah.shape[0])):
        raise ParameterError(f"history: shape {hist.shape}, expected ({nb.n}, {ah.shape[0]}), one column a sample")
    tol, h_max, ch, cg = _setup(nb, rest_ratio)
    y = (0.0,) * (2 * MAX_BODIES) if start is None else tuple(float(v) for v in start)
    mu = (math.inf,) * MAX_BODIES if stop_mu is None else tuple(float(x) for x in stop_mu[:nb.n]) + (
        math.inf,) * (MAX_BODIES - nb.n)
    return _run(nb, ch, cg, ah, av, float(dt_s), tol, h_max, hist, y, float(t0_s), work(), mu)
