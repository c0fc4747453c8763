"""What the stacks' runs (:mod:`.two_block_run`, :mod:`.n_block_run`) share: the step control, the ground as linear
pieces between its samples, the caps that end a run, the first instant at which a resting stack's joint opens, and
an impact's instant inside a step (the Illinois method on the joint's rotation).

At rest each joint's lift-off condition on each corner is a linear function of the ground's acceleration,
ch a_h + cg (g + a_v) > 0; the ground being linear on a piece, so is the condition, and its root on the piece is
exact (:func:`first_crossing`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..compiled import jit, jit_inline
from ..constants import G
from ..errors import ParameterError
from ..rocking.codes import STATUS_EVENT_CAP, STATUS_STEP_CAP, STATUS_TAIL_CAP
from ..rocking.numerics.dopri import first_crossing as cubic_crossing
from ..rocking.numerics.rk import DOPRI54, rk_step
from ..rocking.simulate import finite_series

# Step control, named once (as scipy's _ivp names its own)
RTOL = 1e-8                 # relative tolerance of the error control [-]
ATOL = 1e-10                # absolute tolerance as a fraction of alpha (rotations) and p alpha (rates) [-]
MAX_STEP_P = 0.05           # largest step as a fraction of 1 / p [-]
FIRST_STEP_FRACTION = 0.01  # the first step after a start or an event, as a fraction of the largest [-]
EVENT_TIME_TOL_S = 1e-11    # an event located to this width of step [s]
REST_RATIO = 1e-5           # an impact's rebound below REST_RATIO p alpha shuts the joint [-]
TAIL_S = 60.0               # the free motion after the record followed for at most this long [s]
MAX_STEPS = 2_000_000       # steps tried, accepted or not, per run [-]
MAX_EVENTS = 20_000         # impacts and lift-offs per run [-]
MAX_ROOT_TRIES = 60         # steps tried by the Illinois method before an impact falls back to bisection [-]
HALF_PI = 0.5 * math.pi
#: What a resting stack meets first on a piece: nothing, a joint opening, a joint slipping
REST_HOLDS, REST_OPENS, REST_SLIPS = 0, 1, 2


def ground_series(ah_ms2, av_ms2, dt_s: float) -> tuple[np.ndarray, np.ndarray]:
    """A run's ground checked: (a_h, a_v) [m s-2] as contiguous float arrays (a_v empty where not given).

    Raises
    ------
    ParameterError
        a series not 1-D, shorter than 2 samples or not finite (naming the first bad sample), the vertical's length
        not the horizontal's, or ``dt_s`` not positive
    """
    ah = np.asarray(finite_series("horizontal acceleration", ah_ms2))
    av = np.zeros(0) if av_ms2 is None else np.asarray(finite_series("vertical acceleration", av_ms2))
    if av.shape[0] not in (0, ah.shape[0]):
        raise ParameterError(f"vertical acceleration: {av.shape[0]} samples, expected {ah.shape[0]} as the "
                             "horizontal")
    if not (math.isfinite(dt_s) and dt_s > 0):
        raise ParameterError(f"dt_s = {dt_s!r}: expected a positive, finite sampling interval [s]")
    return ah, av


class Piece(NamedTuple):
    """The ground's linear piece [t0, t0 + span]: its ends' horizontal and vertical accelerations [m s-2]."""

    t0: float
    span: float
    a0: float
    a1: float
    v0: float
    v1: float


@jit
def ground_on(piece, t):
    """(a_h, a_v) at t on the piece."""
    x = (t - piece.t0) / piece.span if piece.span > 0.0 else 0.0
    return piece.a0 + (piece.a1 - piece.a0) * x, piece.v0 + (piece.v1 - piece.v0) * x


@jit
def piece_at(ah, av, dt, t, t_rec, tail_end):
    """The piece holding t (the next one when t is on its end); after the record one still piece to the tail's
    end."""
    n = ah.shape[0]
    if t >= t_rec - 1e-12 * dt:
        return Piece(t_rec, tail_end - t_rec, 0.0, 0.0, 0.0, 0.0)
    k = min(int(t / dt + 1e-9), n - 2)
    if k * dt + dt <= t:                            # t on this piece's end as the run computes it: the next one
        k = min(k + 1, n - 2)
    v0 = av[k] if av.shape[0] > 0 else 0.0
    v1 = av[k + 1] if av.shape[0] > 0 else 0.0
    return Piece(k * dt, dt, ah[k], ah[k + 1], v0, v1)


@jit
def caps(steps, events, t, tail_end):
    """The status bit of the cap the run has reached (:data:`MAX_STEPS`, :data:`MAX_EVENTS`, :data:`TAIL_S`), or 0."""
    if steps >= MAX_STEPS:
        return STATUS_STEP_CAP
    if events >= MAX_EVENTS:
        return STATUS_EVENT_CAP
    return STATUS_TAIL_CAP if t >= tail_end * (1.0 - 1e-15) else 0      # the tail piece's end, to an ulp


@jit
def first_crossing(ch, cg, count, piece, t):
    """The first instant in [t, piece's end] where one of the ``count`` lift-off conditions ch a_h + cg (g + a_v)
    turns positive (the first of equal ones): (t_open, its index), or (NaN, -1)."""
    t1 = piece.t0 + piece.span
    ah0, av0 = ground_on(piece, t)
    ah1, av1 = ground_on(piece, t1)
    best_x, best = 2.0, -1
    for cand in range(count):
        i0 = ch[cand] * ah0 + cg[cand] * (G + av0)
        i1 = ch[cand] * ah1 + cg[cand] * (G + av1)
        x = 2.0
        if i0 > 0.0:
            x = 0.0
        elif i1 > 0.0:
            x = -i0 / (i1 - i0)
        if x < best_x:
            best_x, best = x, cand
    if best < 0:
        return math.nan, -1
    return t + best_x * (t1 - t), best


@jit
def slip_at_rest(mu, piece, t):
    """The first instant in [t, piece's end] where the resting stack's demand |a_h| / (g + a_v) passes ``mu`` (the
    smallest of its joints' friction), or NaN: each sign of a_h - mu (g + a_v) is linear on the piece."""
    t1 = piece.t0 + piece.span
    ah0, av0 = ground_on(piece, t)
    ah1, av1 = ground_on(piece, t1)
    first = math.nan
    for sign in (1.0, -1.0):
        f0, f1 = sign * ah0 - mu * (G + av0), sign * ah1 - mu * (G + av1)
        if f0 > 0.0:
            return t
        if f1 > 0.0:
            root = t + (t1 - t) * f0 / (f0 - f1)
            first = root if math.isnan(first) else min(first, root)
    return first


@jit
def rest_choice(t_open, opens, t_slip, t_end):
    """What a resting stack meets first on a piece: (REST_SLIPS, ``t_slip``) where a joint slips (``t_slip`` not
    NaN) no later than one opens (at ``t_open``, where ``opens``), else (REST_OPENS, ``t_open``), or (REST_HOLDS,
    ``t_end``, the piece's end) where nothing happens on it."""
    if t_slip <= t_open or (not opens and not math.isnan(t_slip)):
        return REST_SLIPS, t_slip
    if not opens:
        return REST_HOLDS, t_end
    return REST_OPENS, t_open


@jit_inline
def _along(weights, y):
    """weights . y over the weights that are not 0 (one weight: that term alone, to the bit)."""
    acc = 0.0
    for q in range(len(weights)):
        if weights[q] != 0.0:
            acc += weights[q] * y[q]
    return acc


@jit_inline
def impact_root(rhs, args, t, y, f, hh, y_end, f_end, weights):
    """The length of the step from (t, y) (``f`` its derivative there) at which a joint's signed rotation
    g = ``weights`` . y, positive at the start and at most 0 at ``y_end`` (after ``hh`` [s]), reaches 0, bracketed
    to :data:`EVENT_TIME_TOL_S` by the Illinois method (regula falsi, the end kept twice running having its value
    halved; Dowell & Jarratt 1971), each trial a step of the model ``rhs`` with ``args`` (DOPRI54) from (t, y). The
    first trial is at the root of g's Hermite cubic over the step (g and its rate, ``weights`` . ``f`` and
    ``weights`` . ``f_end``, at both ends: :func:`~pipeline.rocking.numerics.dopri.first_crossing`), where it has
    one; the rest by the method.

    Returns (converged, lo, y_lo, hi, y_hi, tries): the bracket's near end and the state there, its far end (past
    the root) and the state there, and the steps tried; not converged after :data:`MAX_ROOT_TRIES`.

    References
    ----------
    Dowell, M. & Jarratt, P. (1971). A modified regula falsi method for computing the root of an equation. BIT
    11(2), 168-174.
    """
    lo, g_lo, hi, g_hi, y_hi, y_lo = 0.0, _along(weights, y), hh, _along(weights, y_end), y_end, y
    kept, tries = 0, 0
    guess = hh * cubic_crossing(g_lo, _along(weights, f), g_hi, _along(weights, f_end), hh, 1.0)
    while hi - lo > EVENT_TIME_TOL_S and tries < MAX_ROOT_TRIES:
        mid = guess if lo < guess < hi else (hi - g_hi * (hi - lo) / (g_hi - g_lo) if g_hi != g_lo else lo)
        if not lo < mid < hi:
            mid = 0.5 * (lo + hi)
        trial = rk_step(rhs, args, t, y, f, mid, DOPRI54).y
        tries, guess = tries + 1, -1.0
        g = _along(weights, trial)
        if g <= 0.0:
            hi, g_hi, y_hi = mid, g, trial
            if kept == 1:
                g_lo *= 0.5
            kept = 1
        else:
            lo, g_lo, y_lo = mid, g, trial
            if kept == -1:
                g_hi *= 0.5
            kept = -1
    return hi - lo <= EVENT_TIME_TOL_S, lo, y_lo, hi, y_hi, tries
