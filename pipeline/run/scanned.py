"""A scanned body's scene on one record, as the screening stores it: its nominal scene in the worst of its planes
(:mod:`pipeline.rocking.scanned.planes`), its probabilities (:func:`pipeline.uncertainty.two_sided.scanned_probability`)
and how its plane was chosen; and its margins on its governing record (:func:`scanned_margins`)."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..config import Config
from ..records.record import Record
from ..risk import RELOCATE_BELOW_SCALE
from ..rocking.block import BlockShape
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
from ..rocking.settings import SimulationConfig
from ..uncertainty.orientations import NOT_EVALUATED_ORIENTATION, OrientationProbability
from ..uncertainty.sampling import common_normals
from ..uncertainty.scenes import SceneMotion
from ..uncertainty.two_sided import CANDIDATES, draw_factors, scanned_probability
from .scale_scan import scale_scan


class ScannedScene(NamedTuple):
    """A scanned body's scene on one record (:func:`scanned_scene`).

    Attributes
    ----------
    result : PlaneResult
        Its worst plane's scene.
    probability : OrientationProbability
        Its probabilities (not evaluated without draws).
    orientation : Orientation
        How its planes were chosen: given, scanned, scanned_relative or single_component.
    search : PlaneSearch
        Every plane simulated, with its scene.
    """

    result: PlaneResult
    probability: OrientationProbability
    orientation: Orientation
    search: PlaneSearch


def scanned_scene(rec: Record, base: SceneMotion | None, z: np.ndarray | None, shape: BlockShape, *,
                  direction_deg: float, grid_deg: np.ndarray, cfg: Config, settings: SimulationConfig
                  ) -> ScannedScene:
    """The scene of a scanned body on ``rec``: the worst of its planes (:mod:`pipeline.rocking.scanned.planes`) and its
    probabilities (None ``z``: nominal only; :func:`pipeline.uncertainty.two_sided.scanned_probability`, in the
    :data:`~pipeline.uncertainty.two_sided.CANDIDATES` planes nearest to overturning where the orientation is
    unknown)."""
    given = rec.azimuth_known and not rec.single_component and math.isfinite(shape.azimuth_deg)
    planes = scene_planes(shape, direction_deg=direction_deg, grid_deg=grid_deg, single_component=rec.single_component,
                          azimuth_known=bool(rec.azimuth_known))
    search = worst_scanned(rec.horizontal_ms2, float(rec.azimuths_deg[0]), rec.vertical_ms2, rec.dt_s, shape, planes,
                           settings=settings, g_ms2=cfg.records.g_ms2,
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
                                        planes=ranked if unknown else None, settings=cfg.uncertainty,
                                        simulation=settings, g_ms2=cfg.records.g_ms2)
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
    """The simulated margin of a scanned scene in one plane (:func:`~.scale_scan.scale_scan`, from the factor at which
    the record could first lift the body toward its weaker side), for the record scaled by ``amplitude`` and the
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

    return scale_scan(first, verdict_at, settings=settings, overturns_at_one=overturns_at_one)


def governing_scale(rec, shape: BlockShape, record_deg: float, *, settings: SimulationConfig, g_ms2: float,
                    overturned: bool | None = None) -> tuple[float, int, ScannedPlane]:
    """The simulated margin of a scanned scene whose record direction is ``record_deg`` (:func:`scanned_scale`, in
    :func:`_governing_plane`): (margin, runs, the plane it is for)."""
    governing = _governing_plane(rec, shape, record_deg, settings=settings, g_ms2=g_ms2)
    scale, runs = scanned_scale(rec, shape, governing, settings=settings, g_ms2=g_ms2, overturns_at_one=overturned)
    return scale, runs, governing


def scanned_margins(rec, shape: BlockShape, record_deg: float, cfg: Config, settings: SimulationConfig, *,
                    overturned: bool, want_history: bool) -> tuple:
    """A scanned body's margin task on its governing record (as :func:`~.margins.margin_task` returns it): the
    margin in the plane that governs the record's direction (:func:`governing_scale`), its history when at risk,
    and the sampled margins (each draw's own scan, as factors on the nominal record)."""
    assert shape.scan is not None
    g = cfg.records.g_ms2
    scale, runs, governing = governing_scale(rec, shape, record_deg, settings=settings, g_ms2=g,
                                             overturned=overturned)
    history = None
    if want_history or scale <= RELOCATE_BELOW_SCALE:
        sc = plane_scene(along(rec.horizontal_ms2, float(rec.azimuths_deg[0]), governing), rec.vertical_ms2, rec.dt_s,
                         plane_geometry(shape.scan, governing.body_deg, settings), restitution=shape.restitution,
                         mu=shape.mu, settings=settings, g_ms2=g, history=True)
        history = sc.theta_over_alpha if sc.theta_max > 0 else None
    n = cfg.uncertainty.margin_samples if cfg.sampling else 0
    sampled = np.full(max(n, 0), np.nan)
    if n > 0:
        unc = cfg.uncertainty
        z = common_normals(unc.seed, n)
        for k in range(n):
            f = draw_factors(z[k], unc)
            s_k, r = scanned_scale(rec, shape, governing, settings=settings, g_ms2=g, amplitude=f.amplitude,
                                   width_factor=f.width, height_factor=f.height, restitution_scale=f.restitution,
                                   friction_scale=f.friction)
            sampled[k], runs = s_k * f.amplitude, runs + r
    return scale, runs, history, rec.dt_s, sampled
