"""Scene planner: simulate only the physics a scene calls for, and never skip a scene that moves.

For each (record, block) the planner picks the model from one exact indicator,
the ground's *demand ratio* ``max_t |a_h(t)| / (g + a_v(t))`` (infinite where
g + a_v <= 0). The ground acceleration is linear between samples, so the
ratio's peak over an interval lies at a sample, and the test is exact:

* **none**: the block neither lifts (ratio <= tan alpha) nor slips
  (ratio <= mu) at any sample, *with the vertical included whenever the
  record has one*: the block provably stays at rest, nothing is integrated;
* **sliding**: mu <= tan(alpha) (or a block too squat for pure rocking,
  alpha >= 54.7 deg) and the ratio exceeds mu: the base friction saturates
  before the tipping moment is reached, so the block slides (Coulomb
  stick-slip) and cannot rock;
* **rocking** / **rocking_vertical**: mu > tan(alpha) and the ratio exceeds
  tan(alpha). The vertical is simulated whenever the record has one. The
  setting ``vertical_fraction`` > 0 is an *approximation* that drops a
  vertical whose peak stays below that fraction of g from the simulation
  (never from the decision above); ``screen bench`` measures the verdicts it
  changes.

* **general**: where pure rocking stops holding, the general contact model
  (:mod:`.contact`: slide, slide-rock and free flight, with impacts) continues the
  scene from the state the rocking kernel stopped in (:mod:`.handoff`): the pivot's
  friction demand |f_x/f_z| exceeded mu, the pivot lifted off (f_z <= 0), or the
  ground fell faster than gravity (g + a_v <= 0). A sliding scene that meets free
  flight is simulated by the general model from rest. ``physics`` is then
  ``general``: the verdict rests on it. Pure-rocking scenes are the kernel's
  results, unchanged.

With ``contact_model = false`` (what ``screen bench`` compares with), the kernels
stop at free flight (response ``free_flight``, no verdict) and a friction
exceedance is only flagged (response ``slide_rock``, the pure-rocking verdict).

Responses: rest, slide, rock, slide_rock (slide-rock occurred; without the
contact model: the pure-rocking friction demand exceeded mu), overturn,
free_flight (only without the contact model). Which modes a general scene went
through is in ``contact_modes``.

References
----------
Yim, Chopra & Penzien (1980) EESD 8 (uplift with vertical input,
|a_h| > (g + a_v) tan alpha); Shenton (1996) J. Eng. Mech. 122(7) (rest,
slide, rock, slide-rock and free-flight modes); Zhang & Makris (2001) J. Eng.
Mech. 127(5) (friction demand).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import IntEnum

import numpy as np

from ..constants import G
from . import handoff
from .block import Block
from .codes import (
    STATUS_EVENT_CAP,
    STATUS_GROUND_FLIGHT,
    STATUS_LIFTOFF,
    STATUS_STALLED,
    STATUS_STEP_CAP,
    STATUS_TAIL_CAP,
    STATUS_TIE_HOLD,
    ContactMode,
)
from .rules import motion_threshold, rocks, vertical_kept
from .settings import SimulationConfig
from .simulate import ContactResult, RockResult, continued, from_rest, rock, slide


class Physics(IntEnum):
    """The model a scene is simulated with."""

    none = 0
    sliding = 1
    rocking = 2
    rocking_vertical = 3
    general = 4           # pure rocking continued by the general contact model (slide, slide-rock, flight)


class Response(IntEnum):
    """The simulated response class of a scene."""

    rest = 0
    slide = 1
    rock = 2
    slide_rock = 3
    overturn = 4
    free_flight = 5


class FreeFlight(IntEnum):
    """Loss of contact with the base."""

    none = 0
    ground_flight = 1       # the ground's g + a_v reached 0 (without the contact model: the simulation stopped)
    block_liftoff = 2       # f_z <= 0 while rocking (without the contact model: flagged, the verdict kept)


class Guard(IntEnum):
    """Bits of ``simulation_guard``: the guards a scene met (0: none; none is met on the bundled records).

    Every loop of the simulator either advances time or counts against one of these caps, so a scene always
    ends; where one is met, the scene says so here instead of hanging or guessing in silence.
    """

    event_cap = 1         # impacts and uplifts reached max_events (pure rocking: forced to rest each time after;
                          # general model: ended there with the verdict of the state reached)
    tie_hold = 2          # tie rule 6 (rules): events in a row at one instant on a flat block: held at rest to
                          # the next sample
    stalled = 4           # tie rule 6 on a block off its base: ended there with the verdict of the state reached
    step_cap = 8          # the step budget ran out: ended there with the verdict of the state reached
    tail_cap = 16         # the motion after the record outlasted its cap (general model): stopped, standing


def guard_names(bits: int) -> str:
    """The names of the :class:`Guard` bits set in ``bits``, comma-separated (empty for none)."""
    return ", ".join(g.name for g in Guard if int(bits) & g)


def guarded_scenes(guard: np.ndarray, records, blocks) -> list[tuple[str, str, str]]:
    """(record, block, guard names) of every scene whose ``simulation_guard`` (records x blocks) is set."""
    return [(str(records[i]), str(blocks[j]), guard_names(guard[i, j])) for i, j in zip(*np.nonzero(guard > 0))]


def kernel_guard(status: int) -> int:
    """:class:`Guard` bits of the rocking kernel's ``status`` (through the contact model's bits for the same
    guards, :func:`.handoff.kernel_guards`)."""
    return contact_guard(handoff.kernel_guards(status))


def contact_guard(status: int) -> int:
    """:class:`Guard` bits of the general contact model's ``status``."""
    return ((Guard.event_cap if status & STATUS_EVENT_CAP else 0)
            | (Guard.tie_hold if status & STATUS_TIE_HOLD else 0)
            | (Guard.stalled if status & STATUS_STALLED else 0)
            | (Guard.step_cap if status & STATUS_STEP_CAP else 0)
            | (Guard.tail_cap if status & STATUS_TAIL_CAP else 0))




