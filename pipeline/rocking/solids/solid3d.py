"""The 3D scenes of solids on a record's two horizontal components, one interface for the screening, the margins
and the probabilities: a solid cylinder (:mod:`.cylinder3d`, its scene in :mod:`.cylinder_scene`) and a box with a
depth and a known azimuth (:mod:`.box3d`).

Which scenes are 3D (:func:`solid_of`): a cylinder on two horizontals; a box whose inventory row gives a depth and
an azimuth, on two horizontals of known absolute azimuth. A box with a blank azimuth keeps the planar scan of its
rocking planes (the worst kept), and a box without a depth the planar model (infinitely deep).

Frames: the models' x is the record's first horizontal (compass azimuth ``A``) and their y is 90 deg
counter-clockwise of it seen from above, that is the record's second horizontal (at ``A + 90``, clockwise)
reversed. A box whose width faces compass azimuth ``B`` has its width axis at ``A - B`` in the model; a tilt toward
the model's azimuth ``phi`` leans toward the compass azimuth ``A - phi``.

A box whose other base axis is certified never to lift nor slip under the record (:mod:`.box_planar`) is judged by
its planar scene in the plane of its width, whose equation the 3D model then follows (:func:`judge_solid`).

Where a model stops because its base would slide or lift off (not modeled here), or follows the fall past the
tipping point with its contact held, the scene is decided by the 3D contact model (:mod:`.contact_scene`; the
default, ``[simulation] contact3d = true``). With the setting off, a stopped scene has no verdict (``simulation_guard``
model_limit, ``overturn_simulated`` not_evaluated): never "stands"; an overturning reached with the contact held is
kept and flagged (held_past_alpha).
"""

from __future__ import annotations

import dataclasses
import math
from functools import partial
from typing import NamedTuple

import numpy as np

from ...compiled import jit
from ...constants import G
from ..block import BlockShape, ShapeKind
from ..codes import ContactMode
from ..orientation import PlaneResult
from ..scene import REST_SCENE, FreeFlight, Guard, Physics, Response, Scene
from ..settings import SimulationConfig
from .box3d import Box, BoxOutcome
from .box_scene import BOX, box_of
from .contact_scene import contact_scene
from .cylinder3d import Cylinder, WobbleOutcome
from .cylinder_scene import CYLINDER, cylinder_of
from .family import SolidFamily
from .vec3 import FLAG_FLIGHT, FLAG_NONE, FLAG_SLIDE, FLAG_STEPS


class Solid(NamedTuple):
    """A body simulated in 3D, placed on a record.

    Attributes
    ----------
    body : Cylinder or Box
    azimuth_deg : float
        the box's width axis in the model's frame [deg, from x toward y] (0 for a cylinder)
    alpha : float
        the slenderness its tilt is reported against (a box: the plane of its width) [rad]
    """

    body: Cylinder | Box
    azimuth_deg: float
    alpha: float

    @property
    def family(self) -> SolidFamily:
        """Its body's family (:data:`FAMILIES`)."""
        return FAMILIES[type(self.body)]

    @property
    def physics(self) -> Physics:
        """The code of its exact model's scenes (its family's)."""
        return self.family.physics


#: The families of 3D bodies, by the type of their body: a new body is its module and one line here.
FAMILIES: dict[type, SolidFamily] = {Cylinder: CYLINDER, Box: BOX}


def solid_of(shape: BlockShape, *, record_azimuth_deg: float, known_azimuth: bool) -> Solid | None:
    """The 3D body of an inventory row on a record with two horizontals (the first at compass
    ``record_azimuth_deg``; ``known_azimuth`` False for a relative pair), or None where the scene stays planar."""
    if shape.kind == ShapeKind.cylinder:
        c = cylinder_of(shape)
        return Solid(c, 0.0, math.atan2(c.radius_m, c.half_height_m))
    if math.isnan(shape.depth_m) or math.isnan(shape.azimuth_deg) or not known_azimuth:
        return None
    return Solid(box_of(shape), (record_azimuth_deg - shape.azimuth_deg) % 360.0,
                 math.atan2(shape.width_m, shape.height_m))


