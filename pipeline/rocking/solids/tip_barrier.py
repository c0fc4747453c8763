"""The least energy a convex body standing on the ground needs to tilt beyond an angle: a certificate that a body
still moving after the record stands, for runs that keep only the verdict (the draws and the margin scan).

A convex body whose lowest point touches the ground, turned so that its downward direction is the unit vector d in
its standing axes, has its centre of mass G at the height

    h(d) = max_i v_i . d

above the ground, the support function of its hull's vertices v_i about G (Schneider 2014, sec. 1.7). It stands at
d_0 = (0, 0, -1), where h(d_0) is G's height z_0. A body tilted by rho from its standing pose has d on the circle
C_rho of directions at the angle rho from d_0, and to tilt beyond ``rho_max`` it passes through every circle C_rho
with rho <= rho_max. Its energy per unit mass ``|v_G|^2 / 2 + omega . I omega / 2 + g z_G`` on the way is at least
g (h(d) - o), o the overlap of the ground its stepping allows, so it needs at least

    g (H - o),     H = max_rho min_{d in C_rho} h(d).                                        (1)

On a still ground the contacts only take energy away (Moreau 1988): once the record has ended, a body inside the cap
whose energy is below (1) never tilts beyond ``rho_max`` (:func:`below_barrier`). With ``rho_max`` the angle beyond
which the contact model calls a body overturned (lying on a side; or a scan resting on another face tilted beyond
its smallest static tipping angle), it stands.

**What is computed and what holds.** min over C_rho is taken on :data:`DIRECTIONS` directions of each of
:data:`RADII` circles rho_max j / RADII and of three about the angle at which the body balances on its base's
nearest edge (:data:`NEAR_TIPPING`); as h is Lipschitz in d with the constant max |v_i|, a direction of the
circle lies within pi sin(rho) / DIRECTIONS of a sampled one, and that bound times max |v_i| is subtracted: H is a
lower bound of (1)'s, never above it. The overlap o: a step lets a vertex pass into the ground by at most the step
times its speed, and a vertex's speed is at most sqrt(2 T) (1 + max |v_i| / sqrt(I_min)) for the kinetic energy T
per unit mass, which on a still ground is at most E - g (h_low - o) (h_low the least of h over the cap, bounded the
same way): the largest o solving o = h_s k sqrt(2 (E - g h_low + g o)). The energy the stepping may gain (each step
at most 1e-9 J kg-1, tested) over the longest tail is added to E.

References
----------
Moreau, J. J. (1988). Unilateral contact and dry friction in finite freedom dynamics. In Nonsmooth Mechanics and
Applications, CISM Courses and Lectures 302, 1-82. Springer.
Schneider, R. (2014). Convex Bodies: The Brunn-Minkowski Theory, 2nd ed. Cambridge University Press.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...compiled import jit_inline

#: Directions sampled on each circle of the cap [-]
DIRECTIONS = 720
#: Circles of the cap, rho_max j / RADII for j = 1 .. RADII [-]
RADII = 8
#: Circles at these multiples of the base's tipping angle too, where a slender body's barrier lies [-]
NEAR_TIPPING = (0.9, 1.0, 1.1)
#: The energy a contact-model step may gain, at most (tests/rocking/solids/test_contact3d.py) [J kg-1]
STEP_GAIN_JKG = 1e-9


class TipBarrier(NamedTuple):
    """What a body needs to tilt beyond ``radius_rad``: G's height ``height_m`` [m] (H of (1)), the least height of G
    over the cap ``low_m`` [m] (h_low), and the bound ``speed_per_root`` of a vertex's speed per sqrt(2 T)
    (1 + max |v_i| / sqrt(I_min)) [-]. A radius of 0: no certificate (every run goes on to its end)."""

    radius_rad: float
    height_m: float
    low_m: float
    speed_per_root: float


#: No certificate: the run follows the body after the record until it rests or its tail ends
NO_BARRIER = TipBarrier(0.0, 0.0, 0.0, 0.0)


def tip_barrier(standing: np.ndarray, inertia: np.ndarray, radius_rad: float, *, tipping_rad: float = math.nan
                ) -> TipBarrier:
    """The :class:`TipBarrier` of a body whose hull's vertices about G in its standing axes (z up) are ``standing``
    [m], of principal inertias per unit mass ``inertia`` [m2], to tilt beyond ``radius_rad`` [rad] (see the
    module); ``tipping_rad``, the angle it balances at on its base's nearest edge [rad], adds the circles
    :data:`NEAR_TIPPING` times it, where the barrier of a body that tips over that edge lies."""
    v = np.asarray(standing, dtype=float)
    reach = float(np.max(np.linalg.norm(v, axis=1)))
    below = -v[:, 2]                                        # v . d_0
    z0 = float(np.max(below))
    near = v[below >= z0 - 2.0 * reach * radius_rad]        # the others are never the maximum within the cap
    phi = np.linspace(0.0, 2.0 * math.pi, DIRECTIONS, endpoint=False)
    height, low = -math.inf, z0
    near_tip = [f * tipping_rad for f in NEAR_TIPPING if f * tipping_rad < radius_rad] if tipping_rad > 0.0 else []
    for rho in [radius_rad * j / RADII for j in range(1, RADII + 1)] + near_tip:
        d = np.stack([math.sin(rho) * np.cos(phi), math.sin(rho) * np.sin(phi), np.full(phi.size, -math.cos(rho))])
        h = np.max(near @ d, axis=0)
        err = reach * math.pi * math.sin(rho) / DIRECTIONS
        height = max(height, float(np.min(h)) - err)
        low = min(low, float(np.min(h)) - err - reach * radius_rad / RADII)     # (and between the circles)
    return TipBarrier(float(radius_rad), height, low, 1.0 + reach / math.sqrt(float(np.min(inertia))))


@jit_inline
def below_barrier(energy_jkg, tilt_rad, g_ms2, h_s, barrier, steps_left):
    """Whether a body on a still ground, tilted ``tilt_rad`` [rad] with the energy ``energy_jkg`` per unit mass
    [J kg-1], can never tilt beyond ``barrier.radius_rad`` (its steps of ``h_s`` [s], at most ``steps_left`` of them
    still to take): inside the cap, with its energy and what the steps may gain below (1) of the module."""
    radius, height, low, k = barrier
    if not tilt_rad < radius:
        return False
    above = max(energy_jkg - g_ms2 * low, 0.0)              # o = h k sqrt(2 (above + g o)), its positive root
    a = (h_s * k) ** 2
    overlap = a * g_ms2 + math.sqrt((a * g_ms2) ** 2 + 2.0 * a * above)
    return energy_jkg + steps_left * STEP_GAIN_JKG < g_ms2 * (height - overlap)
