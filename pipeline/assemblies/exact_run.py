"""The exact model of a stack of n blocks from a state, as :mod:`.n_block_verdicts` runs it between slips and
flights: the two-block run (:mod:`.two_block_run`) for two blocks, the n-block run (:mod:`.n_block_run`) for more,
with the n-block run's outcome either way.

Both solve the same equations (Psycharis 1990's modes; the tests compare them run for run:
``tests/assemblies/test_n_block.py``); for two blocks the two-block run writes them out where the n-block run loops
over the blocks, and takes a fraction of its time (docs/validation.md, "Assemblies"). The two-block model is built
from the n-block stack as it stands, its upper block's offset included (a stack whose joint slid), and the states
are mapped between the n-block's joints (psi_0 = phi_1, psi_1 = phi_2 - phi_1, and their rates) and the two-block's
absolute rotations.

References
----------
Psycharis, I. N. (1990). Dynamic behaviour of rocking two-block assemblies. Earthquake Engineering & Structural
Dynamics 19(4), 555-575.
"""

from __future__ import annotations

import numpy as np

from .n_block import MAX_BODIES, NBlock
from .n_block_run import FALLS_NONE, NBlockOutcome, simulate_n_block
from .two_block import Motion, TwoBlock
from .two_block_run import FALLS_STACK, FALLS_TOP, OPENED_GROUND, OPENED_JOINT, simulate_two_block

#: The n-block's pad beyond two blocks
_PAD = (0.0,) * (MAX_BODIES - 2)


def as_two_block(nb: NBlock) -> TwoBlock:
    """The :class:`~.two_block.TwoBlock` of a two-block :class:`~.n_block.NBlock` (its joint's support moved from
    the upper block's frame to the lower's by the upper's offset)."""
    return TwoBlock(nb.b[0], nb.h[0], nb.m[0], nb.i[0], nb.b[1], nb.h[1], nb.m[1], nb.i[1], nb.off[1],
                    nb.lo[1] + nb.off[1], nb.hi[1] + nb.off[1])


def _motion(start: tuple) -> Motion:
    """The two-block state of an n-block state (each joint's psi, then its rate)."""
    psi0, psi1, rate0, rate1 = start[0], start[1], start[MAX_BODIES], start[MAX_BODIES + 1]
    return Motion(psi0, psi0 + psi1, rate0, rate0 + rate1)


def _state(y: Motion) -> tuple:
    """The n-block state of a two-block state."""
    return (y.phi1, y.phi2 - y.phi1) + _PAD + (y.w1, y.w2 - y.w1) + _PAD


def exact_run(nb: NBlock, ah_ms2: np.ndarray, dt_s: float, *, av_ms2: np.ndarray | None = None,
              start: tuple | None = None, t0_s: float = 0.0, stop_mu: tuple | None = None) -> NBlockOutcome:
    """:func:`.n_block_run.simulate_n_block`'s run and outcome, by the two-block run where ``nb`` has two blocks
    (the same arguments: the ground ``ah_ms2``, ``av_ms2`` [m s-2], ``dt_s`` [s] apart; the n-block state
    ``start`` at ``t0_s`` [s], None: rest; each block's friction ``stop_mu`` [-]). For two blocks ``steps`` is 0:
    the two-block run does not count its steps."""
    if nb.n != 2:
        return simulate_n_block(nb, ah_ms2, dt_s, av_ms2=av_ms2, start=start, t0_s=t0_s, stop_mu=stop_mu)
    run = simulate_two_block(as_two_block(nb), ah_ms2, dt_s, av_ms2=av_ms2,
                             start=None if start is None else _motion(start), t0_s=t0_s,
                             stop_mu=None if stop_mu is None else tuple(stop_mu[:2]))
    falls = {FALLS_STACK: 0, FALLS_TOP: 1}.get(run.falls, FALLS_NONE)
    modes = (1 if run.modes & OPENED_GROUND else 0) | (2 if run.modes & OPENED_JOINT else 0)
    return NBlockOutcome(falls, run.t_fall_s, (run.peak_phi1_rad, run.peak_psi_rad) + _PAD, run.impacts,
                         run.liftoffs, modes, run.status, _state(run.final),
                         (run.demand_ground, run.demand_joint) + _PAD, 0, run.t_end_s)