def drawn(solid: Solid, *, R_m: float, alpha: float, mu: float, restitution: float,
          azimuth_deg: float | None = None, record_azimuth_deg: float = 0.0) -> Solid:
    """The solid of one draw of the declared uncertainty (its sampled R, alpha, friction and restitution; a box
    keeps its depth-to-width ratio and takes the drawn compass azimuth where given)."""
    az = solid.azimuth_deg if azimuth_deg is None else (record_azimuth_deg - azimuth_deg) % 360.0
    body, az = solid.family.drawn(solid.body, az, R_m=R_m, alpha=alpha, mu=mu, restitution=restitution)
    return Solid(body, az, alpha)


def run(h1, h2, vertical, dt_s: float, solid: Solid, *, settings: SimulationConfig, g_ms2: float = G,
        amplitude: float = 1.0) -> WobbleOutcome | BoxOutcome:
    """The solid's 3D model on a record's two horizontals (the second 90 deg clockwise of the first) and its
    vertical (None: none), all scaled by ``amplitude``."""
    return solid.family.run(h1, h2, vertical, dt_s, solid.body, solid.azimuth_deg, settings=settings, g_ms2=g_ms2,
                            amplitude=amplitude)


def scene_of(outcome: WobbleOutcome | BoxOutcome, solid: Solid, *, history: bool = False) -> Scene:
    """The :class:`~.scene.Scene` of a 3D run: theta_max as a fraction of the solid's alpha; sliding or lift-off of
    the base (the models' limits) leave no verdict."""
    stopped = outcome.flag in (FLAG_SLIDE, FLAG_FLIGHT, FLAG_STEPS)
    if outcome.overturned:
        response = Response.overturn
    elif outcome.flag == FLAG_FLIGHT:
        response = Response.free_flight
    elif outcome.flag == FLAG_SLIDE:
        response = Response.slide_rock if outcome.theta_max_rad > 0 else Response.slide
    else:
        response = Response.rock if outcome.theta_max_rad > 0 else Response.rest
    guard = ((Guard.model_limit if stopped else 0) | (Guard.step_cap if outcome.flag == FLAG_STEPS else 0)
             | (Guard.held_past_alpha if outcome.held != FLAG_NONE else 0)
             | (Guard.tie_hold if getattr(outcome, "holds", 0) else 0))
    moved = outcome.theta_max_rad > 0
    # proven at rest (physics none) only where the model checked every interval and nothing lifted or slid
    simulated = moved or outcome.flag != FLAG_NONE
    return Scene(physics=solid.physics if simulated else Physics.none, response=response,
                 overturned=outcome.overturned, theta_max=outcome.theta_max_rad / solid.alpha,
                 n_impacts=outcome.impacts, t_overturn=outcome.t_overturn_s, friction_demand=outcome.friction_demand,
                 sliding_max_m=0.0, free_flight=FreeFlight.block_liftoff if outcome.flag == FLAG_FLIGHT
                 else FreeFlight.none, chatter=False, friction_exceeded=1 if outcome.flag == FLAG_SLIDE else 0,
                 theta_over_alpha=outcome.theta / solid.alpha if history else None,
                 contact_modes=int(ContactMode.rock) if moved else 0, guard=int(guard))


class Judged(NamedTuple):
    """A solid's scene on two horizontals (:func:`judge_solid`).

    Attributes
    ----------
    scene : Scene
    lean_deg : float
        where it leant at its peak tilt, as the models' azimuth [deg, from x toward y] (NaN: it never lifted;
        a certified box: its width axis, the plane it rocked in)
    certified : bool
        a box judged in the plane of its width, its other axis certified (:mod:`.box_planar`)
    lean_history_deg : ndarray or None
        with ``history``: where it leans at each sample, as the models' azimuth [deg] (NaN at rest and after
        overturning)
    """

    scene: Scene
    lean_deg: float
    certified: bool
    lean_history_deg: np.ndarray | None = None


