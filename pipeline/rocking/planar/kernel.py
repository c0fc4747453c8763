"""Event-driven rocking kernel (Housner, nonlinear or linearised); Coulomb sliding is in :mod:`.sliding`.

One source, two paths: the functions are compiled with numba when it is
installed (``njit``) and run as plain Python otherwise, or under
``NUMBA_DISABLE_JIT=1`` (the tests run both and compare).

Rocking scheme (Housner 1963; Dormand & Prince 1980, J. Comput. Appl. Math. 6(1), for the Runge-Kutta pair;
Hairer, Norsett & Wanner 1993, Solving ODEs I, section II.6, for dense output and event location):

* the pivot side ``s`` (+1 about O, -1 about O') is discrete state, never
  ``sgn(theta)`` inside the right-hand side;
* the ground acceleration is linear between samples; each sample interval is
  integrated by an embedded Dormand-Prince 5(4) Runge-Kutta pair with error
  control (``rtol``, ``atol`` relative to alpha and p alpha), steps never
  crossing a sample;
* an impact (theta reaching 0 on the pivot side) is located as the root of
  the local solution: first on the cubic Hermite interpolant of the step,
  then by Newton iterations on the Runge-Kutta step length, so the impact
  time is accurate to the integration tolerance (not to a sample);
  there theta = 0, omega <- e omega and the pivot switches;
* "rest" is a mode: an impact whose rebound is slower than
  ``rest_ratio * p * alpha`` ends the Zeno cascade; from rest the block lifts
  again at the exact (linear-in-time) crossing of
  |a_h| = (g + a_v) tan(alpha) (alpha for the linear model), rotating away
  from a_h;
* overturning is |theta| >= pi/2 while the ground moves; after the record
  ends, the energy of the free motion decides (section 1.5), including the
  swing after the next impact, so free rocking need not be integrated.

References
----------
Housner (1963) BSSA 53(2); Yim, Chopra & Penzien (1980) EESD 8; Makris &
Roussos (2000) Geotechnique 50(3); Zhang & Makris (2001) J. Eng. Mech.
127(5), eqs. 10-20. Dormand, J. R. & Prince, P. J. (1980). A family of
embedded Runge-Kutta formulae. J. Comput. Appl. Math. 6(1), 19-26.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...compiled import HAVE_NUMBA, jit, jit_inline, jit_lean, state_factory  # noqa: F401  (HAVE_NUMBA: read by the tests as kernel.*)
from ..codes import (  # noqa: F401  (the status bits and modes the kernel's callers read as kernel.*)
    OVERTURNED,
    REST,
    ROCK,
    STATUS_CHATTER,
    STATUS_FRICTION,
    STATUS_GROUND_FLIGHT,
    STATUS_LIFTOFF,
    STATUS_STEP_CAP,
    STATUS_STEP_UNDERFLOW,
    STATUS_TIE_HOLD,
)
from ..numerics.dopri import (
    HISTORY_TIME_TOL_S,
    dopri_step,
    fill_hermite,
    first_crossing,
    hermite_peak,
    locate_impact,
    pivot_demand,
)
from ..numerics.ground import QUIET_CHUNK, chunk_quiet, exceed_fraction, flight_fraction
from ..rules import MAX_EVENTS_AT_ONE_INSTANT, events_at_instant_compiled, min_advance_compiled
from ..structures import GroundPiece, RockingOutcome
from .chatter import chatter, take_impact

HALF_PI = 0.5 * math.pi


# Step-size control of the Runge-Kutta pair (Hairer, Norsett & Wanner 1993, section II.4), named once
SAFETY = 0.9                    # safety factor on the step the error estimate asks for
ERROR_EXPONENT = -0.2           # -1 / (q + 1), q = 4 the order of the embedded error estimate
MIN_FACTOR = 0.2                # after an accepted step the next is at least this fraction of it
MAX_FACTOR = 5.0                # ... and at most this multiple of it
MIN_FACTOR_REJECTED = 0.1       # a rejected step shrinks at most to this fraction
#: Below this error norm SAFETY err^ERROR_EXPONENT exceeds MAX_FACTOR by more than 0.2 %, whatever pow's rounding:
#: the next step grows by MAX_FACTOR without evaluating the power (the same doubles)
GROWTH_CERTAIN_BELOW = 0.99 * (MAX_FACTOR / SAFETY) ** (1.0 / ERROR_EXPONENT)
MIN_STEP_S = 1e-14              # smallest step [s] near t = 0; rules.min_advance(t) later: a step this small
                                # is accepted (STATUS_STEP_UNDERFLOW), so every accepted step advances time
MAX_STEPS_PER_SAMPLE = 1000     # step budget of a scene: this many step attempts per sample of the record, plus
MAX_STEPS_FIXED = 100000        # ... this many (the cap ends the scene, STATUS_STEP_CAP; never met on the bundled
                                # records, whose busiest scene takes a few steps per sample)
FIRST_STEP_FRACTION = 0.1       # first step, as a fraction of min(largest step, dt)
UPLIFT_STEP_FRACTION = 0.01     # first step after an uplift from rest, the same way
MIN_STEP_AFTER_IMPACT_P = 1e-6  # smallest step kept across an impact, as a fraction of 1/p
SAMPLE_INDEX_TOL = 1e-9         # rounding allowance when t / dt falls on a sample [-]
CAP_TOL = 1e-8                  # a piece is at most dt (1 + CAP_TOL) long, SAMPLE_INDEX_TOL's rounding included;
                                # the same margin keeps _next_step's bound on the error norm clear of rounding [-]
TAIL_TIME_TOL_S = 1e-9          # the record has ended within this of its last sample [s]
TINY = 1e-300                   # guards a division by a difference of |theta| that can be 0

#: The kernel's state while it integrates a scene: one record, changed in place by the step functions
#: (as a solver object's attributes are), and read once at the end into a :class:`RockingOutcome`.
PROGRESS = np.dtype([
    ("t", np.float64),               # time reached [s]
    ("theta", np.float64),           # rotation [rad]
    ("omega", np.float64),           # angular velocity [rad s-1]
    ("pivot", np.float64),           # pivot side s: +1 about O (tipping towards +x), -1 about O'
    ("mode", np.int64),              # REST, ROCK or OVERTURNED (codes.Mode)
    ("h", np.float64),               # the next step the error control asks for [s]
    ("theta_max", np.float64),       # largest |theta| so far [rad]
    ("t_overturn", np.float64),      # [s], NaN while standing
    ("t_first_impact", np.float64),  # [s], NaN before the first impact
    ("friction_max", np.float64),    # largest friction demand |f_x| / f_z while |theta| < alpha [-]
    ("n_impacts", np.int64),
    ("n_uplifts", np.int64),
    ("n_events", np.int64),          # impacts plus uplifts (the chatter cap, max_events, counts them)
    ("n_steps", np.int64),           # step attempts (the step budget counts them)
    ("status", np.int64),            # codes.Status bits
    ("t_event", np.float64),         # time of the last event [s], and events in a row there (tie rule 6)
    ("n_same", np.int64),
    ("out_k", np.int64),             # the next sample of the theta history to fill
    ("overturned", np.bool_),
    ("handed_off", np.bool_),        # stopped where pure rocking stops holding (block.stop_mu)
    ("capped", np.bool_),            # stopped by the step budget
])
new_progress = state_factory(PROGRESS)


class StepLimits(NamedTuple):
    """What the step control of one scene derives from its block and settings, once.

    Attributes
    ----------
    p2 : float
        p^2 [rad2 s-2].
    thr : float
        Uplift threshold on |a_h| / (g + a_v): tan(alpha), or alpha for the linear model [-].
    t_rec : float
        Time of the record's last sample [s].
    atol_theta, atol_omega : float
        Absolute tolerances [rad], [rad s-1].
    h_max : float
        Largest step [s].
    rest_omega : float
        A rebound slower than this ends the impact cascade [rad s-1].
    max_steps : int
        Step budget of the scene (step attempts).
    """

    p2: float
    thr: float
    t_rec: float
    atol_theta: float
    atol_omega: float
    h_max: float
    rest_omega: float
    max_steps: int


@jit
def free_motion_energy(theta, omega, p2, alpha, linear):
    """Energy of the free motion per unit p^2-scaled inertia, and its value at the saddle.

    Nonlinear: E = omega^2/2 + p^2 cos(alpha - |theta|), saddle p^2, pivot p^2 cos(alpha).
    Linear: E = omega^2/2 - p^2 (|theta| - alpha)^2 / 2, saddle 0, pivot -p^2 alpha^2 / 2.
    """
    if linear:
        return 0.5 * omega * omega - 0.5 * p2 * (abs(theta) - alpha) ** 2, 0.0, -0.5 * p2 * alpha * alpha
    return 0.5 * omega * omega + p2 * math.cos(alpha - abs(theta)), p2, p2 * math.cos(alpha)


@jit
def free_outcome(theta, omega, p2, alpha, e, linear):
    """Fate of a block rocking freely (no more ground motion) from (theta, omega).

    Returns (overturns, peak |theta| still to come, impacts counted before it
    overturns or settles: 0 or 1). Energy is conserved between impacts and
    multiplied by e^2 (kinetic part at theta = 0) at each: a block that does
    not escape on its current outward swing, or on the first swing after the
    next impact, never escapes (Housner 1963: energy is lost only at impacts, none is added after the
    record).
    """
    E, E_top, E_pivot = free_motion_energy(theta, omega, p2, alpha, linear)
    outward = theta * omega > 0.0 or (theta == 0.0 and omega != 0.0)
    a = abs(theta)
    if a >= alpha:                 # beyond the saddle: escapes unless moving back over it
        if not outward and E > E_top:
            pass
        else:
            return True, HALF_PI, 0
    if outward:
        if E >= E_top:
            return True, HALF_PI, 0
        return False, _peak_from_energy(E, p2, alpha, linear), 0
    E_next = E_pivot + e * e * (E - E_pivot)                      # next impact keeps e^2 of the kinetic energy
    if E_next >= E_top:
        return True, HALF_PI, 1
    return False, _peak_from_energy(E_next, p2, alpha, linear), 1


@jit
def _peak_from_energy(E, p2, alpha, linear):
    if linear:
        return alpha - math.sqrt(max(-2.0 * E / p2, 0.0))
    return alpha - math.acos(min(max(E / p2, -1.0), 1.0))


@jit
def _limits(block, control, n, dt, max_steps):
    """The scene's :class:`StepLimits` (``n`` samples of interval ``dt`` [s])."""
    p, alpha = block.p, block.alpha
    return StepLimits(p2=p * p, thr=alpha if block.linear else math.tan(alpha), t_rec=(n - 1) * dt,
                      atol_theta=control.atol * alpha, atol_omega=control.atol * alpha * p,
                      h_max=control.max_step_p / p, rest_omega=control.rest_ratio * p * alpha, max_steps=max_steps)


