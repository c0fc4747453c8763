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

Free flight: where g + a_v <= 0 the block leaves its base and neither the
rocking equation nor Coulomb friction holds. The kernels stop there; a scene
that had not overturned before gets the response ``free_flight`` and no
verdict (-1), never an overturn or a slide.

Responses: rest, slide, rock, slide_rock (rocking whose friction demand
|f_x/f_z| exceeded mu somewhere: the pure-rocking result is then not to be
trusted), overturn, free_flight.

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
from .block import Block
from .rules import motion_threshold, rocks, vertical_kept
from .settings import SimulationConfig
from .simulate import RockResult, rock, slide


class Physics(IntEnum):
    """The model a scene is simulated with."""

    none = 0
    sliding = 1
    rocking = 2
    rocking_vertical = 3


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
    ground_flight = 1       # the ground's g + a_v reached 0: the simulation stopped there
    block_liftoff = 2       # f_z <= 0 while rocking: flagged, the verdict kept




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

    @property
    def verdict(self) -> int:
        """1 overturns, 0 stands, -1 undetermined (free flight before any overturning)."""
        if self.overturned:
            return 1
        return -1 if self.response == Response.free_flight else 0


REST_SCENE = Scene(Physics.none, Response.rest, False, 0.0, 0, math.nan, 0.0, 0.0, 0, False, 0)


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
        if res.free_flight:
            return Scene(physics, Response.free_flight, False, 0.0, 0, math.nan, math.nan, res.sliding_max_m,
                         1, False, -1, res.t_flight_s)
        return Scene(physics, Response.slide, False, 0.0, 0, math.nan, math.nan, res.sliding_max_m,
                     0, False, -1)
    av = av_ms2 if physics == Physics.rocking_vertical else None
    rr = rock(ah_ms2, dt_s, p=p, alpha=alpha, e=e, R_m=R_m, av_ms2=av, g_ms2=g_ms2, settings=settings,
              history=history)
    return _rocking_scene(physics, rr, alpha=alpha, mu=mu, history=history)


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
    return Scene(physics, response, res.overturned, res.theta_max, res.n_impacts, res.t_overturn,
                 res.friction_demand, math.nan, 1 if flight else (2 if res.liftoff else 0), res.chatter,
                 int(exceeded), res.t_stop if flight else math.nan, theta)