def judge_solid(h1, h2, vertical, dt_s: float, solid: Solid, *, settings: SimulationConfig = SimulationConfig(),
                g_ms2: float = G, amplitude: float = 1.0, history: bool = False, verdict_only: bool = False) -> Judged:
    """A solid's scene on a record's two horizontals and vertical (all scaled by ``amplitude``): at rest where the
    record leaves it so (:func:`stays_at_rest`: nothing integrated), a box's planar scene in the plane of its width
    where its other axis is certified, else the 3D model's. With ``verdict_only`` (the draws and the margin scan,
    which keep only the verdict) and the contact model on, a body that stays flat (:func:`stays_flat`) stands,
    nothing integrated (:data:`FLAT_SLIDE_SCENE`: its sliding distance is not computed)."""
    if stays_at_rest(h1, h2, vertical, solid, g_ms2=g_ms2, amplitude=amplitude):
        n = np.size(h1)
        return Judged(dataclasses.replace(REST_SCENE, theta_over_alpha=np.zeros(n) if history else None), math.nan,
                      False, np.full(n, math.nan) if history else None)
    if verdict_only and not history and settings.contact3d and stays_flat(vertical, solid, g_ms2=g_ms2,
                                                                          amplitude=amplitude):
        return Judged(FLAT_SLIDE_SCENE, math.nan, False)
    certified_scene = solid.family.certified_scene
    if certified_scene is not None:
        cs = certified_scene(h1, h2, vertical, dt_s, solid.body, solid.azimuth_deg, settings=settings,
                             g_ms2=g_ms2, amplitude=amplitude, history=history)
        if cs.other_axis.certified and cs.scene is not None:
            theta = cs.scene.theta_over_alpha
            lean = None if theta is None else np.where(
                theta > 0, solid.azimuth_deg, np.where(theta < 0, solid.azimuth_deg + 180.0, math.nan))
            return Judged(cs.scene, solid.azimuth_deg if cs.scene.theta_max > 0 else math.nan, True, lean)
    out = run(h1, h2, vertical, dt_s, solid, settings=settings, g_ms2=g_ms2, amplitude=amplitude)
    lean = np.where(out.theta > 0, np.degrees(out.azimuth), math.nan) if history else None
    scene = scene_of(out, solid, history=history)
    if settings.contact3d and scene.guard & (Guard.model_limit | Guard.held_past_alpha):
        alternated = solid.family.alternated if verdict_only and settings.handback else None
        handed, c3 = contact_scene(h1, h2, vertical, dt_s, solid.body, solid.azimuth_deg, solid.alpha, g_ms2=g_ms2,
                                   amplitude=amplitude, history=history, exact=out,
                                   alternated=None if alternated is None else partial(alternated, settings=settings))
        return Judged(handed, c3.lean_at_peak_deg % 360.0 if c3.tilt_max_rad > 0 else math.nan, False, c3.lean_deg)
    return Judged(scene, out.azimuth_max_deg if out.theta_max_rad > 0 else math.nan, False, lean)


def solid_scene(h1, h2, vertical, dt_s: float, record_azimuth_deg: float, solid: Solid, *,
                settings: SimulationConfig = SimulationConfig(), g_ms2: float = G,
                history: bool = False) -> tuple[PlaneResult, bool]:
    """A solid's scene on two horizontals (:func:`judge_solid`) and whether it was certified planar:
    ``azimuth_deg`` is the compass azimuth it leant toward at its peak tilt (a certified box: its width's),
    ``planes_simulated`` 1 (0 when it never lifted)."""
    j = judge_solid(h1, h2, vertical, dt_s, solid, settings=settings, g_ms2=g_ms2, history=history)
    moved = j.scene.theta_max > 0
    lean = (record_azimuth_deg - j.lean_deg) % 360.0 if moved else math.nan
    return PlaneResult(j.scene, lean, 1 if moved else 0, ()), j.certified