@jit
def _begin(progress, start, dt, lim, theta_out):
    """Set the progress record to the start: at rest, or rocking on the side theta (or omega) points to."""
    pr = progress[0]
    th, om = start.theta, start.omega
    pr.t = start.t
    pr.theta = th
    pr.omega = om
    pr.mode = REST
    pr.pivot = 1.0
    if th != 0.0 or om != 0.0:
        pr.mode = ROCK
        pr.pivot = 1.0 if (th > 0.0 or (th == 0.0 and om > 0.0)) else -1.0
    pr.theta_max = abs(th)
    pr.t_overturn = math.nan
    pr.t_first_impact = math.nan
    pr.t_event = -math.inf
    pr.h = min(lim.h_max, dt) * FIRST_STEP_FRACTION
    if theta_out.shape[0] > 0:
        # the history from the start's sample on (a restart mid-record leaves the earlier samples as they are)
        pr.out_k = max(int(math.ceil(start.t / dt - SAMPLE_INDEX_TOL)), 0)
        if pr.out_k == 0:
            theta_out[0] = th
            pr.out_k = 1


@jit_inline
def _piece(ah, av, has_v, dt, t, t_end):
    """The ground's linear piece holding t (the next one when t is on its end); still after the record."""
    n = ah.shape[0]
    k = int(t / dt + SAMPLE_INDEX_TOL)
    t0 = k * dt
    t1 = min(t0 + dt, t_end)
    if t1 <= t:                       # rounding at a sample boundary
        k += 1
        t0 = k * dt
        t1 = min(t0 + dt, t_end)
    a0 = a1 = v0 = v1 = 0.0
    if k < n - 1:
        a0, a1 = ah[k], ah[k + 1]
        if has_v:
            v0, v1 = av[k], av[k + 1]
    return GroundPiece(k=k, t0=t0, t1=t1, a0=a0, a1=a1, v0=v0, v1=v1, sa=(a1 - a0) / dt, sv=(v1 - v0) / dt)


