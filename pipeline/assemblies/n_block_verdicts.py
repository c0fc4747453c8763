"""Each body's verdict for a stack of n blocks under a record: a body falls with the lowest block that falls under it,
or stands; the blocks below a fall go on rocking, as a stack of their own, to the record's end.

The run (:func:`.exact_run.exact_run`: the two-block run for two blocks, the n-block run for more) ends at the first
fall: the lowest falling block and every block above it overturn. Where blocks are left below it, they are followed from
their state at that instant as the stack of those blocks (the fallen ones assumed gone, no longer loading them), and so
on until nothing more falls. Where a joint would slip while the stack is at rest, the level stack's slip
(:mod:`.flat_slip`: the blocks sliding on their joints without rotating, each slip's stop and start located in closed
form) follows it to where every joint sticks again, and the exact model goes on from there with the blocks where they
slid to. Where two blocks rock as one on a corner of the lower and their joint would slip (the blocks' friction given),
the slide-rock model (:mod:`.slide_rock`: the joint sticking or sliding, the stack's landings by its impact law) follows
them until its joint opens, the ground no longer holds the pivot, or a landing leaves its law; sticking, the exact model
goes on from there, else the contact model. Where neither model holds (a joint would open), where the ground falls
faster than gravity, or where a joint of a taller stack would slip while it rocks, the stack is followed from that
instant by the contact model (:mod:`.stack_contact`: flight, landing, sliding and rocking at every joint), until every
joint is shut or turns on a sticking corner again, when the exact model goes on from that state with the blocks where
they slid to (a stack turning as one with one joint slipping and the others shut: the slide-rock model, on the stack's
two parts below and above that joint, :mod:`.slide_rock_parts`), or to the end of the record's free motion; a body that
falls in either falls. A run that ended without a verdict (a cap on steps, events or the free motion after the record,
or a flight without the friction to follow it) leaves the bodies still standing then without one: unknown, never
standing."""

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
from .n_block_run import FALLS_NONE, NBlockOutcome
from .slide_rock import END_CAP, END_EXACT, END_FALLS, rock_start, simulate_slide_rock
from .slide_rock import handback as rock_state
from .stack_contact import simulate_stack_contact
from .stack_pose import shifted, slide_rock_pose, stack_of
from .stepping import ground_series

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


def rocks_as_one(part: NBlock, run: NBlockOutcome) -> bool:
    """Whether the exact model's ``run`` of a two-block stack stopped where its blocks' joint would slip while the
    stack rocks as one on a corner of the lower block (its joint shut, the ground's open), the ground not falling
    faster than gravity: the slide-rock model's start (:mod:`.slide_rock`)."""
    y = run.final
    return (part.n == 2 and bool(run.status & STATUS_FRICTION) and not run.status & STATUS_GROUND_FLIGHT
            and y[0] != 0.0 and y[1] == 0.0 and y[MAX_BODIES + 1] == 0.0)


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


