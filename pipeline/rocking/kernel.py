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

import numpy as np

from ..compiled import HAVE_NUMBA, jit  # noqa: F401  (HAVE_NUMBA: read by the tests as kernel.HAVE_NUMBA)
from .codes import (  # noqa: F401  (the status bits and modes the kernel's callers read as kernel.*)
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
from .rules import MAX_EVENTS_AT_ONE_INSTANT, events_at_instant_compiled, min_advance_compiled
from .structures import RockingOutcome

HALF_PI = 0.5 * math.pi


# Step-size control of the Runge-Kutta pair (Hairer, Norsett & Wanner 1993, section II.4), named once
SAFETY = 0.9                    # safety factor on the step the error estimate asks for
ERROR_EXPONENT = -0.2           # -1 / (q + 1), q = 4 the order of the embedded error estimate
MIN_FACTOR = 0.2                # after an accepted step the next is at least this fraction of it
MAX_FACTOR = 5.0                # ... and at most this multiple of it
MIN_FACTOR_REJECTED = 0.1       # a rejected step shrinks at most to this fraction
MIN_STEP_S = 1e-14              # smallest step [s] near t = 0; rules.min_advance(t) later: a step this small
                                # is accepted (STATUS_STEP_UNDERFLOW), so every accepted step advances time
MAX_STEPS_PER_SAMPLE = 1000     # step budget of a scene: this many step attempts per sample of the record, plus
MAX_STEPS_FIXED = 100000        # ... this many (the cap ends the scene, STATUS_STEP_CAP; never met on the bundled
                                # records, whose busiest scene takes a few steps per sample)
FIRST_STEP_FRACTION = 0.1       # first step, as a fraction of min(largest step, dt)
UPLIFT_STEP_FRACTION = 0.01     # first step after an uplift from rest, the same way
MIN_STEP_AFTER_IMPACT_P = 1e-6  # smallest step kept across an impact, as a fraction of 1/p
NEWTON_ITERATIONS = 8           # Newton iterations locating an impact on the step length
NEWTON_TOL_ALPHA = 1e-13        # |theta| accepted as the impact, as a fraction of alpha
SAMPLE_INDEX_TOL = 1e-9         # rounding allowance when t / dt falls on a sample [-]
TAIL_TIME_TOL_S = 1e-9          # the record has ended within this of its last sample [s]
HISTORY_TIME_TOL_S = 1e-12      # a history sample at k dt belongs to a step that ends within this of it [s]
CROSSING_PROBES = 16            # a step's Hermite cubic is probed at this many points for theta's sign change
CROSSING_BISECTIONS = 50        # ... then bisected this many times (2^-50 of the probe's span)
PEAK_BISECTIONS = 40            # bisections locating the turning point of theta inside a step
TINY = 1e-300                   # guards a division by a difference of |theta| that can be 0

# Dormand & Prince (1980) RK5(4)7M coefficients
C2, C3, C4, C5 = 1 / 5, 3 / 10, 4 / 5, 8 / 9
A21 = 1 / 5
A31, A32 = 3 / 40, 9 / 40
A41, A42, A43 = 44 / 45, -56 / 15, 32 / 9
A51, A52, A53, A54 = 19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729
A61, A62, A63, A64, A65 = 9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656
B1, B3, B4, B5, B6 = 35 / 384, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84
E1, E3, E4, E5, E6, E7 = 71 / 57600, -71 / 16695, 71 / 1920, -17253 / 339200, 22 / 525, -1 / 40


@jit
def rocking_accel(theta, omega, ah, av, s, p2, alpha, g, linear):
    """Angular acceleration [rad s-2] of a rectangular block rocking on pivot side s.

    Nonlinear (M&R eqs. 1-3 with g -> g + a_v, Yim 1980):
    theta'' = -p^2 [ (1 + a_v/g) sin(alpha s - theta) + (a_h/g) cos(alpha s - theta) ];
    linearised (M&R eqs. 8-9): sin(x) -> x, cos(x) -> 1.
    """
    phi = alpha * s - theta
    if linear:
        return -p2 * ((1.0 + av / g) * phi + ah / g)
    return -p2 * ((1.0 + av / g) * math.sin(phi) + (ah / g) * math.cos(phi))


@jit
def _dopri_step(t, th, om, h, t0, a0, sa, v0, sv, s, p2, alpha, g, linear):
    """One Dormand-Prince step; returns theta, omega and their error estimates."""
    k1t = om
    k1o = rocking_accel(th, om, a0 + sa * (t - t0), v0 + sv * (t - t0), s, p2, alpha, g, linear)
    y2t, y2o = th + h * A21 * k1t, om + h * A21 * k1o
    tt = t + C2 * h
    k2t, k2o = y2o, rocking_accel(y2t, y2o, a0 + sa * (tt - t0), v0 + sv * (tt - t0), s, p2, alpha, g, linear)
    y3t = th + h * (A31 * k1t + A32 * k2t)
    y3o = om + h * (A31 * k1o + A32 * k2o)
    tt = t + C3 * h
    k3t, k3o = y3o, rocking_accel(y3t, y3o, a0 + sa * (tt - t0), v0 + sv * (tt - t0), s, p2, alpha, g, linear)
    y4t = th + h * (A41 * k1t + A42 * k2t + A43 * k3t)
    y4o = om + h * (A41 * k1o + A42 * k2o + A43 * k3o)
    tt = t + C4 * h
    k4t, k4o = y4o, rocking_accel(y4t, y4o, a0 + sa * (tt - t0), v0 + sv * (tt - t0), s, p2, alpha, g, linear)
    y5t = th + h * (A51 * k1t + A52 * k2t + A53 * k3t + A54 * k4t)
    y5o = om + h * (A51 * k1o + A52 * k2o + A53 * k3o + A54 * k4o)
    tt = t + C5 * h
    k5t, k5o = y5o, rocking_accel(y5t, y5o, a0 + sa * (tt - t0), v0 + sv * (tt - t0), s, p2, alpha, g, linear)
    y6t = th + h * (A61 * k1t + A62 * k2t + A63 * k3t + A64 * k4t + A65 * k5t)
    y6o = om + h * (A61 * k1o + A62 * k2o + A63 * k3o + A64 * k4o + A65 * k5o)
    tt = t + h
    k6t, k6o = y6o, rocking_accel(y6t, y6o, a0 + sa * (tt - t0), v0 + sv * (tt - t0), s, p2, alpha, g, linear)
    th1 = th + h * (B1 * k1t + B3 * k3t + B4 * k4t + B5 * k5t + B6 * k6t)
    om1 = om + h * (B1 * k1o + B3 * k3o + B4 * k4o + B5 * k5o + B6 * k6o)
    k7t, k7o = om1, rocking_accel(th1, om1, a0 + sa * (tt - t0), v0 + sv * (tt - t0), s, p2, alpha, g, linear)
    et = h * (E1 * k1t + E3 * k3t + E4 * k4t + E5 * k5t + E6 * k6t + E7 * k7t)
    eo = h * (E1 * k1o + E3 * k3o + E4 * k4o + E5 * k5o + E6 * k6o + E7 * k7o)
    return th1, om1, et, eo, k7o


@jit
def _hermite(th0, om0, th1, om1, h, x):
    """Cubic Hermite interpolant of theta on a step, at fraction x in [0, 1]."""
    x2 = x * x
    x3 = x2 * x
    return ((2 * x3 - 3 * x2 + 1) * th0 + (x3 - 2 * x2 + x) * h * om0
            + (-2 * x3 + 3 * x2) * th1 + (x3 - x2) * h * om1)


@jit
def _first_crossing(th0, om0, th1, om1, h, s):
    """Fraction of the step where s*theta first drops below 0 on the Hermite cubic, or -1."""
    prev = 0.0
    for i in range(1, CROSSING_PROBES + 1):
        x = i / CROSSING_PROBES
        v = s * _hermite(th0, om0, th1, om1, h, x)
        if v < 0.0:
            lo, hi = prev, x
            for _ in range(CROSSING_BISECTIONS):
                mid = 0.5 * (lo + hi)
                if s * _hermite(th0, om0, th1, om1, h, mid) < 0.0:
                    hi = mid
                else:
                    lo = mid
            return 0.5 * (lo + hi)
        prev = x
    return -1.0


@jit
def _hermite_rate(th0, om0, th1, om1, h, x):
    """d theta / d x of the Hermite cubic at fraction x (x = (t - t0) / h)."""
    x2 = x * x
    return ((6 * x2 - 6 * x) * (th0 - th1) + (3 * x2 - 4 * x + 1) * h * om0 + (3 * x2 - 2 * x) * h * om1)


@jit
def _hermite_peak(th0, om0, th1, om1, h):
    """Largest |theta| of the Hermite cubic inside a step where omega changes sign."""
    best = max(abs(th0), abs(th1))
    lo, hi = 0.0, 1.0
    # the cubic's rate keeps the sign of omega0 until the turning point: bisection on it
    for _ in range(PEAK_BISECTIONS):
        mid = 0.5 * (lo + hi)
        if _hermite_rate(th0, om0, th1, om1, h, mid) * om0 > 0:
            lo = mid
        else:
            hi = mid
    return max(best, abs(_hermite(th0, om0, th1, om1, h, 0.5 * (lo + hi))))


@jit
def _exceed_fraction(a0, a1, v0, v1, g, thr):
    """First fraction x in [0, 1] where |a| > (g + v) thr on a linear piece, or -1.

    Uplift from rest (thr = tan(alpha), or alpha for the linear model) and the
    start of slip (thr = mu) are both this test.
    """
    best = -1.0
    for sig in (1.0, -1.0):
        l0 = sig * a0 - (g + v0) * thr
        l1 = sig * a1 - (g + v1) * thr
        if l0 > 0.0:
            return 0.0
        if l1 > 0.0:
            x = -l0 / (l1 - l0)
            if best < 0.0 or x < best:
                best = x
    return best


@jit
def _flight_fraction(v0, v1, g):
    """First fraction x in [0, 1] where g + v <= 0 on a linear piece of the vertical, or -1."""
    l0, l1 = g + v0, g + v1
    if l0 <= 0.0:
        return 0.0
    if l1 <= 0.0:
        return l0 / (l0 - l1)
    return -1.0


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
def _fill_hermite(theta_out, out_k, dt, t_start, h, th0, om0, th1, om1, t_stop):
    """theta at the samples k dt <= t_stop of a step from t_start of length h, from its cubic Hermite
    interpolant (0 for a step of length 0); returns the next sample to fill."""
    while out_k < theta_out.shape[0] and out_k * dt <= t_stop + HISTORY_TIME_TOL_S:
        theta_out[out_k] = _hermite(th0, om0, th1, om1, h, (out_k * dt - t_start) / h) if h > 0 else 0.0
        out_k += 1
    return out_k


@jit
def _locate_impact(t, th, om, hh, x, t0, a0, sa, v0, sv, s, p2, alpha, g, linear):
    """The impact inside an accepted step: Newton iterations on the step length, from the Hermite estimate
    ``x`` (a fraction of ``hh``), so that theta(t + h*) = 0 on the Runge-Kutta solution itself.
    Returns (h*, theta, omega) there."""
    hs = x * hh
    ths, oms = th, om
    for _ in range(NEWTON_ITERATIONS):
        ths, oms, _et, _eo, _acc = _dopri_step(t, th, om, hs, t0, a0, sa, v0, sv, s, p2, alpha, g, linear)
        if oms == 0.0 or abs(ths) <= NEWTON_TOL_ALPHA * alpha:
            break
        hs = min(max(hs - ths / oms, 0.0), hh)
    return hs, ths, oms


@jit
def _contact_demand(th1, om1, acc1, s, alpha, R, a_end, v_end, g):
    """Friction and normal force per unit mass at the pivot of a rocking block (Zhang & Makris 2001,
    eqs. 16-20): returns (|f_x| / f_z, lifted), lifted when f_z <= 0 (the demand is then 0, undefined)."""
    phi = alpha * s - th1
    fx = a_end + R * acc1 * math.cos(phi) + R * om1 * om1 * math.sin(phi)
    fz = g + v_end + R * acc1 * math.sin(phi) - R * om1 * om1 * math.cos(phi)
    if fz <= 0.0:
        return 0.0, True
    return abs(fx) / fz, False


@jit
def rock(ah, av, dt, t_end, block, control, start, tail_energy, out):
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
    block : RockingBlock
        The block.
    control : StepControl
        Tolerances and step limits.
    start : RockingState
        Initial state (both 0: at rest) and its time (the theta history, when asked for, starts at t = 0).
    tail_energy : bool
        After the record, decide by :func:`free_outcome` instead of integrating.
    out : RockingOutput
        Arrays to fill (theta at the samples, the impact log); empty arrays skip them.

    Returns
    -------
    RockingOutcome
    """
    p, alpha, e, g, R, linear = block.p, block.alpha, block.e, block.g, block.R, block.linear
    # (block.stop_mu: stop at a friction exceedance or a lift-off, for the general contact model)
    theta_out, impacts_out = out.theta, out.impacts
    n = ah.shape[0]
    has_v = av.shape[0] == n
    p2 = p * p
    thr = alpha if linear else math.tan(alpha)
    t_rec = (n - 1) * dt
    atol_t = control.atol * alpha
    atol_o = control.atol * alpha * p
    h_max = control.max_step_p / p
    rest_omega = control.rest_ratio * p * alpha
    n_out = theta_out.shape[0]
    m_out = impacts_out.shape[0]

    th, om = start.theta, start.omega
    mode = REST
    s = 1.0
    if th != 0.0 or om != 0.0:
        mode = ROCK
        s = 1.0 if (th > 0.0 or (th == 0.0 and om > 0.0)) else -1.0
    t = start.t
    theta_max = abs(th)
    n_imp = 0
    n_up = 0
    n_events = 0
    fric_max = 0.0
    status = 0
    overturned = False
    t_over = math.nan
    t_first = math.nan
    h = min(h_max, dt) * FIRST_STEP_FRACTION
    out_k = 0
    handed_off = False
    capped = False
    max_steps = MAX_STEPS_PER_SAMPLE * n + MAX_STEPS_FIXED
    n_steps = 0
    t_event = -math.inf               # time of the last event (uplift or impact), and events in a row there
    n_same = 0
    if n_out > 0:
        # the history from the start's sample on (a restart mid-record leaves the earlier samples as they are)
        out_k = max(int(math.ceil(start.t / dt - SAMPLE_INDEX_TOL)), 0)
        if out_k == 0:
            theta_out[0] = th
            out_k = 1

    while t < t_end:
        k = int(t / dt + SAMPLE_INDEX_TOL)
        t0 = k * dt
        t1 = min(t0 + dt, t_end)
        if t1 <= t:                       # rounding at a sample boundary
            k += 1
            t0 = k * dt
            t1 = min(t0 + dt, t_end)
        if k < n - 1:
            a0, a1 = ah[k], ah[k + 1]
            v0 = av[k] if has_v else 0.0
            v1 = av[k + 1] if has_v else 0.0
        else:
            a0 = a1 = v0 = v1 = 0.0
            if tail_energy and t >= t_rec:
                break
        sa = (a1 - a0) / dt
        sv = (v1 - v0) / dt
        if mode == REST:
            if k >= n - 1:                # nothing moves it any more
                t = t_end
                break
            if t == t0 and k + 1 < n:
                # fast scan over whole sample intervals that cannot lift the block (linear pieces:
                # below the threshold at both ends means below it throughout)
                j = k
                while j + 1 < n:
                    gj = g + (av[j] if has_v else 0.0)
                    gj1 = g + (av[j + 1] if has_v else 0.0)
                    if abs(ah[j]) > gj * thr or abs(ah[j + 1]) > gj1 * thr or gj <= 0.0 or gj1 <= 0.0:
                        break
                    j += 1
                if j > k:
                    while out_k < n_out and out_k <= j:
                        theta_out[out_k] = 0.0
                        out_k += 1
                    t = min(j * dt, t_end)
                    continue
            aa0, vv0 = a0 + sa * (t - t0), v0 + sv * (t - t0)
            aa1, vv1 = a0 + sa * (t1 - t0), v0 + sv * (t1 - t0)
            xf = _flight_fraction(vv0, vv1, g) if has_v else -1.0
            x = _exceed_fraction(aa0, aa1, vv0, vv1, g, thr)
            if xf >= 0.0 and (x < 0.0 or x >= xf):
                # the ground falls faster than gravity before the block lifts: contact is lost
                t = t + xf * (t1 - t)
                status |= STATUS_GROUND_FLIGHT
                break
            if x >= 0.0:
                t_up = t + x * (t1 - t)
                n_same = events_at_instant_compiled(t_up, t_event, n_same)
                t_event = t_up
                if n_same > MAX_EVENTS_AT_ONE_INSTANT:
                    # tie rule 6: uplift and fall back at one instant without end: held at rest to the next sample
                    status |= STATUS_TIE_HOLD
                    n_same = 0
                    x = -1.0
            if x < 0.0:
                t = t1
            else:
                t = t_up
                a_now = a0 + sa * (t - t0)
                s = -1.0 if a_now > 0.0 else 1.0
                th, om = 0.0, 0.0
                mode = ROCK
                n_up += 1
                n_events += 1
                h = min(h_max, dt) * UPLIFT_STEP_FRACTION
            while out_k < n_out and out_k * dt <= t + HISTORY_TIME_TOL_S:
                theta_out[out_k] = 0.0
                out_k += 1
            continue

        # rocking: one adaptive step inside the sample interval
        n_steps += 1
        if n_steps > max_steps:
            status |= STATUS_STEP_CAP
            capped = True
            break
        min_step = max(MIN_STEP_S, min_advance_compiled(t))
        hh = min(h, h_max, t1 - t)
        if hh <= min_step:
            hh = t1 - t
        th1, om1, et, eo, acc1 = _dopri_step(t, th, om, hh, t0, a0, sa, v0, sv, s, p2, alpha, g, linear)
        sc_t = atol_t + control.rtol * max(abs(th), abs(th1))
        sc_o = atol_o + control.rtol * max(abs(om), abs(om1))
        err = math.sqrt(0.5 * ((et / sc_t) ** 2 + (eo / sc_o) ** 2))
        if err > 1.0 and hh > min_step:
            h = hh * max(MIN_FACTOR_REJECTED, SAFETY * err ** ERROR_EXPONENT)
            if h < min_step:
                status |= STATUS_STEP_UNDERFLOW
                h = min_step
            continue
        if has_v and g + v0 + sv * (t + hh - t0) <= 0.0:
            # contact lost during the step (g + a_v <= 0): the contact model holds no further; the state is
            # carried to that instant
            hf = _flight_fraction(v0 + sv * (t - t0), v0 + sv * (t + hh - t0), g) * hh
            if hf > 0.0:
                th, om, _et, _eo, _acc = _dopri_step(t, th, om, hf, t0, a0, sa, v0, sv, s, p2, alpha, g, linear)
                theta_max = max(theta_max, abs(th))
            t = t + hf
            status |= STATUS_GROUND_FLIGHT
            break
        # accepted: events inside the step
        x = -1.0
        if s * th1 < 0.0:
            x = _first_crossing(th, om, th1, om1, hh, s)
            if x < 0.0:
                x = 1.0
        elif s * om < 0.0 and s * om1 > 0.0:
            x = _first_crossing(th, om, th1, om1, hh, s)
        if x >= 0.0:
            hs, ths, oms = _locate_impact(t, th, om, hh, x, t0, a0, sa, v0, sv, s, p2, alpha, g, linear)
            theta_max = max(theta_max, abs(th), abs(ths))
            if s * om > 0.0 and s * oms < 0.0:
                theta_max = max(theta_max, _hermite_peak(th, om, ths, oms, hs))
            t = t + hs
            out_k = _fill_hermite(theta_out, out_k, dt, t - hs, hs, th, om, ths, oms, t)
            om_after = e * oms                                   # Housner: omega ratio e, energy ratio e^2
            if n_imp < m_out:
                impacts_out[n_imp, 0] = t
                impacts_out[n_imp, 1] = oms
                impacts_out[n_imp, 2] = om_after
            if n_imp == 0:
                t_first = t
            n_imp += 1
            n_events += 1
            th, om, s = 0.0, om_after, -s
            n_same = events_at_instant_compiled(t, t_event, n_same)
            t_event = t
            if abs(om) < rest_omega or n_events >= control.max_events:
                if n_events >= control.max_events:
                    status |= STATUS_CHATTER
                om = 0.0
                mode = REST
            if n_same > MAX_EVENTS_AT_ONE_INSTANT:
                # tie rule 6: impacts without time advancing: held at rest (theta = 0 here) to the next sample
                status |= STATUS_TIE_HOLD
                n_same = 0
                om = 0.0
                mode = REST
                t = t1
            h = max(hh, MIN_STEP_AFTER_IMPACT_P / p)    # the new pivot's motion is smooth: keep the step size
            continue
        if abs(th1) >= HALF_PI:
            frac = (HALF_PI - abs(th)) / max(abs(th1) - abs(th), TINY)
            t_over = t + frac * hh
            overturned = True
            theta_max = HALF_PI
            mode = OVERTURNED
            t = t_over
            break
        # friction and lift-off demand at the step end, while the block can still come back
        # (|theta| < alpha): past the saddle it falls whether or not the base slides
        if abs(th1) < alpha:
            demand, lifted = _contact_demand(th1, om1, acc1, s, alpha, R, a0 + sa * (t + hh - t0),
                                             v0 + sv * (t + hh - t0), g)
            if lifted:
                status |= STATUS_LIFTOFF
            else:
                fric_max = max(fric_max, demand)
            if lifted and block.stop_mu < math.inf or not lifted and demand > block.stop_mu:
                # pure rocking stops holding inside this step: stop at its start, the last state where it held
                # (the general contact model continues from there and locates the event itself)
                if not lifted:
                    status |= STATUS_FRICTION
                handed_off = True
                break
        if om * om1 < 0.0:
            theta_max = max(theta_max, _hermite_peak(th, om, th1, om1, hh))
        theta_max = max(theta_max, abs(th1))
        out_k = _fill_hermite(theta_out, out_k, dt, t, hh, th, om, th1, om1, t + hh)
        t = t + hh
        th, om = th1, om1
        h = hh * min(MAX_FACTOR, max(MIN_FACTOR, SAFETY * err ** ERROR_EXPONENT)) if err > 0 else hh * MAX_FACTOR

    if not overturned and mode == ROCK and (capped or tail_energy and t >= t_rec - TAIL_TIME_TOL_S
                                            and not status & STATUS_GROUND_FLIGHT and not handed_off):
        # after the record (or where the step budget ended the scene): the energy of the free motion decides
        over, peak, extra = free_outcome(th, om, p2, alpha, e, linear)
        theta_max = max(theta_max, peak)
        if over:
            overturned = True
            t_over = t
            mode = OVERTURNED
            n_imp += extra                 # the impact on the way, before the escaping swing
    return RockingOutcome(overturned, t_over, theta_max, n_imp, fric_max, status, t, th, om, mode, n_up, t_first, s)


def empty_theta() -> np.ndarray:
    """An empty output array (skip the theta history)."""
    return np.zeros(0)


def empty_impacts() -> np.ndarray:
    """An empty impact log."""
    return np.zeros((0, 3))
