"""The registry of scene models: every model the planner and the sampled kernels may give a scene to.

:data:`MODELS` lists them in the order they are tried; a scene goes to the first whose certificate holds
(:mod:`.contract` says what each must provide). Adding a model is a module of its own (its kernel, its Python
entry, its compiled twin, its warm-up), its :class:`~.scene.Physics` member, and one line here; see "Adding a
model" in docs/design.md.

The registered models:

* **rest** (``Physics.none``): the exact at-rest certificate. The demand ratio max |a_h| / (g + a_v) never
  exceeds min(tan alpha, mu), with the vertical included whenever the record has one: the block neither lifts
  nor slips at any sample (the ground is linear between samples, so the ratio peaks at one); nothing is
  integrated.
* **sliding**: a block that cannot rock (mu <= tan alpha within the tie rule, or too squat, alpha >= 54.7 deg)
  and is moved: Coulomb stick-slip. Where the ground falls faster than gravity the general contact model takes
  the whole record from rest.
* **rocking_vertical** / **rocking**: pure rocking (Housner 1963), with the vertical where the simulation keeps
  it; the general contact model continues from where pure rocking stops holding (:mod:`.handoff`).
* **general** (never chosen up front): the general contact model (slide, slide-rock, free flight, impacts) over
  the whole record from rest; it is how the others continue.

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. BSSA 53(2), 403-417.
Yim, C.-S., Chopra, A. K. & Penzien, J. (1980). Rocking response of rigid blocks to earthquakes. EESD 8(6),
565-587 (uplift with vertical input, |a_h| > (g + a_v) tan alpha).
Shenton, H. W. (1996). Criteria for initiation of slide, rock, and slide-rock rigid-body modes. J. Eng. Mech.
122(7), 690-693 (a block tips before it slides when mu > tan alpha).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..compiled import jit, rebound, unroll
from ..constants import G
from .block import Block, rigid_block
from .codes import NO_VERDICT, OVERTURNS, STANDS, STATUS_GROUND_FLIGHT, ContactMode
from .contract import SceneFacts, SceneInput, SceneModel, always, never
from .numerics.ground import scaled_demand_ratio
from .planar.handoff import continue_rocking, from_rest, stopped_short
from .planar.kernel import rock as rock_compiled
from .rules import rocks
from .scene import REST_SCENE, FreeFlight, Guard, Physics, Response, Scene, general_scene, rocking_scene
from .settings import SimulationConfig
from .simulate import continued, rock, slide
from .simulate import from_rest as general_from_rest

# --- rest: the exact at-rest certificate ------------------------------------------------------------------------


def at_rest(facts: SceneFacts) -> bool:
    """The block neither lifts nor slips at any sample: its demand ratio is not above min(tan alpha, mu)."""
    return not facts.ratio > facts.threshold


def _rest(scene: SceneInput) -> Scene:
    return REST_SCENE


@jit
def _rest_twin(facts, x, block, control, w):
    return STANDS, False


def _no_warmup() -> None:
    """Nothing compiled to warm up."""


# --- general: the general contact model from rest ---------------------------------------------------------------


def _general(scene: SceneInput) -> Scene:
    """The whole record by the general contact model, from rest (no pure-rocking friction demand: NaN)."""
    theta = np.full(np.asarray(scene.ah_ms2).size, np.nan) if scene.history else None
    co = general_from_rest(scene.ah_ms2, scene.vertical_ms2, scene.dt_s, block=scene.block,
                           settings=scene.settings, theta_out=theta)
    return general_scene(co, alpha=scene.block.alpha, friction_demand=math.nan, friction_exceeded=-1, theta=theta)


@jit
def _project(x):
    """The sample's ground acceleration in its plane, into ``x.a``."""
    for i in range(x.a.size):
        x.a[i] = x.eps * (x.c * x.h1[i] + x.s * x.h2[i])


@jit
def _general_twin(facts, x, block, control, w):
    """The general contact model from rest on the sample's projection (overturns or stands)."""
    _project(x)
    from_zero = rigid_block(block.p, block.alpha, block.e, block.R, block.mu, block.g, block.rest_ratio, bool(False),
                            math.inf)
    # every argument given, typed as the simulator's other calls type them (pipeline.compiled)
    return (OVERTURNS if from_rest(x.a, x.av_s, x.dt, from_zero, bool(True), w.no_output.theta).overturned
            else STANDS), True


def _general_warmup() -> None:
    t = np.linspace(0.0, 2.0, 201)
    a = 3.0 * np.sin(2.0 * np.pi * t)
    falling = np.where(t < 1.0, 0.0, -1.5 * G)
    blk = Block(p=2.0, alpha=0.2, e=0.9, R_m=1.0, mu=0.15)
    for history in (False, True):
        _sliding(SceneInput(ah_ms2=a, av_ms2=falling, vertical_ms2=falling, dt_s=0.01, block=blk,
                            settings=SimulationConfig(), history=history))


