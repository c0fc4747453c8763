"""A cylinder's or a box's scene decided by the 3D contact model (:mod:`.contact3d`) where its exact model stops:
the hand-off of ``[simulation] contact3d = true`` (the default).

The exact models (:mod:`.cylinder3d`, :mod:`.box3d`) hold while the body rocks or wobbles without slipping; where
its base would slide, twist or lift off they stop (``simulation_guard`` model_limit), and where it would slip while
falling past the tipping point they follow the fall with the contact held (held_past_alpha). Such a scene goes on
in the contact model from the exact model's last certified state (:func:`handoff`: the start of the step where the
base would first slip or lift, or the instant at rest a box would slide), with the exact model's history and peak
before it; a scene the exact model stopped without certifying a state (its step cap, or a cylinder that never
lifted while the ground could slide it) is run by the contact model from rest. Its verdict, peak tilt and history
are then the contact model's: physics ``contact3d``. The contact model's own caps
are flagged (step_cap where a step's contact problem ended at its sweep cap, tail_cap where the body still moved
at the end of its tail), never silent. Against PyBullet, handing over the held scenes too changed no agreement
count in any family (docs/validation.md).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial.transform import Rotation

from ..codes import ContactMode
from ..scene import FreeFlight, Guard, Physics, Response, Scene
from .box3d import Box, BoxOutcome
from .box_kernel import REST
from .contact3d import FLAG_TAIL_CAP, Contact3DOutcome, simulate_contact3d
from .contact_start import Start
from .convex_body import ConvexBody, box_body, cylinder_body
from .cylinder3d import Cylinder, WobbleOutcome

#: The base corners of the exact box model (box3d), counter-clockwise from above: c_k = (s_x b_x, s_y b_y, -h).
_CORNER_SIGNS = ((1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0))


def convex_body(body: Cylinder | Box) -> ConvexBody:
    """The contact model's body of an exact model's cylinder or box (restitution: plastic contacts, which give
    Housner's rule at a pivot)."""
    if isinstance(body, Cylinder):
        return cylinder_body(2.0 * body.radius_m, 2.0 * body.half_height_m, mu=body.mu)
    return box_body(2.0 * body.half_width_m, 2.0 * body.half_depth_m, 2.0 * body.half_height_m, mu=body.mu)


def handoff(exact: WobbleOutcome | BoxOutcome | None, body: Cylinder | Box, azimuth_deg: float,
            dt_s: float) -> Start | None:
    """The contact model's :class:`~.contact_start.Start` at the last state ``exact`` certified before it stopped
    (None where it certified none: it never moved, or stopped at a cap); ``azimuth_deg`` the body's at rest.

    A box turns about its pivot corner (``mode``/``pivot`` of its hand-off: a corner, or either corner of an edge, or
    the corner an edge turns on while the other slides); a cylinder rolls on the lowest point of its rim, whose arm
    from G is ``r`` = ((h sin theta - a cos theta) cos phi, ... sin phi, h cos theta + a sin theta) and whose rate
    is theta' e_n + phi' e_z + psi' e_3 (:mod:`.cylinder3d`). Its tilt and lean before are the exact model's."""
    if exact is None or exact.handoff is None or not math.isfinite(exact.handoff[0]):
        return None
    state = exact.handoff
    if isinstance(body, Cylinder):
        th, ph, ps, th_dot, ph_dot, ps_dot = state[1:7]
        a, h = body.radius_m, body.half_height_m
        rot = Rotation.from_euler("ZYZ", [ph, th, ps + math.radians(azimuth_deg)])
        e_n, e_3 = np.array([-math.sin(ph), math.cos(ph), 0.0]), rot.apply([0.0, 0.0, 1.0])
        rate = th_dot * e_n + np.array([0.0, 0.0, ph_dot]) + ps_dot * e_3
        lever, up = h * math.sin(th) - a * math.cos(th), h * math.cos(th) + a * math.sin(th)
        pivot = rot.inv().apply(-np.array([lever * math.cos(ph), lever * math.sin(ph), up]))
        x, y, z, w = rot.as_quat()
        q = np.array([w, x, y, z])
    else:
        q, rate = np.asarray(state[1:5], dtype=float), np.asarray(state[5:8], dtype=float)
        k = 0 if int(state[8]) == REST else int(state[9])
        sx, sy = _CORNER_SIGNS[k % 4]
        pivot = np.array([sx * body.half_width_m, sy * body.half_depth_m, -body.half_height_m])
    upto = int(math.floor(state[0] / dt_s + 1e-9)) + 1
    tilt = np.asarray(exact.theta[:upto], dtype=float)
    lean = np.where(tilt > 0.0, np.asarray(exact.azimuth[:upto], dtype=float), math.nan)
    peak = int(np.nanargmax(tilt)) if np.any(np.isfinite(tilt)) else 0
    return Start(float(state[0]), q, rate, pivot, float(np.nan_to_num(tilt[peak])), float(lean[peak]), tilt, lean)


def contact_scene(h1, h2, vertical, dt_s: float, body: Cylinder | Box, azimuth_deg: float, alpha: float, *,
                  g_ms2: float, amplitude: float = 1.0, history: bool = False,
                  exact: WobbleOutcome | BoxOutcome | None = None) -> tuple[Scene, Contact3DOutcome]:
    """The scene of ``body`` (its width axis at ``azimuth_deg`` in the models' frame: x the record's first
    horizontal, y its second reversed) under the record times ``amplitude``, by the contact model; theta_max (and
    with ``history`` theta_over_alpha) as a fraction of ``alpha``. With the contact model's outcome (where it leant:
    ``lean_at_peak_deg``, with ``history`` ``lean_deg``, in the models' frame)."""
    av = None if vertical is None or np.size(vertical) == 0 else amplitude * np.asarray(vertical, dtype=float)
    out = simulate_contact3d(amplitude * np.asarray(h1, dtype=float), -amplitude * np.asarray(h2, dtype=float), av,
                             dt_s, convex_body(body), yaw_deg=azimuth_deg, g_ms2=g_ms2, history=history,
                             start=handoff(exact, body, azimuth_deg, dt_s))
    return outcome_scene(out, alpha), out


def outcome_scene(out: Contact3DOutcome, alpha: float) -> Scene:
    """The :class:`~pipeline.rocking.scene.Scene` of a contact model's outcome: theta_max (and with a history
    theta_over_alpha) as a fraction of ``alpha`` [rad]; its caps flagged (step_cap, tail_cap), its verdict kept."""
    rocked, slid = out.tilt_max_rad > 1e-6, out.slide_max_m > 1e-9
    if out.overturned:
        response = Response.overturn
    elif rocked and slid:
        response = Response.slide_rock
    elif rocked:
        response = Response.rock
    elif slid:
        response = Response.slide
    else:
        response = Response.rest
    modes = ((int(ContactMode.slide_rock) if rocked and slid else int(ContactMode.rock) if rocked else
              int(ContactMode.slide) if slid else 0) | (int(ContactMode.free_flight) if out.flight else 0))
    guard = (Guard.step_cap if out.capped_steps else 0) | (Guard.tail_cap if out.flags & FLAG_TAIL_CAP else 0)
    flight = FreeFlight.block_liftoff if out.flight else FreeFlight.none
    return Scene(physics=Physics.contact3d, response=response, overturned=out.overturned,
                 theta_max=out.tilt_max_rad / alpha, n_impacts=0, t_overturn=out.t_overturn, friction_demand=math.nan,
                 sliding_max_m=out.slide_max_m, free_flight=flight,
                 chatter=False, friction_exceeded=1 if slid else 0, contact_modes=modes, guard=int(guard),
                 theta_over_alpha=None if out.tilt_rad is None else out.tilt_rad / alpha)

