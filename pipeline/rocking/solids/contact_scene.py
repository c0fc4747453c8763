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
from collections.abc import Callable

import numpy as np

from ..codes import ContactMode
from ..scene import FreeFlight, Guard, Physics, Response, Scene
from .box3d import Box, BoxOutcome
from .contact3d import FLAG_TAIL_CAP, Contact3DOutcome, simulate_contact3d
from .contact_start import Start
from .convex_body import ConvexBody
from .cylinder3d import Cylinder, WobbleOutcome


def convex_body(body: Cylinder | Box) -> ConvexBody:
    """The contact model's body of an exact model's cylinder or box (restitution: plastic contacts, which give
    Housner's rule at a pivot)."""
    return body.convex()


def handoff(exact: WobbleOutcome | BoxOutcome | None, body: Cylinder | Box, azimuth_deg: float,
            dt_s: float) -> Start | None:
    """The contact model's :class:`~.contact_start.Start` at the last state ``exact`` certified before it stopped
    (None where it certified none: it never moved, or stopped at a cap); ``azimuth_deg`` the body's at rest. How the
    body turns there is its hand-off's (:mod:`.handoff3d`); its tilt and lean before are the exact model's."""
    if exact is None or exact.handoff is None:
        return None
    state = exact.handoff
    q, rate, pivot = state.state.turning(body, azimuth_deg)
    upto = int(math.floor(state.t_s / dt_s + 1e-9)) + 1
    tilt = np.asarray(exact.theta[:upto], dtype=float)
    lean = np.where(tilt > 0.0, np.asarray(exact.azimuth[:upto], dtype=float), math.nan)
    peak = int(np.nanargmax(tilt)) if np.any(np.isfinite(tilt)) else 0
    return Start(float(state.t_s), q, rate, pivot, float(np.nan_to_num(tilt[peak])), float(lean[peak]), tilt, lean)


def contact_scene(h1, h2, vertical, dt_s: float, body: Cylinder | Box, azimuth_deg: float, alpha: float, *,
                  g_ms2: float, amplitude: float = 1.0, history: bool = False,
                  exact: WobbleOutcome | BoxOutcome | None = None,
                  alternated: Callable[..., Contact3DOutcome] | None = None) -> tuple[Scene, Contact3DOutcome]:
    """The scene of ``body`` (its width axis at ``azimuth_deg`` in the models' frame: x the record's first
    horizontal, y its second reversed) under the record times ``amplitude``, by the contact model; theta_max (and
    with ``history`` theta_over_alpha) as a fraction of ``alpha``. With the contact model's outcome (where it leant:
    ``lean_at_peak_deg``, with ``history`` ``lean_deg``, in the models' frame). With ``alternated`` (its family's,
    for a verdict only, no history), the contact model handed back to the exact model where it can go on
    (:mod:`.alternate`)."""
    av = None if vertical is None or np.size(vertical) == 0 else amplitude * np.asarray(vertical, dtype=float)
    ax, ay = amplitude * np.asarray(h1, dtype=float), -amplitude * np.asarray(h2, dtype=float)
    start = handoff(exact, body, azimuth_deg, dt_s)
    if alternated is not None and not history:
        out = alternated(ax, ay, av, dt_s, body, azimuth_deg, start, g_ms2=g_ms2)
    else:
        out = simulate_contact3d(ax, ay, av, dt_s, convex_body(body), yaw_deg=azimuth_deg, g_ms2=g_ms2,
                                 history=history, start=start)
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