class _Record:
    """What the runs of one stack have seen so far, bottom first (a mutable tally, gathered by :meth:`verdicts`)."""

    def __init__(self, n: int) -> None:
        self.verdicts = [int(Verdict.no_verdict)] * n
        self.t_fall, self.peaks, self.demand = [math.nan] * n, [0.0] * n, [0.0] * n
        self.impacts, self.opened, self.status, self.handovers = 0, False, 0, 0
        self.slides: list[float] = []
        self.offsets, self.base = [0.0] * n, 0.0

    def exact(self, run: NBlockOutcome, count: int) -> None:
        """The exact model's run of the lowest ``count`` blocks."""
        for k in range(count):
            self.peaks[k] = max(self.peaks[k], run.peak_psi_rad[k])
            self.demand[k] = max(self.demand[k], run.demand[k])
        self.impacts, self.opened = self.impacts + run.impacts, self.opened or run.modes != 0
        self.status |= run.status

    def slid(self, outcome, count: int) -> None:
        """A run that followed a slip (:mod:`.flat_slip`'s, :mod:`.slide_rock`'s or :mod:`.stack_contact`'s): the
        bottom body's shift along the ground, the joints' largest slips and the offsets of the lowest ``count``."""
        self.offsets[1:count] = outcome.offsets_m[1:count]
        self.slides = self.slides or [0.0] * len(self.offsets)
        for k in range(count):
            self.slides[k] = max(self.slides[k], outcome.peak_slide_m[k])
        self.base += outcome.base_shift_m

    def followed(self, flight, count: int) -> None:
        """The contact model's run of the lowest ``count`` blocks: its slips, peaks and falls."""
        self.opened, self.status = True, self.status | flight.status
        self.slid(flight, count)
        for k in range(count):
            self.peaks[k] = max(self.peaks[k], flight.peak_rad[k])
            if not math.isnan(flight.t_fall_s[k]):
                self.verdicts[k], self.t_fall[k] = int(Verdict.overturns), flight.t_fall_s[k]

    def rocked(self, rock, count: int) -> None:
        """The slide-rock model's run of the lowest ``count`` blocks (:class:`.slide_rock.SlideRockOutcome`)."""
        self.opened, self.status, self.impacts = True, self.status | rock.status, self.impacts + rock.impacts
        self.slid(rock, count)
        self.peaks[0], self.demand[0] = max(self.peaks[0], rock.peak_rad[0]), max(self.demand[0], rock.demand_ground)
        if rock.end == END_FALLS:
            self.verdicts[:count], self.t_fall[:count] = [int(Verdict.overturns)] * count, [rock.t_fall_s] * count

    def result(self) -> StackVerdicts:
        """The stack's :class:`StackVerdicts`."""
        self.offsets[0] = self.base
        residual = tuple(x if v == Verdict.stands else math.nan for x, v in zip(self.offsets, self.verdicts))
        return StackVerdicts(tuple(self.verdicts), tuple(self.peaks), tuple(self.t_fall), self.impacts, self.opened,
                             self.status, tuple(self.demand), tuple(self.slides), residual)


class _Ground(NamedTuple):
    """A record's ground, checked: as given to the exact and contact models [m s-2] (``av_ms2`` None where not
    given), as contiguous arrays for the slide-rock model (``av`` empty where not given; plain arrays, which its
    compiled run takes), its interval [s], and the hand-overs its stack may make (:data:`MAX_HANDOVERS` plus one a
    sample)."""

    ah_ms2: np.ndarray
    av_ms2: np.ndarray | None
    ah: np.ndarray
    av: np.ndarray
    dt_s: float
    max_handovers: int


def _follow_slip(nb: NBlock, part: NBlock, mu: tuple, ground: _Ground, run: NBlockOutcome, rec: _Record,
                 rocking_model: bool):
    """Where the exact model's ``run`` of ``part`` (the lowest blocks of ``nb``) stopped at a joint's slip or the
    ground's flight: the slip followed (the module's rules: the level slip's model, the slide-rock model and the
    contact model in turn) into ``rec``, to where the exact model goes on, returned as (the stack where its blocks
    slid to, its n-block state (None: rest), the instant); None where the stack's runs ended (a fall of the whole
    stack, rest after the record, a cap, the hand-overs' cap). ``rocking_model``: whether the slide-rock model
    follows the stack rocking as one with one joint slipping (else the contact model does)."""
    ah_ms2, av_ms2, dt_s = ground.ah_ms2, ground.av_ms2, ground.dt_s
    slid = (rec.base,) + tuple(part.off[k] - nb.off[k] for k in range(1, part.n))
    level = _level_slip(part, mu, ah_ms2, dt_s, av_ms2, run, slid)
    if level is not None:
        back, level_run = level
        rec.slid(level_run, part.n)
        return back, None, level_run.t_end_s
    rocking = rock_start(part, run.final) if rocking_model and rocks_as_one(part, run) else None
    pose, t_from = None, run.t_end_s
    while True:
        if rocking is not None:
            joint = rocking.joint
            rock = simulate_slide_rock(part, mu, ground.ah, ground.av, dt_s, start=rocking, t0_s=t_from,
                                       origin_m=nb.off[joint], joint=joint)
            rec.rocked(rock, part.n)
            if rock.end == END_FALLS or rock.end == END_CAP:
                return None
            back = shifted(part, rock.offsets_m, part.n) if rock.end == END_EXACT and rock.t_end_s > t_from else None
            if back is not None:
                return back, rock_state(rock), rock.t_end_s
            pose, t_from = slide_rock_pose(part, rock.state, rock.pivot, joint), rock.t_end_s
            slid = (rec.base,) + tuple(rock.offsets_m[k] - nb.off[k] for k in range(1, part.n))
        flight = simulate_stack_contact(part, mu, ah_ms2, dt_s, av_ms2=av_ms2, start=run.final, pose=pose,
                                        t0_s=t_from, slid_m=slid, rock_slide=rocking_model)
        if flight.rocking:                          # the stack rocking as one, one joint slipping
            rec.followed(flight, part.n)
            rec.handovers += 1
            if rec.handovers >= ground.max_handovers:
                return None
            rocking, t_from = flight.rocking, flight.t_end_s
            if part.n > 2:                          # the other joints where the contact model left them (two
                part = stack_of(part, flight.offsets_m, part.n)     # blocks: the slide-rock state's u is the one)
            continue
        back = shifted(part, flight.offsets_m, flight.standing) if flight.rested else None
        if flight.rested and back is None:          # handed back where the exact model's stack could not stand
            flight = simulate_stack_contact(part, mu, ah_ms2, dt_s, av_ms2=av_ms2, start=run.final, pose=pose,
                                            t0_s=t_from, hand_back=False, slid_m=slid)
        rec.followed(flight, part.n)
        if back is not None:
            return back, flight.handback, flight.t_end_s
        if flight.rested:                           # at rest after the record
            rec.verdicts[:flight.standing] = [int(Verdict.stands)] * flight.standing
        return None


