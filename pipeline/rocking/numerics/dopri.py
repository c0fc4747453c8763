"""The rocking kernel's Runge-Kutta step, its dense output and the location of impacts inside a step.

The equation of motion of a rocking block (:func:`rocking_accel`) is integrated by the embedded
Dormand-Prince 5(4) pair (:func:`dopri_step`, which also returns the error estimate the step control of
:mod:`.kernel` reads). The seven stages of a step need sin and cos of alpha s - theta: they are taken by
math.sin and math.cos at the step's two ends, and inside it rotated from the start's by the stage's change of theta
(:func:`_rotated`) where that change is at most :data:`ROTATION_MAX_RAD`. Within an accepted step, theta is the
cubic Hermite interpolant of the step's ends (:func:`hermite`): it finds where theta changes sign
(:func:`first_crossing`, safeguarded Newton on the cubic), the turning point's |theta| (:func:`hermite_peak`, the
root of the cubic's rate in closed form) and the history at the samples (:func:`fill_hermite`);
:func:`locate_impact` then refines an impact on the Runge-Kutta solution itself by Newton iterations on the step
length.

References
----------
Dormand, J. R. & Prince, P. J. (1980). A family of embedded Runge-Kutta formulae. J. Comput. Appl. Math.
6(1), 19-26.
Hairer, E., Norsett, S. P. & Wanner, G. (1993). Solving Ordinary Differential Equations I, 2nd ed.,
Springer, section II.6 (dense output, event location).
Zhang, J. & Makris, N. (2001). Rocking response of free-standing blocks under cycloidal pulses. J. Eng. Mech.
127(5), 473-483 (the forces at the pivot, eqs. 16-20).
Makris, N. & Roussos, Y. (2000). Rocking response of rigid blocks under near-source ground motions.
Geotechnique 50(3), 243-262 (the equation of motion, eqs. 1-3 and 8-9).
Yim, C.-S., Chopra, A. K. & Penzien, J. (1980). Rocking response of rigid blocks to earthquakes.
Earthquake Eng. Struct. Dyn. 8(6), 565-587 (the vertical acceleration in the equation of motion).
Abramowitz, M. & Stegun, I. A. (1964). Handbook of Mathematical Functions. National Bureau of Standards,
formulas 4.3.16-4.3.17 (the sine and cosine of a difference) and 4.3.65-4.3.66 (their power series).
Press, W. H., Teukolsky, S. A., Vetterling, W. T. & Flannery, B. P. (2007). Numerical Recipes, 3rd ed., Cambridge
University Press, sections 5.6 (the quadratic's roots without cancellation) and 9.4 (Newton's method safeguarded
by bisection).
"""

from __future__ import annotations

import math

from ...compiled import jit, jit_inline
from .rk import DOPRI54, rk_step

# Event location and dense output, named once
NEWTON_ITERATIONS = 8           # Newton iterations locating an impact on the step length
NEWTON_TOL_ALPHA = 1e-13        # |theta| accepted as the impact, as a fraction of alpha
HISTORY_TIME_TOL_S = 1e-12      # a history sample at k dt belongs to a step that ends within this of it [s]
CROSSING_PROBES = 16            # a step's Hermite cubic is probed at this many points for theta's sign change
CROSSING_ITERATIONS = 60        # ... then at most this many safeguarded Newton iterations in the probes' bracket
CROSSING_TOL = 4.0 * 2.0 ** -52  # the crossing is taken where an iteration moves it by less than this fraction
#: Inside a step, sin and cos of alpha s - theta at a stage are those of the step's start rotated by the stage's
#: change d of theta (Taylor series of sin d to d^7 and cos d to d^6) where |d| is at most this [rad]: the first
#: terms left out, d^9 / 9! and d^8 / 8!, are then below 1e-19; beyond it math.sin and math.cos are called
ROTATION_MAX_RAD = 1.0 / 64.0

