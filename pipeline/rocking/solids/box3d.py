"""A box rocking on an edge or on a corner of its base under both horizontal components of the ground and the
vertical: the 3D model of a statue, cabinet or square column that has a depth.

The box (half-width ``b_x`` along its body axis x, half-depth ``b_y`` along y, half-height ``h``; its centre of
mass G at the centre) stands on a rigid ground that moves with acceleration ``(a_x, a_y, a_z)``. Its orientation
is a unit quaternion ``q`` (body to world), its angular velocity ``omega`` is in the world's axes. The base's
corners are numbered counter-clockwise seen from above, ``c_k = (s_x b_x, s_y b_y, -h)`` with ``(s_x, s_y)`` =
(+, +), (-, +), (-, -), (+, -); edge ``k`` joins corner ``k`` to corner ``k + 1``, and a positive rotation about
the direction from the one to the other lifts the rest of the base.

**Contact modes.** The contact does not slip (friction is checked, below). On a *corner* P the box turns about a
fixed point (three degrees of freedom: a heavy top on a moving base, Goldstein, Poole & Safko 2002, section 5.7):
with ``r = G - P`` and ``I_P = I_G + |r|^2 1 - r r^T`` (per unit mass), Euler's equation about P is::

    I_P omega' = r x g_eff - omega x I_P omega,        g_eff = (-a_x, -a_y, -g - a_z)

and ``q' = (0, omega) q / 2``. On an *edge* (two corners on the ground) it turns about the edge's fixed axis ``u``:
``omega = s u`` and ``s' = u . (r x g_eff) / (u^T I_P u)``, the planar rocking equation of the box in the plane
across that edge (Housner 1963; ``u^T I_P u = 4 R^2 / 3`` for the plane of the width). These are the modes of
Zulli, Contento & Di Egidio (2012) and of Konstantinidis & Makris (2007), written here with a quaternion (no
Euler-angle singularity) and with the twist about the vertical left free on a corner (a point contact has no
torsional friction; Chatzis & Smyth 2012).

**Transitions.** At rest the box lifts about edge k when the inertial force's moment about it exceeds gravity's:
``-a_k (h) > (g + a_z) b_k`` with ``a_k`` the ground acceleration along the edge's outward normal (the threshold
``g tan(alpha)`` of the plane across that edge). On an edge, the normal forces at its two corners follow from
the moment the contact must supply about one of them (``M_P = I_P omega' + omega x I_P omega - r x g_eff``):
``N_2 = -M_P . (e_z x w) / L`` for the corner at distance ``L`` along ``w``, ``N_1 = F_z - N_2``; a corner whose
force falls to zero lifts, and the box turns on the other corner, when it would rise so; where it would not (the
corner's friction couples the two: sticking needs a pull, lifting would push it down), it slides on the ground
without friction while the box turns on the other corner (``omega = s u + psi' e_z``, u along the edge: the Euler
equation with that corner's normal force solved for ``s'``, ``psi''`` and the force) until the force falls to
zero (it lifts) or the twist stops (it sticks again where it can). On a corner, an adjacent corner that reaches the
ground lands. Where the box can go on turning on it alone, it does: the impulse acts at that corner, so the angular
momentum about it is conserved (Housner's rule about a point, ``omega+ = I_Q^-1 (I_G omega- + r_Q x v_G-)``,
``r_Q = G - Q``), and this holds where the impulse presses, inside the corner's friction cone, and the old pivot rises
(faster than :data:`REST_RATE` x ``p alpha`` x the base's smaller half side): a box that rolls from corner to corner
as the ground turns (``benchmarks/box_circular.py``). Otherwise the impulses act on the new edge's axis, so the
angular momentum about that axis is conserved and ``s+ = u . I_P omega- / (u^T I_P u)``. On an edge, the base that
lands flat rocks on the opposite edge with the angular momentum about it conserved (Housner 1963):
``s+ = u' . (I_G omega- + r' x (omega- x r)) / (u'^T I_P' u')``, which is Housner's ``e = 1 - 3/2 sin^2(alpha)`` in
the plane; a declared restitution scales it by its ratio to Housner's value (:attr:`Box.restitution_ratio`). When both
corners next to the pivot land together (a box turning on a corner along its diagonal lands flat), it turns on the
opposite corner with its angular momentum about that corner conserved, the same rule about a point; a single corner
landing is not scaled. A rebound slower than :data:`REST_RATE` x ``p alpha`` rests; more than
:data:`~.box_run.MAX_FLAT_LANDINGS_PER_SAMPLE` flat landings inside one sample interval (a cascade at the threshold of
uplift, its rebounds too small to show at the samples) hold the box at rest to the next sample, as the planar kernel's
tie rule holds a flat block (counted: ``holds``).
Landings are located on the step's cubic of the corner's height; a corner that has just lifted lands where it
returns to the ground.

At rest the box would slide where ``|a_h| > mu (g + a_z)`` (the exact boundary holds): it is not followed in 3D,
the run stops there, flagged.

**Overturning** is the body's axis reaching the horizontal (``R_zz <= 0``) while the ground moves. The contact
force ``F = a_G - g_eff`` is checked on every accepted step: the scene is flagged where the base would leave the
ground (``F_z <= 0``) or slide (``|F_h| > mu F_z``), as in :mod:`.cylinder3d`; on an edge, friction is also checked
at each of its two corners (Coulomb's law at each contact point): their forces across the edge are fixed by the yaw
couple (the second corner's from its Euler equation about the pivot, ``M_z / L``), those along it only in sum, and a
corner that cannot hold is a slide (the box would twist: not followed, no verdict); the same rule holds past the
tipping point (the fall followed with the contact held can confirm an overturning, never make the box stand).
The equations are integrated by the Dormand-Prince 5(4) pair with error control on all seven states; no step
crosses a sample of the record; a cap on the steps ends a run that does not advance, flagged.

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. BSSA 53(2), 403-417.
Konstantinidis, D. & Makris, N. (2007). The dynamics of a rocking block in three dimensions. Proc. 8th HSTAM
International Congress on Mechanics, Patras.
Zulli, D., Contento, A. & Di Egidio, A. (2012). 3D model of rigid block with a rectangular base subject to
pulse-type excitation. Int. J. Non-Linear Mech. 47(6), 679-687.
Chatzis, M. N. & Smyth, A. W. (2012). Modeling of the 3D rocking problem. Int. J. Non-Linear Mech. 47(4),
85-98.
Goldstein, H., Poole, C. & Safko, J. (2002). Classical Mechanics, 3rd ed., Addison Wesley.
Dormand, J. R. & Prince, P. J. (1980). A family of embedded Runge-Kutta formulae. J. Comput. Appl. Math. 6(1),
19-26.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .box_kernel import CORNER, EDGE, REST_RATE
from .box_run import run_box
from .convex_body import ConvexBody, box_body
from .handoff3d import BoxHandoff, BoxState
from .vec3 import FLAG_FLIGHT, FLAG_NONE, FLAG_SLIDE, FLAG_STEPS, ground_components

__all__ = ["Box", "BoxOutcome", "FLAG_NONE", "FLAG_FLIGHT", "FLAG_SLIDE", "FLAG_STEPS", "CORNER", "EDGE",
           "REST_RATE", "simulate_box", "housner_e_box", "box_from_corner", "box_energy", "BoxState"]

HALF_PI = 0.5 * math.pi

#: Default tolerances of the step control: relative, and absolute as a fraction of alpha (angles) and of
#: p alpha (rates)
RTOL = 1e-8
ATOL_ALPHA = 1e-9


class Box(NamedTuple):
    """A box with a depth (per unit mass).

    Attributes
    ----------
    half_width_m : float
        half the base dimension along the body's x axis b_x [m]
    half_depth_m : float
        half the base dimension along the body's y axis b_y [m]
    half_height_m : float
        half the height h [m]
    mu : float
        friction coefficient [-]
    restitution_ratio : float
        the rebound's rate at a flat landing over Housner's (1963) value for the plane the box lands in [-]
        (1: Housner's; :func:`housner_e_box` gives his value in a plane)
    """

    half_width_m: float
    half_depth_m: float
    half_height_m: float
    mu: float
    restitution_ratio: float = 1.0

    def convex(self) -> ConvexBody:
        """The contact model's body of this box: its eight corners (plastic contacts, which give Housner's rule at a
        pivot)."""
        return box_body(2.0 * self.half_width_m, 2.0 * self.half_depth_m, 2.0 * self.half_height_m, mu=self.mu)


class BoxOutcome(NamedTuple):
    """What a 3D box run gives.

    Attributes
    ----------
    overturned : bool
    t_overturn_s : float
        when the body's axis reached the horizontal [s] (NaN when standing)
    theta_max_rad : float
        the peak tilt of the body's axis from the vertical [rad]
    azimuth_max_deg : float
        the azimuth the axis leaned toward at the peak tilt [deg, from x toward y]
    flag : int
        FLAG_NONE, FLAG_FLIGHT, FLAG_SLIDE or FLAG_STEPS (see the module)
    impacts : int
        landings counted (flat, and a corner onto an edge)
    corner_s : float
        time spent turning on a single corner [s]
    theta, azimuth : ndarray
        the tilt of the body's axis [rad] and its azimuth [rad] at the record's samples
    end : BoxState
        where the run ended
    friction_demand : float
        the peak |F_h| / F_z while it rocked [-]
    held : int
        the flag held while the box fell past its tipping point (see the module), FLAG_NONE otherwise
    steps : int
        the Runge-Kutta steps tried (accepted and rejected) and the transitions (what the run cost)
    holds : int
        cascades of flat landings held at rest to the next sample (more than
        :data:`~.box_run.MAX_FLAT_LANDINGS_PER_SAMPLE` in one sample interval: rebounds too small to show at the
        samples, at the threshold of uplift)
    handoff : BoxHandoff or None
        the last state the model certified before it first stopped or held (the start of the step whose contact
        force left the cone, or the instant at rest it would slide); None where it never did
    """

    overturned: bool
    t_overturn_s: float
    theta_max_rad: float
    azimuth_max_deg: float
    flag: int
    impacts: int
    corner_s: float
    theta: np.ndarray
    azimuth: np.ndarray
    end: BoxState
    friction_demand: float
    held: int
    steps: int = 0
    holds: int = 0
    handoff: BoxHandoff | None = None


def housner_e_box(half_width_m: float, half_height_m: float) -> float:
    """Housner's (1963) coefficient of restitution of a box rocking in the plane of a base dimension
    ``1 - 3/2 sin^2(alpha)`` [-]."""
    return 1.0 - 1.5 * math.sin(math.atan2(half_width_m, half_height_m)) ** 2


def box_from_corner(R_m: float, alpha: float, depth_m: float, *, mu: float, restitution: float) -> Box:
    """The :class:`Box` of half-width R sin(alpha), half-height R cos(alpha) and the given depth [m], whose flat
    landings keep the ratio of ``restitution`` (declared in the plane of the width) to Housner's value there."""
    e_h = housner_e_box(R_m * math.sin(alpha), R_m * math.cos(alpha))
    return Box(half_width_m=R_m * math.sin(alpha), half_depth_m=0.5 * depth_m, half_height_m=R_m * math.cos(alpha),
               mu=mu, restitution_ratio=restitution / e_h if e_h > 0.0 else 0.0)