@jit_inline
def _loud(ah, av, has_v, j, g, thr):
    """True when sample j can lift the block at rest (or the ground falls faster than gravity there)."""
    gj = g + (av[j] if has_v else 0.0)
    return abs(ah[j]) > gj * thr or gj <= 0.0


@jit_inline
def _quiet_until(ah, av, has_v, k, g, thr, quiet):
    """The last sample j >= k such that no piece between samples k and j can lift the block (linear pieces:
    below the threshold at both ends means below it throughout). The chunks of the plane's ``quiet`` table
    (:class:`~.numerics.ground.QuietTable`, empty: none) that pass as a whole are skipped unread."""
    n = ah.shape[0]
    use = quiet.peak_ah_ms2.shape[0] == (n + QUIET_CHUNK - 1) // QUIET_CHUNK
    m = k                               # the first sample from k on that can lift the block
    while m < n:
        if use and m % QUIET_CHUNK == 0:
            c = m // QUIET_CHUNK
            while c * QUIET_CHUNK < n and chunk_quiet(quiet, c, g, thr, has_v):
                c += 1
            if c * QUIET_CHUNK > m:
                m = c * QUIET_CHUNK
                continue
        if _loud(ah, av, has_v, m, g, thr):
            break
        m += 1
    if m >= n:
        return n - 1
    return k if m == k else m - 1


