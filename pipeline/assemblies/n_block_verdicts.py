"""Each body's verdict for a stack of n blocks under a record: a body falls with the lowest block that falls under it,
or stands; the blocks below a fall go on rocking, as a stack of their own, to the record's end.

The run (:func:`.exact_run.exact_run`: the two-block run for two blocks, the n-block run for more) ends at the
first fall: the lowest falling block and every block
above it overturn. Where blocks are left below it, they are followed from their state at that instant as the stack of
those blocks (the fallen ones assumed gone, no longer loading them), and so on until nothing more falls. Where a
joint would slip while the stack is at rest, the level stack's slip (:mod:`.flat_slip`: the blocks sliding on their
joints without rotating, each slip's stop and start located in closed form) follows it to where every joint sticks
again, and the exact model goes on from there with the blocks where they slid to; where that model does not hold (a
joint would open), where the ground falls faster than gravity, or where a joint would slip while the stack rocks (the
blocks' friction given), the stack is followed from that instant by the contact model (:mod:`.stack_contact`: flight,
landing, sliding and rocking at every joint), until every joint is shut or turns on a sticking corner again, when the
exact model goes on from that state with the blocks where they slid to, or to the end of the record's free motion; a
body that falls in it falls. A run that ended without a verdict (a cap on steps, events or the free motion after the
record, or a flight without the friction to follow it) leaves the bodies still standing then without one: unknown,
never standing."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..rocking.codes import (
    STATUS_EVENT_CAP,
    STATUS_FRICTION,
    STATUS_GROUND_FLIGHT,
    STATUS_STEP_CAP,
    STATUS_TAIL_CAP,
    Verdict,
)
from ..rocking.simulate import finite_series
from .exact_run import exact_run
from .flat_slip import STUCK, simulate_flat_slip
from .n_block import MAX_BODIES, NBlock
from .n_block_run import FALLS_NONE
from .stack_contact import simulate_stack_contact
from .stack_pose import shifted

#: The run's status bits that leave its verdict open
UNDECIDED_RUN = STATUS_GROUND_FLIGHT | STATUS_STEP_CAP | STATUS_EVENT_CAP | STATUS_TAIL_CAP
#: Hand-overs to the slip's and flight's models and back per stack and record, beyond one a sample of the record (a
#: slip from rest starts where the ground's |a_h| / (g + a_v) rises through a mu, at most once on a linear piece);
#: beyond them the verdict is left open
MAX_HANDOVERS = 1000
#: What the contact model follows (the ground's flight, a joint's slip); the caps that end a run without it
FOLLOWED = STATUS_GROUND_FLIGHT | STATUS_FRICTION
CAPS = STATUS_STEP_CAP | STATUS_EVENT_CAP | STATUS_TAIL_CAP


class StackVerdicts(NamedTuple):
    """Each body's verdict and what the stack's runs saw (bottom first; the same fields for any stack model).

    Attributes
    ----------
    verdicts : tuple of int
        each body's :class:`~pipeline.rocking.codes.Verdict`
    peak_psi_rad : tuple of float
        each joint's largest |rotation| of its body on what it stands on [rad], over every run
    t_fall_s : tuple of float
        when each body fell [s] (NaN: it did not, or the model does not say when)
    impacts : int
        impacts at any joint, over every run
    opened : bool
        a joint opened
    status : int
        the runs' :class:`~pipeline.rocking.codes.Status` bits
    demand : tuple of float
        each joint's largest friction demand |F_t| / F_n [-] (:attr:`.n_block_run.NBlockOutcome.demand`)
    slide_m : tuple of float
        each joint's largest slip from where it stood at the record's start [m] (the bottom body's along the
        ground), over the runs that follow slips (:mod:`.flat_slip`'s and the contact model's); empty where none
        ran
    offset_m : tuple of float
        each standing body's residual offset on what it stands on where the runs ended [m]: the bottom body's base
        moved along the ground, each other body's base centre from the centre of the top of the body under it
        (0 where its joint never slipped; NaN for a body that fell or without a verdict); empty where the
        model does not say
    """

    verdicts: tuple
    peak_psi_rad: tuple
    t_fall_s: tuple
    impacts: int
    opened: bool
    status: int
    demand: tuple
    slide_m: tuple = ()
    offset_m: tuple = ()


def lower_part(nb: NBlock, count: int) -> NBlock:
    """The stack of ``nb``'s lowest ``count`` blocks."""
    def cut(values: tuple) -> tuple:
        return tuple(values[:count]) + (0.0,) * (MAX_BODIES - count)

    return NBlock(count, cut(nb.b), cut(nb.h), cut(nb.m), cut(nb.i), cut(nb.lo), cut(nb.hi), cut(nb.off))


def _level_slip(part: NBlock, mu: tuple, ah_ms2: np.ndarray, dt_s: float, av_ms2: np.ndarray | None, run,
                slid: tuple):
    """Where the exact model's ``run`` stopped at rest because a joint slips: the level stack's slip followed by
    :mod:`.flat_slip` to where every joint sticks again, as (the stack where its blocks slid to, the slip's
    outcome); None where the run was in motion, or the slip leaves that model (the contact model follows it).
    ``slid``: each joint's slip so far [m], from which its largest slip is measured."""
    if run.status & STATUS_GROUND_FLIGHT or any(run.final):
        return None
    level = simulate_flat_slip(part, mu, ah_ms2, dt_s, av_ms2=av_ms2, t0_s=run.t_end_s, slid_m=slid)
    if level.end != STUCK:
        return None
    back = shifted(part, level.offsets_m, part.n)
    return None if back is None else (back, level)


