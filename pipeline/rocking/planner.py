"""Scene planner: simulate only the physics a scene calls for, and never skip a scene that moves.

For each (record, block) the planner gives the scene to the first model of the registry
(:data:`.models.MODELS`) whose certificate holds; it names no model itself. The certificates read one exact
indicator, the ground's *demand ratio* ``max_t |a_h(t)| / (g + a_v(t))`` (infinite where
g + a_v <= 0), and the block (:class:`.contract.SceneFacts`). The ground acceleration is linear between samples,
so the ratio's peak over an interval lies at a sample, and the test is exact:

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

import numpy as np

from ..constants import G
from .block import Block
from .codes import ContactMode
from .contract import SceneFacts, SceneInput
from .models import by_physics, choose
from .numerics.ground import QuietTable
from .rules import motion_threshold, rocks, vertical_kept
from .scene import (
    REST_SCENE,
    FreeFlight,
    Guard,
    Physics,
    Response,
    Scene,
    contact_guard,
    general_scene,
    guard_names,
    guarded_scenes,
    kernel_guard,
)
from .settings import SimulationConfig

__all__ = ["REST_SCENE", "ContactMode", "FreeFlight", "Guard", "Physics", "Response", "Scene", "contact_guard",
           "demand_ratio", "general_scene", "guard_names", "guarded_scenes", "kernel_guard", "motion_threshold",
           "plan", "rocks", "scene_facts", "simulate_scene", "uses_vertical"]


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


def scene_facts(ah_ms2: np.ndarray, av_ms2: np.ndarray | None, *, alpha: float, mu: float, g_ms2: float = G,
                vertical_fraction: float = SimulationConfig.vertical_fraction, ratio: float | None = None
                ) -> SceneFacts:
    """What the certificates read of one scene (:class:`.contract.SceneFacts`); ``ratio`` is the scene's
    :func:`demand_ratio`, when already known."""
    if ratio is None:
        ratio = demand_ratio(ah_ms2, av_ms2, g_ms2=g_ms2)
    return SceneFacts(ratio=ratio, threshold=motion_threshold(alpha, mu), rocks=rocks(alpha, mu),
                      vertical=uses_vertical(av_ms2, g_ms2=g_ms2, vertical_fraction=vertical_fraction),
                      alpha=alpha, mu=mu)


def plan(ah_ms2: np.ndarray, av_ms2: np.ndarray | None, *, alpha: float, mu: float, g_ms2: float = G,
         vertical_fraction: float = SimulationConfig.vertical_fraction, ratio: float | None = None) -> int:
    """Physics code (:class:`Physics`) for one scene: the registered model whose certificate holds first.

    ``none`` only where the block provably neither lifts nor slips at any sample, with the
    vertical included whenever the record has one. ``ratio`` is the scene's
    :func:`demand_ratio`, when already known.
    """
    return choose(scene_facts(ah_ms2, av_ms2, alpha=alpha, mu=mu, g_ms2=g_ms2, vertical_fraction=vertical_fraction,
                              ratio=ratio)).physics


def simulate_scene(ah_ms2, av_ms2, dt_s: float, *, block: Block, settings: SimulationConfig = SimulationConfig(),
                   physics: int | None = None, ratio: float | None = None, history: bool = False,
                   quiet: QuietTable | None = None) -> Scene:
    """Plan and run one scene: the registered model whose certificate holds first, or the model ``physics``.

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
    quiet : QuietTable, optional
        The :class:`~.numerics.ground.QuietTable` of ``ah_ms2`` and ``av_ms2`` (:meth:`.orientation.Planes.quiet`).
    """
    facts = scene_facts(ah_ms2, av_ms2, alpha=block.alpha, mu=block.mu, g_ms2=block.g_ms2,
                        vertical_fraction=settings.vertical_fraction, ratio=ratio)
    model = choose(facts) if physics is None else by_physics(physics)
    return model.simulate(SceneInput(ah_ms2=ah_ms2, av_ms2=av_ms2, vertical_ms2=av_ms2 if facts.vertical else None,
                                     dt_s=dt_s, block=block, settings=settings, history=history, quiet=quiet))
