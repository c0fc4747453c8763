"""What a body model must provide: the contract every entry of the registry (:mod:`.registry`) follows.

A *body model* judges the blocks it claims, on whatever record they stand on: a planar block in the worst of its
rocking planes, a cylinder or a box in 3D, a body given by its scan in the planes of its footprint. The run layer
(the screening, its margins, ``screen bench``, ``screen infer``, fragility and the warm-up) never asks what kind
of block it has: it asks the registry for the first model that claims the block on the record
(:func:`.registry.body_model`) and calls that model's fields. A model provides, as the fields of one
:class:`BodyModel`:

``name``
    Its name, as the progress line and ``screen bench`` print it.
``physics``
    The :class:`~pipeline.rocking.scene.Physics` codes its scenes may store beyond the planar scene models' (the
    planar model's scenes are those of :data:`pipeline.rocking.models.MODELS`).
``claims(shape, placement, settings) -> bool``
    Whether it judges this block (:class:`~pipeline.rocking.block.BlockShape`) on a record placed as
    ``placement`` (:class:`Placement`) under the run's simulator settings
    (:class:`~pipeline.rocking.settings.SimulationConfig`, where the user chooses between models, as
    ``scanned_model`` does). The registry's last model claims every block.
``may_claim(shape, settings) -> bool``
    Whether it could claim the block on some record under the run's simulator settings: the warm-up compiles its
    kernels only then.
``scene(on: OnRecord, shape, block, direction_deg) -> BodyScene``
    The block's scene on one record: the governing plane's :class:`~pipeline.rocking.scene.Scene`, its
    probabilities under the declared uncertainty (where ``on.draws`` holds draws) and how its orientation was
    chosen.
``margins(rec, shape, block, direction_deg, *, setup, overturned, want_history) -> Margin``
    The simulated margin on the block's governing record, its history when at risk, and the sampled margins.
``scale(rec, shape, block, plane_deg, *, settings, g_ms2) -> float``
    The simulated margin alone, in a given record direction (``screen bench``'s margin sweep).
``pulse(shape, block, *, settings, g_ms2) -> Callable[[ah_ms2, dt_s], tuple[bool, int]]``
    A judge of one-directional pulses (``screen infer``): whether the pulse overturns the block, and the runs.
``warmups``
    Optional: calls that each call some of its compiled kernels once on a tiny scene, so that numba compiles them
    before any worker needs them; a call each for kernels that compile apart, so that processes compiling together
    can each take one (the stack's two-block run and n-block run: 17 and 19 s to compile); none where it has no
    kernels of its own, only shared ones.
``warmups_for(shapes, sampling)``
    Optional: its warm-up calls where they depend on the run's blocks (``shapes``; None: not known) and on whether
    it samples, read instead of ``warmups`` (the planar model's: its scene models that the blocks may reach).
``shared_warmups``
    Optional: warm-ups of kernels it shares with other models (the 3D contact model of the cylinder, the box and the
    scanned body in 3D), called once per warm-up whichever of those models it selects.
``draws_warmups``
    Optional: warm-ups of kernels only its draws call (the probabilities under the declared uncertainty), made only
    for a run that samples.
``versus_planar``
    Optional: how ``screen bench`` compares it with the planar model it replaces (:class:`VersusPlanar`).
``stops``
    Optional: why its scenes may end without a verdict, in words (:class:`Stops`), which the recommendations and the
    run's summary read; a scene without a verdict that no model's stops explain was stopped at a cap.

Written the way scipy's ``integrate/_ivp`` lists its solvers in one ``METHODS`` mapping, and as obspy's
readers keep generic code from branching on a format.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..assemblies.stack_scene import RunMemo
from ..records.record import Record
from ..rocking.block import Block, BlockShape
from ..rocking.orientation import PlaneResult, Planes
from ..rocking.settings import SimulationConfig
from ..uncertainty.orientations import OrientationProbability
from ..uncertainty.scenes import SceneMotion
from ..uncertainty.settings import UncertaintyConfig


class Placement(NamedTuple):
    """What a model's claim reads of the record a block stands on.

    Attributes
    ----------
    single_component : bool
        The record has one horizontal only.
    azimuth_deg : float
        Compass azimuth of its first horizontal [deg].
    azimuth_known : bool
        That azimuth is absolute (False: only the pair's relative orientation is known).
    """

    single_component: bool
    azimuth_deg: float
    azimuth_known: bool

    @classmethod
    def of(cls, rec) -> Placement:
        """The placement of a record (or of a floor's motion, which reads the same)."""
        return cls(bool(rec.single_component), float(rec.azimuths_deg[0]), bool(rec.azimuth_known))


def claims_on_two_horizontals(claims: Callable[[BlockShape, Placement, SimulationConfig], bool]
                               ) -> Callable[[BlockShape, SimulationConfig], bool]:
    """A ``may_claim`` that asks ``claims`` on a record of two horizontals whose azimuth is known: the placement
    every registered model claims on, where it claims a block on any (the 3D solids need two horizontals)."""

    def may_claim(shape: BlockShape, settings: SimulationConfig) -> bool:
        return claims(shape, Placement(False, 0.0, True), settings)

    return may_claim


class Setup(NamedTuple):
    """The run's settings a model reads (built once by the run layer from its configuration).

    Attributes
    ----------
    settings : SimulationConfig
        The simulator's settings.
    uncertainty : UncertaintyConfig
        The declared uncertainty.
    g_ms2 : float
        Gravity [m s-2].
    sampling : bool
        The run samples the uncertainty (False: nominal results only).
    history_below_scale : float
        A block whose simulated margin is at most this gets its history on its governing record, as a block at
        risk does (the report's relocation threshold) [-].
    """

    settings: SimulationConfig
    uncertainty: UncertaintyConfig
    g_ms2: float
    sampling: bool
    history_below_scale: float


class OnRecord(NamedTuple):
    """One record as every model's scene takes it (built once per record by the run layer).

    Attributes
    ----------
    record : Record
        The record (or a floor's motion).
    base : SceneMotion or None
        Its motion as the probabilities draw from it (None: nominal only).
    draws : tuple or None
        The selection draws, the independent estimation draws and the random orientation's draws (None: nominal
        only).
    planes : Planes
        Its rocking planes, each simulated once per block.
    grid_deg : ndarray
        The orientation grid of a block whose rocking plane is unknown [deg].
    setup : Setup
        The run's settings.
    scan : bool
        Scan the planes of a block whose rocking plane is unknown (False: the pulse axis only, as ``screen bench``
        compares).
    memo : RunMemo or None
        The record's stack runs, shared by the bodies of each stack (None: nothing shared).
    """

    record: Record
    base: SceneMotion | None
    draws: tuple | None
    planes: Planes
    grid_deg: np.ndarray
    setup: Setup
    scan: bool = True
    memo: RunMemo | None = None


class BodyScene(NamedTuple):
    """A block's scene on one record, as a model returns it.

    Attributes
    ----------
    result : PlaneResult
        The governing plane's scene.
    probability : OrientationProbability
        Its probabilities (not evaluated without draws).
    orientation : int
        How its orientation was chosen (:class:`~pipeline.rocking.orientation.Orientation`).
    detail : callable
        What the scene did, in words, for a slow scene's progress line (called only then).
    """

    result: PlaneResult
    probability: OrientationProbability
    orientation: int
    detail: Callable[[], str]


class Margin(NamedTuple):
    """A block's margins on its governing record.

    Attributes
    ----------
    scale : float
        The first factor of the upward scan (:mod:`.factor_sweep`) that overturns it (inf: none found up to the
        scan's end; NaN: a scaled record without a verdict first, or a block the model cannot overturn) [-].
    runs : int
        Scenes simulated.
    history : ndarray or None
        Its history on the record when at risk (theta(t) / alpha; a solid's also its lean azimuth).
    dt_s : float
        The history's sampling interval [s].
    sampled : ndarray
        The margins of the first draws of the declared uncertainty, as factors on the nominal record [-].
    """

    scale: float
    runs: int
    history: np.ndarray | None
    dt_s: float
    sampled: np.ndarray


class VersusPlanar(NamedTuple):
    """How ``screen bench`` compares a model with the planar model it replaces.

    Attributes
    ----------
    section : str
        The bench's section.
    setting : str
        The model's row.
    setting_planar : str
        The planar row.
    planar : callable
        ``planar(on: OnRecord, shape, block) -> PlaneResult``: the planar model's scene of the same block.
    """

    section: str
    setting: str
    setting_planar: str
    planar: Callable[[OnRecord, BlockShape, Block], PlaneResult]


class PulseOutcome(NamedTuple):
    """A body under one idealized pulse (``screen infer``).

    Attributes
    ----------
    overturned : bool
        The body fell.
    runs : int
        Simulations run.
    offset_m : float
        The body's residual offset on what it stands on where the run ended [m] (0: its joint never slipped), where
        its model follows a joint's slip (the bodies of a stack); NaN otherwise, and for a body that fell or has no
        verdict.
    """

    overturned: bool
    runs: int
    offset_m: float = math.nan


#: ``judge(ah_ms2, dt_s) -> PulseOutcome``: one idealized pulse along a line [m s-2], sampled ``dt_s`` [s] apart
PulseJudge = Callable[[np.ndarray, float], PulseOutcome]


class Stops(NamedTuple):
    """Where a body model stops without a verdict, as its scenes store it.

    Attributes
    ----------
    physics : tuple of int
        The :class:`~pipeline.rocking.scene.Physics` codes of the scenes these words explain.
    words : str
        Why such a scene has no verdict, as a recommendation says it.
    flagged_only : bool
        Only the scenes flagged for an effect the model leaves out (``friction_exceeded``, or the block lifting
        itself off); its other scenes without a verdict were stopped at a cap.
    contact3d_decides : bool
        The 3D contact model takes such a scene over from the state where the model stopped, where
        ``[simulation] contact3d`` is on (the default).
    """

    physics: tuple[int, ...]
    words: str
    flagged_only: bool = False
    contact3d_decides: bool = False


@dataclass(frozen=True)
class BodyModel:
    """One entry of the registry: what a model judges and how (see the module's docstring)."""

    name: str
    physics: tuple[int, ...]
    claims: Callable[[BlockShape, Placement, SimulationConfig], bool]
    may_claim: Callable[[BlockShape, SimulationConfig], bool]
    scene: Callable[[OnRecord, BlockShape, Block, float], BodyScene]
    margins: Callable[..., Margin]
    scale: Callable[..., float]
    pulse: Callable[..., PulseJudge]
    versus_planar: VersusPlanar | None = None
    shared_warmups: tuple[Callable[[], None], ...] = ()
    stops: tuple[Stops, ...] = ()
    draws_warmups: tuple[Callable[[], None], ...] = ()
    warmups: tuple[Callable[[], None], ...] = ()
    warmups_for: Callable[[list | None, bool], tuple[Callable[[], None], ...]] | None = None
