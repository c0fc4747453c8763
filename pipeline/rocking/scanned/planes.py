"""The scenes of a body given by its scan (:class:`~.block.ShapeKind` ``scanned``): the vertical planes it is judged
in, and one plane's scene by the model ``[simulation] scanned_model`` names (:class:`~.settings.ScannedModel`):

* ``rolling`` (the default): the body rolls on the pivots of its convex hull's outline in the plane, in turn
  (:mod:`pipeline.shapes.hull`, :mod:`.rolling`); the model scored against the granite shake-table tests;
* ``two_sided``: it rocks on one pivot per side, the footprint's extreme points within 2 mm of the base
  (:mod:`pipeline.shapes.plane`, :mod:`.two_sided`).

Which planes (:func:`scene_planes`; a body's plane is given in its settled axes, from x toward y, over 360 deg
since its two sides differ; a record's direction ``psi`` meets the body's plane ``B - psi``, B the compass direction
of the body's +x):

The body's planes (:func:`body_planes`) are the grid's (``step_deg``, in the body's settled axes) and the plane in
which it tips most easily, wherever the mesh's rotation puts it.

* **a given azimuth** on two horizontals of known azimuth: every one of the body's planes,
  each under the record's projection on that plane's compass direction; the worst is kept;
* **a blank azimuth** (or a record whose absolute azimuth is unknown): the orientation is unknown, so the search
  runs over both the body's plane and the record's direction, one after the other: every one of the body's planes
  facing the record's pulse axis; then the worst of them facing every direction of the record's grid over 360
  deg (:func:`record_planes`); the worst is kept. This coordinate search is a stated choice: the worst pair of the
  full grid of both (72 x 72 runs) may be worse, and so may a plane between the grid's;
* **one horizontal**: the recorded direction, every one of the body's planes facing it (its azimuth, rarely
  known for one horizontal, is not used).

The scene's verdict is the model's: neither slides (each records the pivot's friction demand and
``friction_exceeded`` flags a scene whose pivot would slip), and a ground
falling faster than gravity, a step or event cap or the free motion's cap leave the scene without a verdict
(``model_limit``). ``theta_max`` is each side's peak tilt over its static tipping angle (a rectangle's: alpha),
the larger of the two.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...constants import G
from ...records.record import project
from ...shapes.hull import HullChain, hull_chain
from ...shapes.plane import PlaneBody, chain_plane, plane_body, weakest_plane
from ...shapes.scan import ScannedShape
from ..block import Block, BlockShape
from ..codes import (
    STATUS_CHATTER,
    STATUS_EVENT_CAP,
    STATUS_GROUND_FLIGHT,
    STATUS_LIFTOFF,
    STATUS_STEP_CAP,
    STATUS_TAIL_CAP,
    STATUS_TIE_HOLD,
    ContactMode,
)
from ..geometry import effective_restitution
from ..geometry import geometry as geometry_of
from ..orientation import PlaneResult
from ..planner import simulate_scene
from ..scene import FreeFlight, Guard, Physics, Response, Scene
from ..settings import ScannedModel, SimulationConfig
from ..simulate import step_control
from .rolling import landing_ratio, roll_on_hull
from .two_sided import rock_two_sided_compiled, two_sided_block

#: A plane replaces the worst so far only where its theta_max is larger by more than this fraction, so that a mirror
#: plane of a symmetric body (the same response to rounding) never displaces the first [-]
TIE_RTOL = 1e-9
#: The status bits that leave a scanned scene without a verdict
NO_VERDICT_STATUS = STATUS_GROUND_FLIGHT | STATUS_STEP_CAP | STATUS_TAIL_CAP | STATUS_EVENT_CAP
#: A plane's two pivots and second moments are a uniform rectangle's within this relative tolerance [-]
RECTANGLE_RTOL = 1e-6


class RectangleSection(NamedTuple):
    """A plane in which a scanned body is a uniform rectangle (its hull's two pivots symmetric about G, its second
    moments a uniform rectangle's: a box's width or depth plane): the planar registry's block of these sizes.

    Attributes
    ----------
    width_m, height_m : float
        Full width and height [m].
    """

    width_m: float
    height_m: float


#: A scanned body's geometry in one plane, as its model takes it
PlaneGeometry = PlaneBody | HullChain | RectangleSection


class ScannedPlane(NamedTuple):
    """One plane of a scanned scene.

    Attributes
    ----------
    record_deg : float
        Compass azimuth the record is projected on [deg, in [0, 360)] (the opposite sense of a horizontal is the
        body's plane + 180 deg: its planes run over 360 deg).
    body_deg : float
        The body's plane facing it, in its settled axes [deg, from x toward y, in [0, 360)].
    """

    record_deg: float
    body_deg: float


class PlaneSearch(NamedTuple):
    """What :func:`worst_scanned` found.

    Attributes
    ----------
    result : PlaneResult
        The worst plane's scene (its azimuth: the record's compass direction).
    governing : ScannedPlane
        That plane.
    scenes : list of (ScannedPlane, Scene)
        Every plane simulated and its scene, in the order simulated.
    """

    result: PlaneResult
    governing: ScannedPlane
    scenes: list[tuple[ScannedPlane, Scene]]

    @property
    def ranked(self) -> list[ScannedPlane]:
        """Every plane simulated, the nearest to overturning first (overturned, then the largest theta_max; the
        order simulated on ties)."""
        return [pl for pl, _sc in sorted(self.scenes, key=lambda item: (-item[1].overturned, -item[1].theta_max))]


#: Two body planes closer than this are one [deg].
SAME_PLANE_DEG = 1e-6


def full_circle(grid_deg: np.ndarray) -> np.ndarray:
    """A grid over [0, 180) doubled to [0, 360) [deg]: a scanned body's two sides differ."""
    return np.concatenate([grid_deg, grid_deg + 180.0])