# --- sliding: Coulomb stick-slip of a block that cannot rock ----------------------------------------------------


def cannot_rock(facts: SceneFacts) -> bool:
    """mu <= tan alpha (within the tie rule) or a block too squat to rock: it slides where it moves."""
    return not facts.rocks


def _may_slide(alpha: float, mu: float) -> bool:
    """A block that cannot rock (:func:`cannot_rock`'s facts: ``rocks`` is :func:`.rules.rocks` of its block)."""
    return not rocks(alpha, mu)


def _may_rock(alpha: float, mu: float) -> bool:
    """A block that rocks: any other is taken at rest or by sliding before the rocking models are tried."""
    return rocks(alpha, mu)


def _sliding(scene: SceneInput) -> Scene:
    """Coulomb stick-slip; where the ground reaches free flight, the general contact model from rest."""
    b = scene.block
    res = slide(scene.ah_ms2, scene.dt_s, mu=b.mu, av_ms2=scene.vertical_ms2, g_ms2=b.g_ms2)
    if res.free_flight and scene.settings.contact_model:
        return _general(scene)
    if res.free_flight:
        return Scene(physics=Physics.sliding, response=Response.free_flight, overturned=False, theta_max=0.0,
                     n_impacts=0, t_overturn=math.nan, friction_demand=math.nan, sliding_max_m=res.sliding_max_m,
                     free_flight=FreeFlight.ground_flight, chatter=False, friction_exceeded=-1,
                     t_flight=res.t_flight_s, contact_modes=ContactMode.slide)
    return Scene(physics=Physics.sliding, response=Response.slide, overturned=False, theta_max=0.0, n_impacts=0,
                 t_overturn=math.nan, friction_demand=math.nan, sliding_max_m=res.sliding_max_m,
                 free_flight=FreeFlight.none, chatter=False, friction_exceeded=-1,
                 contact_modes=ContactMode.slide, guard=Guard.step_cap if res.capped_samples else 0)


@jit
def _sliding_twin(facts, x, block, control, w):
    """Not integrated, except where the contact model takes a free flight of the ground: a block that cannot rock
    cannot overturn by sliding; its verdict is free flight (no verdict) where the ground reaches it."""
    if x.flight and x.contact_model:
        return _general_twin(facts, x, block, control, w)
    return (NO_VERDICT if x.flight else STANDS), False


def _sliding_warmup() -> None:
    t = np.linspace(0.0, 2.0, 201)
    a = 3.0 * np.sin(2.0 * np.pi * t)
    slide(a, 0.01, mu=0.3, av_ms2=0.1 * a)


# --- rocking: pure rocking, continued by the general contact model where it stops holding -----------------------


def keeps_vertical(facts: SceneFacts) -> bool:
    """The block rocks, and the simulation keeps the record's vertical."""
    return facts.vertical


def _rocking_in(scene: SceneInput, physics: int, av_ms2) -> Scene:
    b, settings = scene.block, scene.settings
    rr = rock(scene.ah_ms2, scene.dt_s, p=b.p, alpha=b.alpha, e=b.e, R_m=b.R_m, av_ms2=av_ms2, g_ms2=b.g_ms2,
              settings=settings, history=scene.history, stop_mu=b.mu if settings.contact_model else math.inf,
              quiet=scene.quiet)
    if settings.contact_model:
        cont = continued(scene.ah_ms2, av_ms2, scene.dt_s, rr, block=b, settings=settings)
        if cont is not None:
            return general_scene(cont, alpha=b.alpha, friction_demand=rr.friction_demand,
                                 friction_exceeded=int(rr.friction_demand > b.mu), rocking=rr, theta=rr.theta)
    return rocking_scene(physics, rr, alpha=b.alpha, mu=b.mu, history=scene.history)


def _rocking_vertical(scene: SceneInput) -> Scene:
    return _rocking_in(scene, Physics.rocking_vertical, scene.av_ms2)


def _rocking(scene: SceneInput) -> Scene:
    return _rocking_in(scene, Physics.rocking, None)


@jit
def _rocking_twin(facts, x, block, control, w):
    """Rock the sample in its plane (the vertical in ``x.av_s``; at rest, passing over the chunks its quiet table
    ``w.quiet`` shows cannot lift it); with the contact model, the general model continues where pure rocking stops
    (no_verdict without it, where the ground reached free flight)."""
    _project(x)
    # bool(True): one compiled version for every caller (pipeline.compiled)
    res = rock_compiled(x.a, x.av_s, x.dt, x.t_end, block, control, w.at_rest, bool(True), w.no_output, w.quiet)
    if res.overturned:
        return OVERTURNS, True
    if x.contact_model:
        if stopped_short(res):
            return (OVERTURNS if continue_rocking(res, x.a, x.av_s, x.dt, block, control, bool(True),
                                                 w.no_output.theta).overturned
                    else STANDS), True
        return STANDS, True
    return (NO_VERDICT if res.status & STATUS_GROUND_FLIGHT else STANDS), True


