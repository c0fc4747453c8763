"""The box's exact model (:mod:`.box3d`) as the alternation (:mod:`.alternate`) takes it: the contact model hands a
box back to it wherever the box turns on one base edge, both of its corners sticking and no other corner loaded
(handing it back there, the bundled default's box runs take about half of the contact model's time alone:
docs/validation.md). The exact model goes on from the contact model's state with the edge levelled and the rate
taken about it (:func:`edge_state`), both changes below the contact model's own resolution.
"""

from __future__ import annotations

import math

import numpy as np

from .alternate import ExactModel, Turning
from .attitude import rotation_matrix, turned
from .box3d import Box, BoxOutcome, simulate_box
from .box_kernel import EDGE
from .contact3d import Contact3DOutcome
from .handoff3d import BoxState, base_corner

#: The base edges of :func:`~.convex_body.box_body`'s corners, in the exact model's order: edge k joins its corner k
#: to corner k + 1 (:data:`~.handoff3d.CORNER_SIGNS`), given as the contact model's vertex indices.
BOX_EDGES = np.array([[3, 2], [2, 0], [0, 1], [1, 3]], dtype=np.int64)


def box_model(box: Box, *, dt_s: float, g_ms2: float, rtol: float, atol_alpha: float) -> ExactModel:
    """The box's exact model on the ground sampled at ``dt_s`` [s] (tolerances ``rtol``, ``atol_alpha``) for
    :func:`~.alternate.alternate`, with Housner's restitution (the contact model's plastic impacts at a pivot)."""
    housner = box._replace(restitution_ratio=1.0)

    def run(ax, ay, az, state: BoxState) -> BoxOutcome:
        """The exact model from ``state`` at the first sample of the ground (ax, ay, az) [m s-2]."""
        return simulate_box(ax, ay, az, dt_s, housner, g_ms2=g_ms2, rtol=rtol, atol_alpha=atol_alpha, start=state)

    return ExactModel(body=box.convex(), edges=BOX_EDGES, run=run, state_at=lambda out: edge_state(out, box),
                      turning=lambda state: state.turning(box, 0.0), ending=lambda exact: _ending(exact, box),
                      at_rest=_at_rest,
                      barrier_m=math.hypot(min(box.half_width_m, box.half_depth_m), box.half_height_m))


def edge_state(out: Contact3DOutcome, box: Box) -> BoxState:
    """The exact model's state (q, omega) on edge ``out.edge`` where the contact model stopped: the orientation
    turned so that the edge lies level (the contact model lets a corner sink by up to a step's travel) and the rate
    about the edge alone (the two sticking corners leave only that, to the solver's tolerance). Formed in scalars
    rather than by numpy's calls on 3-vectors, whose per-call overhead would be paid at each hand-back of each draw."""
    q, w = np.asarray(out.q_end, dtype=float), np.asarray(out.rate_end_rad_s, dtype=float)
    d = base_corner(box, (out.edge + 1) % 4) - base_corner(box, out.edge)
    u0, u1, u2 = (row[0] * d[0] + row[1] * d[1] + row[2] * d[2] for row in rotation_matrix(q).tolist())
    size = math.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
    u0, u1, u2 = u0 / size, u1 / size, u2 / size
    flat = math.hypot(u0, u1)
    l0, l1 = u0 / flat, u1 / flat                                   # the edge levelled, a unit vector
    a0, a1, a2 = -u2 * l1, u2 * l0, u0 * l1 - u1 * l0               # the edge x the levelled edge
    sine = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
    levelled = q.copy()
    if sine > 0.0:
        angle = math.atan2(sine, u0 * l0 + u1 * l1)
        turned(q, a0 / sine * angle, a1 / sine * angle, a2 / sine * angle, 1.0, levelled)
    along = w[0] * l0 + w[1] * l1
    return BoxState(levelled, np.array([along * l0, along * l1, 0.0]), EDGE, out.edge)


def _at_rest(exact: BoxOutcome) -> bool:
    """The exact segment ran to the record's end and ended at rest, flat and still."""
    return not np.any(exact.end.rate_rad_s) and exact.theta[-1] == 0.0


def _ending(exact: BoxOutcome, box: Box) -> Turning:
    """Where an exact segment reached the record's end still moving: its last state, turning on its lowest corner."""
    q = exact.end.q / np.linalg.norm(exact.end.q)
    corners = np.array([base_corner(box, k) for k in range(4)])
    low = int(np.argmin(corners @ rotation_matrix(q)[2]))
    return q, exact.end.rate_rad_s.copy(), corners[low]
