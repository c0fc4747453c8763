"""A cylinder's or a box's scene decided by the 3D contact model (:mod:`.contact3d`) where its exact model stops:
the hand-off of ``[simulation] contact3d = true`` (the default).

The exact models (:mod:`.cylinder3d`, :mod:`.box3d`) hold while the body rocks or wobbles without slipping; where
its base would slide, twist or lift off they stop (``simulation_guard`` model_limit), and where it would slip while
falling past the tipping point they follow the fall with the contact held (held_past_alpha). Such a scene is run
again by the contact model over the whole record from rest (nothing of the exact model's run is carried over), and
its verdict, peak tilt and history are the contact model's: physics ``contact3d``. The contact model's own caps
are flagged (step_cap where a step's contact problem ended at its sweep cap, tail_cap where the body still moved
at the end of its tail), never silent. Against PyBullet, handing over the held scenes too changed no agreement
count in any family (docs/validation.md).
"""

from __future__ import annotations

import math

import numpy as np

from ..codes import ContactMode
from ..scene import FreeFlight, Guard, Physics, Response, Scene
from .box3d import Box
from .contact3d import FLAG_TAIL_CAP, Contact3DOutcome, simulate_contact3d
from .convex_body import ConvexBody, box_body, cylinder_body
from .cylinder3d import Cylinder


def convex_body(body: Cylinder | Box) -> ConvexBody:
    """The contact model's body of an exact model's cylinder or box (restitution: plastic contacts, which give
    Housner's rule at a pivot)."""
    if isinstance(body, Cylinder):
        return cylinder_body(2.0 * body.radius_m, 2.0 * body.half_height_m, mu=body.mu)
    return box_body(2.0 * body.half_width_m, 2.0 * body.half_depth_m, 2.0 * body.half_height_m, mu=body.mu)


def contact_scene(h1, h2, vertical, dt_s: float, body: Cylinder | Box, azimuth_deg: float, alpha: float, *,
                  g_ms2: float, amplitude: float = 1.0, history: bool = False) -> tuple[Scene, Contact3DOutcome]:
    """The scene of ``body`` (its width axis at ``azimuth_deg`` in the models' frame: x the record's first
    horizontal, y its second reversed) under the record times ``amplitude``, by the contact model; theta_max (and
    with ``history`` theta_over_alpha) as a fraction of ``alpha``. With the contact model's outcome (where it leant:
    ``lean_at_peak_deg``, with ``history`` ``lean_deg``, in the models' frame)."""
    av = None if vertical is None or np.size(vertical) == 0 else amplitude * np.asarray(vertical, dtype=float)
    out = simulate_contact3d(amplitude * np.asarray(h1, dtype=float), -amplitude * np.asarray(h2, dtype=float), av,
                             dt_s, convex_body(body), yaw_deg=azimuth_deg, g_ms2=g_ms2, history=history)
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