@jit_inline
def _from_rest(ah, av, has_v, dt, t_end, pc, g, lim, progress, theta_out, quiet):
    """Advance a block at rest: over the samples that cannot lift it, then to its uplift (rocking away from
    a_h), to the loss of contact, or to the piece's end. Returns whether the scene goes on."""
    pr = progress[0]
    t, t0, t1 = pr.t, pc.t0, pc.t1
    if pc.k >= ah.shape[0] - 1:       # nothing moves it any more
        pr.t = t_end
        return False
    if t == t0 and pc.k + 1 < ah.shape[0]:
        j = _quiet_until(ah, av, has_v, pc.k, g, lim.thr, quiet)
        if j > pc.k:
            while pr.out_k < theta_out.shape[0] and pr.out_k <= j:
                theta_out[pr.out_k] = 0.0
                pr.out_k += 1
            pr.t = min(j * dt, t_end)
            return True
    aa0, vv0 = pc.a0 + pc.sa * (t - t0), pc.v0 + pc.sv * (t - t0)
    aa1, vv1 = pc.a0 + pc.sa * (t1 - t0), pc.v0 + pc.sv * (t1 - t0)
    xf = flight_fraction(vv0, vv1, g) if has_v else -1.0
    x = exceed_fraction(aa0, aa1, vv0, vv1, g, lim.thr)
    if xf >= 0.0 and (x < 0.0 or x >= xf):
        # the ground falls faster than gravity before the block lifts: contact is lost
        pr.t = t + xf * (t1 - t)
        pr.status |= STATUS_GROUND_FLIGHT
        return False
    t_up = t1
    if x >= 0.0:
        t_up = t + x * (t1 - t)
        pr.n_same = events_at_instant_compiled(t_up, pr.t_event, pr.n_same)
        pr.t_event = t_up
        if pr.n_same > MAX_EVENTS_AT_ONE_INSTANT:
            # tie rule 6: uplift and fall back at one instant without end: held at rest to the next sample
            pr.status |= STATUS_TIE_HOLD
            pr.n_same = 0
            x = -1.0
    if x < 0.0:
        pr.t = t1
    else:
        pr.t = t_up
        pr.pivot = -1.0 if pc.a0 + pc.sa * (t_up - t0) > 0.0 else 1.0
        pr.theta, pr.omega, pr.mode = 0.0, 0.0, ROCK
        pr.n_uplifts += 1
        pr.n_events += 1
        pr.h = min(lim.h_max, dt) * UPLIFT_STEP_FRACTION
    while pr.out_k < theta_out.shape[0] and pr.out_k * dt <= pr.t + HISTORY_TIME_TOL_S:
        theta_out[pr.out_k] = 0.0
        pr.out_k += 1
    return True


