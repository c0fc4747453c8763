"""The scene of a solid cylinder on a record with two horizontal components: one run of the 3D model
(:mod:`.cylinder3d`), no orientation scan (the cylinder is axisymmetric, so the record's orientation changes only
the direction it leans toward, tested), as a :class:`~.scene.Scene` the screening stores like any other.

Frames: the model's x is the record's first horizontal (compass azimuth ``A``) and its y is 90 deg counter-clockwise
of it seen from above, that is the record's second horizontal (at ``A + 90``, clockwise) reversed. A tilt toward
the model's azimuth ``phi`` leans toward the compass azimuth ``A - phi``.

Where the model stops because the base would slide or lift off (not modeled in 3D), the scene has no verdict
(``simulation_guard`` model_limit, ``overturn_simulated`` not_evaluated): never "stands". An overturning reached
with the rim held past alpha (:mod:`.cylinder3d`) is kept and flagged (held_past_alpha).
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import G
from .block import BlockShape
from .codes import ContactMode
from .cylinder3d import FLAG_FLIGHT, FLAG_NONE, FLAG_SLIDE, FLAG_STEPS, Cylinder, WobbleOutcome, simulate_cylinder
from .geometry import cylinder_p_e, effective_restitution
from .orientation import PlaneResult
from .scene import FreeFlight, Guard, Physics, Response, Scene
from .settings import SimulationConfig


def cylinder_of(shape: BlockShape, *, restitution_factor: float = 1.0) -> Cylinder:
    """The 3D model's :class:`~.cylinder3d.Cylinder` of an inventory cylinder: the declared restitution, else the
    cylinder's Housner value (:func:`~.geometry.effective_restitution`)."""
    a, h = shape.width_m / 2.0, shape.height_m / 2.0
    e = float(effective_restitution(np.array(shape.restitution), cylinder_p_e(a, h)[1], restitution_factor))
    return Cylinder(radius_m=a, half_height_m=h, mu=shape.mu, restitution=e)


def run_on_record(h1, h2, vertical, dt_s: float, cylinder: Cylinder, *, settings: SimulationConfig,
                  g_ms2: float = G, amplitude: float = 1.0) -> WobbleOutcome:
    """The 3D model on a record's two horizontals (the second 90 deg clockwise of the first) and its vertical
    (None: none), all scaled by ``amplitude``."""
    av = None if vertical is None or np.size(vertical) == 0 else amplitude * np.asarray(vertical, dtype=float)
    return simulate_cylinder(amplitude * np.asarray(h1, dtype=float), -amplitude * np.asarray(h2, dtype=float), av,
                             dt_s, cylinder, g_ms2=g_ms2, rtol=settings.rtol, atol_alpha=settings.atol)


def lean_azimuth_deg(outcome: WobbleOutcome, azimuth0_deg: float) -> float:
    """The compass azimuth the cylinder leant toward at its peak tilt (or fell toward) [deg, in [0, 360)]."""
    return (azimuth0_deg - outcome.azimuth_max_deg) % 360.0


def scene_of(outcome: WobbleOutcome, alpha: float, *, history: bool = False) -> Scene:
    """The :class:`~.scene.Scene` of a 3D run: theta_max as a fraction of alpha; sliding or lift-off of the base
    (the model's limits) leave no verdict."""
    stopped = outcome.flag in (FLAG_SLIDE, FLAG_FLIGHT, FLAG_STEPS)
    if outcome.overturned:
        response = Response.overturn
    elif outcome.flag == FLAG_FLIGHT:
        response = Response.free_flight
    elif outcome.flag == FLAG_SLIDE:
        response = Response.slide_rock
    else:
        response = Response.rock if outcome.theta_max_rad > 0 else Response.rest
    guard = ((Guard.model_limit if stopped else 0) | (Guard.step_cap if outcome.flag == FLAG_STEPS else 0)
             | (Guard.held_past_alpha if outcome.held != FLAG_NONE else 0))
    moved = outcome.theta_max_rad > 0
    return Scene(physics=Physics.wobbling if moved else Physics.none, response=response,
                 overturned=outcome.overturned, theta_max=outcome.theta_max_rad / alpha, n_impacts=outcome.impacts,
                 t_overturn=outcome.t_overturn_s, friction_demand=outcome.friction_demand, sliding_max_m=0.0,
                 free_flight=FreeFlight.block_liftoff if outcome.flag == FLAG_FLIGHT else FreeFlight.none,
                 chatter=False, friction_exceeded=1 if outcome.flag == FLAG_SLIDE else 0,
                 theta_over_alpha=outcome.theta / alpha if history else None,
                 contact_modes=int(ContactMode.rock) if moved else 0, guard=int(guard))


def cylinder_scene(h1, h2, vertical, dt_s: float, azimuth0_deg: float, shape: BlockShape, *,
                   settings: SimulationConfig = SimulationConfig(), g_ms2: float = G,
                   history: bool = False) -> PlaneResult:
    """A cylinder's scene on two horizontals: one 3D run; ``azimuth_deg`` is the compass azimuth it leant toward
    at its peak tilt, ``planes_simulated`` 1 (0 when it never lifted)."""
    c = cylinder_of(shape)
    out = run_on_record(h1, h2, vertical, dt_s, c, settings=settings, g_ms2=g_ms2)
    sc = scene_of(out, math.atan2(c.radius_m, c.half_height_m), history=history)
    return PlaneResult(sc, lean_azimuth_deg(out, azimuth0_deg) if out.theta_max_rad > 0 else math.nan,
                       1 if out.theta_max_rad > 0 else 0, ())


