"""The stacks' impact location (:func:`pipeline.assemblies.stepping.impact_root`) against closed-form roots, and the
two-block run ended where a joint first needs more friction than it has (``stop_mu``) against the whole run."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.assemblies import n_block as n_blocks
from pipeline.assemblies.n_block_verdicts import judge_n_block
from pipeline.assemblies.stack import StackBody
from pipeline.assemblies.stack_scene import judge
from pipeline.assemblies.stepping import EVENT_TIME_TOL_S, impact_root
from pipeline.assemblies.two_block import two_block
from pipeline.assemblies.two_block_run import simulate_two_block
from pipeline.assemblies.two_block_verdicts import judge_two_block
from pipeline.compiled import jit
from pipeline.rocking.codes import STATUS_FRICTION, STATUS_GROUND_FLIGHT
from pipeline.rocking.numerics.rk import DOPRI54, rk_step

DT = 0.005
TIMES = np.arange(0.0, 3.0, DT)
RHO = 2500.0


@jit
def _oscillator(t, y, omega):
    """x'' = -omega^2 x as (x, v)."""
    return (y[1], -omega * omega * y[0]), 0.0


@jit
def _root(x0, v0, omega, hh):
    """impact_root on x over one step of ``hh`` from (x0, v0)."""
    y = (x0, v0)
    f = _oscillator(0.0, y, omega)[0]
    st = rk_step(_oscillator, omega, 0.0, y, f, hh, DOPRI54)
    return impact_root(_oscillator, omega, 0.0, y, f, hh, st.y, st.f, (1.0, 0.0))


@jit
def _x_after(x0, v0, omega, h):
    """x after one DOPRI54 step of ``h`` from (x0, v0)."""
    y = (x0, v0)
    return rk_step(_oscillator, omega, 0.0, y, _oscillator(0.0, y, omega)[0], h, DOPRI54).y[0]


@pytest.mark.parametrize("into", [0.1, 0.4, 0.7, 0.95])
@pytest.mark.parametrize("hh", [1e-3, 4e-3])
def test_an_impact_is_located_at_the_root(into, hh):
    """x = cos(omega t + phase), the step of 0.2 rad of its turn, reaching 0 at ``into`` of the step: the bracket
    holds the root of the step's own x (bisected to 1e-15 s as the reference), is within the tolerance wide, lies
    on the closed form's root to the step's error, and is found in far fewer trials than bisection's
    log2(hh / tol)."""
    omega = 0.2 / hh
    phase = 0.5 * math.pi - 0.2 * into
    x0, v0 = math.cos(phase), -omega * math.sin(phase)
    converged, lo, _, hi, y_hi, tries = _root(x0, v0, omega, hh)
    a, b = 0.0, hh
    while b - a > 1e-15:
        mid = 0.5 * (a + b)
        a, b = (a, mid) if _x_after(x0, v0, omega, mid) <= 0.0 else (mid, b)
    assert converged and hi - lo <= EVENT_TIME_TOL_S
    assert lo <= b and a <= hi
    assert y_hi[0] <= 0.0
    assert 0.5 * (lo + hi) == pytest.approx(into * hh, rel=1e-7)
    assert tries < 0.5 * math.log2(hh / EVENT_TIME_TOL_S)


def _sine(ap, tp):
    return np.where(TIMES < tp, ap * np.sin(2 * np.pi * TIMES / tp), 0.0)


STATUE = (StackBody(0.6, 1.0, RHO * 0.6, 0.5), StackBody(0.3, 1.2, RHO * 0.36, 0.25))
DRUMS = (StackBody(0.5, 1.5, RHO * 0.75, 0.5), StackBody(0.5, 1.0, RHO * 0.5, 0.25))


@pytest.mark.parametrize("bodies", [STATUE, DRUMS], ids=["statue", "drums"])
@pytest.mark.parametrize("ap, tp", [(1.5, 0.5), (2.6, 0.5), (4.0, 0.4), (6.0, 0.6), (9.0, 1.0)])
def test_the_two_block_run_stops_where_its_demand_first_passes_mu(bodies, ap, tp):
    """Given the joints' friction, a run that stops (status friction) is one whose whole run's demand passes it,
    stopped with demands that pass it and no larger than the whole run's; one that does not stop is the whole run,
    to the bit."""
    tb, ah = two_block(*bodies), _sine(ap, tp)
    mu = tuple(b.mu for b in bodies)
    whole = simulate_two_block(tb, ah, DT)
    stopped = simulate_two_block(tb, ah, DT, stop_mu=mu)
    passes = whole.demand_ground > mu[0] or whole.demand_joint > mu[1]
    if stopped.status & STATUS_FRICTION:
        assert passes
        assert stopped.demand_ground > mu[0] or stopped.demand_joint > mu[1]
        assert stopped.demand_ground <= whole.demand_ground and stopped.demand_joint <= whole.demand_joint
        assert stopped.peak_psi_rad <= whole.peak_psi_rad and stopped.peak_phi1_rad <= whole.peak_phi1_rad
        assert stopped.t_end_s <= (whole.t_fall_s if whole.t_fall_s == whole.t_fall_s else whole.t_end_s)
    else:
        assert repr(stopped) == repr(whole)          # NaN where nothing fell: equal by their text


@pytest.mark.parametrize("bodies", [STATUE, DRUMS], ids=["statue", "drums"])
@pytest.mark.parametrize("ap, tp", [(1.5, 0.5), (2.6, 0.5), (4.0, 0.4), (6.0, 0.6), (9.0, 1.0)])
def test_a_stack_judged_as_the_whole_two_block_run_then_the_n_block_stack(bodies, ap, tp):
    """The stack's verdicts as ``screen`` judges them equal those of the whole two-block run where its demands stay
    within the joints' friction and no flight, and otherwise those of the n-block stack judged from rest."""
    ah, mu = _sine(ap, tp), tuple(b.mu for b in bodies)
    whole = judge_two_block(two_block(*bodies), ah, DT)
    run = whole.run
    holds = not (run.status & STATUS_GROUND_FLIGHT or run.demand_ground > mu[0] or run.demand_joint > mu[1])
    judged = judge(two_block(*bodies), ah, DT, bodies=bodies, slips_first=False)
    if holds:
        assert judged.verdicts == (int(whole.lower), int(whole.upper))
    else:
        assert judged == judge_n_block(n_blocks.n_block(bodies), ah, DT, mu=mu)
