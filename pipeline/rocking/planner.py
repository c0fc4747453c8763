"""Scene planner: simulate only the physics a scene calls for.

For each (record, block) the cheap indicators below pick the model; the
ground acceleration is linear between samples, so its peak over an interval
is at a sample and the indicators are exact:

* **rest**: the ground neither lifts the block (|a_h| <= (g + a_v) tan alpha)
  nor makes it slip (|a_h| <= mu (g + a_v)): nothing is integrated;
* **sliding**: mu <= tan(alpha) and the ground exceeds mu (g + a_v): the base
  friction saturates before the tipping moment is reached, so the block slides
  (Coulomb stick-slip model) and cannot rock;
* **rocking**: mu > tan(alpha) and the ground exceeds (g + a_v) tan(alpha);
* **rocking_vertical**: as rocking, with the vertical component, when the
  record has one and max |a_v| moves the uplift threshold by more than
  ``vertical_fraction`` (a setting); otherwise a_v is left out.

A block too squat for pure rocking (alpha >= 54.7 deg) gets the sliding model
or rest, never a rocking simulation.

Responses: rest, slide, rock, slide_rock (rocking whose friction demand
|f_x/f_z| exceeded mu somewhere: the pure-rocking result is then not to be
trusted), overturn.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..config import SimulationConfig
from ..constants import G
from ..criteria import rocking_applicable
from .simulate import rock, slide

PHYSICS = {"none": 0, "sliding": 1, "rocking": 2, "rocking_vertical": 3}
RESPONSE = {"rest": 0, "slide": 1, "rock": 2, "slide_rock": 3, "overturn": 4}


def uses_vertical(av_ms2: np.ndarray | None, *, g_ms2: float, vertical_fraction: float) -> bool:
    """True when a vertical component exists and max |a_v| exceeds ``vertical_fraction`` g."""
    return av_ms2 is not None and float(np.max(np.abs(av_ms2))) > vertical_fraction * g_ms2


def plan(ah_ms2: np.ndarray, av_ms2: np.ndarray | None, *, alpha: float, mu: float, g_ms2: float = G,
         vertical_fraction: float = SimulationConfig.vertical_fraction) -> int:
    """Physics code (:data:`PHYSICS`) for one scene."""
    use_v = uses_vertical(av_ms2, g_ms2=g_ms2, vertical_fraction=vertical_fraction)
    gv = g_ms2 + av_ms2 if use_v else g_ms2
    peak = np.abs(ah_ms2)
    tan_a = math.tan(alpha)
    if mu > tan_a and rocking_applicable(alpha):
        if np.any(peak > gv * tan_a):
            return PHYSICS["rocking_vertical"] if use_v else PHYSICS["rocking"]
        return PHYSICS["none"]
    if np.any(peak > mu * gv):
        return PHYSICS["sliding"]
    return PHYSICS["none"]


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
    free_flight: bool
    chatter: bool
    #: 1 where the pure-rocking friction demand exceeded mu, -1 where it is not defined (sliding).
    friction_exceeded: int


def simulate_scene(ah_ms2, av_ms2, dt_s: float, *, p: float, alpha: float, e: float, R_m: float, mu: float,
                   g_ms2: float = G, settings: SimulationConfig = SimulationConfig(),
                   physics: int | None = None) -> Scene:
    """Plan and run one scene.

    Parameters
    ----------
    ah_ms2 : ndarray
        Ground acceleration along the block's rocking plane [m s-2].
    av_ms2 : ndarray or None
        Vertical ground acceleration, up positive [m s-2].
    dt_s : float
        Sampling interval [s].
    p, alpha, e, R_m, mu : float
        Block frequency parameter [rad s-1], slenderness [rad], restitution [-],
        corner distance [m], friction [-].
    physics : int, optional
        Force a physics code instead of planning (benchmarks, reference runs).
    """
    if physics is None:
        physics = plan(ah_ms2, av_ms2, alpha=alpha, mu=mu, g_ms2=g_ms2,
                       vertical_fraction=settings.vertical_fraction)
    if physics == PHYSICS["none"]:
        return Scene(physics, RESPONSE["rest"], False, 0.0, 0, math.nan, 0.0, 0.0, False, False, 0)
    if physics == PHYSICS["sliding"]:
        use_v = uses_vertical(av_ms2, g_ms2=g_ms2, vertical_fraction=settings.vertical_fraction)
        res = slide(ah_ms2, dt_s, mu=mu, av_ms2=av_ms2 if use_v else None, g_ms2=g_ms2)
        return Scene(physics, RESPONSE["slide"], False, 0.0, 0, math.nan, math.nan, res.sliding_max_m,
                     res.free_flight, False, -1)
    av = av_ms2 if physics == PHYSICS["rocking_vertical"] else None
    res = rock(ah_ms2, dt_s, p=p, alpha=alpha, e=e, R_m=R_m, av_ms2=av, g_ms2=g_ms2, settings=settings)
    exceeded = res.friction_demand > mu
    if res.overturned:
        response = RESPONSE["overturn"]
    elif exceeded:
        response = RESPONSE["slide_rock"]
    else:
        response = RESPONSE["rock"]
    return Scene(physics, response, res.overturned, res.theta_max, res.n_impacts, res.t_overturn,
                 res.friction_demand, math.nan, res.free_flight, res.chatter, int(exceeded))
