"""Where the contact model takes several of its steps as one: a body rocking in earnest with no impact ahead.

The contact model (:mod:`.contact3d`) steps the record's interval in equal steps h of at most its ``MAX_STEP_S``.
Where the body tilts beyond ``FINE_TILT_TO`` times its smallest static tipping angle, is not around a flight and no
vertex clear of the ground would reach it within twice the longer step at its present speed, ``m`` of those steps
are taken as one Moreau-Jean step of m h, the ground at its middle (linear between samples, as for every step):
``m`` is the largest divisor of the steps a sampling interval is taken in with m h <= :data:`LONG_STEP_S`, and a
long step starts only at a multiple of ``m``, so that it never straddles a sample. Below that tilt, around a flight and
wherever an impact could come within the long step, every step is the one the model takes without them.

An impact ahead is looked for among the vertices near the ground (:mod:`.near_ground`), each vertex clear of the
ground at ``z`` above it and moving down at ``u`` (its vertical velocity, G's and the rotation's):

    z + S m h min(u, 0) <= gap,      S = :data:`IMPACT_SAFETY`,

and for every other vertex by the list's own bound on their height less ``S m h (|v| + |w| rho)`` (rho the body's
reach): a body whose next pivot is about to land keeps its short steps through the landing, where a plastic impact
at a new contact is resolved (Housner's rule; Moreau 1988).

The time a body passes an angle (its smallest static tipping angle, for a body found toppled after the record) is
taken linear between the ends of the step that passed it, rather than at the step's end, which a long step puts up
to :data:`LONG_STEP_S` later.

References
----------
Moreau, J. J. (1988). Unilateral contact and dry friction in finite freedom dynamics. In Nonsmooth Mechanics and
Applications, CISM Courses and Lectures 302, 1-82. Springer.
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. BSSA 53(2), 403-417.
"""

from __future__ import annotations

import math

from ...compiled import jit_inline
from .near_ground import least_outside

#: The longest step [s] the contact model takes where the body rocks with no impact ahead (chosen by measurement
#: against steps a fifth to a tenth as long on the peer families and the granite rocks' tests, docs/validation.md).
LONG_STEP_S = 1.3e-3
#: How many times a long step's length an impact ahead is looked for [-]: a vertex that would reach the ground
#: within IMPACT_SAFETY m h at its present speed keeps the steps short.
IMPACT_SAFETY = 2.0


def steps_merged(n_sub: int, h_s: float, *, longest_s: float | None = None) -> int:
    """The steps of ``h_s`` [s] taken as one where the body rocks with no impact ahead: the largest divisor ``m`` of
    ``n_sub`` (the steps a sampling interval is taken in) with ``m h_s <= longest_s`` [s] (None: the 3D contact
    model's :data:`LONG_STEP_S`, as it stands when called; the stacks' contact model gives its option); at least 1."""
    bound = LONG_STEP_S if longest_s is None else longest_s
    most = min(n_sub, int(bound * (1.0 + 1e-9) / h_s))
    return max((m for m in range(1, most + 1) if n_sub % m == 0), default=1)


@jit_inline
def impact_ahead(vertices, r, x, v, w, nr, gap, span_s):
    """Whether a vertex clear of the ground (more than ``gap`` [m] above it) could reach it within
    :data:`IMPACT_SAFETY` times ``span_s`` [s] at its present speed: the body at ``x`` (G), turned by ``r`` (its
    rotation now), moving at ``v``, ``w``; its vertices near the ground listed in ``nr``
    (:class:`~.near_ground.Near`; with no list, an impact is taken to be ahead)."""
    n = nr.n_listed[0]
    if n < 0:
        return True
    reach = IMPACT_SAFETY * span_s
    speed = math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2) + math.sqrt(w[0] ** 2 + w[1] ** 2 + w[2] ** 2) * nr.state[4]
    if least_outside(r, x[2], nr) - reach * speed <= gap:
        return True
    for j in range(n):
        i = nr.members[j]
        z = x[2] + r[2, 0] * vertices[i, 0] + r[2, 1] * vertices[i, 1] + r[2, 2] * vertices[i, 2]
        if z > gap:
            r0 = r[0, 0] * vertices[i, 0] + r[0, 1] * vertices[i, 1] + r[0, 2] * vertices[i, 2]
            r1 = r[1, 0] * vertices[i, 0] + r[1, 1] * vertices[i, 1] + r[1, 2] * vertices[i, 2]
            if z + reach * min(v[2] + w[0] * r1 - w[1] * r0, 0.0) <= gap:
                return True
    return False


@jit_inline
def last_passed(t0, t1, tilt0, tilt1, angle, before):
    """When the tilt last passed ``angle`` upward [s]: within the step from ``t0`` to ``t1`` [s] (from ``tilt0`` to
    ``tilt1`` [rad]) where it did there (``tilt0 <= angle < tilt1``), linear between the step's ends; else
    ``before``."""
    if tilt0 <= angle < tilt1:
        return t0 + (angle - tilt0) / (tilt1 - tilt0) * (t1 - t0)
    return before