@jit
def rocking_accel(theta, omega, ah, av, s, p2, alpha, g, linear):
    """Angular acceleration [rad s-2] of a rectangular block rocking on pivot side s.

    Nonlinear (M&R eqs. 1-3 with g -> g + a_v, Yim 1980):
    theta'' = -p^2 [ (1 + a_v/g) sin(alpha s - theta) + (a_h/g) cos(alpha s - theta) ];
    linearised (M&R eqs. 8-9): sin(x) -> x, cos(x) -> 1.
    """
    phi = alpha * s - theta
    if linear:
        return accel_linear(phi, ah, av, p2, g)
    return accel_nonlinear(math.sin(phi), math.cos(phi), ah, av, p2, g)


@jit
def accel_nonlinear(sin_phi, cos_phi, ah, av, p2, g):
    """:func:`rocking_accel` of the nonlinear model from sin and cos of phi = alpha s - theta."""
    return -p2 * ((1.0 + av / g) * sin_phi + (ah / g) * cos_phi)


@jit
def accel_linear(phi, ah, av, p2, g):
    """:func:`rocking_accel` of the linearised model from phi = alpha s - theta."""
    return -p2 * ((1.0 + av / g) * phi + ah / g)


@jit
def pivot_demand(sin_phi, cos_phi, om, acc, R, a_h, a_v, g):
    """Friction and normal force per unit mass at the pivot of a rocking block (Zhang & Makris 2001,
    eqs. 16-20), from sin and cos of phi = alpha s - theta (:func:`dopri_step` returns them at a step's end),
    the angular velocity ``om`` and acceleration ``acc``, under the ground's ``a_h`` and ``a_v``: returns
    (|f_x| / f_z, lifted), lifted when f_z <= 0 (the demand is then 0, undefined)."""
    fx = a_h + R * acc * cos_phi + R * om * om * sin_phi
    fz = g + a_v + R * acc * sin_phi - R * om * om * cos_phi
    if fz <= 0.0:
        return 0.0, True
    return abs(fx) / fz, False


@jit_inline
def _plane(t, y, args):
    """f of a plane's (theta, omega) at ``t`` (``args``: the ground piece, pivot side, p^2, alpha, g, linear), as
    :func:`rocking_accel` writes it; sin and cos of alpha s - theta kept (what the pivot's forces need)."""
    pc, s, p2, alpha, g, linear = args
    th, om = y
    phi = alpha * s - th
    sin_phi, cos_phi = math.sin(phi), math.cos(phi)
    return (om, _accel_at(t, phi, sin_phi, cos_phi, pc, p2, g, linear)), (sin_phi, cos_phi)


@jit_inline
def _accel_at(t, phi, sin_phi, cos_phi, pc, p2, g, linear):
    """:func:`rocking_accel` at ``t`` under the ground piece ``pc`` (linear between its samples), from
    phi = alpha s - theta and its sin and cos."""
    ah, av = pc.a0 + pc.sa * (t - pc.t0), pc.v0 + pc.sv * (t - pc.t0)
    return accel_linear(phi, ah, av, p2, g) if linear else accel_nonlinear(sin_phi, cos_phi, ah, av, p2, g)


@jit_inline
def _rotated(sin0, cos0, d):
    """sin and cos of phi0 - d from those of phi0, for |d| <= :data:`ROTATION_MAX_RAD`: the angle-difference
    identities (Abramowitz & Stegun 1964, 4.3.16-17) with the series of sin d and cos d (4.3.65-66) by Horner's
    scheme in d^2. Within a few units in the last place of math.sin and math.cos of phi0 - d
    (``tests/rocking/numerics/test_properties_rotated.py``)."""
    d2 = d * d
    sin_d = d * (1.0 + d2 * (-1.0 / 6.0 + d2 * (1.0 / 120.0 + d2 * (-1.0 / 5040.0))))
    cos_d = 1.0 + d2 * (-0.5 + d2 * (1.0 / 24.0 + d2 * (-1.0 / 720.0)))
    return sin0 * cos_d - cos0 * sin_d, cos0 * cos_d + sin0 * sin_d