def judge_n_block(nb: NBlock, ah_ms2: np.ndarray, dt_s: float, *, av_ms2: np.ndarray | None = None,
                  mu: tuple | None = None, slide_rock: bool = True) -> StackVerdicts:
    """Each body's verdict for the stack ``nb`` at rest under ``ah_ms2`` [m s-2] (samples ``dt_s`` [s] apart, the
    vertical ``av_ms2`` [m s-2] when given), by the module's rules; ``mu``: each block's friction at its base [-],
    with which the ground's flight and a joint's slip are followed (None: the joints hold, their demands kept, and a
    flight leaves the run without a verdict). ``slide_rock``: a stack rocking as one while one joint slips is
    followed by the slide-rock model (:mod:`.slide_rock`; False: by the contact model alone, as the tests' reference
    does)."""
    ah_ms2 = finite_series("horizontal acceleration", ah_ms2)        # checked once for the runs below
    av_ms2 = None if av_ms2 is None else finite_series("vertical acceleration", av_ms2)
    ground = _Ground(ah_ms2, av_ms2, *ground_series(ah_ms2, av_ms2, dt_s), dt_s, MAX_HANDOVERS + ah_ms2.shape[0])
    rec = _Record(nb.n)
    part, start, t0 = nb, None, 0.0
    while True:
        run = exact_run(part, ah_ms2, dt_s, av_ms2=av_ms2, start=start, t0_s=t0,
                        stop_mu=None if mu is None else tuple(mu[:part.n]))
        rec.exact(run, part.n)
        if (run.falls == FALLS_NONE and run.status & FOLLOWED and not run.status & CAPS and mu is not None
                and rec.handovers < ground.max_handovers):
            rec.handovers += 1
            after = _follow_slip(nb, part, mu, ground, run, rec, slide_rock)
            if after is None:
                break
            part, start, t0 = after
            continue
        if run.falls == FALLS_NONE:
            verdict = Verdict.no_verdict if run.status & (UNDECIDED_RUN | STATUS_FRICTION) else Verdict.stands
            rec.verdicts[:part.n] = [int(verdict)] * part.n
            break
        for k in range(run.falls, part.n):
            rec.verdicts[k], rec.t_fall[k] = int(Verdict.overturns), run.t_fall_s
        if run.falls == 0:
            break
        count = run.falls
        state = run.final
        start = tuple(state[:count]) + (0.0,) * (MAX_BODIES - count) + tuple(
            state[MAX_BODIES:MAX_BODIES + count]) + (0.0,) * (MAX_BODIES - count)
        part, t0 = lower_part(part, count), run.t_fall_s
    return rec.result()