def body_planes(grid_deg: np.ndarray, scan: ScannedShape | None = None) -> list[float]:
    """The body's planes a search runs over: the grid over [0, 180) doubled to [0, 360) [deg], in the body's own
    axes, and the plane of the footprint's smallest uplift (:func:`~pipeline.shapes.plane.weakest_plane`, the normal
    of its footprint's edge nearest to G) where it falls between the grid's, so that plane is judged whatever the
    mesh's rotation."""
    planes = [float(phi) for phi in full_circle(grid_deg)]
    if scan is not None:
        weak = weakest_plane(scan)
        if min(abs((weak - phi + 180.0) % 360.0 - 180.0) for phi in planes) > SAME_PLANE_DEG:
            planes.append(weak)
    return planes


def scene_planes(shape: BlockShape, *, direction_deg: float, grid_deg: np.ndarray, single_component: bool,
                 azimuth_known: bool) -> list[ScannedPlane]:
    """The planes a scanned body is judged in first on one record (see the module; a blank azimuth on two
    horizontals continues with :func:`record_planes`)."""
    scan = shape.scan
    assert scan is not None
    if azimuth_known and not single_component and math.isfinite(shape.azimuth_deg):
        return [ScannedPlane(float((shape.azimuth_deg - phi) % 360.0), phi) for phi in body_planes(grid_deg, scan)]
    return [ScannedPlane(float(direction_deg % 360.0), phi) for phi in body_planes(grid_deg, scan)]


def record_planes(plane: ScannedPlane, grid_deg: np.ndarray) -> list[ScannedPlane]:
    """The body's plane of ``plane`` facing every direction of the record's grid over 360 deg but its own."""
    return [plane._replace(record_deg=float(psi)) for psi in full_circle(grid_deg) if float(psi) != plane.record_deg]


def along(horizontal_ms2: np.ndarray, azimuth0_deg: float, plane: ScannedPlane) -> np.ndarray:
    """The record's horizontal motion along a plane's compass direction [m s-2]."""
    return np.ascontiguousarray(project(np.atleast_2d(horizontal_ms2), azimuth0_deg, plane.record_deg), dtype=float)