@jit_inline
def _plane_near(t, y, args):
    """:func:`_plane` at a stage of a step from theta0, whose sin and cos of alpha s - theta0 are known
    (``args``: _plane's, then theta0 and them): rotated by the stage's change of theta (:func:`_rotated`)."""
    pc, s, p2, alpha, g, linear, th0, sin0, cos0 = args
    th, om = y
    phi = alpha * s - th
    d = th - th0
    if abs(d) <= ROTATION_MAX_RAD:
        sin_phi, cos_phi = _rotated(sin0, cos0, d)
    else:
        sin_phi, cos_phi = math.sin(phi), math.cos(phi)
    return (om, _accel_at(t, phi, sin_phi, cos_phi, pc, p2, g, linear)), (sin_phi, cos_phi)


@jit
def dopri_step(t, th, om, h, pc, s, p2, alpha, g, linear):
    """One Dormand-Prince step (:func:`~.rk.rk_step` with :data:`~.rk.DOPRI54`) of length ``h`` [s] from
    (t, theta, omega) on pivot side ``s`` under the ground piece ``pc`` (:class:`~.structures.GroundPiece`);
    returns theta, omega, their error estimates, the angular acceleration at the step's end, and sin and cos of
    alpha s - theta there (what the pivot's forces need).

    The stages inside the step rotate the start's sin and cos by their change of theta (:func:`_plane_near`)
    where it is at most :data:`ROTATION_MAX_RAD`: then math.sin and math.cos are called at the step's two ends
    only, not at each of its seven stages. The last stage, rotated, enters the error estimate; the values returned
    at the end are evaluated once more by math.sin and math.cos, so that they are :func:`rocking_accel`'s own
    doubles."""
    y = (th, om)
    args = (pc, s, p2, alpha, g, linear)
    f, (sin0, cos0) = _plane(t, y, args)
    st = rk_step(_plane_near, (pc, s, p2, alpha, g, linear, th, sin0, cos0), t, y, f, h, DOPRI54)
    f_end, (sin_end, cos_end) = _plane(t + h, st.y, args)
    return st.y[0], st.y[1], st.err[0], st.err[1], f_end[1], sin_end, cos_end


@jit
def hermite(th0, om0, th1, om1, h, x):
    """Cubic Hermite interpolant of theta on a step, at fraction x in [0, 1]."""
    x2 = x * x
    x3 = x2 * x
    return ((2 * x3 - 3 * x2 + 1) * th0 + (x3 - 2 * x2 + x) * h * om0
            + (-2 * x3 + 3 * x2) * th1 + (x3 - x2) * h * om1)


@jit
def first_crossing(th0, om0, th1, om1, h, s):
    """Fraction of the step where s*theta first drops below 0 on the Hermite cubic, or -1: the first of
    :data:`CROSSING_PROBES` probes below 0 brackets it, then :func:`_bracketed_root`."""
    prev = 0.0
    for i in range(1, CROSSING_PROBES + 1):
        x = i / CROSSING_PROBES
        v = s * hermite(th0, om0, th1, om1, h, x)
        if v < 0.0:
            return _bracketed_root(th0, om0, th1, om1, h, s, prev, x)
        prev = x
    return -1.0


@jit
def _bracketed_root(th0, om0, th1, om1, h, s, lo, hi):
    """The root of the Hermite cubic between ``lo`` (s*theta >= 0) and ``hi`` (s*theta < 0): Newton's iterations
    on the cubic, the bracket narrowed by every evaluation; a Newton step that would leave the bracket, or that is
    more than half the last step, is a bisection instead (safeguarded Newton, after ``rtsafe`` of Press et al. 2007,
    section 9.4). Ends where a step moves the root by less than :data:`CROSSING_TOL` of it, or after
    :data:`CROSSING_ITERATIONS` (the last estimate, inside the bracket)."""
    dx_old = dx = hi - lo
    x = 0.5 * (lo + hi)
    for _ in range(CROSSING_ITERATIONS):
        v = s * hermite(th0, om0, th1, om1, h, x)
        if v == 0.0:
            return x
        if v < 0.0:
            hi = x
        else:
            lo = x
        rate = s * hermite_rate(th0, om0, th1, om1, h, x)
        dx_old, newton = dx, x - v / rate if rate != 0.0 else math.nan
        if lo < newton < hi and abs(2.0 * v) <= abs(dx_old * rate):
            dx = v / rate
            x = newton
        else:
            dx = 0.5 * (hi - lo)
            x = lo + dx
        if abs(dx) <= CROSSING_TOL * x:
            return x
    return x


