"""A body of a stack under a record in one vertical plane: its :class:`~pipeline.rocking.scene.Scene`.

Where the stack's certificate holds (:func:`.stack.stays_shut`: no interface lifts off nor slips at any sample, the
ground linear between samples) nothing is integrated: every body stands at rest (physics ``none``). Otherwise the
two-block model (:mod:`.two_block_run`) runs and each body is judged (:func:`.two_block_verdicts.judge_two_block`):
the body's scene reads its own verdict, its peak rotation on what it stands on (the lower block on the ground, the
upper on the lower) over that joint's smaller tipping angle at rest, to the first fall, and the run's impacts. The
model does not slide nor follow flight off a support: the friction its joint needs (|F_t| / F_n, inside the tipping
angles: :func:`.two_block.demands`) is the scene's ``friction_demand``, flagged where it exceeds the body's mu
(``friction_exceeded``; response slide or slide_rock), the verdict there assuming the joint holds; the ground
falling faster than gravity, or a cap met without a verdict, leaves the scene without one.

References
----------
Psycharis, I. N. (1990). Dynamic behaviour of rocking two-block assemblies. Earthquake Engineering & Structural
Dynamics 19(4), 555-575.
"""

from __future__ import annotations

import math

import numpy as np

from ..rocking.codes import (
    STATUS_EVENT_CAP,
    STATUS_GROUND_FLIGHT,
    STATUS_STEP_CAP,
    STATUS_TAIL_CAP,
    ContactMode,
    Verdict,
)
from ..rocking.scene import REST_SCENE, FreeFlight, Guard, Physics, Response, Scene
from ..rocking.settings import SimulationConfig
from .stack import StackPlace, stays_shut
from .two_block import TwoBlock, tipping_angles, two_block
from .two_block_run import FALLS_STACK, simulate_two_block
from .two_block_verdicts import TwoBlockVerdict, judge_two_block


def stack_blocks(place: StackPlace) -> TwoBlock:
    """The two-block model of ``place``'s stack (two bodies: :data:`pipeline.stacks.MAX_BODIES`)."""
    lower, upper = place.bodies
    return two_block(lower, upper, label=f"stack {' < '.join(reversed(place.ids))}")


def body_verdict(place: StackPlace, ah_ms2: np.ndarray, av_ms2: np.ndarray | None, dt_s: float, *,
                 tb: TwoBlock | None = None, settings: SimulationConfig = SimulationConfig()) -> int:
    """The :class:`~pipeline.rocking.codes.Verdict` of ``place``'s body under the ground (``ah_ms2``, ``av_ms2``)
    [m s-2], ``dt_s`` [s] apart; ``tb``: the stack's model when already built."""
    return body_scene(place, ah_ms2, av_ms2, dt_s, tb=tb, settings=settings).verdict     # Scene.verdict's codes


def body_scene(place: StackPlace, ah_ms2: np.ndarray, av_ms2: np.ndarray | None, dt_s: float, *,
               tb: TwoBlock | None = None, settings: SimulationConfig = SimulationConfig(),
               memo: RunMemo | None = None, key: tuple | None = None) -> Scene:
    """The scene of ``place``'s body under the ground (``ah_ms2``, ``av_ms2``) [m s-2], samples ``dt_s`` [s] apart
    (the module's rules); ``tb``: the stack's model when already built; ``settings``: the rocking kernel's tolerances
    for the lower block left alone. ``memo`` and ``key``: the stack's run is kept in ``memo`` under ``key`` (what
    makes the ground, for one record) with the stack's bodies, so that the other body of the stack reads it."""
    full_key = None if key is None else (place.bodies, *key)
    judged = None if memo is None or full_key is None else memo.get(full_key)
    if judged is None:
        judged = stack_run(place, ah_ms2, av_ms2, dt_s, tb=tb, settings=settings)
        if memo is not None and full_key is not None:
            memo.put(full_key, judged)
    if judged is AT_REST:
        return REST_SCENE
    return scene_of(stack_blocks(place) if tb is None else tb, judged, place.position,
                    place.bodies[place.position].mu)


#: A stack's run where its certificate holds: nothing integrated, every body at rest
AT_REST = "at rest"