def _rocking_warmup() -> None:
    t = np.linspace(0.0, 2.0, 201)
    a = 3.0 * np.sin(2.0 * np.pi * t)
    rock(a, 0.01, p=2.0, alpha=0.2, e=0.9, R_m=1.0)
    rock(a, 0.01, p=2.0, alpha=0.2, e=0.9, R_m=1.0, av_ms2=0.1 * a, history=True, log_impacts=2)
    scaled_demand_ratio(a, np.zeros_like(a), 1.0, 0.0, 1.5, 0.1 * a, True, G, False)     # the margin's scan of a block
    blk = Block(p=2.0, alpha=0.2, e=0.9, R_m=1.0, mu=0.21)
    for history in (False, True):
        _rocking(SceneInput(ah_ms2=a, av_ms2=None, vertical_ms2=None, dt_s=0.01, block=blk,
                            settings=SimulationConfig(), history=history))


# --- the registry -----------------------------------------------------------------------------------------------

#: Every scene model, in the order the planner tries them: a scene goes to the first whose certificate holds.
MODELS: tuple[SceneModel, ...] = (
    SceneModel(physics=Physics.none, certificate=at_rest, simulate=_rest, twin=_rest_twin, warmup=_no_warmup),
    SceneModel(physics=Physics.sliding, certificate=cannot_rock, simulate=_sliding, twin=_sliding_twin,
               warmup=_sliding_warmup, may_claim=_may_slide),
    SceneModel(physics=Physics.rocking_vertical, certificate=keeps_vertical, simulate=_rocking_vertical,
               twin=_rocking_twin, warmup=_rocking_warmup, may_claim=_may_rock),
    SceneModel(physics=Physics.rocking, certificate=always, simulate=_rocking, twin=_rocking_twin,
               warmup=_no_warmup, may_claim=_may_rock),
    SceneModel(physics=Physics.general, certificate=never, simulate=_general, twin=_general_twin,
               warmup=_general_warmup),
)


def choose(facts: SceneFacts, models: tuple[SceneModel, ...] | None = None) -> SceneModel:
    """The first model of ``models`` (default: the registry, :data:`MODELS`) whose certificate holds for ``facts``."""
    for model in MODELS if models is None else models:
        if model.certificate(facts):
            return model
    raise LookupError(f"no scene model's certificate holds for {facts}: the registry must end with one that "
                      "always does")


def by_physics(physics: int, models: tuple[SceneModel, ...] | None = None) -> SceneModel:
    """The registered model of a :class:`~.scene.Physics` code (the first, where several declare it)."""
    for model in MODELS if models is None else models:
        if model.physics == physics:
            return model
    raise LookupError(f"no scene model is registered for physics code {physics}")


#: The registry's certificates and twins for the compiled dispatch (:func:`judge`), in the order of the registry
#: as imported; :func:`compiled_judge` builds the dispatch again where the registry has changed since.
_IMPORTED = MODELS
_CERTIFICATES = tuple(jit(m.certificate) for m in MODELS)
_TWINS = tuple(m.twin for m in MODELS)


@jit
def judge(facts, x, block, control, w):
    """One uncertainty sample in one plane by the registered model whose certificate holds first (compiled):
    ``(outcome, integrated)`` from its twin (:mod:`.contract`)."""
    chosen = -1
    k = 0
    for certificate in unroll(_CERTIFICATES):
        if chosen < 0 and certificate(facts):
            chosen = k
        k += 1
    outcome, integrated = STANDS, False
    k = 0
    for twin in unroll(_TWINS):
        if k == chosen:
            outcome, integrated = twin(facts, x, block, control, w)
        k += 1
    return outcome, integrated


def compiled_judge():
    """:func:`judge` for the registry as it stands now (:data:`MODELS`): the compiled function cached on disk where
    the registry is the one imported, else a copy built for the registry as it is (:func:`_judge_for`)."""
    return judge if MODELS == _IMPORTED else _judge_for(MODELS)


@functools.lru_cache(maxsize=4)
def _judge_for(models: tuple[SceneModel, ...]):
    """The compiled dispatch of ``models`` (compiled on its first call, not cached on disk)."""
    return rebound(judge, _CERTIFICATES=tuple(jit(m.certificate) for m in models),
                   _TWINS=tuple(m.twin for m in models))
