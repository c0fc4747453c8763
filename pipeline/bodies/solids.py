"""The 3D body models: a solid cylinder (wobbling) and a box with a depth and an azimuth (3D rocking), judged on a
record's two horizontals by :mod:`pipeline.rocking.solids.solid3d`.

The cylinder model claims a cylinder on any record with two horizontals; the box model claims a box whose
inventory row gives a depth and an azimuth, on two horizontals of known absolute azimuth (:func:`solid_of`). On
one horizontal, or a box without them, the planar model judges the block. A box whose other base axis is
certified never to lift nor slip is judged by its planar scene in the plane of its width. A one-directional pulse
(``screen infer``) is judged by the planar model of the same block, along the pulse's component in its plane.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..rocking.block import Block, BlockShape
from ..rocking.orientation import Orientation, PlaneResult, worst_plane
from ..rocking.scene import Physics
from ..rocking.settings import SimulationConfig
from ..rocking.solids.box3d import Box, simulate_box
from ..rocking.solids.contact3d import simulate_contact3d
from ..rocking.solids.convex_body import box_body
from ..rocking.solids.cylinder3d import Cylinder, simulate_cylinder
from ..rocking.solids.solid3d import (
    Solid,
    cannot_tip,
    drawn,
    flight_factor,
    judge_solid,
    lift_factor,
    solid_of,
    solid_scene,
)
from ..uncertainty.orientations import NOT_EVALUATED_ORIENTATION, one_plane
from ..uncertainty.sampling import common_normals, sample_block
from ..uncertainty.solids import solid_probability
from .contract import (
    BodyModel,
    BodyScene,
    Margin,
    OnRecord,
    Placement,
    Setup,
    Stops,
    VersusPlanar,
    claims_on_two_horizontals,
)
from .factor_sweep import factor_sweep
from .planar import planar_pulse


def placed(shape: BlockShape, rec) -> Solid | None:
    """The 3D body of ``shape`` on ``rec`` (None: the scene stays planar)."""
    if rec.single_component:
        return None
    return solid_of(shape, record_azimuth_deg=float(rec.azimuths_deg[0]), known_azimuth=bool(rec.azimuth_known))


def _solid(rec, shape: BlockShape) -> Solid:
    solid = placed(shape, rec)
    assert solid is not None, "a solid model was given a block it does not claim"
    return solid


def scene(on: OnRecord, shape: BlockShape, block: Block, direction_deg: float) -> BodyScene:
    """A solid on a record with two horizontals: the nominal scene (a box's planar scene where its other axis is
    certified, else the 3D model's), its probability (one judgement per draw; a box's azimuth drawn as a planar
    scene's is, a cylinder's none) and how its orientation was chosen."""
    rec, setup = on.record, on.setup
    solid = _solid(rec, shape)
    res, certified = solid_scene(rec.horizontal_ms2[0], rec.horizontal_ms2[1], rec.vertical_ms2, rec.dt_s,
                                 float(rec.azimuths_deg[0]), solid, settings=setup.settings, g_ms2=setup.g_ms2)
    code = (Orientation.axisymmetric if solid.physics == Physics.wobbling
            else Orientation.given_certified if certified else Orientation.given_3d)
    orient = NOT_EVALUATED_ORIENTATION
    if on.base is not None and on.draws is not None:
        prob = solid_probability(on.base, on.draws[0], shape, solid, record_azimuth_deg=float(rec.azimuths_deg[0]),
                                 settings=setup.uncertainty, simulation=setup.settings, g_ms2=setup.g_ms2)
        orient = one_plane(prob, res.azimuth_deg)
    return BodyScene(res, orient, code, lambda: _detail(res, code))


def _detail(res: PlaneResult, code: int) -> str:
    """What a slow 3D scene was doing."""
    if code == Orientation.given_certified:
        return "box in the plane of its width (its other axis certified)"
    body = "cylinder" if code == Orientation.axisymmetric else "box"
    return f"{body} in 3D, leaning toward {res.azimuth_deg:.0f} deg"


def solid_scale_simulated(rec, solid: Solid, *, settings, g_ms2: float,
                          overturns_at_one: bool | None = None) -> tuple[float, int]:
    """The first factor on a record's two horizontals and vertical that overturns the solid, by its 3D model, in the
    upward scan of :func:`~.factor_sweep.factor_sweep` from the factor at which it first lifts
    (:func:`~pipeline.rocking.solids.solid3d.lift_factor`); and the scenes simulated. With the contact model on, a
    solid that cannot tip (:func:`~pipeline.rocking.solids.solid3d.cannot_tip`) stands at every factor below the
    one at which the ground first falls away (:func:`~pipeline.rocking.solids.solid3d.flight_factor`): those steps
    of the scan are decided by that certificate, nothing simulated."""
    h = rec.horizontal_ms2
    f = lift_factor(h[0], h[1], rec.vertical_ms2, solid, g_ms2=g_ms2)
    if not math.isfinite(f):
        return math.inf, 0
    flat_below = (flight_factor(rec.vertical_ms2, g_ms2=g_ms2) if settings.contact3d and cannot_tip(solid)
                  else 0.0)

    def verdict_at(factor: float) -> int:
        return judge_solid(h[0], h[1], rec.vertical_ms2, rec.dt_s, solid, settings=settings, g_ms2=g_ms2,
                           amplitude=factor, verdict_only=True).scene.verdict

    return factor_sweep(f, verdict_at, settings=settings, overturns_at_one=overturns_at_one, stands_below=flat_below)


def solid_history(rec, solid: Solid, *, settings, g_ms2: float) -> np.ndarray | None:
    """A solid's history on two horizontals (:func:`~pipeline.rocking.solids.solid3d.judge_solid`), shape (2, n):
    theta(t)/alpha and the compass azimuth it leans toward [deg] (NaN at rest and after overturning; a box judged in
    the plane of its width leans along it), or None where nothing lifts."""
    h = rec.horizontal_ms2
    got = judge_solid(h[0], h[1], rec.vertical_ms2, rec.dt_s, solid, settings=settings, g_ms2=g_ms2, history=True)
    theta, lean = got.scene.theta_over_alpha, got.lean_history_deg
    if theta is None or lean is None or not got.scene.theta_max > 0:
        return None
    return np.vstack([theta, (float(rec.azimuths_deg[0]) - lean) % 360.0])


def margins(rec, shape: BlockShape, block: Block, direction_deg: float, *, setup: Setup, overturned: bool,
            want_history: bool) -> Margin:
    """A solid's margins on two horizontals, by its 3D model (a box's planar scene where its other axis is
    certified): its scale scan, its history when at risk (:func:`solid_history`), and the sampled margins (each
    draw's own scan, as factors on the nominal record)."""
    g, settings = setup.g_ms2, setup.settings
    solid = _solid(rec, shape)
    scale, runs = solid_scale_simulated(rec, solid, settings=settings, g_ms2=g, overturns_at_one=overturned)
    history = None
    if want_history or scale <= setup.history_below_scale:
        history = solid_history(rec, solid, settings=settings, g_ms2=g)
    n = setup.uncertainty.margin_samples if setup.sampling else 0
    sampled = np.full(max(n, 0), np.nan)
    if n > 0:
        sb = sample_block(common_normals(setup.uncertainty.seed, n), shape, settings=setup.uncertainty, g_ms2=g)
        for k in range(n):
            az = None if np.isnan(sb.azimuth_deg[k]) else float(sb.azimuth_deg[k])
            body = drawn(solid, R_m=float(sb.R_m[k]), alpha=float(sb.alpha[k]), mu=float(sb.mu[k]),
                         restitution=float(sb.e[k]), azimuth_deg=az, record_azimuth_deg=float(rec.azimuths_deg[0]))
            eps = float(sb.amplitude[k])
            scaled = dataclasses.replace(rec, horizontal_ms2=eps * rec.horizontal_ms2,
                                         vertical_ms2=None if rec.vertical_ms2 is None else eps * rec.vertical_ms2)
            s_k, r = solid_scale_simulated(scaled, body, settings=settings, g_ms2=g)
            sampled[k], runs = s_k * eps, runs + r
    return Margin(scale, runs, history, rec.dt_s, sampled)


def scale(rec, shape: BlockShape, block: Block, plane_deg: float, *, settings: SimulationConfig,
          g_ms2: float) -> float:
    """The simulated margin by the 3D model (on both horizontals: ``plane_deg`` is not used)."""
    return solid_scale_simulated(rec, _solid(rec, shape), settings=settings, g_ms2=g_ms2)[0]


def _cylinder_versus(on: OnRecord, shape: BlockShape, block: Block) -> PlaneResult:
    """The planar scan of the same cylinder: every rocking plane, the worst kept, with its own p and restitution."""
    settings = on.setup.settings
    return worst_plane(on.planes, [0.0, *on.grid_deg.tolist()], on.record.dt_s, settings=settings, block=block,
                       refine_span_deg=settings.orientation_step_deg, refine_deg=settings.orientation_refine_deg)


def _box_versus(on: OnRecord, shape: BlockShape, block: Block) -> PlaneResult:
    """The box's planar scene in the plane of its width (the component along its azimuth)."""
    settings = on.setup.settings
    return worst_plane(on.planes, [float(shape.azimuth_deg)], on.record.dt_s, settings=settings, block=block,
                       refine_span_deg=0.0, refine_deg=settings.orientation_refine_deg)


def _claims(physics: Physics):
    def claims(shape: BlockShape, placement: Placement, settings: SimulationConfig) -> bool:
        if placement.single_component:
            return False
        solid = solid_of(shape, record_azimuth_deg=placement.azimuth_deg, known_azimuth=placement.azimuth_known)
        return solid is not None and solid.physics == physics

    return claims, claims_on_two_horizontals(claims)


def contact_warmup() -> None:
    """The 3D contact model's kernel (the hand-off of both solids), on a tiny scene that tips a box."""
    a = 3.0 * np.sin(2.0 * np.pi * np.linspace(0.0, 2.0, 201))
    simulate_contact3d(a, 0.5 * a, None, 0.01, box_body(0.2, 0.3, 1.0, mu=0.7))


def _cylinder_warmup() -> None:
    """The 3D cylinder's kernel, on a tiny scene that lifts it."""
    a = 3.0 * np.sin(2.0 * np.pi * np.linspace(0.0, 2.0, 201))
    simulate_cylinder(a, 0.5 * a, None, 0.01, Cylinder(radius_m=0.1, half_height_m=0.5, mu=0.7, restitution=0.8))


def _box_warmup() -> None:
    """The 3D box's kernel, on a tiny scene that lifts it onto a corner."""
    a = 3.0 * np.sin(2.0 * np.pi * np.linspace(0.0, 2.0, 201))
    simulate_box(a, 0.5 * a, None, 0.01, Box(half_width_m=0.1, half_depth_m=0.15, half_height_m=0.5, mu=0.7))


#: Where the exact 3D models stop: the base would slide, twist or lift off, which they do not follow.
_EXACT_3D_STOP = "the model stops where the base slides, twists or lifts off"

_cylinder_claims, _cylinder_may = _claims(Physics.wobbling)
_box_claims, _box_may = _claims(Physics.rocking3d)

#: A solid cylinder on two horizontals: wobbling in 3D.
CYLINDER = BodyModel(
    name="cylinder", physics=(Physics.wobbling, Physics.contact3d), claims=_cylinder_claims,
    may_claim=_cylinder_may, scene=scene, margins=margins, scale=scale, pulse=planar_pulse, warmups=(_cylinder_warmup,),
    shared_warmups=(contact_warmup,), stops=(Stops((Physics.wobbling,), _EXACT_3D_STOP, contact3d_decides=True),),
    versus_planar=VersusPlanar("cylinders", "3D model (one run, no orientation scan)",
                               "planar scan of the same cylinders (worst plane; vs the 3D verdicts)", _cylinder_versus))
#: A box with a depth and an azimuth on two horizontals of known azimuth: rocking in 3D.
BOX = BodyModel(
    name="box in 3D", physics=(Physics.rocking3d, Physics.contact3d), claims=_box_claims, may_claim=_box_may,
    scene=scene, margins=margins, scale=scale, pulse=planar_pulse, warmups=(_box_warmup,),
    shared_warmups=(contact_warmup,), stops=(Stops((Physics.rocking3d,), _EXACT_3D_STOP, contact3d_decides=True),),
    versus_planar=VersusPlanar("boxes in 3D", "3D model (one run at the box's azimuth, both horizontals)",
                               "planar scene in the plane of the width (vs the 3D verdicts)", _box_versus))
