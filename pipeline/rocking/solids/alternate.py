"""A box's scene that left its exact model, run by the contact model and handed back to the exact model wherever it
rocks on an edge without slipping again (the draws and the margin scan, which keep only the verdict).

The contact model (:mod:`.contact3d`) follows every mode at once, in steps of at most 0.5 ms; the exact model
(:mod:`.box3d`) follows a box on an edge or a corner whose contact holds, at the steps its error control allows.
Once a box has slid, it mostly rocks on an edge again with that edge's two corners sticking (handing it back there,
the bundled default's box runs take 0.52 of the contact model's time alone: docs/validation.md). The contact model
therefore stops at the first sample after a whole sampling interval turning on one base edge, both of its corners
loaded and inside their friction cones and no other corner loaded, a step taken in parts judged by its last part
(``edges`` of :func:`~.contact3d.simulate_contact3d`), and the exact model goes on from there on that edge
(:func:`_exact_state`: the edge levelled and the rate taken about it, both changes below the contact model's own
resolution). Where the exact model stops again (its base would slide or lift off, or it falls past the tipping point
with its contact held), the contact model goes on from the exact model's last certified state, as in
:mod:`.contact_scene`. Where the record ends while the box still moves, the contact model follows it to rest or to
its side (its tail). After :data:`MAX_HANDBACKS` hand-backs the contact model runs to the end alone: the run always
ends, with the contact model's verdict.

The impacts: the contact model's plastic contacts give Housner's (1963) rule at a pivot, so the exact model runs with
Housner's restitution (``restitution_ratio`` 1), the same physics; a declared restitution is the contact model's
(which does not read it) wherever this alternation runs.

Where the models meet, the verdict can differ from the contact model's alone where the scene is chaotic: on the
bundled default's 2,133 box runs, in 2.2 % of them, against 1.6 % between the contact model and itself at half its
step (docs/validation.md). Only the verdict, the peak tilt and where it leant, the time of
overturning and the costs are kept: not the sliding distance nor the histories (the nominal scene, which reports
them, runs the contact model alone).

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. BSSA 53(2), 403-417.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .attitude import rotation, turned
from .box3d import Box, BoxOutcome, simulate_box
from .box_kernel import EDGE
from .contact3d import Contact3DOutcome, simulate_contact3d
from .contact_start import Start
from .handoff3d import BoxState, base_corner
from .vec3 import FLAG_NONE

#: The base edges of :func:`~.convex_body.box_body`'s corners, in the exact model's order: edge k joins its corner k
#: to corner k + 1 (:data:`~.handoff3d.CORNER_SIGNS`), given as the contact model's vertex indices.
BOX_EDGES = np.array([[3, 2], [2, 0], [0, 1], [1, 3]], dtype=np.int64)
#: Hand-backs to the exact model at most in one scene; then the contact model goes on alone [-].
MAX_HANDBACKS = 50


def alternate(ax, ay, az, dt_s: float, box: Box, azimuth_deg: float, start: Start | None, *, g_ms2: float,
              rtol: float, atol_alpha: float) -> Contact3DOutcome:
    """The box (width axis at ``azimuth_deg`` in the models' frame) under the ground (ax, ay, az) [m s-2] (az None:
    none) sampled at ``dt_s``, from ``start`` (None: at rest), by the contact model handed back to the exact model
    (tolerances ``rtol``, ``atol_alpha``) on every edge it rocks on without slipping; the contact model's outcome
    with the verdict, peak and costs of the whole run."""
    ax, ay = np.asarray(ax, dtype=float), np.asarray(ay, dtype=float)
    az = None if az is None or np.size(az) == 0 else np.asarray(az, dtype=float)
    housner = box._replace(restitution_ratio=1.0)
    body, peak, costs = box.convex(), (0.0, math.nan), _Costs()
    handbacks = 0
    while True:
        out = simulate_contact3d(ax, ay, az, dt_s, body, yaw_deg=azimuth_deg, g_ms2=g_ms2, start=start,
                                 edges=BOX_EDGES if handbacks < MAX_HANDBACKS else None)
        peak, costs = _peak(peak, out.tilt_max_rad, out.lean_at_peak_deg), costs.add(out)
        if out.edge < 0:
            return _whole(out, peak, costs)
        handbacks += 1
        i = int(round(out.t_end_s / dt_s))
        exact = simulate_box(ax[i:], ay[i:], None if az is None else az[i:], dt_s, housner, g_ms2=g_ms2, rtol=rtol,
                             atol_alpha=atol_alpha, start=_exact_state(out, box))
        peak = _peak(peak, exact.theta_max_rad, exact.azimuth_max_deg)
        if exact.overturned and exact.held == FLAG_NONE:
            return _whole(out, peak, costs, overturned_at=i * dt_s + exact.t_overturn_s)
        if exact.flag == FLAG_NONE and exact.held == FLAG_NONE and _at_rest(exact):
            return _whole(out, peak, costs)
        start, certified = _resume(exact, out, box, i * dt_s, dt_s, peak)
        handbacks = handbacks if certified else MAX_HANDBACKS


class _Costs(NamedTuple):
    """What the contact model's runs of a scene cost and flagged, summed (:class:`~.contact3d.Contact3DOutcome`'s
    fields of the same names)."""

    steps: int = 0
    integrated_steps: int = 0
    sweeps: int = 0
    capped_steps: int = 0
    flags: int = 0
    flight: bool = False

    def add(self, out: Contact3DOutcome) -> _Costs:
        """These costs and ``out``'s."""
        return _Costs(self.steps + out.steps, self.integrated_steps + out.integrated_steps, self.sweeps + out.sweeps,
                      self.capped_steps + out.capped_steps, self.flags | out.flags, self.flight or out.flight)