@jit_inline
def _impact_fraction(th, om, th1, om1, hh, s):
    """Fraction of an accepted step where theta first meets 0 on the pivot side, or -1 (no impact)."""
    if s * th1 < 0.0:
        x = first_crossing(th, om, th1, om1, hh, s)
        return 1.0 if x < 0.0 else x
    if s * om < 0.0 and s * om1 > 0.0:
        return first_crossing(th, om, th1, om1, hh, s)
    return -1.0


@jit_inline
def _impact(hh, x, dt, pc, block, control, lim, progress, out):
    """The impact inside an accepted step of length ``hh``: located (:func:`.dopri.locate_impact`), logged,
    omega multiplied by e and the pivot switched (Housner 1963); a rebound slower than ``rest_omega``, the
    event cap or tie rule 6 ends in rest."""
    pr = progress[0]
    t, th, om, s = pr.t, pr.theta, pr.omega, pr.pivot
    hs, ths, oms = locate_impact(t, th, om, hh, x, pc, s, lim.p2, block.alpha, block.g, block.linear)
    pr.theta_max = max(pr.theta_max, abs(th), abs(ths))
    if s * om > 0.0 and s * oms < 0.0:
        pr.theta_max = max(pr.theta_max, hermite_peak(th, om, ths, oms, hs))
    t = t + hs
    pr.out_k = fill_hermite(out.theta, pr.out_k, dt, t - hs, hs, th, om, ths, oms, t)
    take_impact(t, oms, block.e, lim.rest_omega, control.max_events, progress, out.impacts)
    if pr.n_same > MAX_EVENTS_AT_ONE_INSTANT:
        # tie rule 6: impacts without time advancing: held at rest (theta = 0 here) to the next sample
        pr.status |= STATUS_TIE_HOLD
        pr.n_same = 0
        pr.omega, pr.mode, pr.t = 0.0, REST, pc.t1
    if pr.mode == ROCK and control.chatter:   # the cascade's small flights in closed form while they hold
        chatter(dt, pc, block, control, lim.rest_omega, lim.p2, progress, out.theta, out.impacts)
    pr.h = max(hh, MIN_STEP_AFTER_IMPACT_P / block.p)    # the new pivot's motion is smooth: keep the step size


@jit_inline
def _to_ground_flight(hh, pc, block, lim, progress):
    """Contact lost during a step (g + a_v reaching 0): the state carried to that instant, where the rocking
    model stops holding."""
    pr = progress[0]
    t = pr.t
    hf = flight_fraction(pc.v0 + pc.sv * (t - pc.t0), pc.v0 + pc.sv * (t + hh - pc.t0), block.g) * hh
    if hf > 0.0:
        th, om, _et, _eo, _acc, _sin, _cos = dopri_step(t, pr.theta, pr.omega, hf, pc, pr.pivot, lim.p2,
                                                        block.alpha, block.g, block.linear)
        pr.theta, pr.omega = th, om
        pr.theta_max = max(pr.theta_max, abs(th))
    pr.t = t + hf
    pr.status |= STATUS_GROUND_FLIGHT


@jit_inline
def _pivot_holds(sin1, cos1, om1, acc1, hh, pc, block, progress):
    """Record the pivot's friction demand (or its lift-off) at the step's end (``sin1``, ``cos1``: of
    alpha s - theta there); False where pure rocking stops holding for this block (``block.stop_mu``), so that
    the general contact model continues from the step's start."""
    pr = progress[0]
    te = pr.t + hh
    demand, lifted = pivot_demand(sin1, cos1, om1, acc1, block.R, pc.a0 + pc.sa * (te - pc.t0),
                                     pc.v0 + pc.sv * (te - pc.t0), block.g)
    if lifted:
        pr.status |= STATUS_LIFTOFF
    else:
        pr.friction_max = max(pr.friction_max, demand)
    if lifted and block.stop_mu < math.inf or not lifted and demand > block.stop_mu:
        if not lifted:
            pr.status |= STATUS_FRICTION
        return False
    return True


