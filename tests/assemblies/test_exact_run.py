"""The exact run of a stack between slips and flights (:func:`pipeline.assemblies.exact_run.exact_run`): for two
blocks the two-block run, against the n-block run of the same stack (the other implementation of the same
equations) from rest and from moving states, with and without the friction that stops it, and with the upper block
offset as a slip leaves it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.assemblies import n_block as nbm
from pipeline.assemblies.exact_run import as_two_block, exact_run
from pipeline.assemblies.n_block_run import FALLS_NONE, simulate_n_block
from pipeline.assemblies.stack import StackBody
from pipeline.assemblies.stack_pose import shifted
from pipeline.assemblies.two_block import two_block
from pipeline.rocking.codes import STATUS_FRICTION

DT = 0.005
TIMES = np.arange(0.0, 3.0, DT)
N = nbm.MAX_BODIES
RHO = 2500.0
PAIRS = {"statue": (StackBody(0.6, 1.0, RHO * 0.6, 0.5), StackBody(0.3, 1.2, RHO * 0.36, 0.25)),
         "drums": (StackBody(0.5, 1.5, RHO * 0.75, 0.5), StackBody(0.5, 1.0, RHO * 0.5, 0.25)),
         "offset": (StackBody(0.6, 1.2, 3.0, 0.6), StackBody(0.4, 0.9, 1.0, 0.6, 0.05))}


def _sine(ap, tp):
    return np.where(TIMES < tp, ap * np.sin(2 * np.pi * TIMES / tp), 0.0)


def _start(psi0, psi1, rate0, rate1):
    return (psi0, psi1) + (0.0,) * (N - 2) + (rate0, rate1) + (0.0,) * (N - 2)


def _same(a, b):
    """Two n-block outcomes of the same run: the same fall, events and status; peaks, demands, state and end to
    the runs' tolerances."""
    assert (a.falls, a.impacts, a.liftoffs, a.modes, a.status) == (b.falls, b.impacts, b.liftoffs, b.modes, b.status)
    assert a.peak_psi_rad == pytest.approx(b.peak_psi_rad, abs=1e-9)
    np.testing.assert_allclose(a.demand, b.demand, rtol=1e-6, atol=1e-9)
    assert a.t_end_s == pytest.approx(b.t_end_s, abs=1e-6)      # where it came to rest: events to the runs' errors
    assert math.isnan(a.t_fall_s) == math.isnan(b.t_fall_s)
    if a.falls == FALLS_NONE:
        np.testing.assert_allclose(a.final, b.final, atol=1e-7)


def test_the_two_block_model_of_an_n_block_stack_is_the_pair_s():
    """The pair's two-block model built from its n-block stack is the one built from its bodies (the joint's
    support in the lower's frame)."""
    for lower, upper in PAIRS.values():
        assert as_two_block(nbm.n_block((lower, upper))) == pytest.approx(two_block(lower, upper), abs=1e-15)


@pytest.mark.parametrize("pair", PAIRS)
@pytest.mark.parametrize("ap, tp", [(2.0, 0.5), (4.0, 0.4), (6.0, 0.6), (9.0, 1.0)])
@pytest.mark.parametrize("stop", [False, True])
def test_two_blocks_from_rest_run_as_the_n_block_run(pair, ap, tp, stop):
    """From rest, with or without the friction that stops the run where a joint would slip."""
    nb = nbm.n_block(PAIRS[pair])
    mu = tuple(b.mu for b in PAIRS[pair]) if stop else None
    a, b = exact_run(nb, _sine(ap, tp), DT, stop_mu=mu), simulate_n_block(nb, _sine(ap, tp), DT, stop_mu=mu)
    _same(a, b)


@pytest.mark.parametrize("pair", PAIRS)
@pytest.mark.parametrize("start", [_start(0.01, 0.0, 0.05, 0.0), _start(-0.004, 0.0, 0.0, 0.0),
                                   _start(0.0, 0.02, 0.0, -0.1), _start(0.005, -0.01, 0.02, 0.03),
                                   _start(0.0, 0.0, 0.0, 0.0)])
@pytest.mark.parametrize("stop", [False, True])
def test_two_blocks_from_a_moving_state_run_as_the_n_block_run(pair, start, stop):
    """From states a hand-back leaves (the ground joint open or shut, the blocks' joint open or shut, both open),
    from 0.4 s into a pulse."""
    nb = nbm.n_block(PAIRS[pair])
    mu = tuple(b.mu for b in PAIRS[pair]) if stop else None
    ah = _sine(3.0, 0.8)
    a = exact_run(nb, ah, DT, start=start, t0_s=0.4, stop_mu=mu)
    b = simulate_n_block(nb, ah, DT, start=start, t0_s=0.4, stop_mu=mu)
    _same(a, b)


def test_a_stack_whose_joint_slid_runs_as_the_n_block_run():
    """The upper block moved along the joint (as :func:`.stack_pose.shifted` leaves a slip): the support and the
    offset follow, and the runs agree."""
    nb = nbm.n_block(PAIRS["statue"])
    moved = shifted(nb, (0.0, 0.04), 2)
    assert moved is not None and moved.off[1] == pytest.approx(0.04)
    for ap in (3.0, 5.0, 8.0):
        _same(exact_run(moved, _sine(ap, 0.5), DT), simulate_n_block(moved, _sine(ap, 0.5), DT))


def test_the_friction_stops_both_at_the_same_instant():
    """A slip at rest: both runs stop at the instant the ground's demand passes the smaller friction."""
    nb = nbm.n_block(PAIRS["statue"])
    mu = (0.5, 0.25)
    ah = _sine(0.3 * 9.80665, 1.0)
    a, b = exact_run(nb, ah, DT, stop_mu=mu), simulate_n_block(nb, ah, DT, stop_mu=mu)
    assert a.status & STATUS_FRICTION and b.status & STATUS_FRICTION
    assert a.t_end_s == b.t_end_s