def box_energy(state: BoxState, box: Box, *, g_ms2: float = 9.80665, pivot: int = -1) -> float:
    """The mechanical energy per unit mass of a box turning about a fixed base corner [m2 s-2]: g times G's
    height above the ground (the lowest corner at the ground) plus the kinetic energy of the rotation about the
    pivot corner (``pivot``, default the lowest)."""
    (q0, q1, q2, q3), (wx, wy, wz) = (float(v) for v in state.q), (float(v) for v in state.rate_rad_s)
    n = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    q0, q1, q2, q3 = q0 / n, q1 / n, q2 / n, q3 / n
    rot = np.array([[1 - 2 * (q2 * q2 + q3 * q3), 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)],
                    [2 * (q1 * q2 + q0 * q3), 1 - 2 * (q1 * q1 + q3 * q3), 2 * (q2 * q3 - q0 * q1)],
                    [2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), 1 - 2 * (q1 * q1 + q2 * q2)]])
    bx, by, hz = box.half_width_m, box.half_depth_m, box.half_height_m
    corners = np.array([[bx, by, -hz], [-bx, by, -hz], [-bx, -by, -hz], [bx, -by, -hz]]) @ rot.T
    k = int(np.argmin(corners[:, 2])) if pivot < 0 else pivot
    r = -corners[k]
    inertia_g = rot @ np.diag([(by * by + hz * hz) / 3, (bx * bx + hz * hz) / 3, (bx * bx + by * by) / 3]) @ rot.T
    inertia_p = inertia_g + (r @ r) * np.eye(3) - np.outer(r, r)
    w = np.array([wx, wy, wz])
    return float(g_ms2 * r[2] + 0.5 * w @ inertia_p @ w)


