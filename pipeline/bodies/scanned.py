"""The body model of a body given by its scan (inventory column ``mesh``): its nominal scene in the worst of its
planes (:mod:`pipeline.rocking.scanned.planes`, two-sided rocking or rolling on its hull), its probabilities
(:func:`pipeline.uncertainty.two_sided.scanned_probability`) and how its plane was chosen; its margins on its
governing record (:func:`scanned_margins`); a pulse facing its weakest plane, either way (``screen infer``).
It claims every block with a scan, on any record, unless ``[simulation] scanned_model = "contact3d"`` chooses the 3D
model's entry (:data:`.scanned3d.SCANNED_3D`)."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..records.record import Record
from ..rocking.block import Block, BlockShape
from ..rocking.orientation import Orientation, PlaneResult, plane_grid
from ..rocking.scanned.planes import (
    PlaneSearch,
    ScannedPlane,
    along,
    body_planes,
    plane_geometry,
    plane_scene,
    scene_planes,
    uplift_tan_alpha,
    worst_scanned,
)
from ..rocking.scanned.rolling import roll_on_hull
from ..rocking.scanned.two_sided import rock_two_sided_fast
from ..rocking.scanned.two_sided_body import TwoSided
from ..rocking.scene import Physics
from ..rocking.settings import ScannedModel, SimulationConfig
from ..shapes.hull import rectangle_chain
from ..shapes.plane import weakest_plane
from ..uncertainty.orientations import NOT_EVALUATED_ORIENTATION, OrientationProbability
from ..uncertainty.sampling import common_normals
from ..uncertainty.scenes import SceneMotion
from ..uncertainty.two_sided import CANDIDATES, draw_factors, scanned_probability
from .contract import (
    BodyModel,
    BodyScene,
    Margin,
    OnRecord,
    Placement,
    PulseJudge,
    PulseOutcome,
    Setup,
    Stops,
    claims_on_two_horizontals,
)
from .factor_sweep import factor_sweep


class ScannedScene(NamedTuple):
    """A scanned body's scene on one record (:func:`scanned_scene`): ``result``, ``probability`` and ``orientation``
    as a :class:`~.contract.BodyScene` holds them (the orientation given, scanned, scanned_relative or
    single_component), and ``search``, every plane simulated with its scene."""

    result: PlaneResult
    probability: OrientationProbability
    orientation: Orientation
    search: PlaneSearch


def scanned_scene(rec: Record, base: SceneMotion | None, z: np.ndarray | None, shape: BlockShape, *,
                  direction_deg: float, grid_deg: np.ndarray, setup: Setup) -> ScannedScene:
    """The scene of a scanned body on ``rec``: the worst of its planes (:mod:`pipeline.rocking.scanned.planes`) and its
    probabilities (None ``z``: nominal only; :func:`pipeline.uncertainty.two_sided.scanned_probability`, in the
    :data:`~pipeline.uncertainty.two_sided.CANDIDATES` planes nearest to overturning where the orientation is
    unknown)."""
    settings, g = setup.settings, setup.g_ms2
    given = rec.azimuth_known and not rec.single_component and math.isfinite(shape.azimuth_deg)
    planes = scene_planes(shape, direction_deg=direction_deg, grid_deg=grid_deg, single_component=rec.single_component,
                          azimuth_known=bool(rec.azimuth_known))
    search = worst_scanned(rec.horizontal_ms2, float(rec.azimuths_deg[0]), rec.vertical_ms2, rec.dt_s, shape, planes,
                           settings=settings, g_ms2=g,
                           then_grid_deg=None if given or rec.single_component else grid_deg)
    res = search.result
    code = (Orientation.single_component if rec.single_component else Orientation.given if given
            else Orientation.scanned if rec.azimuth_known else Orientation.scanned_relative)
    if base is None or z is None:
        return ScannedScene(res, NOT_EVALUATED_ORIENTATION, code, search)
    unknown = not given
    ranked = search.ranked if unknown else []
    worst, random = scanned_probability(base, z, shape,
                                        candidates=ranked[:CANDIDATES] if unknown else [search.governing],
                                        planes=ranked if unknown else None, settings=setup.uncertainty,
                                        simulation=settings, g_ms2=g)
    if not unknown:
        random = worst
    return ScannedScene(res, OrientationProbability(worst, res.azimuth_deg, random.p, random.low, random.high,
                                                    worst.simulations + (random.simulations if unknown else 0)),
                        code, search)


def _governing_plane(rec, shape: BlockShape, record_deg: float, *, settings: SimulationConfig, g_ms2: float
                     ) -> ScannedPlane:
    """The plane of a scanned scene whose record direction is ``record_deg``: with a given azimuth, the body's plane
    facing it; else the worst of the body's planes facing it (:func:`~pipeline.rocking.scanned.planes.body_planes`)."""
    assert shape.scan is not None
    if rec.azimuth_known and not rec.single_component and math.isfinite(shape.azimuth_deg):
        return ScannedPlane(record_deg, (shape.azimuth_deg - record_deg) % 360.0)
    grid = plane_grid(settings.orientation_step_deg)
    planes = [ScannedPlane(record_deg, phi) for phi in body_planes(grid, shape.scan)]
    return worst_scanned(rec.horizontal_ms2, float(rec.azimuths_deg[0]), rec.vertical_ms2, rec.dt_s, shape, planes,
                         settings=settings, g_ms2=g_ms2).governing