@jit_inline
def _accept(hh, th1, om1, err, dt, h_max, progress, theta_out):
    """Take an accepted step without events: the peak inside it, the history, and the next step's size."""
    pr = progress[0]
    t, th, om = pr.t, pr.theta, pr.omega
    if om * om1 < 0.0:
        pr.theta_max = max(pr.theta_max, hermite_peak(th, om, th1, om1, hh))
    pr.theta_max = max(pr.theta_max, abs(th1))
    pr.out_k = fill_hermite(theta_out, pr.out_k, dt, t, hh, th, om, th1, om1, t + hh)
    pr.t, pr.theta, pr.omega = t + hh, th1, om1
    pr.h = _next_step(hh, err, dt, h_max)


@jit_inline
def _next_step(hh, err, dt, h_max):
    """The step the error control asks for after an accepted step of ``hh`` [s] with error norm ``err`` <= 1.

    The next step is min(this, h_max, what is left of its piece), and a piece is at most dt (1 + :data:`CAP_TOL`)
    long, the rounding :data:`SAMPLE_INDEX_TOL` allows included; where this is certainly at least that cap
    (err <= (SAFETY hh / cap)^5, with a margin far beyond the power's rounding), the cap is returned in its place:
    the next step is the same double, and err^ERROR_EXPONENT is not evaluated."""
    if err > 0 and not err < GROWTH_CERTAIN_BELOW:
        cap = min(h_max, dt * (1.0 + CAP_TOL))
        r = SAFETY * hh / cap
        if hh * MAX_FACTOR >= cap and err <= r * r * r * r * r * (1.0 - CAP_TOL):
            return cap
        return hh * min(MAX_FACTOR, max(MIN_FACTOR, SAFETY * err ** ERROR_EXPONENT))
    return hh * MAX_FACTOR


@jit_inline
def step_error(th, om, th1, om1, et, eo, lim, rtol):
    """The step's error norm against the tolerances (``lim.atol_theta``, ``lim.atol_omega``; relative ``rtol``):
    above 1 the step is rejected (Hairer, Norsett & Wanner 1993, section II.4)."""
    sc_t = lim.atol_theta + rtol * max(abs(th), abs(th1))
    sc_o = lim.atol_omega + rtol * max(abs(om), abs(om1))
    return math.sqrt(0.5 * ((et / sc_t) ** 2 + (eo / sc_o) ** 2))


@jit_inline
def reject(hh, err, min_step, progress):
    """A rejected step of length ``hh``: the next is shorter, never below ``min_step`` (flagged where it would be)."""
    pr = progress[0]
    pr.h = hh * max(MIN_FACTOR_REJECTED, SAFETY * err ** ERROR_EXPONENT)
    if pr.h < min_step:
        pr.status |= STATUS_STEP_UNDERFLOW
        pr.h = min_step


@jit_inline
def _rocking_step(has_v, dt, pc, block, control, lim, progress, out):
    """One adaptive step of a rocking block inside the ground piece, with its events: a rejected step
    shrinks; an accepted one ends at an impact, at overturning (|theta| = pi/2), where contact is lost or
    pure rocking stops holding, or goes on. Returns whether the scene goes on."""
    pr = progress[0]
    pr.n_steps += 1
    if pr.n_steps > lim.max_steps:
        pr.status |= STATUS_STEP_CAP
        pr.capped = True
        return False
    t, th, om, s = pr.t, pr.theta, pr.omega, pr.pivot
    min_step = max(MIN_STEP_S, min_advance_compiled(t))
    hh = min(pr.h, lim.h_max, pc.t1 - t)
    if hh <= min_step:
        hh = pc.t1 - t
    th1, om1, et, eo, acc1, sin1, cos1 = dopri_step(t, th, om, hh, pc, s, lim.p2, block.alpha, block.g, block.linear)
    err = step_error(th, om, th1, om1, et, eo, lim, control.rtol)
    if err > 1.0 and hh > min_step:
        reject(hh, err, min_step, progress)
        return True
    if has_v and block.g + pc.v0 + pc.sv * (t + hh - pc.t0) <= 0.0:
        _to_ground_flight(hh, pc, block, lim, progress)
        return False
    x = _impact_fraction(th, om, th1, om1, hh, s)
    if x >= 0.0:
        _impact(hh, x, dt, pc, block, control, lim, progress, out)
        return True
    if abs(th1) >= HALF_PI:
        frac = (HALF_PI - abs(th)) / max(abs(th1) - abs(th), TINY)
        pr.t_overturn = t + frac * hh
        pr.overturned, pr.theta_max, pr.mode, pr.t = True, HALF_PI, OVERTURNED, pr.t_overturn
        return False
    # past the saddle (|theta| >= alpha) the block falls whether or not its base slides: no demand there
    if abs(th1) < block.alpha and not _pivot_holds(sin1, cos1, om1, acc1, hh, pc, block, progress):
        pr.handed_off = True
        return False
    _accept(hh, th1, om1, err, dt, lim.h_max, progress, out.theta)
    return True