@jit
def hermite_rate(th0, om0, th1, om1, h, x):
    """d theta / d x of the Hermite cubic at fraction x (x = (t - t0) / h)."""
    x2 = x * x
    return ((6 * x2 - 6 * x) * (th0 - th1) + (3 * x2 - 4 * x + 1) * h * om0 + (3 * x2 - 2 * x) * h * om1)


@jit
def hermite_peak(th0, om0, th1, om1, h):
    """Largest |theta| of the Hermite cubic inside a step where omega changes sign: at the turning point, the
    root in [0, 1] of the cubic's rate, a quadratic A x^2 + B x + C whose values at 0 and 1 (h omega0, h omega1)
    differ in sign, so that it has exactly one root there (the quadratic formula in its cancellation-free form;
    Press et al. 2007, section 5.6)."""
    best = max(abs(th0), abs(th1))
    d, a0, a1 = th0 - th1, h * om0, h * om1
    qa, qb, qc = 6.0 * d + 3.0 * a0 + 3.0 * a1, -6.0 * d - 4.0 * a0 - 2.0 * a1, a0
    x = _unit_root(qa, qb, qc)
    return max(best, abs(hermite(th0, om0, th1, om1, h, x)))


@jit
def _unit_root(qa, qb, qc):
    """The root in [0, 1] of A x^2 + B x + C, whose values at 0 and 1 differ in sign (clamped to [0, 1] against
    rounding). C / q is not it where it lies outside [0, 1], nor where it is 0 and the other root, q / A, lies in
    [0, 1]: C is then 0 or rounded to it (h omega0 a subnormal), and the rate changes sign at the other root."""
    disc = max(qb * qb - 4.0 * qa * qc, 0.0)
    q = -0.5 * (qb + math.copysign(math.sqrt(disc), qb))
    x = math.nan
    if q != 0.0:
        x = qc / q
    if qa != 0.0 and (not 0.0 <= x <= 1.0 or (x == 0.0 and 0.0 <= q / qa <= 1.0)):
        x = q / qa
    return min(max(x, 0.0), 1.0) if x == x else 0.5


@jit
def fill_hermite(theta_out, out_k, dt, t_start, h, th0, om0, th1, om1, t_stop):
    """theta at the samples k dt <= t_stop of a step from t_start of length h, from its cubic Hermite
    interpolant (0 for a step of length 0); returns the next sample to fill."""
    while out_k < theta_out.shape[0] and out_k * dt <= t_stop + HISTORY_TIME_TOL_S:
        theta_out[out_k] = hermite(th0, om0, th1, om1, h, (out_k * dt - t_start) / h) if h > 0 else 0.0
        out_k += 1
    return out_k


@jit
def locate_impact(t, th, om, hh, x, pc, s, p2, alpha, g, linear):
    """The impact inside an accepted step: Newton iterations on the step length, from the Hermite estimate
    ``x`` (a fraction of ``hh``), so that theta(t + h*) = 0 on the Runge-Kutta solution itself.
    Returns (h*, theta, omega) there."""
    hs = x * hh
    ths, oms = th, om
    for _ in range(NEWTON_ITERATIONS):
        ths, oms, _et, _eo, _acc, _sin, _cos = dopri_step(t, th, om, hs, pc, s, p2, alpha, g, linear)
        if oms == 0.0 or abs(ths) <= NEWTON_TOL_ALPHA * alpha:
            break
        hs = min(max(hs - ths / oms, 0.0), hh)
    return hs, ths, oms