def scanned_scale(rec, shape: BlockShape, plane: ScannedPlane, *, settings: SimulationConfig, g_ms2: float,
                  overturns_at_one: bool | None = None, amplitude: float = 1.0, width_factor: float = 1.0,
                  height_factor: float = 1.0, restitution_scale: float = 1.0, friction_scale: float = 1.0
                  ) -> tuple[float, int]:
    """The simulated margin of a scanned scene in one plane (:func:`~.factor_sweep.factor_sweep`, from the factor at
    which the record could first lift the body toward its weaker side), for the record scaled by ``amplitude`` and the
    body by a draw's factors."""

    assert shape.scan is not None
    geometry = plane_geometry(shape.scan, plane.body_deg, settings)
    ah = amplitude * along(rec.horizontal_ms2, float(rec.azimuths_deg[0]), plane)
    av = None if rec.vertical_ms2 is None else amplitude * rec.vertical_ms2
    tan_a = uplift_tan_alpha(geometry, width_factor=width_factor, height_factor=height_factor)
    lift = np.abs(ah) - (av * tan_a if av is not None else 0.0)
    if not np.any(lift > 0):
        return math.inf, 0
    first = float(np.min(g_ms2 * tan_a / lift[lift > 0]))

    def verdict_at(factor: float) -> int:
        return plane_scene(factor * ah, None if av is None else factor * av, rec.dt_s, geometry,
                           restitution=shape.restitution, mu=shape.mu, settings=settings, g_ms2=g_ms2,
                           width_factor=width_factor, height_factor=height_factor,
                           restitution_scale=restitution_scale, friction_scale=friction_scale).verdict

    return factor_sweep(first, verdict_at, settings=settings, overturns_at_one=overturns_at_one)


def governing_scale(rec, shape: BlockShape, record_deg: float, *, settings: SimulationConfig, g_ms2: float,
                    overturned: bool | None = None) -> tuple[float, int, ScannedPlane]:
    """The simulated margin of a scanned scene whose record direction is ``record_deg`` (:func:`scanned_scale`, in
    :func:`_governing_plane`): (margin, runs, the plane it is for)."""
    governing = _governing_plane(rec, shape, record_deg, settings=settings, g_ms2=g_ms2)
    scale, runs = scanned_scale(rec, shape, governing, settings=settings, g_ms2=g_ms2, overturns_at_one=overturned)
    return scale, runs, governing


