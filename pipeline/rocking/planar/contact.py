"""A planar rigid block on a moving base with every contact mode: rest, slide, rock, slide-rock, free flight.

Pure rocking (:mod:`.kernel`) is the right model while the pivot sticks and the block stays on its base.
Where it stops (the friction demand exceeds mu, the block's own motion lifts its pivot, or the ground
falls faster than gravity), this model continues from the state it stopped in. It is compiled with numba
when installed, as :mod:`.kernel`.

The model's equations, events, transitions and impact law are in :mod:`.contact_laws`.

Integration: the classical fourth-order Runge-Kutta method on steps that never cross a sample (the
ground is linear between samples), of at most dt / STEPS_PER_SAMPLE and MAX_STEP_P / p, but for the slide mode,
whose slip is cubic in time on a piece (the step exact for it): one step to the piece's end, cut where the slip rate
would dip to 0 inside it (its lowest point known in closed form); events are
located on the step length to a bracket of the step times 2^-48 (the bracket bisection's 48 halvings leave) by the
ITP method (Oliveira & Takahashi 2020, :mod:`..numerics.itp`), which interpolates the one indicator of the mode that
is negative at the bracket's end rather than the smallest of them, whose kink where two cross slows it: 21
evaluations an event on 400 continuations at scale, against 42 (docs/validation.md). After the record, the ground is
still: the motion is followed until the block rests, overturns, or rocks on a sticking pivot, whose fate the energy
of free rocking decides as in :mod:`.kernel`.

References
----------
Oliveira, I. F. D. & Takahashi, R. H. C. (2020). An enhancement of the bisection method average performance
preserving minmax optimality. ACM Transactions on Mathematical Software 47(1), 5:1-5:24.
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. BSSA 53(2), 403-417
(the energy of free rocking after the record). The model's own references are in :mod:`.contact_laws`.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...compiled import jit, jit_inline, jit_lean, state_factory
from ..codes import (
    FLIGHT,
    MODE_FLIGHT,
    OVERTURNED,
    REST,
    ROCK,
    SLIDE,
    STATUS_ENDED,
    STATUS_EVENT_CAP,
    STATUS_GROUND_FLIGHT,
    STATUS_LIFTOFF,
    STATUS_STALLED,
    STATUS_STEP_CAP,
    STATUS_TAIL_CAP,
    STATUS_TIE_HOLD,
)
from ..numerics.dopri import HISTORY_TIME_TOL_S
from ..numerics.ground import exceed_fraction, flight_fraction
from ..numerics.itp import EXTRA_GUARD, evaluations_cap, itp_point
from ..rules import MAX_EVENTS_AT_ONE_INSTANT, events_at_instant_compiled
from ..structures import ContactOutcome, ContactState, GroundPiece
from .contact_laws import (
    FLAT_ANGLE_ALPHA,
    _branch,
    _constrain,
    _event_branches,
    _mode_bit,
    _onset,
    _rk4,
    _slip_point,
    _smallest,
    _transition,
    corner_offsets,
    event_value,
    state_verdict,
)
from .kernel import HALF_PI, SAMPLE_INDEX_TOL, TINY, free_outcome

__all__ = ["ContactOutcome", "ContactState", "move"]

# modes, mode bits and status bits: the simulator's one vocabulary (codes.py)

# Step and event control, named once
STEPS_PER_SAMPLE = 2          # Runge-Kutta steps per sample interval, at least
MAX_STEP_P = 0.02             # largest step as a fraction of 1/p
EVENT_BRACKET_BITS = 48       # an event is located inside a step to a bracket of the step's length times 2^-this
MAX_EVENTS = 20000            # cap on transitions and impacts
MAX_TAIL_PERIODS = 200.0      # motion followed after the record, in units of 2 pi / p
MAX_STEPS_PER_SAMPLE = 1000   # step budget: step attempts per sample of the record (with the tail's steps), plus
MAX_STEPS_FIXED = 100000      # ... this many; the cap ends the scene (STATUS_STEP_CAP)


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
    blk : RigidBlock
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
    hist = theta_out if theta_out is not None else np.empty(0)
    return _move(ah, av, dt, blk, start, tail_energy, t_stop, hand_back, hist, new_motion())


@jit_lean
def _move(ah, av, dt, blk, start, tail_energy, t_stop, hand_back, hist, progress):
    """:func:`move`'s loop on the history and progress record it made."""
    n = ah.shape[0]
    has_v = av.shape[0] == n
    lim = _limits(blk, n, dt, MAX_STEPS_PER_SAMPLE * n + MAX_STEPS_FIXED, MAX_EVENTS)
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
    # bool(False): one compiled version for every caller (pipeline.compiled)
    over, peak, extra = free_outcome(pr.theta, pr.w, blk.p * blk.p, blk.alpha, blk.e, bool(False))
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
def _event_step(mode, c, sigma, x, y, th, u, v, w, t, hh, hh_branches, pc, blk):
    """The length of a step from t that ends at the mode's first event inside ``hh`` (the event function is
    negative at its end, where the mode's indicators are ``hh_branches``): located on the step length by ITP
    (:mod:`..numerics.itp`) to a bracket of ``hh`` 2^-:data:`EVENT_BRACKET_BITS` across which the event function
    changes sign, its end returned (where the event has happened). The event function is the smallest of the mode's
    indicators, with a kink where two of them cross; ITP interpolates the indicator that is negative at the
    bracket's end instead, smooth through its root, while the event function's sign keeps the bracket."""
    g, t0 = blk.g, pc.t0
    lo, hi = 0.0, hh
    lo_branches = _event_branches(mode, c, sigma, x, y, th, u, v, w, pc.a0 + pc.sa * (t - t0),
                                  g + pc.v0 + pc.sv * (t - t0), blk)
    k = _smallest(hh_branches)
    f_lo = max(_branch(lo_branches, k), 0.0)            # no event yet at the step's start (a rounding below 0: 0)
    f_hi = min(_branch(hh_branches, k), 0.0)            # the event has happened at its end: the smallest is below 0
    width = hh * 2.0 ** -EVENT_BRACKET_BITS
    n_max = evaluations_cap(hh, width)
    j = 0
    while hi - lo > width and j < n_max + EXTRA_GUARD:
        mid = itp_point(lo, hi, f_lo, f_hi, j, n_max, width, hh)
        xm_, ym_, thm, um, vm, wm = _rk4(mode, c, sigma, x, y, th, u, v, w, t, mid, t0, pc.a0, pc.sa, pc.v0, pc.sv,
                                         blk)
        tm = t + mid
        mid_branches = _event_branches(mode, c, sigma, xm_, ym_, thm, um, vm, wm, pc.a0 + pc.sa * (tm - t0),
                                       g + pc.v0 + pc.sv * (tm - t0), blk)
        if event_value(mid_branches) < 0.0:                 # the event has happened by mid
            hi = mid
            k = _smallest(mid_branches)
            f_hi = min(_branch(mid_branches, k), 0.0)
            f_lo = max(_branch(lo_branches, k), 0.0)
        else:
            lo, lo_branches = mid, mid_branches
            f_lo = max(_branch(mid_branches, k), 0.0)
        j += 1
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
    # sliding, the step is exact whatever its length (the slip is cubic on the piece): one step to the piece's end
    hh = min(pc.t1 - t, t_stop - t) if mode == SLIDE else min(lim.h_max, pc.t1 - t, t_stop - t)
    pr.n_steps += 1
    if mode == SLIDE:
        hh = _slide_dip(sigma, u, t, hh, pc, blk)
    x1, y1, th1, u1, v1s, w1 = _rk4(mode, c, sigma, x, y, th, u, v, w, t, hh, t0, pc.a0, pc.sa, pc.v0, pc.sv, blk)
    te = t + hh
    branches = _event_branches(mode, c, sigma, x1, y1, th1, u1, v1s, w1, pc.a0 + pc.sa * (te - t0),
                               g + pc.v0 + pc.sv * (te - t0), blk)
    ev = event_value(branches)
    if ev < 0.0:
        hh = _event_step(mode, c, sigma, x, y, th, u, v, w, t, hh, branches, pc, blk)
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
def _slide_dip(sigma, u, t, hh, pc, blk):
    """A sliding step of length ``hh`` from t cut where its slip rate sigma u, positive at both ends, would dip to 0
    inside it: sigma u is a quadratic in time (its rate -sigma a - mu G is linear on the piece), so its lowest point
    is known; the step ends there when that is at most 0 (the event, located inside by :func:`_event_step`), else it
    stays ``hh``. A step checked at its end alone would pass over such a stop."""
    s0 = -sigma * (pc.a0 + pc.sa * (t - pc.t0)) - blk.mu * (blk.g + pc.v0 + pc.sv * (t - pc.t0))
    s1 = -sigma * (pc.a0 + pc.sa * (t + hh - pc.t0)) - blk.mu * (blk.g + pc.v0 + pc.sv * (t + hh - pc.t0))
    if not (sigma * u > 0.0 and s0 < 0.0 < s1):     # a slip that starts here (sigma u = 0) grows first
        return hh
    tau = hh * s0 / (s0 - s1)
    return tau if sigma * u + 0.5 * s0 * tau <= 0.0 else hh


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