def _peak(peak: tuple[float, float], tilt_rad: float, lean_deg: float) -> tuple[float, float]:
    """The larger of the peak tilt so far and ``tilt_rad`` [rad], with where it leant [deg]."""
    return (tilt_rad, lean_deg) if tilt_rad > peak[0] else peak


def _whole(out: Contact3DOutcome, peak: tuple[float, float], costs: _Costs,
           overturned_at: float = math.nan) -> Contact3DOutcome:
    """The scene's outcome: the last contact run's, with the whole run's peak and costs, overturned at
    ``overturned_at`` [s] where an exact segment overturned it (NaN: as the last contact run says)."""
    by_exact = math.isfinite(overturned_at)
    over = out.overturned or by_exact
    return out._replace(overturned=over, t_overturn=overturned_at if by_exact else out.t_overturn,
                        tilt_max_rad=0.5 * math.pi if over else peak[0], lean_at_peak_deg=peak[1],
                        edge=-1, q_end=None, rate_end_rad_s=None, **costs._asdict())


def _at_rest(exact: BoxOutcome) -> bool:
    """The exact segment ran to the record's end and ended at rest, flat and still."""
    return not np.any(exact.end.rate_rad_s) and exact.theta[-1] == 0.0


def _exact_state(out: Contact3DOutcome, box: Box) -> BoxState:
    """The exact model's state (q, omega) on edge ``out.edge`` where the contact model stopped: the orientation
    turned so that the edge lies level (the contact model lets a corner sink by up to a step's travel) and the rate
    about the edge alone (the two sticking corners leave only that, to the solver's tolerance)."""
    q = np.asarray(out.q_end, dtype=float)
    u = _rotation(q) @ (base_corner(box, (out.edge + 1) % 4) - base_corner(box, out.edge))
    u = u / np.linalg.norm(u)
    level = np.array([u[0], u[1], 0.0]) / math.hypot(u[0], u[1])
    axis = np.cross(u, level)
    sine = float(np.linalg.norm(axis))
    levelled = q.copy()
    if sine > 0.0:
        turn = axis / sine * math.atan2(sine, float(np.dot(u, level)))
        turned(q, turn[0], turn[1], turn[2], 1.0, levelled)
    rate = float(np.dot(np.asarray(out.rate_end_rad_s, dtype=float), level)) * level
    return BoxState(levelled, rate, EDGE, out.edge)


def _rotation(q: np.ndarray) -> np.ndarray:
    """The rotation matrix of the unit quaternion ``q`` (w, x, y, z)."""
    r = np.empty((3, 3))
    rotation(np.asarray(q, dtype=float), r)
    return r


def _resume(exact: BoxOutcome, out: Contact3DOutcome, box: Box, t0_s: float, dt_s: float,
            peak: tuple[float, float]) -> tuple[Start, bool]:
    """Where the contact model goes on after an exact segment that began at ``t0_s`` [s] (``dt_s`` the record's
    sampling [s]), and whether the exact model may take the scene again: its certified state where it stopped; where
    it stopped without one (its step cap), the contact model's own state where it handed the scene over (and the
    contact model goes on alone); where the record ended while the box still moved, its last state turning on its
    lowest corner (the contact model's tail)."""
    lean = math.radians(peak[1])
    stopped = exact.flag != FLAG_NONE or exact.held != FLAG_NONE
    if stopped and exact.handoff is not None:
        q, rate, pivot = exact.handoff.state.turning(box, 0.0)
        return Start(t0_s + exact.handoff.t_s, q, rate, pivot, peak[0], lean), True
    if stopped:
        q_end, rate_end = np.asarray(out.q_end, dtype=float), np.asarray(out.rate_end_rad_s, dtype=float)
        return Start(out.t_end_s, q_end, rate_end, base_corner(box, out.edge), peak[0], lean), False
    q = exact.end.q / np.linalg.norm(exact.end.q)
    corners = np.array([base_corner(box, k) for k in range(4)])
    low = int(np.argmin(corners @ _rotation(q)[2]))
    return (Start(t0_s + (np.size(exact.theta) - 1) * dt_s, q, exact.end.rate_rad_s.copy(), corners[low], peak[0],
                  lean), True)
