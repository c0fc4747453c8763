"""The planar body model: a block judged in its rocking plane, or in the worst of them where its plane is unknown.

It claims every block no other model of the registry claims (the registry's last entry). Its scene goes to the
planar registry's scene models (:mod:`pipeline.rocking.models`: at rest, sliding, rocking, the general contact
model), chosen per plane by their certificates; its probabilities sample the declared uncertainty per orientation
where the plane is unknown (:mod:`pipeline.uncertainty.orientations`), else in its one plane
(:mod:`pipeline.uncertainty.scenes`); its margin is the upward scan of factors on the record in its governing
plane (:func:`overturn_scale_simulated`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import numpy as np

from ..constants import G
from ..rocking import models as scene_models
from ..rocking.block import Block, BlockShape, dynamics
from ..rocking.numerics.ground import quiet_table, scaled_demand_ratio, scaled_quiet_table
from ..rocking.orientation import Orientation, PlaneResult, Planes, plane_grid, worst_plane
from ..rocking.planar.sampled import SampledBlocks, SampledMotion, kernels, sample_rules
from ..rocking.planner import ContactMode, Physics, guard_names, rocks, simulate_scene
from ..rocking.settings import SimulationConfig
from ..rocking.simulate import finite_series
from ..uncertainty.orientations import (
    NOT_EVALUATED_ORIENTATION,
    OrientationProbability,
    one_plane,
    orientation_probability,
)
from ..uncertainty.sampling import common_normals, sample_block
from ..uncertainty.scenes import SceneMotion, scene_probability
from .contract import BodyModel, BodyScene, Margin, OnRecord, Placement, PulseJudge, PulseOutcome, Setup
from .factor_sweep import factor_sweep


def scene_planes(rec, block_azimuth_deg: float, direction_deg: float, grid_deg: np.ndarray
                 ) -> tuple[int, list[float]]:
    """The orientation code (:class:`~pipeline.rocking.orientation.Orientation`) of a scene and the planes it is
    simulated in.

    A block with a given azimuth on a record of known azimuth: its own plane. A blank azimuth, or a record whose
    absolute azimuth is unknown (the pair's relative orientation is known): ``direction_deg`` (the pulse axis) and
    every plane of the grid (the worst is kept). A single horizontal: the one plane recorded.
    """
    if rec.single_component:
        return Orientation.single_component, [direction_deg]
    if rec.azimuth_known and not np.isnan(block_azimuth_deg):
        return Orientation.given, [direction_deg]
    code = Orientation.scanned if rec.azimuth_known else Orientation.scanned_relative
    return code, [direction_deg, *grid_deg.tolist()]


def planar_scene(on: OnRecord, shape: BlockShape, block: Block, direction_deg: float) -> BodyScene:
    """The block's scene on ``on``: the worst of its planes (its own where given) and its probabilities."""
    rec, settings = on.record, on.setup.settings
    step = settings.orientation_step_deg
    code, azimuths = scene_planes(rec, shape.azimuth_deg, direction_deg, on.grid_deg)
    if not on.scan:
        azimuths = azimuths[:1]
    scanned = code in (Orientation.scanned, Orientation.scanned_relative)
    res = worst_plane(on.planes, azimuths, rec.dt_s, settings=settings, refine_span_deg=step if scanned else 0.0,
                      refine_deg=settings.orientation_refine_deg, block=block)
    orient = NOT_EVALUATED_ORIENTATION
    if on.base is not None and on.draws is not None:
        orient = _probability(on, shape, scanned=scanned, azimuths=azimuths, nominal=res)
    sc = res.scene
    return BodyScene(res, orient, code, lambda: _detail(sc, res.azimuth_deg, res.planes_simulated,
                                                         orient.simulations))


def _detail(sc, azimuth_deg: float, planes: int, sampled: int) -> str:
    """What a slow scene was doing: its physics, the modes it went through, the guards it met, its planes."""
    modes = ", ".join(m.name for m in ContactMode if sc.contact_modes & m) or "none"
    guards = guard_names(sc.guard) or "none"
    return (f"physics {Physics(sc.physics).name}, contact modes {modes}, guards {guards}; {planes} plane(s) "
            f"integrated (governing plane {azimuth_deg:.0f} deg), {max(sampled, 0)} sampled plane(s)")


def _ranked(res: PlaneResult, planes: Planes, azimuths: list[float]) -> list[float]:
    """The planes of a scene by decreasing nominal peak rotation (the planes integrated), then the others by
    decreasing demand ratio."""
    moved = [az for az, _theta in sorted(res.responses, key=lambda r: -r[1])]
    rest, _ = planes.by_demand(tuple(dict.fromkeys(Planes.key(a) for a in azimuths)))
    return list(dict.fromkeys([*moved, *rest]))


def _probability(on: OnRecord, shape: BlockShape, *, scanned: bool, azimuths: list[float],
                 nominal: PlaneResult) -> OrientationProbability:
    """The block's probabilities of overturning under the declared uncertainty: per orientation when its rocking
    plane is unknown (scanned on a two-component record), else in its one plane."""
    assert on.base is not None and on.draws is not None
    base: SceneMotion = on.base
    z, z_estimate, z_average = on.draws
    unc, settings, g = on.setup.uncertainty, on.setup.settings, on.setup.g_ms2
    if not scanned or base.single:
        one = dataclasses.replace(shape, azimuth_deg=math.nan if scanned else azimuths[0])
        prob = scene_probability(base, z, one, settings=unc, simulation=settings, g_ms2=g)
        return one_plane(prob, azimuths[0])
    sample_grid, candidates = on.grid_deg, list(azimuths)
    if unc.orientation_step_deg > 0:        # a coarser grid for the samples, with the pulse axis and the nominal
        sample_grid = plane_grid(unc.orientation_step_deg)                                       # worst plane
        candidates = list(dict.fromkeys([float(azimuths[0]), float(nominal.azimuth_deg) % 180.0,
                                         *sample_grid.tolist()]))
    return orientation_probability(dataclasses.replace(base, planes_deg=np.asarray(candidates)), z, shape,
                                   grid_deg=sample_grid, prefer_deg=nominal.azimuth_deg, settings=unc,
                                   simulation=settings, g_ms2=g, z_estimate=z_estimate, z_average=z_average,
                                   nominal_overturned=bool(nominal.scene.overturned),
                                   ranked_deg=_ranked(nominal, on.planes, azimuths))


def overturn_scale_simulated(ah_ms2: np.ndarray, av_ms2, dt_s: float, *, block: Block, settings,
                             overturns_at_one: bool | None = None) -> tuple[float, int]:
    """Smallest factor on the record under which the block overturns (upward scan).

    Parameters
    ----------
    ah_ms2, av_ms2 : ndarray
        Horizontal acceleration along the block's direction and vertical (or None) [m s-2].
    dt_s : float
        Sampling interval [s].
    block : Block
        The block.
    settings : SimulationConfig
        ``margin_step`` and ``margin_max_factor``, and the integration settings.
    overturns_at_one : bool, optional
        The simulated verdict of the unscaled record, when already known.

    Returns
    -------
    scale : float
        The first factor of the scan that overturns (below 1 for a standing scene when a smaller factor overturns
        it); ``inf`` when none up to ``margin_max_factor``; NaN for blocks the rocking model does not apply to
        (sliding or squat blocks never overturn in it), and when a scaled record reaches free flight before any
        overturning.
    runs : int
        Scenes simulated (not the factors below the one that first lifts the block: they stand by the at-rest
        certificate).
    """
    if not rocks(block.alpha, block.mu):
        return math.nan, 0
    f = lift_factor(ah_ms2, av_ms2, alpha=block.alpha, g_ms2=block.g_ms2)
    if math.isinf(f):
        return math.inf, 0
    table = quiet_table(ah_ms2, av_ms2)
    # the sampled kernel checks nothing: series not finite times some factor keep the planner's scene, which refuses
    judged = _compiled_verdict if _stays_finite(max(1.0, settings.margin_max_factor), ah_ms2, av_ms2) \
        else _planner_verdict
    verdict_at = judged(ah_ms2, av_ms2, dt_s, table, block=block, settings=settings)
    # below f no sample lifts the block (the at-rest certificate of every such factor): it stands, nothing simulated
    return factor_sweep(f, verdict_at, settings=settings, overturns_at_one=overturns_at_one, stands_below=f)


def _planner_verdict(ah_ms2: np.ndarray, av_ms2, dt_s: float, table, *, block: Block,
                     settings: SimulationConfig) -> Callable[[float], int]:
    """The scan's ``verdict_at(factor)``: the planner's scene of the record scaled by ``factor`` (its quiet ``table``,
    :func:`~pipeline.rocking.numerics.ground.quiet_table`, scaled with it)."""
    across, vertical = np.zeros_like(ah_ms2), np.zeros(0) if av_ms2 is None else av_ms2

    def verdict_at(factor: float) -> int:
        ratio = scaled_demand_ratio(ah_ms2, across, 1.0, 0.0, factor, vertical, av_ms2 is not None, block.g_ms2, False)
        return simulate_scene(factor * ah_ms2, None if av_ms2 is None else factor * av_ms2, dt_s, block=block,
                              settings=settings, ratio=ratio, quiet=scaled_quiet_table(table, factor)).verdict

    return verdict_at


def _compiled_verdict(ah_ms2: np.ndarray, av_ms2, dt_s: float, table, *, block: Block,
                      settings: SimulationConfig) -> Callable[[float], int]:
    """The scan's ``verdict_at(factor)`` by the sampled kernel
    (:func:`~pipeline.rocking.planar.sampled.sample_verdicts`: one draw of the block at amplitude ``factor`` in the
    one plane of ``ah_ms2``, its quiet ``table`` scaled with it): the verdict of :func:`_planner_verdict`, whose
    equality tests/rocking/planar/test_sampled_kernels.py and tests/bodies/test_planar_margin.py check, without
    the planner's Python at each factor (``benchmarks/margin_scan_cost.py`` times both)."""
    h1 = finite_series("horizontal acceleration", ah_ms2).view(np.ndarray)          # its shape checked once
    av = np.zeros(0) if av_ms2 is None else finite_series("vertical acceleration", av_ms2).view(np.ndarray)
    motion = SampledMotion(h1, np.zeros_like(h1), av, float(dt_s), table.peak_ah_ms2, table.least_av_ms2)
    rules = sample_rules(settings, block.g_ms2)
    sample_verdicts = kernels().sample_verdicts
    one, zero = np.ones((1, 1)), np.zeros((1, 1))            # the plane of ah_ms2 itself: a = factor (1 h1 + 0 h2)
    params = [np.array([float(x)]) for x in (block.p, block.alpha, block.e, block.R_m, block.mu)]
    verdict, planes = np.empty(1, dtype=np.int64), np.zeros(1, dtype=np.int64)

    def verdict_at(factor: float) -> int:
        sample_verdicts(motion, one, zero, SampledBlocks(np.array([float(factor)]), *params), rules, verdict, planes)
        return int(verdict[0])

    return verdict_at


def lift_factor(ah_ms2: np.ndarray, av_ms2, *, alpha: float, g_ms2: float = G) -> float:
    """The smallest factor on the record at which the block at rest first lifts [-] (inf: never): the least f with
    |f a_h| > (g + f a_v) tan alpha at a sample (the uplift condition with a vertical, Yim et al. 1980); below it no
    sample lifts the block.

    References
    ----------
    Yim, C.-S., Chopra, A. K. & Penzien, J. (1980). Rocking response of rigid blocks to earthquakes. Earthquake
    Engineering & Structural Dynamics 8(6), 565-587.
    """
    tan_a = math.tan(alpha)
    lift = np.abs(ah_ms2) - (av_ms2 * tan_a if av_ms2 is not None else 0.0)
    return float(np.min(g_ms2 * tan_a / lift[lift > 0])) if np.any(lift > 0) else math.inf


def _stays_finite(top: float, *series) -> bool:
    """Whether every series given (None: none) stays finite times any factor up to ``top`` (a NaN or an infinity
    anywhere in one fails too: its peak is then not finite)."""
    return all(a is None or math.isfinite(top * float(np.max(np.abs(a)))) for a in series)


def theta_history(ah_ms2, av_ms2, dt_s: float, *, block: Block, settings) -> np.ndarray | None:
    """theta(t) / alpha at every sample of the scene, or None where nothing rocks."""
    return simulate_scene(ah_ms2, av_ms2, dt_s, block=block, settings=settings, history=True).theta_over_alpha


def sampled_margins(ah_ms2: np.ndarray, av_ms2, dt_s: float, *, shape: BlockShape, setup: Setup
                    ) -> tuple[np.ndarray, int]:
    """The simulated margin of the first ``margin_samples`` draws of the block (common random numbers), as factors
    on the *nominal* record: the sampled block's scan on the record scaled by the draw's amplitude factor, times
    that factor (none where the run does not sample). Returns the margins and the scenes simulated."""
    unc = setup.uncertainty
    n = unc.margin_samples if setup.sampling else 0       # --samples 0: nominal results only
    if n <= 0:
        return np.zeros(0), 0
    sb = sample_block(common_normals(unc.seed, n), dataclasses.replace(shape, azimuth_deg=math.nan),
                      settings=unc, g_ms2=setup.g_ms2)
    out, runs = np.full(n, np.nan), 0
    for k in range(n):
        eps = float(sb.amplitude[k])
        av = None if av_ms2 is None else eps * av_ms2
        scale, r = overturn_scale_simulated(eps * ah_ms2, av, dt_s, block=sb.block(k), settings=setup.settings)
        out[k], runs = scale * eps, runs + r
    return out, runs


def planar_margins(rec, shape: BlockShape, block: Block, direction_deg: float, *, setup: Setup, overturned: bool,
                   want_history: bool) -> Margin:
    """The block's margins in its governing plane (``direction_deg``) of its governing record."""
    settings = setup.settings
    ah = rec.along(direction_deg)
    scale, runs = overturn_scale_simulated(ah, rec.vertical_ms2, rec.dt_s, block=block, settings=settings,
                                           overturns_at_one=overturned)
    history = theta_history(ah, rec.vertical_ms2, rec.dt_s, block=block, settings=settings) \
        if want_history or scale <= setup.history_below_scale else None
    sampled, more = sampled_margins(ah, rec.vertical_ms2, rec.dt_s, shape=shape, setup=setup)
    return Margin(scale, runs + more, history, rec.dt_s, sampled)


def planar_scale(rec, shape: BlockShape, block: Block, plane_deg: float, *, settings: SimulationConfig,
                 g_ms2: float) -> float:
    """The simulated margin in the record direction ``plane_deg``."""
    return overturn_scale_simulated(rec.along(plane_deg), rec.vertical_ms2, rec.dt_s, settings=settings,
                                    block=block)[0]


def planar_pulse(shape: BlockShape, block: Block, *, settings: SimulationConfig, g_ms2: float) -> PulseJudge:
    """A judge of one-directional pulses in the block's plane: one simulation each."""
    def judge(ah_ms2: np.ndarray, dt_s: float) -> PulseOutcome:
        return PulseOutcome(bool(simulate_scene(ah_ms2, None, dt_s, block=block, settings=settings).overturned), 1)

    return judge


def scene_warmups(shapes: list[BlockShape] | None, sampling: bool) -> tuple[Callable[[], None], ...]:
    """The warm-up calls of the planar scene models (the registry as it stands), one a model so that processes
    compiling together can each take one: every model where the run samples (its draws vary each block's slenderness
    and friction) or its blocks are not known; else the models that one of the blocks' nominal (alpha, mu) may
    reach (:attr:`~pipeline.rocking.contract.SceneModel.may_claim`). A block that cannot rock (mu at or below tan
    alpha) then compiles neither pure rocking's kernel nor its continuation (26.8 of the 36.1 s of every model's in
    one measurement, from an empty cache in one process)."""
    models = scene_models.MODELS
    if not sampling and shapes is not None:
        blocks = dynamics(list(shapes))
        models = tuple(m for m in models if any(m.may_claim(b.alpha, b.mu) for b in blocks))
    return tuple(m.warmup for m in models)


def draws_warmup() -> None:
    """The sampled kernels of the probabilities (the planar draws), on a tiny scene with and without a vertical."""
    a = 3.0 * np.sin(2.0 * np.pi * np.linspace(0.0, 2.0, 201))
    one = np.ones(1)
    out = np.zeros(1, dtype=np.int64)
    blocks = SampledBlocks(one, 2.0 * one, 0.2 * one, 0.9 * one, one, 0.7 * one)
    rules = sample_rules(SimulationConfig(), G)
    sample_verdicts, sample_plane_outcomes = kernels()                   # the registry's, as it stands
    for vertical in (np.zeros(0), 0.1 * a):
        motion = SampledMotion(a, np.zeros_like(a), vertical, 0.01)
        sample_verdicts(motion, np.ones((1, 1)), np.zeros((1, 1)), blocks, rules, out, out.copy())
        sample_plane_outcomes(motion, np.ones((1, 2)), np.zeros((1, 2)), blocks, rules,
                              np.zeros((1, 2), dtype=np.int8), out.copy())


def _everywhere(shape: BlockShape, placement: Placement, settings: SimulationConfig) -> bool:
    return True


def _always(shape: BlockShape, settings: SimulationConfig) -> bool:
    return True


#: The planar body model: every block no other model claims.
PLANAR = BodyModel(name="planar", physics=(), claims=_everywhere, may_claim=_always, scene=planar_scene,
                   margins=planar_margins, scale=planar_scale, pulse=planar_pulse, warmups_for=scene_warmups,
                   draws_warmups=(draws_warmup,))