def stack_run(place: StackPlace, ah_ms2: np.ndarray, av_ms2: np.ndarray | None, dt_s: float, *,
              tb: TwoBlock | None = None, settings: SimulationConfig = SimulationConfig()):
    """The stack's verdicts under the ground (:class:`~.two_block_verdicts.TwoBlockVerdict`), or :data:`AT_REST`
    where its certificate holds."""
    if stays_shut(place.bodies, ah_ms2, av_ms2):
        return AT_REST
    tb = stack_blocks(place) if tb is None else tb
    return judge_two_block(tb, ah_ms2, dt_s, av_ms2=av_ms2, settings=settings)


class RunMemo:
    """The stack runs of one record, shared between the bodies of each stack: at most ``capacity`` kept, the
    oldest dropped first (memory stays bounded whatever the inventory)."""

    def __init__(self, capacity: int = 4096) -> None:
        self.capacity = capacity
        self._runs: dict = {}
        self.hits = 0

    def get(self, key: tuple):
        """The run kept under ``key``, or None."""
        run = self._runs.get(key)
        self.hits += run is not None
        return run

    def put(self, key: tuple, run) -> None:
        """Keep ``run`` under ``key``, dropping the oldest beyond the capacity."""
        self._runs[key] = run
        if len(self._runs) > self.capacity:
            del self._runs[next(iter(self._runs))]


def scene_of(tb: TwoBlock, judged: TwoBlockVerdict, index: int, mu: float = math.inf) -> Scene:
    """Body ``index``'s (0 the lower) :class:`~pipeline.rocking.scene.Scene` from the stack's verdicts; ``mu``: the
    friction at the body's lower face [-], against which its joint's friction demand is flagged."""
    run = judged.run
    verdict = judged.lower if index == 0 else judged.upper
    ground, joint = tipping_angles(tb)
    theta_max = run.peak_phi1_rad / min(ground) if index == 0 else run.peak_psi_rad / min(joint)
    overturned = verdict == Verdict.overturns
    flight = bool(run.status & STATUS_GROUND_FLIGHT) and not overturned
    response = (Response.overturn if overturned else Response.free_flight if flight
                else Response.rock if run.modes else Response.rest)
    guard = ((Guard.step_cap if run.status & STATUS_STEP_CAP else 0)
             | (Guard.event_cap if run.status & STATUS_EVENT_CAP else 0)
             | (Guard.tail_cap if run.status & STATUS_TAIL_CAP else 0)
             | (Guard.model_limit if verdict == Verdict.no_verdict and not flight else 0))
    fell_together = run.falls == FALLS_STACK or index == 1
    demand = run.demand_ground if index == 0 else run.demand_joint
    exceeded = demand > mu
    if exceeded and response in (Response.rest, Response.rock):
        response = Response.slide_rock if response == Response.rock else Response.slide
    return Scene(physics=Physics.stack, response=response, overturned=overturned, theta_max=float(theta_max),
                 n_impacts=int(run.impacts), t_overturn=float(run.t_fall_s) if overturned and fell_together
                 else math.nan, friction_demand=float(demand), sliding_max_m=math.nan,
                 free_flight=FreeFlight.ground_flight if flight else FreeFlight.none,
                 chatter=bool(run.status & STATUS_EVENT_CAP), friction_exceeded=int(exceeded),
                 contact_modes=int(ContactMode.rock) if run.modes else 0, guard=int(guard))


def body_history(place: StackPlace, ah_ms2: np.ndarray, av_ms2: np.ndarray | None, dt_s: float, *,
                 tb: TwoBlock | None = None) -> np.ndarray:
    """The body's rotation on what it stands on over that joint's smaller tipping angle at rest [-], at every sample
    of the ground (``ah_ms2``, ``av_ms2``) [m s-2], ``dt_s`` [s] apart, to the stack's first fall (NaN after it)."""
    tb = stack_blocks(place) if tb is None else tb
    hist = np.full((2, np.asarray(ah_ms2).shape[0]), np.nan)
    hist[:, 0] = 0.0
    simulate_two_block(tb, ah_ms2, dt_s, av_ms2=av_ms2, history=hist)
    ground, joint = tipping_angles(tb)
    return hist[0] / min(ground) if place.position == 0 else hist[1] / min(joint)
