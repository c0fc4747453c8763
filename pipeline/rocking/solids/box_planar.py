"""Where a box with a depth may be judged in the plane of its width on two horizontals: a certificate that its other
base axis never lifts and its base never slips, from the record and the planar run's own peak tilt.

**The certificate.** Let the box (half-width ``b``, half-depth ``c``, half-height ``h``, ``R = sqrt(b^2 + h^2)``,
``alpha = atan(b / h)``) rock in the plane of its width on an edge parallel to its depth, tilt ``theta``, under the
ground's acceleration ``a_x`` along the width, ``a_y`` along the depth and ``a_v`` up (per unit mass throughout).
While both ends of the edge press, the box turns about the depth axis only, a principal axis: the angular momentum
about G stays along it, so the contact's moment about G along the width axis is zero. The normal forces ``N_1``,
``N_2`` at the edge's ends (``y = +c``, ``-c``; any load along a straight edge is equivalent to these) and the
friction, which carries the box with the ground across (``F_y = a_y``) at the ground, ``z_G`` below G, then give::

    c (N_1 - N_2) = -z_G a_y,    N_1 + N_2 = N = g + a_v + z_G''

so both ends press while ``|a_y| z_G <= c N``: flat on its base, the condition of uplift at rest about a depth
edge (``|a_y| h > c (g + a_v)``); on an edge, the same with the moving G. Friction holds while
``F_x^2 + a_y^2 <= mu^2 N^2``. Bounds from the planar run (``theta_max``: its peak |theta| < alpha; ``D``: its peak
|F_x / N| while rocking; at rest ``|F_x| / N = |a_x| / (g + a_v) <= tan alpha``, else it would have lifted):

* ``z_G = R cos(alpha - |theta|) <= R cos(alpha - theta_max)``;
* Housner's equation with the vertical (Yim, Chopra & Penzien 1980), ``p^2 = 3 g / (4 R)``, gives
  ``R |theta''| <= (3/4) ((g + a_v) sin(alpha) + |a_x|) =: A(t)`` for |theta| <= alpha;
* ``theta'^2 <= 2 max_t(A / R) theta_max``: a speed v at a tilt theta_0 was built up from a turning point (moving
  toward the pivot's side of zero, looking back) or is spent before one (moving away, looking forward), inside
  [-theta_max, theta_max] and with no impact on the way (impacts happen at theta = 0 and only slow it);
* ``z_G'' = R sin(alpha - |theta|) |theta|'' - R cos(alpha - |theta|) theta'^2 >= -(sin(alpha) A(t)
  + 2 theta_max max_t A)`` (the term in R cancels), hence ``N >= N_lb(t) = g + a_v - sin(alpha) A(t) - 2
  theta_max max_t A``.

**Friction at each end of the edge.** On an edge the friction is checked at each of its two ends, not on the total
force alone. The contact's moment about G along the vertical is zero too (the angular momentum stays along the depth
axis), and the edge lies ``d = R sin(alpha - |theta|) <= b`` from G across it, so the ends' forces across the edge
differ by a couple: ``X_1 - X_2 = d a_y / c``, ``X_1 + X_2 = F_x``; their normal forces are ``N_{1,2} = (N -+ z_G
a_y / c) / 2``; the forces along the edge add to ``a_y`` and split freely. Taking that split in proportion to the
normal forces, each end holds where ``|X_i| <= m' N_i`` with ``m' = sqrt(mu^2 - a_y^2 / N^2)``; with ``|X_i| <= (D'
N + b |a_y| / c) / 2`` and ``N_i >= (N - z_G |a_y| / c) / 2``, both hold where ``N (m' - D') >= |a_y| (b + m'
z_G) / c``, and (``m'`` growing with N) where it holds at ``N_lb``. A box with a cross motion can thus slip at one
end, and twist, where the total force is well inside the friction cone.

A planar run that never lifted leaves the box flat: there ``N = g + a_v`` and ``z_G = h`` exactly, its base carries
any couple, and the certificate is the exact condition of uplift and slip at rest (its boundary, equality,
certified). Certified where, at every sample, ``N_lb > 0``, ``|a_y| R cos(alpha - theta_max) <= c N_lb`` and, flat
throughout, ``a_y^2 <= (mu^2 - D'^2) N_lb^2``; having rocked, ``mu N_lb > |a_y|`` and ``N_lb (m' - D') >= |a_y| (b +
m' z_ub) / c`` with ``m' = sqrt(mu^2 - a_y^2 / N_lb^2)``; ``D' = max(D, min(max_t |a_x| / (g + a_v), tan alpha))``.
Between samples the ground is linear: the margins of the lift and of the flat slip conditions are concave there (a
linear term minus absolute values of linear terms), so their least value over an interval is at a sample, and the
check is exact for the bounds; the ends' friction condition (not concave: m' is a square root) is checked at the
samples. Under the
certificate the 3D model (:mod:`.box3d`) never leaves the edges of the depth axis, never slides, and follows the
planar equation of the width's plane, which it reduces to (tested to 1e-5 alpha on pulses); the planar run is kept.
In long trains of impacts with a restitution near 1 the two integrations can still part (5 of 1,100 certified
draws on the bundled records, none robust to x0.98 and x1.02: docs/validation.md). Only a planar run that stands by
pure rocking (or stays at rest) without a guard is certified; an overturning, a hand-off to the general contact
model or a flagged run go to the 3D model.

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. BSSA 53(2), 403-417.
Yim, C.-S., Chopra, A. K. & Penzien, J. (1980). Rocking response of rigid blocks to earthquakes. Earthquake
Engineering & Structural Dynamics 8(6), 565-587.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...constants import G
from ..block import Block
from ..planner import simulate_scene
from ..scene import Physics, Scene
from ..settings import SimulationConfig
from .box3d import Box, housner_e_box

#: The planar physics a certified scene may have: at rest, or pure rocking (with or without the vertical)
PLANAR_CERTIFIABLE = (Physics.none, Physics.rocking, Physics.rocking_vertical)

#: Housner's ratio R |theta''| / (g sin(alpha) + |a_x|) of a box [-]: R p^2 / g = 3/4 (I_O = 4 m R^2 / 3)
BOX_INERTIA_FACTOR = 0.75


class OtherAxis(NamedTuple):
    """The certificate of a box's other base axis (:func:`other_axis_certificate`).

    Attributes
    ----------
    certified : bool
        The depth edges' ends both press and friction holds at every sample, under the bounds of the module.
    lift_margin : float
        The least of ``1 - |a_y| z_G / (c N_lb)`` over the samples [-] (below 0: not certified; -inf where N_lb
        reached 0).
    slip_margin : float
        The least over the samples of ``1 - sqrt(D'^2 N_lb^2 + a_y^2) / (mu N_lb)`` (flat throughout), or of the
        worse end of the edge, ``1 - (D' N_lb + |a_y| (b + m' z_ub) / c) / (m' N_lb)`` (having rocked; -inf where
        ``mu N_lb <= |a_y|``) [-].
    """

    certified: bool
    lift_margin: float
    slip_margin: float


NOT_CERTIFIED = OtherAxis(False, -math.inf, -math.inf)


def other_axis_certificate(along_ms2, across_ms2, vertical_ms2, box: Box, *, theta_max_rad: float,
                           friction_demand: float, g_ms2: float = G) -> OtherAxis:
    """Whether a box rocking in the plane of its width, with the planar run's peak tilt and friction demand, keeps
    both ends of its depth edges on the ground and its base from slipping at every sample (the module's bounds).

    Parameters
    ----------
    along_ms2, across_ms2 : ndarray
        The ground's acceleration along the box's width and along its depth [m s-2].
    vertical_ms2 : ndarray or None
        The vertical, up positive [m s-2] (None: none).
    box : Box
        The box (its half-width, half-depth, half-height and friction).
    theta_max_rad : float
        The planar run's largest |theta| [rad]; at or above alpha nothing is certified.
    friction_demand : float
        The planar run's largest |F_x / F_z| while rocking [-].
    g_ms2 : float
        Gravity [m s-2].
    """
    b, c, h = box.half_width_m, box.half_depth_m, box.half_height_m
    alpha = math.atan2(b, h)
    if not theta_max_rad < alpha or not friction_demand < box.mu:
        return NOT_CERTIFIED
    ax = np.abs(np.asarray(along_ms2, dtype=float))
    ay = np.abs(np.asarray(across_ms2, dtype=float))
    gv = g_ms2 + (np.zeros_like(ax) if vertical_ms2 is None or np.size(vertical_ms2) == 0
                  else np.asarray(vertical_ms2, dtype=float))
    if np.any(gv <= 0.0):
        return NOT_CERTIFIED
    if theta_max_rad > 0.0:
        sin_a = math.sin(alpha)
        demand = BOX_INERTIA_FACTOR * (gv * sin_a + ax)                 # R |theta''| <= A(t)
        n_lb = gv - sin_a * demand - 2.0 * theta_max_rad * float(np.max(demand))
        z_ub = math.hypot(b, h) * math.cos(alpha - theta_max_rad)
    else:                                                               # flat throughout: N and z_G exact
        n_lb, z_ub = gv, h
    if np.any(n_lb <= 0.0):
        return NOT_CERTIFIED
    lift = 1.0 - float(np.max(ay * z_ub / (c * n_lb)))
    d = max(friction_demand, min(float(np.max(ax / gv)), b / h))
    if theta_max_rad > 0.0:
        slip = _edge_ends_margin(ay, n_lb, d, b=b, c=c, z_ub=z_ub, mu=box.mu)
    else:
        slip = 1.0 - float(np.max(np.sqrt((d * n_lb) ** 2 + ay ** 2) / (box.mu * n_lb)))
    return OtherAxis(lift >= 0.0 and slip >= 0.0, lift, slip)


def _edge_ends_margin(ay: np.ndarray, n_lb: np.ndarray, d: float, *, b: float, c: float, z_ub: float,
                      mu: float) -> float:
    """The least margin over the samples of friction at the worse end of the edge (the module's bound): 1 - (D' N_lb
    + |a_y| (b + m' z_ub) / c) / (m' N_lb), ``m' = sqrt(mu^2 - a_y^2 / N_lb^2)``; -inf where ``mu N_lb <= |a_y|``."""
    ratio = ay / n_lb
    if np.any(ratio >= mu):
        return -math.inf
    m = np.sqrt(mu * mu - ratio * ratio)
    return 1.0 - float(np.max((d * n_lb + ay * (b + m * z_ub) / c) / (m * n_lb)))


class CertifiedScene(NamedTuple):
    """A box's scene in the plane of its width (None where the record lifts the box at rest about a depth edge, so
    nothing can be certified and nothing was run), and its other axis's certificate."""

    scene: Scene | None
    other_axis: OtherAxis


def lifts_across_at_rest(across_ms2, vertical_ms2, box: Box, *, g_ms2: float = G) -> bool:
    """Whether the ground lifts the box at rest about an edge of its depth axis at some sample (``|a_y| h > c (g +
    a_v)``, or g + a_v <= 0): then no bound of :func:`other_axis_certificate` can hold (its N_lb <= g + a_v and its
    z_G bound >= h), and the planar run is not needed."""
    gv = g_ms2 + (0.0 if vertical_ms2 is None or np.size(vertical_ms2) == 0 else np.asarray(vertical_ms2))
    return bool(np.any(np.abs(across_ms2) * box.half_height_m > box.half_depth_m * gv) or np.any(gv <= 0.0))


def width_components(h1, h2, azimuth_deg: float):
    """The record's two horizontals (the second 90 deg clockwise of the first) resolved along a box's width and
    depth, the width at ``azimuth_deg`` from the first toward the reversed second (the 3D models' frame,
    :mod:`.solid3d`) [m s-2]."""
    x, y = np.asarray(h1, dtype=float), -np.asarray(h2, dtype=float)
    cs, sn = math.cos(math.radians(azimuth_deg)), math.sin(math.radians(azimuth_deg))
    return cs * x + sn * y, -sn * x + cs * y


def width_block(box: Box, *, g_ms2: float = G) -> Block:
    """The planar :class:`~.block.Block` of a box in the plane of its width, with the restitution of its flat
    landings there."""
    R = math.hypot(box.half_width_m, box.half_height_m)
    e = box.restitution_ratio * housner_e_box(box.half_width_m, box.half_height_m)
    return Block(p=math.sqrt(0.75 * g_ms2 / R), alpha=math.atan2(box.half_width_m, box.half_height_m),
                 e=min(max(e, 0.0), 1.0), R_m=R, mu=box.mu, g_ms2=g_ms2)


def planar_box_scene(h1, h2, vertical, dt_s: float, box: Box, azimuth_deg: float, *,
                     settings: SimulationConfig = SimulationConfig(), g_ms2: float = G, amplitude: float = 1.0,
                     history: bool = False) -> CertifiedScene:
    """The planar scene of a box in the plane of its width on a record's two horizontals and vertical (all scaled by
    ``amplitude``), and whether its other axis is certified (then the 3D model follows the same equation); no scene
    where the record lifts the box at rest about a depth edge (:func:`lifts_across_at_rest`)."""
    along, across = width_components(h1, h2, azimuth_deg)
    along, across = amplitude * along, amplitude * across
    av = None if vertical is None or np.size(vertical) == 0 else amplitude * np.asarray(vertical, dtype=float)
    if lifts_across_at_rest(across, av, box, g_ms2=g_ms2):
        return CertifiedScene(None, NOT_CERTIFIED)
    block = width_block(box, g_ms2=g_ms2)
    sc = simulate_scene(along, av, dt_s, block=block, settings=settings, history=history)
    dropped_vertical = av is not None and sc.physics == Physics.rocking      # the 3D model keeps it
    if sc.physics not in PLANAR_CERTIFIABLE or sc.overturned or sc.guard or dropped_vertical:
        return CertifiedScene(sc, NOT_CERTIFIED)
    cert = other_axis_certificate(along, across, av, box, theta_max_rad=sc.theta_max * block.alpha,
                                  friction_demand=sc.friction_demand, g_ms2=g_ms2)
    return CertifiedScene(sc, cert)
