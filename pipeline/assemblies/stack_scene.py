"""A body of a stack under a record in one vertical plane: its :class:`~pipeline.rocking.scene.Scene`.

Where the stack's certificate holds (:func:`.stack.stays_shut`: no interface lifts off nor slips at any sample, the
ground linear between samples) nothing is integrated: every body stands at rest (physics ``none``). Otherwise the
stack's model runs and each body is judged: two blocks by the two-block model
(:func:`.two_block_verdicts.judge_two_block`), three to :data:`.n_block.MAX_BODIES` by the n-block model
(:func:`.n_block_verdicts.judge_n_block`). The body's scene reads its own verdict, its peak rotation on what it
stands on (the bottom block on the ground, each other on the block below) over that joint's smaller tipping angle at
rest, and the runs' impacts. The exact models do not slide nor follow flight off a support: the friction its joint
needs (|F_t| / F_n, inside the tipping angles: :func:`.two_block.demands`) is the scene's ``friction_demand``,
flagged where it exceeds the body's mu (``friction_exceeded``; response slide or slide_rock). Where a joint would
slip or the ground falls faster than gravity the stack's contact model follows it (:mod:`.stack_contact`, through
:func:`.n_block_verdicts.judge_n_block`), and the scene keeps its verdict with the flight flagged (``free_flight``);
a cap met without a verdict leaves the scene without one.

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
from . import n_block as n_blocks
from . import two_block
from .n_block import NBlock
from .n_block_run import simulate_n_block
from .n_block_verdicts import StackVerdicts, judge_n_block
from .stack import StackPlace, at_rest, slips_at_rest
from .two_block import TwoBlock
from .two_block_run import FALLS_STACK, FALLS_TOP, simulate_two_block
from .two_block_verdicts import TwoBlockVerdict, judge_two_block

#: A stack's model: two blocks, or three and more
StackModel = TwoBlock | NBlock


def stack_blocks(place: StackPlace) -> StackModel:
    """The model of ``place``'s stack: the two-block model for two bodies, the n-block model for more."""
    label = f"stack {' < '.join(reversed(place.ids))}"
    if len(place.bodies) == 2:
        lower, upper = place.bodies
        return two_block.two_block(lower, upper, label=label)
    return n_blocks.n_block(place.bodies, label=label)


def tipping_angles(model: StackModel) -> tuple:
    """Each joint's tipping angles at rest on its + and - corner [rad], bottom first."""
    return two_block.tipping_angles(model) if isinstance(model, TwoBlock) else n_blocks.tipping_angles(model)


def judge(model: StackModel, ah_ms2: np.ndarray, dt_s: float, *, av_ms2: np.ndarray | None = None,
          settings: SimulationConfig = SimulationConfig(), bodies: tuple | None = None,
          slips_first: bool | None = None) -> StackVerdicts:
    """Each body's verdict under the ground (``ah_ms2``, ``av_ms2``) [m s-2], ``dt_s`` [s] apart, by the stack's
    model; ``settings``: the rocking kernel's tolerances for the lower of two blocks left alone; ``bodies``: the
    stack's :class:`~.stack.StackBody` rows, whose friction follows a flight of the ground or a joint's slip
    (:mod:`.stack_contact`; None: the joints hold and a flight leaves the verdict open). Two blocks whose run meets
    a flight, or needs more friction than a joint has (the two-block run ended where it first does), are judged
    again as the n-block stack of those bodies, and are judged so at once where a joint slips while the stack is
    still at rest (:func:`.stack.slips_at_rest`; ``slips_first``: its answer, when already known)."""
    mu = None if bodies is None else tuple(b.mu for b in bodies)
    if isinstance(model, TwoBlock) and bodies is not None and (
            slips_at_rest(bodies, ah_ms2, av_ms2) if slips_first is None else slips_first):
        model = n_blocks.n_block(bodies)            # the two-block run would need more friction than a joint has
    if isinstance(model, TwoBlock):
        judged = from_two_block(judge_two_block(model, ah_ms2, dt_s, av_ms2=av_ms2, settings=settings, stop_mu=mu))
        if mu is None or not (judged.status & STATUS_GROUND_FLIGHT or any(d > m for d, m in zip(judged.demand, mu))):
            return judged
        model = n_blocks.n_block(bodies)
    return judge_n_block(model, ah_ms2, dt_s, av_ms2=av_ms2, mu=mu)


def from_two_block(judged: TwoBlockVerdict) -> StackVerdicts:
    """The two-block verdicts as :class:`.n_block_verdicts.StackVerdicts` (its peaks are the first run's, to the
    first fall; the upper's time of fall is the run's, the lower's only where it fell with the upper; its joints
    never slip, so a standing body's residual offset is 0)."""
    run = judged.run
    t_upper = run.t_fall_s if run.falls in (FALLS_STACK, FALLS_TOP) else math.nan
    t_lower = run.t_fall_s if run.falls == FALLS_STACK else math.nan
    verdicts = (int(judged.lower), int(judged.upper))
    return StackVerdicts(verdicts, (run.peak_phi1_rad, run.peak_psi_rad), (t_lower, t_upper), int(run.impacts),
                         run.modes != 0, int(run.status), (run.demand_ground, run.demand_joint),
                         offset_m=tuple(0.0 if v == Verdict.stands else math.nan for v in verdicts))