def _slid(outcome, count: int, base: float, offsets: list, slides: list, n: int) -> tuple[float, list]:
    """A run that followed a slip (:class:`.flat_slip.FlatSlipOutcome` or :class:`.stack_contact.
    StackContactOutcome`) taken into the stack's record: the bottom body's total shift along the ground and the
    joints' largest slips are returned, the offsets of the lowest ``count`` joints set in ``offsets`` in place."""
    offsets[1:count] = outcome.offsets_m[1:count]
    slides = slides or [0.0] * n
    for k in range(count):
        slides[k] = max(slides[k], outcome.peak_slide_m[k])
    return base + outcome.base_shift_m, slides


def judge_n_block(nb: NBlock, ah_ms2: np.ndarray, dt_s: float, *, av_ms2: np.ndarray | None = None,
                  mu: tuple | None = None) -> StackVerdicts:
    """Each body's verdict for the stack ``nb`` at rest under ``ah_ms2`` [m s-2] (samples ``dt_s`` [s] apart, the
    vertical ``av_ms2`` [m s-2] when given), by the module's rules; ``mu``: each block's friction at its base [-],
    with which the ground's flight and a joint's slip are followed (None: the joints hold, their demands kept, and a
    flight leaves the run without a verdict)."""
    n = nb.n
    ah_ms2 = finite_series("horizontal acceleration", ah_ms2)        # checked once for the runs below
    av_ms2 = None if av_ms2 is None else finite_series("vertical acceleration", av_ms2)
    verdicts = [int(Verdict.no_verdict)] * n
    t_fall, peaks, demand = [math.nan] * n, [0.0] * n, [0.0] * n
    impacts, opened, status, handovers = 0, False, 0, 0
    slides: list[float] = []
    offsets, base = [0.0] * n, 0.0
    part, start, t0 = nb, None, 0.0
    while True:
        run = exact_run(part, ah_ms2, dt_s, av_ms2=av_ms2, start=start, t0_s=t0,
                        stop_mu=None if mu is None else tuple(mu[:part.n]))
        for k in range(part.n):
            peaks[k] = max(peaks[k], run.peak_psi_rad[k])
            demand[k] = max(demand[k], run.demand[k])
        impacts, opened, status = impacts + run.impacts, opened or run.modes != 0, status | run.status
        if (run.falls == FALLS_NONE and run.status & FOLLOWED and not run.status & CAPS and mu is not None
                and handovers < MAX_HANDOVERS + ah_ms2.shape[0]):
            handovers += 1
            slid = (base,) + tuple(part.off[k] - nb.off[k] for k in range(1, part.n))
            level = _level_slip(part, mu, ah_ms2, dt_s, av_ms2, run, slid)
            if level is not None:
                back, level_run = level
                base, slides = _slid(level_run, part.n, base, offsets, slides, n)
                part, start, t0 = back, None, level_run.t_end_s
                continue
            flight = simulate_stack_contact(part, mu, ah_ms2, dt_s, av_ms2=av_ms2, start=run.final,
                                            t0_s=run.t_end_s, slid_m=slid)
            back = shifted(part, flight.offsets_m, flight.standing) if flight.rested else None
            if flight.rested and back is None:      # handed back where the exact model's stack could not stand
                flight = simulate_stack_contact(part, mu, ah_ms2, dt_s, av_ms2=av_ms2, start=run.final,
                                                t0_s=run.t_end_s, hand_back=False, slid_m=slid)
            opened, status = True, status | flight.status
            base, slides = _slid(flight, part.n, base, offsets, slides, n)
            for k in range(part.n):
                peaks[k] = max(peaks[k], flight.peak_rad[k])
                if not math.isnan(flight.t_fall_s[k]):
                    verdicts[k], t_fall[k] = int(Verdict.overturns), flight.t_fall_s[k]
            if back is not None:
                part, start, t0 = back, flight.handback, flight.t_end_s
                continue
            if flight.rested:                       # at rest after the record
                verdicts[:flight.standing] = [int(Verdict.stands)] * flight.standing
            break
        if run.falls == FALLS_NONE:
            verdict = Verdict.no_verdict if run.status & (UNDECIDED_RUN | STATUS_FRICTION) else Verdict.stands
            verdicts[:part.n] = [int(verdict)] * part.n
            break
        for k in range(run.falls, part.n):
            verdicts[k], t_fall[k] = int(Verdict.overturns), run.t_fall_s
        if run.falls == 0:
            break
        count = run.falls
        state = run.final
        start = tuple(state[:count]) + (0.0,) * (MAX_BODIES - count) + tuple(
            state[MAX_BODIES:MAX_BODIES + count]) + (0.0,) * (MAX_BODIES - count)
        part, t0 = lower_part(part, count), run.t_fall_s
    offsets[0] = base
    residual = tuple(x if v == Verdict.stands else math.nan for x, v in zip(offsets, verdicts))
    return StackVerdicts(tuple(verdicts), tuple(peaks), tuple(t_fall), impacts, opened, status, tuple(demand),
                         tuple(slides), residual)