def plane_geometry(scan: ScannedShape, body_deg: float, settings: SimulationConfig) -> PlaneGeometry:
    """The body's geometry in its plane ``body_deg`` as the model of ``settings.scanned_model`` takes it.

    With the rolling model, two exact shortcuts: a hull with one pivot per side in that plane (a prism's: the two
    ends of its flat base) rolls as the two-sided model rocks it, on the same two pivots by the same equations and
    impact rule, so it is given to that model, whose integrator is adaptive (the rolling model's steps are fixed);
    and where the body is a uniform rectangle in that plane (:func:`rectangle_section`), it is the block of the
    planar registry, whose models also slide, fly and take over where pure rocking stops holding."""
    if settings.scanned_model == ScannedModel.two_sided:
        return plane_body(scan, body_deg)
    chain = hull_chain(scan, body_deg)
    if len(chain.pivots_m) > 2:
        return chain
    return rectangle_section(chain) or chain_plane(chain)


def rectangle_section(chain: HullChain) -> RectangleSection | None:
    """The uniform rectangle a chain of one pivot per side is, where it is one (pivots symmetric about G, second
    moments b^2 / 3 along the plane and h^2 / 3 up, all within :data:`RECTANGLE_RTOL`), else None."""
    if len(chain.pivots_m) != 2:
        return None
    (u_minus, z_minus), (u_plus, z_plus) = chain.pivots_m
    b, h = 0.5 * (u_plus - u_minus), -0.5 * (z_minus + z_plus)
    close = (math.isclose(u_plus, -u_minus, rel_tol=RECTANGLE_RTOL) and math.isclose(z_plus, z_minus,
                                                                                      rel_tol=RECTANGLE_RTOL)
             and math.isclose(chain.second_u_m2, b * b / 3.0, rel_tol=RECTANGLE_RTOL)
             and math.isclose(chain.second_z_m2, h * h / 3.0, rel_tol=RECTANGLE_RTOL))
    return RectangleSection(2.0 * b, 2.0 * h) if close else None


def uplift_tan_alpha(geometry: PlaneGeometry, *, width_factor: float = 1.0, height_factor: float = 1.0) -> float:
    """tan alpha of the weaker side's pivot at rest, of the body scaled by a draw's factors: the record lifts the
    body where |a_h| exceeds (g + a_v) times this [-]."""
    if isinstance(geometry, HullChain):
        return geometry.base_tan_alpha() * width_factor / height_factor
    if isinstance(geometry, RectangleSection):
        return geometry.width_m * width_factor / (geometry.height_m * height_factor)
    two = geometry.two_sided(width_factor=width_factor, height_factor=height_factor)
    return math.tan(min(two.side(1.0)[0], two.side(-1.0)[0]))


def restitution_factor(body: PlaneBody | HullChain, restitution: float) -> float:
    """The factor on the impact rule's ratios of a declared restitution (NaN: the rule's own, 1): the declared value
    over the geometric mean of the rule's ratios onto either side (the two-sided body's impacts, the rolling
    chain's landings on the two ends of its base), so that a rectangle's impacts keep the declared ratio."""
    if not math.isfinite(restitution):
        return 1.0
    if isinstance(body, HullChain):
        both = landing_ratio(body, onto_plus=True) * landing_ratio(body, onto_plus=False)
    else:
        two = body.two_sided()
        both = two.impact_ratio(1.0) * two.impact_ratio(-1.0)
    return restitution / math.sqrt(max(both, 1e-300))