def scanned_margins(rec, shape: BlockShape, block: Block, record_deg: float, *, setup: Setup, overturned: bool,
                    want_history: bool) -> Margin:
    """A scanned body's margins on its governing record: the margin in the plane that governs the record's
    direction (:func:`governing_scale`), its history when at risk, and the sampled margins (each draw's own scan,
    as factors on the nominal record)."""
    assert shape.scan is not None
    g, settings = setup.g_ms2, setup.settings
    scale, runs, governing = governing_scale(rec, shape, record_deg, settings=settings, g_ms2=g,
                                             overturned=overturned)
    history = None
    if want_history or scale <= setup.history_below_scale:
        sc = plane_scene(along(rec.horizontal_ms2, float(rec.azimuths_deg[0]), governing), rec.vertical_ms2, rec.dt_s,
                         plane_geometry(shape.scan, governing.body_deg, settings), restitution=shape.restitution,
                         mu=shape.mu, settings=settings, g_ms2=g, history=True)
        history = sc.theta_over_alpha if sc.theta_max > 0 else None
    n = setup.uncertainty.margin_samples if setup.sampling else 0
    sampled = np.full(max(n, 0), np.nan)
    if n > 0:
        unc = setup.uncertainty
        z = common_normals(unc.seed, n)
        for k in range(n):
            f = draw_factors(z[k], unc)
            s_k, r = scanned_scale(rec, shape, governing, settings=settings, g_ms2=g, amplitude=f.amplitude,
                                   width_factor=f.width, height_factor=f.height, restitution_scale=f.restitution,
                                   friction_scale=f.friction)
            sampled[k], runs = s_k * f.amplitude, runs + r
    return Margin(scale, runs, history, rec.dt_s, sampled)


def scene(on: OnRecord, shape: BlockShape, block: Block, direction_deg: float) -> BodyScene:
    """The scanned body's scene on ``on`` (:func:`scanned_scene`)."""
    got = scanned_scene(on.record, on.base, None if on.draws is None else on.draws[0], shape,
                        direction_deg=direction_deg, grid_deg=on.grid_deg, setup=on.setup)
    res = got.result
    return BodyScene(res, got.probability, got.orientation,
                     lambda: f"scanned body, {res.planes_simulated} planes, governing {res.azimuth_deg:.0f} deg")


def scale(rec, shape: BlockShape, block: Block, plane_deg: float, *, settings: SimulationConfig,
          g_ms2: float) -> float:
    """The simulated margin in the plane that governs the record direction ``plane_deg`` (:func:`governing_scale`)."""
    return governing_scale(rec, shape, plane_deg, settings=settings, g_ms2=g_ms2)[0]


def pulse(shape: BlockShape, block: Block, *, settings: SimulationConfig, g_ms2: float) -> PulseJudge:
    """A judge of one-directional pulses: the body's weakest plane (the smallest footprint extent,
    :func:`pipeline.shapes.plane.weakest_plane`) facing the pulse, either way; two runs each."""
    assert shape.scan is not None
    body = plane_geometry(shape.scan, weakest_plane(shape.scan), settings)

    def judge(ah_ms2: np.ndarray, dt_s: float) -> PulseOutcome:
        return PulseOutcome(any(plane_scene(sense * ah_ms2, None, dt_s, body, restitution=shape.restitution,
                                            mu=shape.mu, settings=settings, g_ms2=g_ms2).overturned
                                for sense in (1.0, -1.0)), 2)

    return judge


def warmup() -> None:
    """The two-sided and rolling kernels, with and without a vertical, on a tiny scene that lifts the body."""
    a = 3.0 * np.sin(2.0 * np.pi * np.linspace(0.0, 2.0, 201))
    for vertical in (None, 0.1 * a):
        rock_two_sided_fast(a, 0.01, TwoSided(0.05, 0.08, 0.5, 0.02), av=vertical)
        for history in (None, np.zeros_like(a)):
            roll_on_hull(a, 0.01, rectangle_chain(0.2, 1.0), av_ms2=vertical, theta_out=history)


def _claims(shape: BlockShape, placement: Placement, settings: SimulationConfig) -> bool:
    return shape.scan is not None and settings.scanned_model != ScannedModel.contact3d


#: A body given by its scan, on any record, in its vertical planes (``scanned_model`` rolling or two_sided).
SCANNED = BodyModel(name="scanned body", physics=(Physics.two_sided, Physics.rolling), claims=_claims,
                    may_claim=claims_on_two_horizontals(_claims), scene=scene, margins=scanned_margins, scale=scale,
                    pulse=pulse, warmups=(warmup,),
                    stops=(Stops((Physics.two_sided, Physics.rolling),
                                 "a scanned body's pivot would slip or lift off, which its model does not follow",
                                 flagged_only=True),))
