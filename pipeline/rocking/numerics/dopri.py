"""The rocking kernel's Runge-Kutta step, its dense output and the location of impacts inside a step.

The equation of motion of a rocking block (:func:`rocking_accel`) is integrated by the embedded
Dormand-Prince 5(4) pair (:func:`dopri_step`, which also returns the error estimate the step control of
:mod:`.kernel` reads). Within an accepted step, theta is the cubic Hermite interpolant of the step's ends
(:func:`hermite`): it finds where theta changes sign (:func:`first_crossing`), the turning point's |theta|
(:func:`hermite_peak`) and the history at the samples (:func:`fill_hermite`); :func:`locate_impact` then
refines an impact on the Runge-Kutta solution itself by Newton iterations on the step length.

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
"""

from __future__ import annotations

import math

from ...compiled import jit
from .rk import DOPRI54

# Event location and dense output, named once
NEWTON_ITERATIONS = 8           # Newton iterations locating an impact on the step length
NEWTON_TOL_ALPHA = 1e-13        # |theta| accepted as the impact, as a fraction of alpha
HISTORY_TIME_TOL_S = 1e-12      # a history sample at k dt belongs to a step that ends within this of it [s]
CROSSING_PROBES = 16            # a step's Hermite cubic is probed at this many points for theta's sign change
CROSSING_BISECTIONS = 50        # ... then bisected this many times (2^-50 of the probe's span)
PEAK_BISECTIONS = 40            # bisections locating the turning point of theta inside a step

# The Dormand & Prince (1980) RK5(4)7M tableau (:data:`.rk.DOPRI54`) as scalars, for the step unrolled over a plane's
# two states (:func:`dopri_step`)
_T = DOPRI54
C2, C3, C4, C5 = (float(c) for c in _T.nodes[:4])
A21 = float(_T.rows[0, 0])
A31, A32 = (float(a) for a in _T.rows[1, :2])
A41, A42, A43 = (float(a) for a in _T.rows[2, :3])
A51, A52, A53, A54 = (float(a) for a in _T.rows[3, :4])
A61, A62, A63, A64, A65 = (float(a) for a in _T.rows[4, :5])
B1, B3, B4, B5, B6 = (float(_T.b[j]) for j in (0, 2, 3, 4, 5))
E1, E3, E4, E5, E6, E7 = (float(_T.e[j]) for j in (0, 2, 3, 4, 5, 6))


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
    return accel_nonlinear(math.sin(phi), math.cos(phi), ah, av, p2, g)


@jit
def accel_nonlinear(sin_phi, cos_phi, ah, av, p2, g):
    """:func:`rocking_accel` of the nonlinear model from sin and cos of phi = alpha s - theta."""
    return -p2 * ((1.0 + av / g) * sin_phi + (ah / g) * cos_phi)


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


@jit
def dopri_step(t, th, om, h, pc, s, p2, alpha, g, linear):
    """One Dormand-Prince step of length ``h`` [s] from (t, theta, omega) on pivot side ``s`` under the ground
    piece ``pc`` (:class:`~.structures.GroundPiece`); returns theta, omega, their error estimates, the
    angular acceleration at the step's end, and sin and cos of alpha s - theta there (what the pivot's forces
    need: computed once, the same doubles as :func:`rocking_accel`'s).

    This is :func:`~.rk.rk_step` with :data:`~.rk.DOPRI54`, unrolled over the two scalar states and summed in its
    order (the same doubles: tested): the planar kernel's hot path, where the loop over arrays measured 45 %
    slower on the bundled records' rocking scenes."""
    t0, a0, sa, v0, sv = pc.t0, pc.a0, pc.sa, pc.v0, pc.sv
    k1t = om
    k1o = rocking_accel(th, om, a0 + sa * (t - t0), v0 + sv * (t - t0), s, p2, alpha, g, linear)
    y2t, y2o = th + h * (A21 * k1t), om + h * (A21 * k1o)
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
    ah7, av7 = a0 + sa * (tt - t0), v0 + sv * (tt - t0)
    phi7 = alpha * s - th1                          # rocking_accel at the step's end, its sin and cos kept
    sin7, cos7 = math.sin(phi7), math.cos(phi7)
    k7t = om1
    k7o = -p2 * ((1.0 + av7 / g) * phi7 + ah7 / g) if linear else accel_nonlinear(sin7, cos7, ah7, av7, p2, g)
    et = h * (E1 * k1t + E3 * k3t + E4 * k4t + E5 * k5t + E6 * k6t + E7 * k7t)
    eo = h * (E1 * k1o + E3 * k3o + E4 * k4o + E5 * k5o + E6 * k6o + E7 * k7o)
    return th1, om1, et, eo, k7o, sin7, cos7


@jit
def hermite(th0, om0, th1, om1, h, x):
    """Cubic Hermite interpolant of theta on a step, at fraction x in [0, 1]."""
    x2 = x * x
    x3 = x2 * x
    return ((2 * x3 - 3 * x2 + 1) * th0 + (x3 - 2 * x2 + x) * h * om0
            + (-2 * x3 + 3 * x2) * th1 + (x3 - x2) * h * om1)


@jit
def first_crossing(th0, om0, th1, om1, h, s):
    """Fraction of the step where s*theta first drops below 0 on the Hermite cubic, or -1."""
    prev = 0.0
    for i in range(1, CROSSING_PROBES + 1):
        x = i / CROSSING_PROBES
        v = s * hermite(th0, om0, th1, om1, h, x)
        if v < 0.0:
            lo, hi = prev, x
            for _ in range(CROSSING_BISECTIONS):
                mid = 0.5 * (lo + hi)
                if s * hermite(th0, om0, th1, om1, h, mid) < 0.0:
                    hi = mid
                else:
                    lo = mid
            return 0.5 * (lo + hi)
        prev = x
    return -1.0


@jit
def hermite_rate(th0, om0, th1, om1, h, x):
    """d theta / d x of the Hermite cubic at fraction x (x = (t - t0) / h)."""
    x2 = x * x
    return ((6 * x2 - 6 * x) * (th0 - th1) + (3 * x2 - 4 * x + 1) * h * om0 + (3 * x2 - 2 * x) * h * om1)


@jit
def hermite_peak(th0, om0, th1, om1, h):
    """Largest |theta| of the Hermite cubic inside a step where omega changes sign."""
    best = max(abs(th0), abs(th1))
    lo, hi = 0.0, 1.0
    # the cubic's rate keeps the sign of omega0 until the turning point: bisection on it
    for _ in range(PEAK_BISECTIONS):
        mid = 0.5 * (lo + hi)
        if hermite_rate(th0, om0, th1, om1, h, mid) * om0 > 0:
            lo = mid
        else:
            hi = mid
    return max(best, abs(hermite(th0, om0, th1, om1, h, 0.5 * (lo + hi))))


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