def simulate_box(ax_ms2, ay_ms2, az_ms2, dt_s: float, box: Box, *, azimuth_deg: float = 0.0,
                 g_ms2: float = 9.80665, rtol: float = RTOL, atol_alpha: float = ATOL_ALPHA,
                 start: BoxState | None = None) -> BoxOutcome:
    """Run a box on two horizontal components and the vertical of a record (the module's model).

    Parameters
    ----------
    ax_ms2, ay_ms2, az_ms2 : array_like
        ground acceleration along x, y (horizontal, y 90 deg counter-clockwise of x seen from above) and up
        [m s-2], one sample each per ``dt_s``; ``az_ms2`` may be None (no vertical)
    dt_s : float
        sampling interval [s]
    box : Box
    azimuth_deg : float
        the direction of the box's width axis at rest [deg, from x toward y]
    g_ms2 : float
        gravity [m s-2]
    rtol, atol_alpha : float
        tolerances of the step control (relative; absolute as a fraction of the smaller alpha, and of p alpha for
        rates)
    start : BoxState, optional
        the state at the first sample (turning on its ``pivot`` in its ``mode``); default at rest at
        ``azimuth_deg``

    Returns
    -------
    BoxOutcome
        After overturning the tilt reads pi/2; after a flag (flight, sliding, the step cap) NaN.
    """
    ax, ay, az = ground_components(ax_ms2, ay_ms2, az_ms2)
    dims = (box.half_width_m, box.half_depth_m, box.half_height_m)
    if not all(math.isfinite(v) and v > 0 for v in dims):
        raise ValueError(f"the box's half-dimensions are {dims} m; expected three positive finite lengths")
    if start is None:
        psi = math.radians(azimuth_deg)
        y0 = np.array([math.cos(psi / 2), 0.0, 0.0, math.sin(psi / 2), 0.0, 0.0, 0.0])
        mode, pivot = -1, 0
    else:
        y0, mode, pivot = np.concatenate([start.q, start.rate_rad_s]).astype(float), int(start.mode), int(start.pivot)
    tilt = np.full(ax.size, np.nan)
    azimuth = np.full(ax.size, np.nan)
    y_end, cert = np.empty(7), np.full(10, np.nan)
    r = run_box(ax, ay, az, float(dt_s), float(g_ms2), *dims, float(box.mu), float(box.restitution_ratio),
                float(rtol), float(atol_alpha), y0, mode, pivot, tilt, azimuth, y_end, cert)
    if r.overturned:
        k = int(np.ceil(r.t_overturn / dt_s))
        tilt[k:], azimuth[k:] = HALF_PI, r.azimuth_max
    return BoxOutcome(bool(r.overturned), float(r.t_overturn), float(r.tilt_max),
                      float(np.degrees(r.azimuth_max) % 360.0), int(r.flag), int(r.impacts), float(r.corner_s),
                      tilt, azimuth, BoxState(y_end[:4].copy(), y_end[4:].copy(), int(r.mode), int(r.pivot)),
                      float(r.demand), int(r.held), int(r.steps), int(r.holds), _handoff(cert))


def _handoff(cert: np.ndarray) -> BoxHandoff | None:
    """The kernel's certified state (t, the 7 states, the mode, the pivot: :func:`~.box_run.certify`) as a
    :class:`~.handoff3d.BoxHandoff` (None: t NaN, it never stopped nor held)."""
    if not math.isfinite(cert[0]):
        return None
    return BoxHandoff(float(cert[0]), BoxState(np.array(cert[1:5]), np.array(cert[5:8]), int(cert[8]), int(cert[9])))