def demand_ratio(ah_ms2: np.ndarray, av_ms2: np.ndarray | None, *, g_ms2: float = G) -> float:
    """Peak of |a_h| / (g + a_v) over the samples [-]; ``inf`` where g + a_v <= 0 somewhere.

    The block lifts iff the ratio exceeds tan(alpha), and slips from rest iff it exceeds mu
    (exact: the ground is linear between samples, so the ratio peaks at a sample).
    """
    ah = np.abs(np.asarray(ah_ms2, dtype=float))
    if av_ms2 is None:
        return float(np.max(ah)) / g_ms2
    gv = g_ms2 + np.asarray(av_ms2, dtype=float)
    if np.any(gv <= 0.0):
        return math.inf
    return float(np.max(ah / gv))


def uses_vertical(av_ms2: np.ndarray | None, *, g_ms2: float, vertical_fraction: float) -> bool:
    """True when the simulation includes the vertical component.

    Always when the record has one and ``vertical_fraction`` is 0 (the default). A positive
    fraction drops a vertical whose peak stays at or below that fraction of g (an approximation,
    measured by ``screen bench``); a vertical that reaches g + a_v <= 0 is never dropped.
    """
    if av_ms2 is None:
        return False
    if vertical_fraction <= 0.0:            # the default: no pass over the samples
        return True
    return vertical_kept(float(np.max(np.abs(av_ms2))), g_ms2, vertical_fraction)


def plan(ah_ms2: np.ndarray, av_ms2: np.ndarray | None, *, alpha: float, mu: float, g_ms2: float = G,
         vertical_fraction: float = SimulationConfig.vertical_fraction, ratio: float | None = None) -> int:
    """Physics code (:class:`Physics`) for one scene.

    ``none`` only where the block provably neither lifts nor slips at any sample, with the
    vertical included whenever the record has one. ``ratio`` is the scene's
    :func:`demand_ratio`, when already known.
    """
    if ratio is None:
        ratio = demand_ratio(ah_ms2, av_ms2, g_ms2=g_ms2)
    if not ratio > motion_threshold(alpha, mu):
        return Physics.none
    if not rocks(alpha, mu):
        return Physics.sliding
    use_v = uses_vertical(av_ms2, g_ms2=g_ms2, vertical_fraction=vertical_fraction)
    return Physics.rocking_vertical if use_v else Physics.rocking


