"""A body of the 3D contact model (:mod:`.contact3d`) flat on its base, sticking or sliding, stepped as the
translation it is.

A body flat on its base (tilt 0, no rotation) whose contacts are plastic stays flat through a Moreau step (Moreau
1988) wherever impulses that keep it so exist. Per unit mass, with ``h`` the step, ``N = h (g + a_v)`` the normal
impulse that stops it sinking (``g + a_v > 0``) and ``v_f = v - h a_h`` its horizontal velocity without friction,
Coulomb's law gives the velocity after the step

    v+ = 0                                  where |v_f| <= mu N (it sticks; the friction impulse T = -v_f)
    v+ = v_f (1 - mu N / |v_f|)             elsewhere (it slides; T = -mu N v_f / |v_f|),

the same for every contact, so their friction has no moment about the vertical through G. Its moment about the
horizontal axes, T at the base a height z_G below G, is balanced by normal impulses whose resultant acts at

    c = -z_G T / N                          (from G's foot, in the ground's plane)

and non-negative normal impulses have that resultant exactly when c lies in the base's polygon: the body flat and
translated is then a solution of the step's contact problem. A rigid body with friction need not have a single one;
that it is the one the contact problem's solver finds is measured (tests/rocking/solids/test_properties_flat_slide.py:
pushed boxes to 1e-6; docs/validation.md: 440 scenes on real records). Each step is
checked so (:func:`slide_step`): where c would leave the polygon by a rounding's margin (:data:`INSIDE_MARGIN`) or
where ``g + a_v <= 0``, the contact model takes the step from the state reached. A body that sticks stays in flat
steps while the ground's demand is beyond the at-rest threshold (its deeper side may hold it where the isotropic
threshold does not), and goes back to the at-rest hold (:mod:`.at_rest`) where that threshold holds it again.

The body enters flat steps where the contact model leaves it flat on its base and not turning
(:func:`flat_and_sliding`: tilted below ``REST_TILT_RAD``, three loaded contacts or more, the rate times its size
below ``REST_SPEED``, still moving), set down flat as a body found at rest is, its velocity kept level
(:func:`set_flat`); and where the at-rest hold of a body on its base lets it go (:func:`held_through`).

References
----------
Moreau, J. J. (1988). Unilateral contact and dry friction in finite freedom dynamics. In Nonsmooth Mechanics and
Applications, CISM Courses and Lectures 302, 1-82. Springer.
"""

from __future__ import annotations

import math

from ...compiled import jit_inline
from .at_rest import ground_at, rest_through, within
from .attitude import headed, rotation
from .contact_pose import heading, record

#: A flat slide's step is taken only where the centre of the normal impulses it needs lies inside the base's polygon
#: by more than this fraction of the distance from G's foot to each edge [-]; nearer, the contact model takes it.
INSIDE_MARGIN = 1e-9
#: How a flat slide ended (:func:`slide_through`).
SLIDE_LEFT = 0      # the contact model takes the next step (c outside the base, g + a_v <= 0, the tail's cap)
SLIDE_STUCK = 1     # the body sticks where the at-rest certificate holds it


@jit_inline
def inside(cx, cy, edges, m):
    """The point (cx, cy) (in the axes the body stands in, from G's foot) inside the base's polygon ``edges`` (its
    first ``m`` rows, :func:`~.contact_pose.base_edges`) by :data:`INSIDE_MARGIN`."""
    if m == 0:
        return False
    for e in range(m):
        if edges[e, 0] * cx + edges[e, 1] * cy > (1.0 - INSIDE_MARGIN) * edges[e, 2]:
            return False
    return True


@jit_inline
def flat_and_sliding(n_c, tilt, rest_tilt, v, w, size, rest_speed, impulses, loaded):
    """The contact model's state that enters a flat slide: on three contacts or more that the last step loaded
    (``impulses`` at the vertices listed in ``loaded``: how many, then which), tilted below ``rest_tilt`` [rad],
    turning at a rate times ``size`` below ``rest_speed`` [m s-1], moving along the ground at ``rest_speed`` or more
    and not off it (a vertical speed below ``rest_speed``)."""
    if n_c < 3 or tilt >= rest_tilt or abs(v[2]) >= rest_speed:
        return False
    if math.sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) * size >= rest_speed:
        return False
    if math.sqrt(v[0] * v[0] + v[1] * v[1]) < rest_speed:
        return False
    normal = 0.0
    for c in range(loaded[0]):
        normal += impulses[loaded[c + 1], 2]
    return normal > 0.0


@jit_inline
def set_flat(v, w, q, x, r, z0, impulses, pose):
    """A body entering flat steps: set down as it stood (its heading and place kept, G at ``z0``; ``r`` its
    rotation so), not turning, its velocity level, its next contact problem from no impulse."""
    headed(heading(r, pose.x_ref), pose.q_rest, q)
    rotation(q, r)
    x[2] = z0
    v[2] = 0.0
    w[:] = 0.0
    impulses[:] = 0.0


