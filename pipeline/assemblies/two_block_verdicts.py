"""Each body's verdict for two stacked blocks under a record: the upper block falls with the stack, falls alone, or
stands; the lower block, once the upper has fallen off it, rocks alone on to the record's end.

The two-block run (:func:`.two_block_run.simulate_two_block`) ends at the first fall. Where the upper block falls
alone, the lower block is followed from its state at that instant by the rocking kernel as a single block of its
own (Housner's equation and impact; the fallen block assumed gone, no longer loading it), and judged by it. A run
that ended without a verdict (the ground falling faster than gravity, a cap) gives both bodies none: unknown, never
standing.

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
from ..rocking.block import rigid_block
from ..rocking.codes import (
    STATUS_EVENT_CAP,
    STATUS_GROUND_FLIGHT,
    STATUS_STEP_CAP,
    STATUS_STEP_UNDERFLOW,
    STATUS_TAIL_CAP,
    Verdict,
)
from ..rocking.planar import kernel
from ..rocking.settings import SimulationConfig
from ..rocking.simulate import step_control
from ..rocking.structures import RockingOutput, RockingState
from .two_block import TwoBlock
from .two_block_run import FALLS_NONE, FALLS_STACK, TwoBlockOutcome, simulate_two_block

#: The two-block run's status bits that leave its verdict open
UNDECIDED_RUN = STATUS_GROUND_FLIGHT | STATUS_STEP_CAP | STATUS_EVENT_CAP | STATUS_TAIL_CAP
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
                    settings: SimulationConfig = SimulationConfig()) -> TwoBlockVerdict:
    """Each body's verdict for the stack ``tb`` at rest under ``ah_ms2`` [m s-2] (samples ``dt_s`` [s] apart, the
    vertical ``av_ms2`` [m s-2] when given); ``settings``: the rocking kernel's tolerances for the lower block alone.
    """
    run = simulate_two_block(tb, ah_ms2, dt_s, av_ms2=av_ms2)
    if run.falls == FALLS_STACK:
        return TwoBlockVerdict(Verdict.overturns, Verdict.overturns, run, 0)
    if run.falls == FALLS_NONE:
        verdict = Verdict.no_verdict if run.status & UNDECIDED_RUN else Verdict.stands
        return TwoBlockVerdict(verdict, verdict, run, 0)
    overturned, status = _lower_alone(tb, run, ah_ms2, av_ms2, dt_s, settings)
    lower = Verdict.overturns if overturned else (Verdict.no_verdict if status & UNDECIDED_ALONE else Verdict.stands)
    return TwoBlockVerdict(lower, Verdict.overturns, run, status)


def _lower_alone(tb: TwoBlock, run: TwoBlockOutcome, ah_ms2, av_ms2, dt_s: float,
                 settings: SimulationConfig) -> tuple[bool, int]:
    """The lower block as a single block from its state where the upper fell, to the record's end (the energy of
    its free motion deciding after it): (overturned, the kernel's status)."""
    radius, alpha = math.hypot(tb.b1, tb.h1), math.atan2(tb.b1, tb.h1)
    block = rigid_block(math.sqrt(0.75 * G / radius), alpha, 1.0 - 1.5 * math.sin(alpha) ** 2, radius, math.inf, G,
                        float(settings.rest_ratio), False, math.inf)
    ah = np.ascontiguousarray(ah_ms2, dtype=np.float64)
    av = np.zeros(0) if av_ms2 is None else np.ascontiguousarray(av_ms2, dtype=np.float64)
    t_rec = (ah.shape[0] - 1) * dt_s
    start = RockingState(theta=float(run.final.phi1), omega=float(run.final.w1), t=min(float(run.t_fall_s), t_rec))
    o = kernel.rock(ah, av, float(dt_s), t_rec, block, step_control(settings), start, True,
                    RockingOutput(theta=kernel.empty_theta(), impacts=kernel.empty_impacts()))
    return bool(o.overturned), int(o.status)
