"""A scene's outcome and its codes: the model that simulated it (:class:`Physics`), its response class, its loss of
contact, the simulator's guards it met, and the :class:`Scene` every model returns.

References
----------
Shenton, H. W. (1996). Criteria for initiation of slide, rock, and slide-rock rigid-body modes. J. Eng. Mech.
122(7), 690-693 (the rest, slide, rock, slide-rock and free-flight modes).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import IntEnum

import numpy as np

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
from .planar import handoff
from .simulate import ContactResult, RockResult


class Physics(IntEnum):
    """The model a scene is simulated with."""

    none = 0
    sliding = 1
    rocking = 2
    rocking_vertical = 3
    general = 4           # pure rocking continued by the general contact model (slide, slide-rock, flight)
    wobbling = 5          # a cylinder rocking and rolling on its rim under both horizontals (rocking.cylinder3d)
    rocking3d = 6         # a box with a depth on an edge or a corner under both horizontals (rocking.box3d)
    two_sided = 7         # a body given by its scan, each side's pivot its own, in a vertical plane (rocking.scanned)
    rolling = 8           # a body given by its scan rolling on its convex hull in a vertical plane (rocking.rolling)
    contact3d = 9         # a cylinder or a box by the 3D contact model where its exact model stopped
                          # (rocking.solids.contact_scene; [simulation] contact3d = true)
    stack = 10            # a body of a stack of blocks rocking in a vertical plane (assemblies.stack_scene)


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
    model_limit = 32      # the 3D model stopped where its base would slide or lift off (not modeled), or at its step
                          # cap; or the two-sided or rolling model of a scanned body, or the model of a stack, met a
                          # free flight of the ground, its step or event cap or its free motion's cap: no verdict
    held_past_alpha = 64  # the 3D model's base would slide or lift off while it fell past alpha: followed with the
                          # rim held; its overturning kept (it had no verdict otherwise)


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
        return -1 if self.response == Response.free_flight or self.guard & Guard.model_limit else 0


REST_SCENE = Scene(physics=Physics.none, response=Response.rest, overturned=False, theta_max=0.0, n_impacts=0,
                   t_overturn=math.nan, friction_demand=0.0, sliding_max_m=0.0, free_flight=0, chatter=False,
                   friction_exceeded=0)


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


def rocking_scene(physics: int, res: RockResult, *, alpha: float, mu: float, history: bool) -> Scene:
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