def _pushes(x, y, solid: Solid) -> list[tuple[np.ndarray, float]]:
    """The ground's push against each way the solid at rest can lift, and that way's tan of slenderness: a
    cylinder's |a_h| and tan alpha; a box's acceleration along each base edge's inward normal and b_n / h."""
    tans = _tipping_tans(solid)
    if len(tans) == 1:
        return [(np.hypot(x, y), tans[0])]
    c, s = math.cos(math.radians(solid.azimuth_deg)), math.sin(math.radians(solid.azimuth_deg))
    along, across = c * x + s * y, -s * x + c * y
    tw, td = tans
    return [(along, tw), (-along, tw), (across, td), (-across, td)]


def _tipping_tans(solid: Solid) -> tuple[float, ...]:
    """The tan of each static tipping angle of the solid as it stands: a cylinder's (r / h); a box's about the edges
    across its width and across its depth (b / h, d / h; half sizes)."""
    return solid.family.tipping_tans(solid.body)


def _components(h1, h2, vertical, amplitude: float = 1.0):
    """The models' (x, y, z) ground components of a record's two horizontals and vertical, times ``amplitude``."""
    x, y = amplitude * np.asarray(h1, dtype=float), -amplitude * np.asarray(h2, dtype=float)
    v = np.zeros_like(x) if vertical is None or np.size(vertical) == 0 else amplitude * np.asarray(vertical, float)
    return x, y, v


def tan_alpha_min(solid: Solid) -> float:
    """The tan of the solid's smallest static tipping angle as it stands (:func:`_tipping_tans`) [-]."""
    return min(_tipping_tans(solid))


def cannot_tip(solid: Solid) -> bool:
    """Whether the solid standing on its base is certified not to tip while the ground pushes it up (g + a_z > 0
    throughout): mu < tan alpha_min (:func:`tan_alpha_min`; strictly: at mu = tan alpha_min the contact force can
    reach a base edge).

    What holds (rigid body, Coulomb's law at every point of a flat base): while the body stands flat, turning only
    about the vertical (a principal axis, so no gyroscopic moment), the base's friction forces, at h below G, tilt it
    with the moment h F_t, which the normal forces balance where their centre of pressure lies h F_t / F_n from
    below G. Coulomb's law bounds that offset by mu h, below the base's inradius about G (h tan alpha_min), and
    every such point is a centre of pressure the base's contacts can give with non-negative normal forces (each
    contact's own friction offset is below the inradius too, so the origin lies in the hull of the offset contacts).
    So the flat motion, sliding and twisting, meets every equation of the model at every instant while the ground
    pushes up, and so does a step of the 3D contact model. That it is the motion the model follows (a rigid body with
    friction need not have a single solution) is measured: the contact model keeps the three sliding objects of
    tests/rocking/solids/test_cannot_tip.py within 1e-4 rad of flat on real records. Where the
    ground falls away faster than gravity the body flies, and a flat landing is not robust (the contact model
    overturns a squat box, mu 0.15 against tan alpha_min 0.5, thrown up by El Centro #6 x10), so the certificate
    stops there (:func:`stays_flat`)."""
    return solid.body.mu < tan_alpha_min(solid)


def stays_flat(vertical, solid: Solid, *, g_ms2: float = G, amplitude: float = 1.0) -> bool:
    """Whether the solid standing on its base stays flat under the record times ``amplitude``, whatever its
    horizontals: it cannot tip (:func:`cannot_tip`) and ``amplitude`` is below :func:`flight_factor`, so the ground
    pushes it up at every sample (and between them: the ground is linear there)."""
    return cannot_tip(solid) and amplitude < flight_factor(vertical, g_ms2=g_ms2)