def plane_scene(ah_ms2: np.ndarray, av_ms2: np.ndarray | None, dt_s: float, geometry: PlaneGeometry, *,
                restitution: float, mu: float, settings: SimulationConfig = SimulationConfig(), g_ms2: float = G,
                history: bool = False, width_factor: float = 1.0, height_factor: float = 1.0,
                restitution_scale: float = 1.0, friction_scale: float = 1.0) -> Scene:
    """One plane's :class:`~.scene.Scene` by the model of its geometry (:func:`plane_geometry`).

    Parameters
    ----------
    ah_ms2, av_ms2 : ndarray
        Ground acceleration along the plane's + side and vertical (None: none) [m s-2].
    dt_s : float
        Sampling interval [s].
    geometry : PlaneBody, HullChain or RectangleSection
        The body in the plane: one pivot per side (the two-sided model), its hull's chain (the rolling model) or a
        uniform rectangle (the planar registry's block, :func:`pipeline.rocking.planner.simulate_scene`).
    restitution : float
        The declared restitution (NaN: the impact rule's own) [-].
    mu : float
        Friction coefficient: the rectangle's; against it the two-sided model's friction demand is flagged [-].
    width_factor, height_factor, restitution_scale, friction_scale : float
        A draw's factors on the body's sizes, on its impact ratios and on its friction (the rectangle's only) [-].
    """
    if isinstance(geometry, RectangleSection):
        shape = geometry_of(geometry.height_m * height_factor, geometry.width_m * width_factor, g_ms2=g_ms2)
        block = Block(p=float(shape.p), alpha=float(shape.alpha), R_m=float(shape.R), mu=mu * friction_scale,
                      e=float(effective_restitution(restitution, shape.e_housner, restitution_scale)), g_ms2=g_ms2)
        return simulate_scene(ah_ms2, av_ms2, dt_s, block=block, settings=settings, history=history)
    if isinstance(geometry, HullChain):
        return _rolling_scene(ah_ms2, av_ms2, dt_s, geometry, restitution=restitution, mu=mu, g_ms2=g_ms2,
                              history=history, width_factor=width_factor, height_factor=height_factor,
                              restitution_scale=restitution_scale)
    two = geometry.two_sided(width_factor=width_factor, height_factor=height_factor)
    factor = restitution_factor(geometry, restitution) * restitution_scale
    theta = np.zeros(np.asarray(ah_ms2).size) if history else np.zeros(0)
    av = np.zeros(0) if av_ms2 is None else np.ascontiguousarray(av_ms2, dtype=float)
    out = rock_two_sided_compiled(np.ascontiguousarray(ah_ms2, dtype=float), av, float(dt_s),
                                  two_sided_block(two, restitution_factor=factor, g_ms2=g_ms2),
                                  step_control(settings), theta)
    (a_plus, _r, _i), (a_minus, _r2, _i2) = two.side(1.0), two.side(-1.0)
    alpha = min(a_plus, a_minus)
    # a pivot that would slip is a sliding this model does not follow: no verdict, never "stands"
    slips = out.friction_max > mu and not out.overturned
    guard = ((Guard.model_limit if (out.status & NO_VERDICT_STATUS or slips) and not out.overturned else 0)
             | (Guard.tie_hold if out.status & STATUS_TIE_HOLD else 0)
             | (Guard.event_cap if out.status & STATUS_CHATTER else 0))
    flight = out.status & STATUS_GROUND_FLIGHT and not out.overturned
    response = (Response.overturn if out.overturned else Response.free_flight if flight
                else Response.slide_rock if out.friction_max > mu else Response.rock if out.n_uplifts
                else Response.rest)
    return Scene(physics=Physics.two_sided, response=response, overturned=bool(out.overturned),
                 theta_max=max(out.theta_max_plus / a_plus, out.theta_max_minus / a_minus),
                 n_impacts=int(out.n_impacts), t_overturn=float(out.t_overturn),
                 friction_demand=float(out.friction_max),
                 sliding_max_m=math.nan, free_flight=FreeFlight.ground_flight if flight else FreeFlight.none,
                 chatter=bool(out.status & STATUS_CHATTER), friction_exceeded=int(out.friction_max > mu),
                 theta_over_alpha=theta / alpha if history else None,
                 contact_modes=ContactMode.rock if out.n_uplifts else 0, guard=guard)