@jit_inline
def slide_step(x, v, gx, gy, gz, mu, g, h, z0, cos_psi, sin_psi, edges, m):
    """One Moreau step of the body sliding flat (see the module) from G's place ``x`` and velocity ``v``, both
    updated in place where it is taken: the ground (gx, gy, gz) at the step's middle [m s-2], the body's heading
    ``psi`` by its cosine and sine, its base's polygon ``edges`` (first ``m`` rows). Whether it is taken (``v`` 0
    where it sticks); where not, the contact model takes it."""
    normal = h * (g + gz)
    if normal <= 0.0:
        return False
    fx, fy = v[0] - h * gx, v[1] - h * gy
    speed = math.sqrt(fx * fx + fy * fy)
    stuck = speed <= mu * normal
    scale = 0.0 if stuck else 1.0 - mu * normal / speed
    tx, ty = fx * scale - fx, fy * scale - fy           # the friction impulse
    cx, cy = -z0 * tx / normal, -z0 * ty / normal      # where the normal impulses' resultant acts
    if not inside(cos_psi * cx + sin_psi * cy, -sin_psi * cx + cos_psi * cy, edges, m):
        return False
    x[0] += 0.5 * h * v[0]
    x[1] += 0.5 * h * v[1]
    v[0], v[1] = fx * scale, fy * scale
    x[0] += 0.5 * h * v[0]
    x[1] += 0.5 * h * v[1]
    return True


@jit_inline
def slide_through(ax, ay, az, k, n_sub, k_end, x, v, mu, g, h, z0, psi, edges, m, threshold, hist, slide_max):
    """The body flat on its base from step ``k`` (:func:`slide_step`; the ground none from the record's last sample
    on), sliding or sticking, until the contact model must take a step, it sticks where the at-rest certificate
    (``threshold``, :mod:`.at_rest`) holds it, or step ``k_end``; its tilt (0) at the samples into ``hist``. Returns
    the step reached, how it ended (:data:`SLIDE_LEFT`, :data:`SLIDE_STUCK`), the steps taken and the largest slide of
    G so far [m]."""
    cos_psi, sin_psi, n = math.cos(psi), math.sin(psi), ax.size
    taken = 0
    while k < k_end:
        gx, gy, gz = ground_at(ax, ay, az, k, n_sub) if k < (n - 1) * n_sub else (0.0, 0.0, 0.0)
        if v[0] == 0.0 and v[1] == 0.0 and within(gx, gy, gz, threshold, g):
            return k, SLIDE_STUCK, taken, slide_max
        if not slide_step(x, v, gx, gy, gz, mu, g, h, z0, cos_psi, sin_psi, edges, m):
            return k, SLIDE_LEFT, taken, slide_max
        k, taken = k + 1, taken + 1
        slide_max = max(slide_max, math.sqrt(x[0] * x[0] + x[1] * x[1]))
        if k % n_sub == 0:
            record(hist, k // n_sub, 0.0, math.nan)
    return k, SLIDE_LEFT, taken, slide_max


@jit_inline
def held_through(ax, ay, az, k, n_sub, k_end, held, g, hist, tilt_held, lean_held, x, v, mu, h, z0, r, x_ref, edges, m,
                 slide_max, steps, flat_steps):
    """A body held still (:func:`~.at_rest.rest_through`, ``held`` its threshold, ``tilt_held`` and ``lean_held``
    its tilt and lean [rad]) or, on its base with ``m`` edges of its polygon in ``edges`` (0: none, or not on its
    base), moving (``v`` not 0) or beyond that threshold, stepped flat (:func:`slide_through`; its heading read from
    ``r``, as it was set down or flat, along its standing x axis ``x_ref``) from step ``k``. Returns the step
    reached, whether it is still held or flat (False: the contact model takes the next step), whether the run ends
    there (at rest after the record), the counts ``steps`` and ``flat_steps`` with this call's added, and the largest
    slide of G so far [m]."""
    if v[0] == 0.0 and v[1] == 0.0:
        reached, resting, ended = rest_through(ax, ay, az, k, n_sub, ax.size, held, g, hist, tilt_held, lean_held)
        k, steps = reached, steps + reached - k
        if resting or ended or m == 0:
            return k, resting, ended, steps, flat_steps, slide_max
    k, how, taken, slide_max = slide_through(ax, ay, az, k, n_sub, k_end, x, v, mu, g, h, z0, heading(r, x_ref), edges,
                                             m, held, hist, slide_max)
    return k, how == SLIDE_STUCK or k >= k_end, False, steps + taken, flat_steps + taken, slide_max