def body_verdict(place: StackPlace, ah_ms2: np.ndarray, av_ms2: np.ndarray | None, dt_s: float, *,
                 tb: StackModel | None = None, settings: SimulationConfig = SimulationConfig()) -> int:
    """The :class:`~pipeline.rocking.codes.Verdict` of ``place``'s body under the ground (``ah_ms2``, ``av_ms2``)
    [m s-2], ``dt_s`` [s] apart; ``tb``: the stack's model when already built."""
    return body_scene(place, ah_ms2, av_ms2, dt_s, tb=tb, settings=settings).verdict     # Scene.verdict's codes


def body_scene(place: StackPlace, ah_ms2: np.ndarray, av_ms2: np.ndarray | None, dt_s: float, *,
               tb: StackModel | None = None, settings: SimulationConfig = SimulationConfig(),
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
              tb: StackModel | None = None, settings: SimulationConfig = SimulationConfig()):
    """The stack's verdicts under the ground (:class:`~.n_block_verdicts.StackVerdicts`), or :data:`AT_REST`
    where its certificate holds."""
    rest = at_rest(place.bodies, ah_ms2, av_ms2)
    if rest.stays_shut:
        return AT_REST
    tb = stack_blocks(place) if tb is None else tb
    return judge(tb, ah_ms2, dt_s, av_ms2=av_ms2, settings=settings, bodies=place.bodies,
                 slips_first=rest.slips_at_rest)


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


def scene_of(tb: StackModel, judged: StackVerdicts, index: int, mu: float = math.inf) -> Scene:
    """Body ``index``'s (0 the bottom) :class:`~pipeline.rocking.scene.Scene` from the stack's verdicts; ``mu``: the
    friction at the body's lower face [-], against which its joint's friction demand is flagged."""
    verdict = judged.verdicts[index]
    theta_max = judged.peak_psi_rad[index] / min(tipping_angles(tb)[index])
    overturned = verdict == Verdict.overturns
    flight = bool(judged.status & STATUS_GROUND_FLIGHT) and not overturned
    unfollowed = flight and verdict == Verdict.no_verdict        # a flight followed leaves a verdict
    response = (Response.overturn if overturned else Response.free_flight if unfollowed
                else Response.rock if judged.opened else Response.rest)
    guard = ((Guard.step_cap if judged.status & STATUS_STEP_CAP else 0)
             | (Guard.event_cap if judged.status & STATUS_EVENT_CAP else 0)
             | (Guard.tail_cap if judged.status & STATUS_TAIL_CAP else 0)
             | (Guard.model_limit if verdict == Verdict.no_verdict and not flight else 0))
    demand = judged.demand[index]
    exceeded = demand > mu
    if exceeded and response in (Response.rest, Response.rock):
        response = Response.slide_rock if response == Response.rock else Response.slide
    t_fall = judged.t_fall_s[index]
    return Scene(physics=Physics.stack, response=response, overturned=overturned, theta_max=float(theta_max),
                 n_impacts=int(judged.impacts), t_overturn=float(t_fall) if overturned else math.nan,
                 friction_demand=float(demand),
                 sliding_max_m=float(judged.slide_m[index]) if judged.slide_m else math.nan,
                 free_flight=FreeFlight.ground_flight if flight else FreeFlight.none,
                 chatter=bool(judged.status & STATUS_EVENT_CAP), friction_exceeded=int(exceeded),
                 contact_modes=int(ContactMode.rock) if judged.opened else 0, guard=int(guard))


def body_history(place: StackPlace, ah_ms2: np.ndarray, av_ms2: np.ndarray | None, dt_s: float, *,
                 tb: StackModel | None = None) -> np.ndarray:
    """The body's rotation on what it stands on over that joint's smaller tipping angle at rest [-], at every sample
    of the ground (``ah_ms2``, ``av_ms2``) [m s-2], ``dt_s`` [s] apart, by the exact model alone: to the stack's first
    fall or the ground's first flight (NaN after it), through a joint's slip as if it held (the verdict follows both
    with the stack's contact model, whose motion this history does not show)."""
    tb = stack_blocks(place) if tb is None else tb
    n = len(place.bodies)
    hist = np.full((n, np.asarray(ah_ms2).shape[0]), np.nan)
    hist[:, 0] = 0.0
    if isinstance(tb, TwoBlock):
        simulate_two_block(tb, ah_ms2, dt_s, av_ms2=av_ms2, history=hist)   # rows phi_1 and psi: the joints'
    else:
        simulate_n_block(tb, ah_ms2, dt_s, av_ms2=av_ms2, history=hist)
    return hist[place.position] / min(tipping_angles(tb)[place.position])