def flight_factor(vertical, *, g_ms2: float = G) -> float:
    """The smallest factor on the record at which the ground falls away as fast as gravity at some sample
    (g + factor a_z <= 0) [-] (inf: none; its vertical never falls)."""
    if vertical is None or np.size(vertical) == 0:
        return math.inf
    fall = -float(np.min(vertical))
    return g_ms2 / fall if fall > 0.0 else math.inf


#: The scene of a solid that cannot tip (:func:`cannot_tip`) where only its verdict is wanted: it stands; it slides
#: (its distance is not computed, NaN), or rests.
FLAT_SLIDE_SCENE = Scene(physics=Physics.sliding, response=Response.slide, overturned=False, theta_max=0.0,
                         n_impacts=0, t_overturn=math.nan, friction_demand=math.nan, sliding_max_m=math.nan,
                         free_flight=0, chatter=False, friction_exceeded=-1, contact_modes=int(ContactMode.slide))


def lift_factor(h1, h2, vertical, solid: Solid, *, g_ms2: float = G) -> float:
    """The smallest factor on the record at which the solid at rest first lifts [-] (inf: never): a cylinder where
    |a_h| > (g + a_z) tan alpha in any direction, a box about the first of its four base edges whose moment balance
    fails (-a . n > (g + a_z) b_n / h, n the edge's outward normal)."""
    x, y, v = _components(h1, h2, vertical)
    best = math.inf
    for push, tan_b in _pushes(x, y, solid):
        lift = push - v * tan_b
        if np.any(lift > 0):
            best = min(best, float(np.min(g_ms2 * tan_b / lift[lift > 0])))
    return best


def stays_at_rest(h1, h2, vertical, solid: Solid, *, g_ms2: float = G, amplitude: float = 1.0) -> bool:
    """Whether the record (times ``amplitude``) leaves the solid at rest throughout, as its 3D model would: at no
    sample does the ground lift it (:func:`lift_factor`'s condition), slide its base (|a_h| > mu (g + a_z)) or fall
    away (g + a_z <= 0). Exact: the ground is linear between samples and each margin is convex there, so its peak
    is at a sample; the boundaries hold, as in the models. Compiled, and it stops at the first sample that moves
    the solid (:func:`_quiet_throughout`)."""
    tans = _tipping_tans(solid)
    v = _NO_VERTICAL if vertical is None or np.size(vertical) == 0 else np.asarray(vertical, dtype=float)
    c, s = math.cos(math.radians(solid.azimuth_deg)), math.sin(math.radians(solid.azimuth_deg))
    return _quiet_throughout(np.asarray(h1, dtype=float), np.asarray(h2, dtype=float), v, float(amplitude),
                             float(g_ms2), float(solid.body.mu), c, s, tans[0], tans[-1], len(tans) == 1)


_NO_VERTICAL = np.zeros(0)


@jit
def _quiet_throughout(h1, h2, vertical, amplitude, g, mu, c, s, tan_w, tan_d, round_base):
    """The samples' test of :func:`stays_at_rest`, in the models' frame (x the first horizontal, y the second
    reversed, :func:`_components`): g + a_z > 0, |a_h| <= mu (g + a_z), and the push against each way it can lift
    within (g + a_z) times that way's tan (:func:`_pushes`: a cylinder's |a_h| against tan alpha; a box's
    acceleration along and across its width, at ``c``, ``s`` the cosine and sine of its azimuth, against ``tan_w``
    and ``tan_d``), each term as :func:`_pushes` forms it; False at the first sample that fails."""
    for i in range(h1.size):
        x, y = amplitude * h1[i], -amplitude * h2[i]
        gv = g + (amplitude * vertical[i] if vertical.size else 0.0)
        radial = math.hypot(x, y)
        if gv <= 0.0 or radial > mu * gv:
            return False
        if round_base:
            if radial > gv * tan_w:
                return False
        else:
            along, across = c * x + s * y, -s * x + c * y
            if along > gv * tan_w or -along > gv * tan_w or across > gv * tan_d or -across > gv * tan_d:
                return False
    return True