@dataclass(frozen=True)
class Scene:
    """Simulated outcome of one scene (the per-scene variables of screening.nc)."""

    physics: int
    response: int
    overturned: bool
    theta_max: float
    n_impacts: int
    t_overturn: float
    friction_demand: float
    sliding_max_m: float
    #: 0 none; 1 the ground's g + a_v reached 0 (simulation stopped, no verdict); 2 lift-off of the
    #: rocking block by its own motion (f_z <= 0; flagged, verdict kept).
    free_flight: int
    chatter: bool
    #: 1 where the pure-rocking friction demand exceeded mu, -1 where it is not defined (sliding).
    friction_exceeded: int
    #: time contact was lost (g + a_v = 0) [s], NaN without free flight.
    t_flight: float = math.nan
    #: theta(t) / alpha at every sample when asked for (rocking scenes), else None.
    theta_over_alpha: np.ndarray | None = None
    #: :class:`ContactMode` bits of the modes the scene went through (0 at rest).
    contact_modes: int = 0
    #: :class:`Guard` bits of the simulator's guards the scene met (0: none).
    guard: int = 0

    @property
    def verdict(self) -> int:
        """1 overturns, 0 stands, -1 undetermined (free flight before any overturning, without the contact
        model)."""
        if self.overturned:
            return 1
        return -1 if self.response == Response.free_flight else 0


REST_SCENE = Scene(physics=Physics.none, response=Response.rest, overturned=False, theta_max=0.0, n_impacts=0,
                   t_overturn=math.nan, friction_demand=0.0, sliding_max_m=0.0, free_flight=0, chatter=False,
                   friction_exceeded=0)


def simulate_scene(ah_ms2, av_ms2, dt_s: float, *, block: Block, settings: SimulationConfig = SimulationConfig(),
                   physics: int | None = None, ratio: float | None = None, history: bool = False) -> Scene:
    """Plan and run one scene.

    Parameters
    ----------
    ah_ms2 : ndarray
        Ground acceleration along the block's rocking plane [m s-2].
    av_ms2 : ndarray or None
        Vertical ground acceleration, up positive [m s-2].
    dt_s : float
        Sampling interval [s].
    block : Block
        The block.
    settings : SimulationConfig
        Integration settings.
    physics : int, optional
        Force a physics code instead of planning (benchmarks, reference runs).
    ratio : float, optional
        The scene's :func:`demand_ratio`, when already known.
    history : bool
        Keep theta(t)/alpha at every sample (rocking scenes).
    """
    p, alpha, e, R_m, mu, g_ms2 = block
    if physics is None:
        physics = plan(ah_ms2, av_ms2, alpha=alpha, mu=mu, g_ms2=g_ms2,
                       vertical_fraction=settings.vertical_fraction, ratio=ratio)
    if physics == Physics.none:
        return REST_SCENE
    use_v = uses_vertical(av_ms2, g_ms2=g_ms2, vertical_fraction=settings.vertical_fraction)
    if physics == Physics.sliding:
        res = slide(ah_ms2, dt_s, mu=mu, av_ms2=av_ms2 if use_v else None, g_ms2=g_ms2)
        if res.free_flight and settings.contact_model:
            theta = np.full(np.asarray(ah_ms2).size, np.nan) if history else None
            return general_scene(from_rest(ah_ms2, av_ms2 if use_v else None, dt_s, block=block, settings=settings,
                                           theta_out=theta),
                                 alpha=alpha, friction_demand=math.nan, friction_exceeded=-1, theta=theta)
        if res.free_flight:
            return Scene(physics=physics, response=Response.free_flight, overturned=False, theta_max=0.0,
                         n_impacts=0, t_overturn=math.nan, friction_demand=math.nan, sliding_max_m=res.sliding_max_m,
                         free_flight=FreeFlight.ground_flight, chatter=False, friction_exceeded=-1,
                         t_flight=res.t_flight_s, contact_modes=ContactMode.slide)
        return Scene(physics=physics, response=Response.slide, overturned=False, theta_max=0.0, n_impacts=0,
                     t_overturn=math.nan, friction_demand=math.nan, sliding_max_m=res.sliding_max_m,
                     free_flight=FreeFlight.none, chatter=False, friction_exceeded=-1,
                     contact_modes=ContactMode.slide, guard=Guard.step_cap if res.capped_samples else 0)
    av = av_ms2 if physics == Physics.rocking_vertical else None
    rr = rock(ah_ms2, dt_s, p=p, alpha=alpha, e=e, R_m=R_m, av_ms2=av, g_ms2=g_ms2, settings=settings,
              history=history, stop_mu=mu if settings.contact_model else math.inf)
    if settings.contact_model:
        cont = continued(ah_ms2, av, dt_s, rr, block=block, settings=settings)
        if cont is not None:
            return general_scene(cont, alpha=alpha, friction_demand=rr.friction_demand,
                                 friction_exceeded=int(rr.friction_demand > mu), rocking=rr, theta=rr.theta)
    return _rocking_scene(physics, rr, alpha=alpha, mu=mu, history=history)


