"""The stack body model: a body of a stack (inventory ``stands_on``, :mod:`pipeline.stacks`) judged with the whole
stack, each body keeping its own verdict.

It claims every block that is a body of a stack, on any record (the registry's first entry: a stack's body is never
judged as if it stood alone). A scene simulates the stack in the body's rocking plane, or, where the plane is
unknown, in the pulse axis and every plane of the orientation grid, and keeps the plane worst for that body
(overturned, then without a verdict, then the largest rotation); a plane where the stack's certificate holds is not
integrated (:mod:`pipeline.assemblies.stack_scene`). Its probability draws the amplitude and the bodies' sizes
(:mod:`pipeline.uncertainty.stacks`) in the governing plane, and for an unknown orientation also a uniform plane per
draw (the random orientation); its margin is the upward scan of factors on the record in the governing plane
(:mod:`.factor_sweep`), from the factor at which an interface would first lift off.
"""

from __future__ import annotations

import math

import numpy as np

from ..assemblies.stack import StackBody, StackPlace, interfaces, uplift_ratios
from ..assemblies.stack_scene import AT_REST, body_history, body_scene, body_verdict, stack_blocks, stack_run
from ..constants import G
from ..rocking.block import Block, BlockShape
from ..rocking.codes import Verdict
from ..rocking.orientation import Orientation, PlaneResult
from ..rocking.scene import Physics, Scene
from ..rocking.settings import SimulationConfig
from ..uncertainty.orientations import NOT_EVALUATED_ORIENTATION, OrientationProbability, one_plane
from ..uncertainty.sampling import common_normals, lognormal_factor
from ..uncertainty.stacks import drawn_stack, stack_probability
from .contract import BodyModel, BodyScene, Margin, OnRecord, Placement, PulseJudge, PulseOutcome, Setup, Stops
from .factor_sweep import factor_sweep
from .planar import scene_planes


def _place(shape: BlockShape) -> StackPlace:
    assert shape.stack is not None, "the stack model was given a block that is in no stack"
    return shape.stack


def _rank(sc: Scene) -> tuple:
    """Worse first for a body: overturned, then without a verdict, then the larger rotation."""
    return (sc.overturned, sc.verdict < 0, sc.theta_max)


def stack_scene(on: OnRecord, shape: BlockShape, block: Block, direction_deg: float) -> BodyScene:
    """The body's scene on ``on``: the worst of its planes for it (its stack's own where given) and its
    probabilities."""
    place, rec, setup = _place(shape), on.record, on.setup
    code, azimuths = scene_planes(rec, shape.azimuth_deg, direction_deg, on.grid_deg)
    if not on.scan:
        azimuths = azimuths[:1]
    tb = stack_blocks(place)
    worst: tuple[Scene, float] | None = None
    responses: list[tuple[float, float]] = []
    for az in azimuths:
        sc = body_scene(place, on.planes.along(az), on.planes.vertical, rec.dt_s, tb=tb, settings=setup.settings,
                        memo=on.memo, key=("plane", float(az)))
        if sc.physics != Physics.none:
            responses.append((az % 180.0, sc.theta_max))
        if worst is None or _rank(sc) > _rank(worst[0]):
            worst = (sc, az % 180.0)
        if sc.overturned:
            break                                       # as the planar scan: the first plane that overturns
    assert worst is not None
    res = PlaneResult(worst[0], worst[1], len(responses), tuple(responses))
    orient = NOT_EVALUATED_ORIENTATION
    if on.base is not None and on.draws is not None:
        orient = _probability(on, place, code=code, plane_deg=float(worst[1] if code != Orientation.given
                                                                    else azimuths[0]))
    sc = res.scene
    return BodyScene(res, orient, code, lambda: (f"physics {Physics(sc.physics).name}, stack "
                                                 f"{' < '.join(reversed(place.ids))}; {res.planes_simulated} "
                                                 f"plane(s) integrated, {max(orient.simulations, 0)} sampled"))


def _probability(on: OnRecord, place: StackPlace, *, code: int, plane_deg: float) -> OrientationProbability:
    """The body's probabilities: in its governing plane, and, where its plane is unknown on two horizontals, for a
    random orientation too."""
    assert on.base is not None and on.draws is not None
    z, _z_estimate, z_average = on.draws
    unc, settings = on.setup.uncertainty, on.setup.settings
    given = code == Orientation.given
    prob = stack_probability(on.base, z, place, plane_deg=plane_deg, given_azimuth=given, random_orientation=False,
                             settings=unc, simulation=settings, memo=on.memo)
    if given or on.base.single or code == Orientation.single_component:
        return one_plane(prob, plane_deg)
    rand = stack_probability(on.base, z_average, place, plane_deg=plane_deg, given_azimuth=False,
                             random_orientation=True, settings=unc, simulation=settings, memo=on.memo)
    if prob.drawn == 0:
        return NOT_EVALUATED_ORIENTATION
    return OrientationProbability(prob, plane_deg, rand.p, rand.low, rand.high, prob.simulations + rand.simulations)


def lift_factor(place: StackPlace, ah_ms2: np.ndarray, av_ms2: np.ndarray | None, *, g_ms2: float = G) -> float:
    """The smallest factor on the ground (a_h, a_v) at which an interface of the stack would start to tip at a
    sample (:func:`pipeline.assemblies.stack.uplift_ratios`; inf where none would)."""
    ah = np.asarray(ah_ms2, dtype=float)
    av = np.zeros_like(ah) if av_ms2 is None else np.asarray(av_ms2, dtype=float)
    least = math.inf
    for face in interfaces(place.bodies):
        for ratio in uplift_ratios(face):
            demand = ah - ratio * av                    # f (a_h - r a_v) = r g at the crossing
            with np.errstate(divide="ignore", invalid="ignore"):
                f = np.where(demand * ratio > 0.0, ratio * g_ms2 / demand, math.inf)
            least = min(least, float(np.min(f)))
    return least


