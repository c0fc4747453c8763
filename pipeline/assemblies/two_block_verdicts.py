"""Each body's verdict for two stacked blocks under a record: the upper block falls with the stack, falls alone, or
stands; the lower block, once the upper has fallen off it, rocks alone on to the record's end.

The two-block run (:func:`.two_block_run.simulate_two_block`) ends at the first fall. Where the upper block falls
alone, the lower block is followed from its state at that instant by the rocking kernel as a single block of its
own (Housner's equation and impact; the fallen block assumed gone, no longer loading it), and judged by it. A run
that ended without a verdict (the ground falling faster than gravity, a cap) gives both bodies none: unknown, never
standing; but a free motion after the record that outlasts its cap stands where its energy certifies it
(:func:`energy_below_barrier`).

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. Bulletin of the
Seismological Society of America 53(2), 403-417.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..constants import G
from ..rocking.block import BlockShape, dynamics, rigid_block
from ..rocking.codes import (
    STATUS_EVENT_CAP,
    STATUS_FRICTION,
    STATUS_GROUND_FLIGHT,
    STATUS_STEP_CAP,
    STATUS_STEP_UNDERFLOW,
    STATUS_TAIL_CAP,
    Verdict,
)
from ..rocking.numerics.ground import NO_QUIET
from ..rocking.planar import kernel
from ..rocking.settings import SimulationConfig
from ..rocking.simulate import step_control
from ..rocking.structures import RockingOutput, RockingState
from .two_block import Motion, TwoBlock, kinetic_energy, potential_energy, tipping_angles
from .two_block_run import FALLS_NONE, FALLS_STACK, TwoBlockOutcome, simulate_two_block

#: The two-block run's status bits that leave its verdict open
UNDECIDED_RUN = STATUS_GROUND_FLIGHT | STATUS_STEP_CAP | STATUS_EVENT_CAP | STATUS_TAIL_CAP
#: Points an edge of the grid the barrier is sought on [-]
BARRIER_GRID = 2001
#: The barrier's share the energy must stay below it by, for the integration's error in the energy [-]
BARRIER_MARGIN = 1e-6
#: The box's corner kept this far inside |phi_2| < pi/2 [rad]
BOX_CLEARANCE_RAD = 0.01
#: The rocking kernel's status bits that leave the lower block's verdict open
UNDECIDED_ALONE = STATUS_GROUND_FLIGHT | STATUS_STEP_CAP | STATUS_STEP_UNDERFLOW


class TwoBlockVerdict(NamedTuple):
    """Each body's :class:`~pipeline.rocking.codes.Verdict` and what decided it.

    Attributes
    ----------
    lower, upper : Verdict
        the lower and the upper block's
    run : TwoBlockOutcome
        the two-block run
    lower_alone_status : int
        the rocking kernel's status bits for the lower block after the upper fell (0 when not run)
    """

    lower: Verdict
    upper: Verdict
    run: TwoBlockOutcome
    lower_alone_status: int


def judge_two_block(tb: TwoBlock, ah_ms2: np.ndarray, dt_s: float, *, av_ms2: np.ndarray | None = None,
                    settings: SimulationConfig = SimulationConfig(), stop_mu: tuple | None = None) -> TwoBlockVerdict:
    """Each body's verdict for the stack ``tb`` at rest under ``ah_ms2`` [m s-2] (samples ``dt_s`` [s] apart, the
    vertical ``av_ms2`` [m s-2] when given); ``settings``: the rocking kernel's tolerances for the lower block alone.
    ``stop_mu``: the friction at the ground joint and at the blocks' joint [-]; where a joint's demand passes it,
    the run ends there and both bodies are left without a verdict (the model does not hold).
    """
    run = simulate_two_block(tb, ah_ms2, dt_s, av_ms2=av_ms2, stop_mu=stop_mu)
    if run.status & STATUS_FRICTION:
        return TwoBlockVerdict(Verdict.no_verdict, Verdict.no_verdict, run, 0)
    if run.falls == FALLS_STACK:
        return TwoBlockVerdict(Verdict.overturns, Verdict.overturns, run, 0)
    if run.falls == FALLS_NONE:
        settled = run.status == STATUS_TAIL_CAP and energy_below_barrier(tb, run.final)
        verdict = Verdict.no_verdict if run.status & UNDECIDED_RUN and not settled else Verdict.stands
        return TwoBlockVerdict(verdict, verdict, run, 0)
    overturned, status = _lower_alone(tb, run, ah_ms2, av_ms2, dt_s, settings)
    lower = Verdict.overturns if overturned else (Verdict.no_verdict if status & UNDECIDED_ALONE else Verdict.stands)
    return TwoBlockVerdict(lower, Verdict.overturns, run, status)


def energy_below_barrier(tb: TwoBlock, y: Motion) -> bool:
    """Whether the free motion from ``y`` (no more ground motion) can never let a block fall.

    It cannot where ``y`` is inside the box of each joint's tipping angles at rest, corner by corner
    (:func:`.two_block.tipping_angles`; the box kept inside |phi_2| < pi/2), and its energy (kinetic and potential
    above rest) is below the least potential energy on the box's boundary: energy is never gained without ground
    motion (only impacts and stops change it, and they lose it) and the rotations move continuously, so the motion
    stays in the box, where nothing falls. The least potential energy on each edge is bounded below by its least value
    on a grid of :data:`BARRIER_GRID` points less L h / 2, L bounding its slope (:func:`_slope_bound`) and h the
    grid's spacing; the energy must stay :data:`BARRIER_MARGIN` of it below.
    """
    (a1p, a1m), (a2p, a2m) = tipping_angles(tb)
    a2p = min(a2p, 0.5 * math.pi - a1p - BOX_CLEARANCE_RAD)
    a2m = min(a2m, 0.5 * math.pi - a1m - BOX_CLEARANCE_RAD)
    inside = -a1m < y.phi1 < a1p and -a2m < y.phi2 - y.phi1 < a2p
    if min(a1p, a1m, a2p, a2m) <= 0.0 or not inside:
        return False
    edges = [(lambda u: (a1p, a1p + u), -a2m, a2p), (lambda u: (-a1m, -a1m + u), -a2m, a2p),
             (lambda u: (u, u + a2p), -a1m, a1p), (lambda u: (u, u - a2m), -a1m, a1p)]
    barrier = math.inf
    for point, lo, hi in edges:
        spacing = (hi - lo) / (BARRIER_GRID - 1)
        least = min(_potential(tb, *point(u)) for u in np.linspace(lo, hi, BARRIER_GRID))
        barrier = min(barrier, least - 0.5 * _slope_bound(tb) * spacing)
    return _energy(tb, y) < barrier * (1.0 - BARRIER_MARGIN)


def _slope_bound(tb: TwoBlock) -> float:
    """A bound on |dV/du| [J rad-1] along any edge of the box (u turning phi_2, or phi_1 and phi_2 together): g times
    each mass times the largest distance of its centre from the corners it turns about."""
    lever1 = math.hypot(tb.b1, tb.h1)
    joint = 2.0 * math.hypot(tb.b1, tb.h1)                  # any corner of the lower's top from a ground corner
    lever2 = max(math.hypot(tb.right - tb.offset, tb.h2), math.hypot(tb.offset - tb.left, tb.h2))
    return G * (tb.m1 * lever1 + tb.m2 * (joint + lever2))


def _joint_states(y: Motion) -> tuple[int, int]:
    """The joints' corners a state stands on (+1 at 0 rotation and rate)."""
    psi, rate = y.phi2 - y.phi1, y.w2 - y.w1
    j1 = 1 if (y.phi1 > 0 or (y.phi1 == 0 and y.w1 >= 0)) else -1
    j2 = 1 if (psi > 0 or (psi == 0 and rate >= 0)) else -1
    return j1, j2