def general_scene(co: ContactResult, *, alpha: float, friction_demand: float, friction_exceeded: int,
                  rocking: RockResult | None = None, theta: np.ndarray | None = None) -> Scene:
    """A scene decided by the general contact model (``co``), after the pure rocking ``rocking`` when it
    came first. ``free_flight`` says which loss of contact happened first: the ground's, else the block's own.
    ``theta``: the scene's theta history [rad] at the samples (kept as theta / alpha), when asked for."""
    modes = co.modes | (ContactMode.rock if rocking is not None else 0)
    if co.overturned:
        response = Response.overturn
    elif modes & ContactMode.slide_rock:
        response = Response.slide_rock
    elif modes & ContactMode.rock:
        response = Response.rock
    elif modes & ContactMode.slide:
        response = Response.slide
    else:
        response = Response.rest
    flight = FreeFlight.none
    if co.status & STATUS_GROUND_FLIGHT:
        flight = FreeFlight.ground_flight
    elif co.status & STATUS_LIFTOFF:
        flight = FreeFlight.block_liftoff
    theta_max = max(co.theta_max_rad / alpha, rocking.theta_max if rocking is not None else 0.0)
    n_impacts = co.n_impacts + (rocking.n_impacts if rocking is not None else 0)
    guard = contact_guard(co.status)           # the continuation's status holds the first pure-rocking part's guards
    return Scene(physics=Physics.general, response=response, overturned=co.overturned, theta_max=theta_max,
                 n_impacts=n_impacts, t_overturn=co.t_overturn, friction_demand=friction_demand,
                 sliding_max_m=co.slip_max_m, free_flight=flight, chatter=guard & Guard.event_cap > 0,
                 friction_exceeded=friction_exceeded,
                 t_flight=rocking.t_stop if rocking is not None and rocking.free_flight else math.nan,
                 theta_over_alpha=None if theta is None else theta / alpha, contact_modes=modes, guard=guard)


def _rocking_scene(physics: int, res: RockResult, *, alpha: float, mu: float, history: bool) -> Scene:
    """A rocking simulation's outcome as a :class:`Scene`."""
    exceeded = res.friction_demand > mu
    flight = res.free_flight and not res.overturned
    if res.overturned:
        response = Response.overturn
    elif flight:
        response = Response.free_flight
    elif exceeded:
        response = Response.slide_rock
    else:
        response = Response.rock
    theta = res.theta / alpha if history and res.theta is not None else None
    free_flight = FreeFlight.ground_flight if flight else (FreeFlight.block_liftoff if res.liftoff else
                                                          FreeFlight.none)
    return Scene(physics=physics, response=response, overturned=res.overturned, theta_max=res.theta_max,
                 n_impacts=res.n_impacts, t_overturn=res.t_overturn, friction_demand=res.friction_demand,
                 sliding_max_m=math.nan, free_flight=free_flight, chatter=res.chatter,
                 friction_exceeded=int(exceeded), t_flight=res.t_stop if flight else math.nan,
                 theta_over_alpha=theta, contact_modes=ContactMode.rock, guard=kernel_guard(res.status))