def stack_scale(place: StackPlace, ah_ms2: np.ndarray, av_ms2, dt_s: float, *, settings: SimulationConfig,
                overturns_at_one: bool | None = None) -> tuple[float, int]:
    """The first factor of the upward scan on the record (``ah_ms2``, ``av_ms2``) [m s-2] that overturns the body
    (inf: none up to ``margin_max_factor``; NaN: a factor without a verdict first) and the runs."""
    f = lift_factor(place, ah_ms2, av_ms2)
    if not math.isfinite(f):
        return math.inf, 0
    tb = stack_blocks(place)

    def verdict_at(factor: float) -> int:
        av = None if av_ms2 is None else factor * av_ms2
        return body_verdict(place, factor * ah_ms2, av, dt_s, tb=tb, settings=settings)

    return factor_sweep(f, verdict_at, settings=settings, overturns_at_one=overturns_at_one)


def stack_margins(rec, shape: BlockShape, block: Block, direction_deg: float, *, setup: Setup, overturned: bool,
                  want_history: bool) -> Margin:
    """The body's margins in its governing plane (``direction_deg``) of its governing record, and its history there
    (:func:`~pipeline.assemblies.stack_scene.body_history`) where at risk."""
    place, ah, av = _place(shape), rec.along(direction_deg), rec.vertical_ms2
    scale, runs = stack_scale(place, ah, av, rec.dt_s, settings=setup.settings, overturns_at_one=overturned)
    history = body_history(place, ah, av, rec.dt_s) if want_history or scale <= setup.history_below_scale else None
    unc = setup.uncertainty
    n = unc.margin_samples if setup.sampling else 0
    sampled = np.full(max(n, 0), np.nan)
    z = common_normals(unc.seed, n) if n > 0 else np.zeros((0, 6))
    for k in range(len(z)):
        eps = float(lognormal_factor(z[k, 0], unc.amplitude_cov))
        s, more = stack_scale(drawn_stack(place, z[k], unc), eps * ah, None if av is None else eps * av, rec.dt_s,
                              settings=setup.settings)
        sampled[k], runs = s * eps, runs + more
    return Margin(scale, runs, history, rec.dt_s, sampled)


def scale(rec, shape: BlockShape, block: Block, plane_deg: float, *, settings: SimulationConfig,
          g_ms2: float) -> float:
    """The body's simulated margin in the record direction ``plane_deg``."""
    return stack_scale(_place(shape), rec.along(plane_deg), rec.vertical_ms2, rec.dt_s, settings=settings)[0]


def pulse(shape: BlockShape, block: Block, *, settings: SimulationConfig, g_ms2: float) -> PulseJudge:
    """A judge of one-directional pulses in the stack's plane: one run of the stack each, with the body's residual
    offset on what it stands on."""
    place = _place(shape)
    tb = stack_blocks(place)

    def judge(ah_ms2: np.ndarray, dt_s: float) -> PulseOutcome:
        judged = stack_run(place, ah_ms2, None, dt_s, tb=tb, settings=settings)
        if judged is AT_REST:
            return PulseOutcome(False, 1, 0.0)
        verdict = judged.verdicts[place.position]
        offset = judged.offset_m[place.position] if judged.offset_m else math.nan
        return PulseOutcome(verdict == Verdict.overturns, 1, float(offset))

    return judge


def _warm_stacks(*bodies: StackBody) -> None:
    """The stack of ``bodies`` judged on a tiny record that lets its top fall, with and without a vertical."""
    from ..assemblies.stack_scene import judge

    t = np.linspace(0.0, 1.0, 101)
    place = StackPlace(bodies, 0, tuple(f"b{k}" for k in range(len(bodies))))
    for av in (None, 0.1 * np.sin(2.0 * np.pi * t)):
        judge(stack_blocks(place), 6.0 * np.sin(2.0 * np.pi * t), 0.01, av_ms2=av)


def warmup() -> None:
    """The two-block run and the kernel that continues the lower block alone, on a tiny stack that lets its top
    fall."""
    _warm_stacks(StackBody(0.6, 0.6, 1.0, 0.6), StackBody(0.1, 0.8, 0.2, 0.6))


def _n_block_warmup() -> None:
    """The n-block run, on a tiny stack of three that lets its top fall."""
    _warm_stacks(StackBody(0.6, 0.6, 1.0, 0.6), StackBody(0.4, 0.3, 0.5, 0.6), StackBody(0.1, 0.8, 0.2, 0.6))


def _claims(shape: BlockShape, placement: Placement, settings: SimulationConfig) -> bool:
    return shape.stack is not None


def _may_claim(shape: BlockShape, settings: SimulationConfig) -> bool:
    return shape.stack is not None


#: The stack model: every body of a stack, on any record.
STACK = BodyModel(
    name="stack", physics=(Physics.stack,), claims=_claims, may_claim=_may_claim, scene=stack_scene,
    margins=stack_margins, scale=scale, pulse=pulse, warmups=(warmup, _n_block_warmup),
    stops=(Stops((Physics.stack,), "the stack's model met the ground falling faster than gravity, or a cap on its "
                 "steps, its impacts or its free motion after the record (it leaves out sliding and flight)"),))