def _rolling_scene(ah_ms2: np.ndarray, av_ms2: np.ndarray | None, dt_s: float, chain: HullChain, *,
                   restitution: float, mu: float, g_ms2: float, history: bool, width_factor: float,
                   height_factor: float, restitution_scale: float) -> Scene:
    """One plane's scene by the rolling model (:mod:`.rolling`): theta_max and the history over each side's
    static tipping angle (:meth:`~pipeline.shapes.hull.HullChain.tipping_rad`); a pivot that needs more friction
    than ``mu`` is flagged (``friction_exceeded``, response slide_rock) and one whose normal force reaches 0 too
    (``free_flight`` block_liftoff); either leaves the scene without a verdict (``Guard.model_limit``) unless it
    overturned: the slip or the lift-off is not modeled, so "stands" would not be a verdict."""
    factor = restitution_factor(chain, restitution) * restitution_scale
    body = chain if width_factor == 1.0 and height_factor == 1.0 else chain.scaled(width_factor=width_factor,
                                                                                     height_factor=height_factor)
    theta = np.zeros(np.asarray(ah_ms2).size) if history else None
    out = roll_on_hull(ah_ms2, dt_s, body, av_ms2=av_ms2, restitution_factor=factor, g_ms2=g_ms2, theta_out=theta)
    tip_plus, tip_minus = body.tipping_rad()
    moved = out.theta_max > 0.0
    flight = bool(out.status & STATUS_GROUND_FLIGHT) and not out.overturned
    exceeded = out.friction_demand > mu
    response = (Response.overturn if out.overturned else Response.free_flight if flight
                else Response.slide_rock if exceeded else Response.rock if moved else Response.rest)
    left_out = (exceeded or bool(out.status & STATUS_LIFTOFF)) and not out.overturned
    guard = ((Guard.model_limit if out.verdict < 0 or left_out else 0)
             | (Guard.event_cap if out.status & STATUS_EVENT_CAP else 0))
    return Scene(physics=Physics.rolling, response=response, overturned=bool(out.overturned),
                 theta_max=max(out.theta_max_plus / tip_plus, out.theta_max_minus / tip_minus),
                 n_impacts=int(out.n_impacts), t_overturn=float(out.t_overturn),
                 friction_demand=float(out.friction_demand), sliding_max_m=math.nan,
                 free_flight=(FreeFlight.ground_flight if flight else FreeFlight.block_liftoff
                              if out.status & STATUS_LIFTOFF else FreeFlight.none),
                 chatter=bool(out.status & STATUS_EVENT_CAP), friction_exceeded=int(exceeded),
                 theta_over_alpha=None if theta is None else theta / min(tip_plus, tip_minus),
                 contact_modes=ContactMode.rock if moved else 0, guard=guard)


def worst_scanned(horizontal_ms2: np.ndarray, azimuth0_deg: float, av_ms2: np.ndarray | None, dt_s: float,
                  shape: BlockShape, planes: list[ScannedPlane], *, settings: SimulationConfig = SimulationConfig(),
                  g_ms2: float = G, then_grid_deg: np.ndarray | None = None) -> PlaneSearch:
    """The worst of ``planes`` (overturned, then without a verdict, then the largest theta_max, the first of the
    planes on ties within :data:`TIE_RTOL`); with ``then_grid_deg`` (a blank azimuth on two horizontals), then the
    worst's body plane facing every direction of that grid (:func:`record_planes`), the worst of all kept."""
    scan = shape.scan
    assert scan is not None
    best: tuple | None = None
    scenes: list[tuple[ScannedPlane, Scene]] = []
    geometry: dict[float, PlaneGeometry] = {}

    def run(batch: list[ScannedPlane]) -> None:
        nonlocal best
        for pl in batch:
            if pl.body_deg not in geometry:
                geometry[pl.body_deg] = plane_geometry(scan, pl.body_deg, settings)
            sc = plane_scene(along(horizontal_ms2, azimuth0_deg, pl), av_ms2, dt_s, geometry[pl.body_deg],
                             restitution=shape.restitution, mu=shape.mu, settings=settings, g_ms2=g_ms2)
            scenes.append((pl, sc))
            rank = (sc.overturned, sc.verdict < 0)
            if best is None or rank > best[0] or (rank == best[0]
                                                  and sc.theta_max > best[1].theta_max * (1 + TIE_RTOL)):
                best = (rank, sc, pl)

    run(planes)
    if then_grid_deg is not None:
        assert best is not None
        run(record_planes(best[2], then_grid_deg))
    assert best is not None
    return PlaneSearch(PlaneResult(scene=best[1], azimuth_deg=best[2].record_deg, planes_simulated=len(scenes),
                                   responses=tuple((pl.record_deg, sc.theta_max) for pl, sc in scenes)),
                       best[2], scenes)
