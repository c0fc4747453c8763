"""A body of the 3D contact model (:mod:`.contact3d`) at rest, held there without integrating: the at-rest
certificate and the steps it holds.

A body in contact and still stays still through a step where the ground's demand at the step's middle,
|a_h| / (g + a_v), is at or below min(mu, tan alpha): the resultant of gravity and the ground's inertial force,
through G, then meets the ground inside the circle of radius d about G's foot (d the distance from there to the
nearest edge of the polygon the contacts span, tan alpha = d / z_G) and inside every contact's friction cone in
proportion to its share of the load, so impulses that hold every contact still exist and the step leaves the body
where it is. A body on its base gets the threshold of its standing pose (:func:`~.convex_body.base_threshold`); a
body still on another face of its hull (a scan toppled onto a face) the threshold of the contacts it rests on
(:func:`~.convex_body.support_threshold`).

A held body skips a whole sampling interval at once where the demand at both its samples is below the threshold by
:data:`CALM_MARGIN` (|a_h| - c (g + a_v) is convex along the linear ground between them), and otherwise checks each
step's middle.
"""

from __future__ import annotations

import math

from ...compiled import jit_inline
from .attitude import headed
from .contact_pose import heading, record

#: A body held at rest skips a whole sampling interval at once where the ground's demand at its two samples is
#: below the at-rest threshold by this fraction [-] (so that no rounding of the steps' middles in between can reach
#: it); elsewhere every step's middle is checked. The same steps are held as when each is checked.
CALM_MARGIN = 1e-9


@jit_inline
def ground_at(ax, ay, az, k, n_sub, within=0.5):
    """The ground's acceleration at the fraction ``within`` of step ``k`` (default its middle; linear between
    samples) [m s-2]."""
    i, frac = k // n_sub, (k % n_sub + within) / n_sub
    return (ax[i] + frac * (ax[i + 1] - ax[i]), ay[i] + frac * (ay[i + 1] - ay[i]),
            az[i] + frac * (az[i + 1] - az[i]))


@jit_inline
def within(gx, gy, gz, limit, g):
    """The ground's acceleration (gx, gy, gz) within the demand ratio ``limit``: |a_h| <= limit (g + a_v), g + a_v > 0
    (the at-rest certificate with ``limit`` the body's threshold)."""
    gv = g + gz
    return gv > 0.0 and math.sqrt(gx * gx + gy * gy) <= limit * gv


@jit_inline
def calm_until(ax, ay, az, i, threshold, g):
    """The first sample at or after ``i`` that does not begin a calm interval: one whose two samples are both
    within the threshold by :data:`CALM_MARGIN` (then every step's middle in it is inside the at-rest certificate
    too); the record's last sample at most."""
    limit = (1.0 - CALM_MARGIN) * threshold
    if not within(ax[i], ay[i], az[i], limit, g):
        return i
    while i < ax.size - 1 and within(ax[i + 1], ay[i + 1], az[i + 1], limit, g):
        i += 1
    return i


@jit_inline
def hold_calm(ax, ay, az, i, threshold, g, hist, tilt, lean):
    """The body at rest at sample ``i``: the sampling intervals it is held through at once (:func:`calm_until`),
    their samples recorded at its ``tilt`` and ``lean`` [rad]; how many."""
    calm_to = calm_until(ax, ay, az, i, threshold, g)
    for j in range(i + 1, calm_to + 1):
        record(hist, j, tilt, lean)
    return calm_to - i


@jit_inline
def rest_through(ax, ay, az, k, n_sub, n, threshold, g, hist, tilt, lean):
    """The body at rest at step ``k`` (tilted ``tilt``, leaning toward ``lean`` [rad]): held through the calm
    sampling intervals from there (:func:`hold_calm`) and through this step where its ground is within the at-rest
    certificate. Returns the step reached, whether it still rests, and whether the run ends there (it rests after
    the record)."""
    during = k < (n - 1) * n_sub
    if during and k % n_sub == 0:
        k += hold_calm(ax, ay, az, k // n_sub, threshold, g, hist, tilt, lean) * n_sub
        during = k < (n - 1) * n_sub
    gx, gy, gz = ground_at(ax, ay, az, k, n_sub) if during else (0.0, 0.0, 0.0)
    if not within(gx, gy, gz, threshold, g):
        return k, False, False
    k += 1                                          # the at-rest certificate: nothing moves this step
    if hist.shape[0] and k % n_sub == 0:
        record(hist, k // n_sub, tilt, lean)
    return k, True, not during


@jit_inline
def set_down(v, w, q, x, r, z0, impulses, pose):
    """A body found at rest on its base: still, set down as it stood (its heading and place kept), its next motion
    from no impulse (:func:`set_still`); True (it rests)."""
    headed(heading(r, pose.x_ref), pose.q_rest, q)
    x[2] = z0
    return set_still(v, w, impulses)


@jit_inline
def set_still(v, w, impulses):
    """A body found at rest on another face: still where it is, its next motion from no impulse; True (it rests)."""
    v[:] = 0.0
    w[:] = 0.0
    impulses[:] = 0.0
    return True