def _energy(tb: TwoBlock, y: Motion) -> float:
    """Kinetic and potential energy above rest [J]."""
    j1, j2 = _joint_states(y)
    return float(kinetic_energy(tb, y, j1, j2) + potential_energy(tb, y, j1, j2))


def _potential(tb: TwoBlock, phi1: float, phi2: float) -> float:
    """The potential energy above rest at the rotations (phi_1, phi_2) [J]."""
    return _energy(tb, Motion(phi1, phi2, 0.0, 0.0))


def _lower_alone(tb: TwoBlock, run: TwoBlockOutcome, ah_ms2, av_ms2, dt_s: float,
                 settings: SimulationConfig) -> tuple[bool, int]:
    """The lower block as a single block from its state where the upper fell, to the record's end (the energy of
    its free motion deciding after it): (overturned, the kernel's status)."""
    alone = dynamics([BlockShape(height_m=2.0 * tb.h1, width_m=2.0 * tb.b1, mu=math.inf)])[0]
    block = rigid_block(alone.p, alone.alpha, alone.e, alone.R_m, math.inf, G, float(settings.rest_ratio), False,
                        math.inf)
    ah = np.ascontiguousarray(ah_ms2, dtype=np.float64)
    av = np.zeros(0) if av_ms2 is None else np.ascontiguousarray(av_ms2, dtype=np.float64)
    t_rec = (ah.shape[0] - 1) * dt_s
    start = RockingState(theta=float(run.final.phi1), omega=float(run.final.w1), t=min(float(run.t_fall_s), t_rec))
    o = kernel.rock(ah, av, float(dt_s), t_rec, block, step_control(settings), start, True,
                    RockingOutput(theta=kernel.empty_theta(), impacts=kernel.empty_impacts()), NO_QUIET)
    return bool(o.overturned), int(o.status)