@jit
def _after_record(block, lim, tail_energy, progress):
    """After the record (or where the step budget ended the scene): the energy of the free motion decides."""
    pr = progress[0]
    if pr.overturned or pr.mode != ROCK:
        return
    if pr.capped or (tail_energy and pr.t >= lim.t_rec - TAIL_TIME_TOL_S and not pr.status & STATUS_GROUND_FLIGHT
                     and not pr.handed_off):
        over, peak, extra = free_outcome(pr.theta, pr.omega, lim.p2, block.alpha, block.e, block.linear)
        pr.theta_max = max(pr.theta_max, peak)
        if over:
            pr.overturned, pr.t_overturn, pr.mode = True, pr.t, OVERTURNED
            pr.n_impacts += extra                 # the impact on the way, before the escaping swing


@jit
def _outcome(progress):
    """The progress record as the kernel's :class:`RockingOutcome`."""
    pr = progress[0]
    return RockingOutcome(overturned=pr.overturned, t_overturn=pr.t_overturn, theta_max_rad=pr.theta_max,
                          n_impacts=pr.n_impacts, friction_max=pr.friction_max, status=pr.status, t_stop=pr.t,
                          theta_end=pr.theta, omega_end=pr.omega, mode_end=pr.mode, n_uplifts=pr.n_uplifts,
                          t_first_impact=pr.t_first_impact, pivot_end=pr.pivot)


@jit
def rock(ah, av, dt, t_end, block, control, start, tail_energy, out, quiet):
    """Integrate rocking under a sampled ground motion.

    Parameters
    ----------
    ah, av : ndarray
        Horizontal and vertical ground acceleration at t = k dt [m s-2]
        (``av`` empty: no vertical). Zero after the last sample.
    dt : float
        Sampling interval [s].
    t_end : float
        End of the simulation [s] (>= the record's end to see it all).
    block : RigidBlock
        The block.
    control : StepControl
        Tolerances and step limits.
    start : RockingState
        Initial state (both 0: at rest) and its time (the theta history, when asked for, starts at t = 0).
    tail_energy : bool
        After the record, decide by :func:`free_outcome` instead of integrating.
    out : RockingOutput
        Arrays to fill (theta at the samples, the impact log); empty arrays skip them.
    quiet : QuietTable
        The plane's :class:`~.numerics.ground.QuietTable` of ``ah`` and ``av`` (``NO_QUIET``: none); the
        outcome is the same with or without it.

    Returns
    -------
    RockingOutcome
    """
    return _rock(ah, av, dt, t_end, block, control, start, tail_energy, out, quiet, new_progress())


@jit_lean
def _rock(ah, av, dt, t_end, block, control, start, tail_energy, out, quiet, progress):
    """:func:`rock`'s loop on the progress record it made."""
    n = ah.shape[0]
    has_v = av.shape[0] == n
    lim = _limits(block, control, n, dt, MAX_STEPS_PER_SAMPLE * n + MAX_STEPS_FIXED)
    _begin(progress, start, dt, lim, out.theta)
    while progress[0].t < t_end:
        pc = _piece(ah, av, has_v, dt, progress[0].t, t_end)
        if pc.k >= n - 1 and tail_energy and progress[0].t >= lim.t_rec:
            break
        if progress[0].mode == REST:
            if not _from_rest(ah, av, has_v, dt, t_end, pc, block.g, lim, progress, out.theta, quiet):
                break
        elif not _rocking_step(has_v, dt, pc, block, control, lim, progress, out):
            break
    _after_record(block, lim, tail_energy, progress)
    return _outcome(progress)


def empty_theta() -> np.ndarray:
    """An empty output array (skip the theta history)."""
    return np.zeros(0)


def empty_impacts() -> np.ndarray:
    """An empty impact log."""
    return np.zeros((0, 3))
