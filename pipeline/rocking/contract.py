"""What a scene model must provide: the contract every model of the registry (:mod:`.models`) follows.

A *scene* is one record (or one plane of it) and one block. A *model* simulates the scenes it is chosen for. The
planner (:func:`.planner.plan`) and the sampled kernels (:mod:`.sampled`) never name a model: they try the
registered models in order and give the scene to the first whose certificate holds. A model provides, as the
fields of one :class:`SceneModel`:

``physics``
    Its :class:`~.scene.Physics` member: the code ``screening.nc`` stores for the scenes it simulated.
``certificate(facts) -> bool``
    When the planner may choose it, from the scene's :class:`SceneFacts`. It must be a proof, never a guess:
    a certificate that holds for a scene that moves must belong to a model that simulates that motion ("only
    the effects a scene calls for" never skips a scene that moves). A plain function of the facts; the registry
    compiles its twin for the sampled kernels.
``simulate(scene: SceneInput) -> Scene``
    Its Python entry: the nominal scene's :class:`~.scene.Scene`.
``twin(facts, plane: PlaneSample, block: RigidBlock, control: StepControl, workspace: SampleWorkspace)``
    Its compiled twin for the sampled kernels: one uncertainty sample in one plane, returning
    ``(outcome, integrated)``, a :class:`~.codes.Verdict` code and whether anything was integrated. It takes
    the decisions ``simulate`` takes, on the same kernels, so that a sample with the nominal block and unit
    factors gets the nominal verdict (tested).
``warmup()``
    Calls its compiled kernels once on a tiny scene (:mod:`.warmup`), so that numba compiles them before any
    worker needs them.
``may_claim(alpha, mu) -> bool``
    Optional (default: every block): whether a block of that nominal slenderness [rad] and friction [-] may have a
    scene the model takes, chosen or continuing another. A superset is safe (a warm-up then made for nothing); a
    block left out would compile the model's kernels in a worker, unannounced. A run without draws warms up only
    the models its blocks may reach (``pipeline.bodies.planar.scene_warmups``).

A model whose certificate is ``never`` is not chosen up front: it continues other models (the general contact
model takes over where pure rocking stops holding) or is run by name (``simulate_scene(physics=...)``).

Written the way scipy's ``integrate/_ivp/base.py`` documents what an ``OdeSolver`` provides and ``ivp.py`` lists
its methods in one ``METHODS`` mapping.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .block import Block
from .numerics.ground import QuietTable
from .scene import Scene
from .settings import SimulationConfig
from .structures import RockingOutput, RockingState


class SceneFacts(NamedTuple):
    """What the planner knows of a scene before simulating it: all a certificate reads (a numba namedtuple).

    Attributes
    ----------
    ratio : float
        The demand ratio max_t |a_h| / (g + a_v) [-] (``inf`` where g + a_v <= 0 at some sample).
    threshold : float
        min(tan alpha, mu): the ratio above which the block lifts or slips from rest [-].
    rocks : bool
        The block tips before it slides and can rock (:func:`.rules.rocks`).
    vertical : bool
        The simulation keeps the record's vertical (:func:`.rules.vertical_kept`).
    alpha : float
        The block's slenderness [rad].
    mu : float
        Its friction coefficient [-].
    """

    ratio: float
    threshold: float
    rocks: bool
    vertical: bool
    alpha: float
    mu: float


@dataclass(frozen=True)
class SceneInput:
    """One nominal scene as a model's Python entry takes it.

    Attributes
    ----------
    ah_ms2 : ndarray
        Ground acceleration along the rocking plane [m s-2].
    av_ms2 : ndarray or None
        The record's vertical, up positive [m s-2] (None: none recorded).
    vertical_ms2 : ndarray or None
        The vertical the simulation keeps (None where ``vertical_fraction`` drops it) [m s-2].
    dt_s : float
        Sampling interval [s].
    block : Block
        The block.
    settings : SimulationConfig
        The simulator's settings.
    history : bool
        Keep theta(t) / alpha at every sample.
    quiet : QuietTable or None
        The plane's :class:`~.numerics.ground.QuietTable` of ``ah_ms2`` and ``av_ms2``, where the caller has one
        (the rocking kernel reads it; the outcome is the same without it).
    """

    ah_ms2: np.ndarray
    av_ms2: np.ndarray | None
    vertical_ms2: np.ndarray | None
    dt_s: float
    block: Block
    settings: SimulationConfig
    history: bool
    quiet: QuietTable | None = None


class PlaneSample(NamedTuple):
    """One uncertainty sample in one plane, as a compiled twin takes it (a numba namedtuple).

    Attributes
    ----------
    a : ndarray
        Buffer for the sample's projection on the plane [m s-2].
    h1, h2 : ndarray
        The record's two horizontals [m s-2].
    c, s : float
        The plane's projection weights: a = eps (c h1 + s h2).
    eps : float
        The sample's amplitude factor [-].
    av_s : ndarray
        The sample's scaled vertical as the simulation keeps it (empty: none) [m s-2].
    dt, t_end : float
        Sampling interval and the record's end [s].
    flight : bool
        The kept vertical reaches g + a_v <= 0 at some sample.
    contact_model : bool
        The general contact model continues where pure rocking stops holding.
    """

    a: np.ndarray
    h1: np.ndarray
    h2: np.ndarray
    c: float
    s: float
    eps: float
    av_s: np.ndarray
    dt: float
    t_end: float
    flight: bool
    contact_model: bool


class SampleWorkspace(NamedTuple):
    """What the sampled kernels set up once per call (a numba namedtuple)."""

    n: int                      # samples of the record
    has_v: bool                 # the record has a vertical
    t_end: float                # its end [s]
    a: np.ndarray               # buffer for a plane's projection [m s-2]
    av_s: np.ndarray            # buffer for a sample's scaled vertical [m s-2] (empty without one)
    quiet: QuietTable           # buffers for the sample's quiet table: the record's vector table scaled (empty: none)
    none: np.ndarray            # an empty vertical
    no_output: RockingOutput    # no theta history, no impact log
    at_rest: RockingState       # the state at rest


@dataclass(frozen=True)
class SceneModel:
    """A model of a scene: the fields the contract above asks for."""

    physics: int
    certificate: Callable[[SceneFacts], bool]
    simulate: Callable[[SceneInput], Scene]
    twin: Callable
    warmup: Callable[[], None]
    may_claim: Callable[[float, float], bool] = lambda alpha, mu: True   # every block


def never(facts: SceneFacts) -> bool:
    """The certificate of a model that is never chosen up front (it continues others, or is run by name)."""
    return False


def always(facts: SceneFacts) -> bool:
    """The certificate of the last model of the registry: it takes every scene the others left."""
    return True
