"""Two stacked blocks rocking (pipeline.assemblies.two_block*): against the single block of their outline (Housner's
equation and impact, solved by the rocking kernel), against Lagrange's equations of their energy solved by scipy's
DOP853 with events (tests/support/two_block_reference.py), and the invariants (mirror symmetry, energy never
gained at an impact, the exact lift-off bound)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import two_block_reference as ref

from pipeline.assemblies.stack import StackBody
from pipeline.assemblies.two_block import Motion, projected_rates, tipping_angles, two_block
from pipeline.assemblies.two_block_run import (
    FALLS_NONE,
    FALLS_STACK,
    FALLS_TOP,
    OPENED_BOTH,
    OPENED_GROUND,
    OPENED_JOINT,
    REST_RATIO,
    scales,
    simulate_two_block,
)
from pipeline.assemblies.two_block_verdicts import energy_below_barrier, judge_two_block
from pipeline.errors import BlockParameterError, ParameterError
from pipeline.rocking.codes import STATUS_GROUND_FLIGHT, STATUS_TAIL_CAP, Verdict
from pipeline.rocking.settings import SimulationConfig
from pipeline.rocking.simulate import rock

G = 9.80665
DT = 0.005
TIMES = np.arange(0.0, 3.0, DT)
RHO = 2500.0


def _sine(ap, tp, phase=0.0):
    """One cycle of a sine (phase 0) or cosine (phase pi/2) pulse [m s-2] of period ``tp`` [s]."""
    return np.where(TIMES < tp, ap * np.sin(2 * np.pi * TIMES / tp + phase), 0.0)


def _bodies(lower, upper, offset=0.0):
    """(width, height) pairs to StackBody's of one density."""
    return (StackBody(lower[0], lower[1], RHO * lower[0] * lower[1], 0.8),
            StackBody(upper[0], upper[1], RHO * upper[0] * upper[1], 0.8, offset))


# A statue on its plinth (the statue rocks first), a column of two drums (the pair rocks as one first), a squat
# capital on a slender shaft
STATUE, DRUMS, CAPITAL = ((0.6, 1.0), (0.3, 1.2)), ((0.5, 1.5), (0.5, 1.0)), ((0.4, 1.4), (0.36, 0.5))


@pytest.mark.parametrize("ap, tp, phase", [(5.0, 0.3, 0.0), (6.0, 0.3, 0.0), (6.0, 0.6, 0.0), (6.0, 1.0, 0.0),
                                           (8.0, 0.3, 0.0), (5.0, 0.6, math.pi / 2), (9.0, 0.4, math.pi / 2)])
def test_a_thin_slab_on_a_block_rocks_as_the_block_of_their_outline(ap, tp, phase):
    """A slab 0.05 m thick on a 0.5 x 1.0 m block of the same width and density: the joint stays shut (tan alpha of
    the slab 10) and the pair is the 0.5 x 1.05 m block, the same mass about the same corner, its impact Housner's
    (e = 1 - 1.5 sin^2 alpha). The rocking kernel on that block: the same verdict, peaks within 1e-4 alpha."""
    lower, upper = _bodies((0.5, 1.0), (0.5, 0.05))
    tb = two_block(lower, upper)
    b, h = 0.25, 0.525
    alpha, radius = math.atan(b / h), math.hypot(b, h)
    a = _sine(ap, tp, phase)
    out = simulate_two_block(tb, a, DT)
    single = rock(a, DT, p=math.sqrt(0.75 * G / radius), alpha=alpha, e=1 - 1.5 * math.sin(alpha) ** 2, R_m=radius,
                  settings=SimulationConfig(rtol=1e-10, atol=1e-12), tail="integrate", t_end_s=TIMES[-1] + 60)
    assert (out.falls == FALLS_STACK) == single.overturned
    if not single.overturned:
        assert out.peak_phi1_rad / alpha == pytest.approx(single.theta_max, abs=1e-4)
        assert out.peak_psi_rad == 0.0 and out.modes == OPENED_GROUND


@pytest.mark.parametrize("lower, upper", [STATUE, DRUMS, ((0.3, 1.2), (0.2, 0.6))])
def test_an_impact_keeps_housners_share_of_the_rate(lower, upper):
    """Housner (1963): a block's rate after an impact is (1 - 1.5 sin^2 alpha) of the rate before (its angular
    momentum about the new corner kept). The upper block on the shut lower (alpha = atan(b2 / h2)); the pair of one
    width and density rocking as one (alpha of their outline)."""
    tb = two_block(*_bodies(lower, upper))
    alpha2 = math.atan(upper[0] / upper[1])
    w = projected_rates(tb, Motion(0.0, 0.0, 0.0, -1.3), (0, 1), (0, -1))
    assert w == pytest.approx((0.0, -1.3 * (1 - 1.5 * math.sin(alpha2) ** 2)), rel=1e-13, abs=1e-15)
    same = two_block(*_bodies((lower[0], lower[1]), (lower[0], upper[1])))
    alpha = math.atan(lower[0] / (lower[1] + upper[1]))
    w = projected_rates(same, Motion(0.0, 0.0, -0.7, -0.7), (1, 0), (-1, 0))
    assert w == pytest.approx((-0.7 * (1 - 1.5 * math.sin(alpha) ** 2),) * 2, rel=1e-13)


def _reference(lower, upper, a, offset=0.0, av=None):
    tb = two_block(*_bodies(lower, upper, offset))
    (b1, h1), (b2, h2) = (lower[0] / 2, lower[1] / 2), (upper[0] / 2, upper[1] / 2)
    pair = ref.Pair(b1, h1, RHO * lower[0] * lower[1], b2, h2, RHO * upper[0] * upper[1], offset)
    sc = scales(tb)
    return simulate_two_block(tb, a, DT, av_ms2=av), ref.simulate(pair, a, DT, rest1=REST_RATIO * sc.p1 * sc.alpha1,
                                                                  rest2=REST_RATIO * sc.p2 * sc.alpha2, av=av)


def _agree(out, truth, tb_scales):
    """The same verdict and modes, peaks within 1 % (or 1e-4 alpha, for a lift-off of a few microradians)."""
    assert out.falls == truth.falls
    opened = ((OPENED_GROUND if any(g for g, _ in truth.modes) else 0)
              | (OPENED_JOINT if any(j for _, j in truth.modes) else 0)
              | (OPENED_BOTH if (True, True) in truth.modes else 0))
    assert out.modes == opened
    if out.falls == FALLS_NONE:
        assert out.peak_phi1_rad == pytest.approx(truth.peak_phi1, rel=0.01, abs=1e-4 * tb_scales.alpha1)
    if out.falls != FALLS_TOP:
        assert out.peak_psi_rad == pytest.approx(truth.peak_psi, rel=0.01, abs=1e-4 * tb_scales.alpha2)


#: Pulses and stacks of every mode: the statue rocks alone (on the shut plinth), then with it; the drums rock as
#: one, then open; the top falls; the stack falls; an offset statue
CASES = [(STATUE, 3.0, 0.4, 0.0, 0.0), (STATUE, 3.0, 0.8, 0.0, 0.0), (STATUE, 5.0, 0.4, 0.0, 0.0),
         (STATUE, 5.0, 0.8, 0.0, 0.0), (STATUE, 8.0, 0.4, 0.0, 0.0), (STATUE, 8.0, 0.8, 0.0, 0.0),
         (STATUE, 4.0, 0.6, math.pi / 2, 0.0), (STATUE, 4.0, 0.6, 0.0, 0.08),
         (DRUMS, 3.0, 0.4, 0.0, 0.0), (DRUMS, 3.0, 0.8, 0.0, 0.0), (DRUMS, 5.0, 0.4, 0.0, 0.0),
         (DRUMS, 5.0, 0.8, 0.0, 0.0), (DRUMS, 8.0, 0.4, 0.0, 0.0), (DRUMS, 8.0, 0.8, 0.0, 0.0),
         (DRUMS, 6.0, 0.5, math.pi / 2, 0.0), (DRUMS, 7.0, 0.3, math.pi / 2, 0.0),
         (CAPITAL, 3.0, 0.4, 0.0, 0.0), (CAPITAL, 3.0, 0.8, 0.0, 0.0), (CAPITAL, 5.0, 0.4, 0.0, 0.0),
         (CAPITAL, 5.0, 0.8, 0.0, 0.0), (CAPITAL, 8.0, 0.4, 0.0, 0.0), (CAPITAL, 8.0, 0.8, 0.0, 0.0),
         (CAPITAL, 6.0, 0.6, math.pi / 2, 0.0), (CAPITAL, 4.5, 0.5, 0.0, -0.02)]
FAST = {1, 13}


@pytest.mark.parametrize("k", [pytest.param(k, marks=() if k in FAST else pytest.mark.slow) for k in range(len(CASES))])
def test_the_model_agrees_with_lagranges_equations_solved_by_scipy(k):
    """Verdicts and modes identical and peaks within 1 % against the independent solution (Lagrange's equations of
    the blocks' energy, DOP853 with event location), on 24 pulses covering the modes: each joint open alone, both,
    the top falling, the stack falling (two in ``make test``, all in the slow tests)."""
    (lower, upper), ap, tp, phase, offset = CASES[k]
    a = _sine(ap, tp, phase)
    out, truth = _reference(lower, upper, a, offset)
    _agree(out, truth, scales(two_block(*_bodies(lower, upper, offset))))


#: Pulses with a vertical (a cosine of the same period, ``share`` of the horizontal's amplitude, up first)
VERTICAL = [(STATUE, 4.0, 0.6, 0.5), (STATUE, 6.0, 0.5, 0.4), (DRUMS, 4.0, 0.6, 0.5), (DRUMS, 7.0, 0.4, 0.3),
            (CAPITAL, 5.0, 0.5, 0.5)]


@pytest.mark.parametrize("k", [pytest.param(k, marks=() if k == 0 else pytest.mark.slow) for k in range(len(VERTICAL))])
def test_with_a_vertical_the_model_agrees_with_lagranges_equations(k):
    """The vertical enters gravity (g + a_v) in the equations, the lift-off tests and the exact lift-off from rest:
    against the independent solution with the same vertical, the same verdicts and modes and peaks within 1 %."""
    (lower, upper), ap, tp, share = VERTICAL[k]
    a = _sine(ap, tp)
    av = np.where(TIMES < tp, share * ap * np.cos(2 * np.pi * TIMES / tp), 0.0)
    out, truth = _reference(lower, upper, a, av=av)
    flat, _ = _reference(lower, upper, a)
    _agree(out, truth, scales(two_block(*_bodies(lower, upper))))
    assert (out.peak_phi1_rad, out.peak_psi_rad, out.falls) != (flat.peak_phi1_rad, flat.peak_psi_rad, flat.falls)


@pytest.mark.slow
def test_the_cases_cover_every_mode():
    """The 24 cases open each joint alone, both at once, let the top fall and the stack fall."""
    seen, falls = set(), set()
    for (lower, upper), ap, tp, phase, offset in CASES:
        out = simulate_two_block(two_block(*_bodies(lower, upper, offset)), _sine(ap, tp, phase), DT)
        seen.add(out.modes)
        falls.add(out.falls)
    assert {OPENED_GROUND, OPENED_JOINT} <= seen and any(m & OPENED_BOTH for m in seen)
    assert falls == {FALLS_NONE, FALLS_TOP, FALLS_STACK}


@pytest.mark.parametrize("lower, upper", [STATUE, DRUMS, CAPITAL])
@pytest.mark.parametrize("ap, tp", [(4.0, 0.5), (7.0, 0.4)])
def test_a_mirrored_ground_mirrors_the_motion(lower, upper, ap, tp):
    """A stack symmetric about its axis under -a_h: the same verdict and peaks (to rounding)."""
    tb = two_block(*_bodies(lower, upper))
    a = _sine(ap, tp)
    one, other = simulate_two_block(tb, a, DT), simulate_two_block(tb, -a, DT)
    assert (one.falls, one.impacts, one.modes) == (other.falls, other.impacts, other.modes)
    assert (one.peak_phi1_rad, one.peak_psi_rad) == pytest.approx((other.peak_phi1_rad, other.peak_psi_rad),
                                                                 rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("lower, upper, ratio", [(*STATUE, 0.15 / 0.6), (*DRUMS, 0.25 / 1.25)])
def test_at_rest_a_joint_opens_only_above_its_bound(lower, upper, ratio):
    """A ground held at the stack's first lift-off bound does not move it; a rounding above it does. By hand: the
    statue's joint b2 / h2 = 0.15 / 0.6 (its plinth's base 0.3 / 0.9125, z_G = (1500 x 0.5 + 900 x 1.6) / 2400 m per
    metre of depth, is higher); the drums' base b1 / z_G = 0.25 / 1.25 (z_G = (1.5 x 0.75 + 1.0 x 2.0) / 2.5 m; their
    joint's 0.25 / 0.5 is higher)."""
    tb = two_block(*_bodies(lower, upper))
    held = np.full(400, ratio * G)
    assert simulate_two_block(tb, held, DT).liftoffs == 0
    assert simulate_two_block(tb, held * (1 + 1e-9), DT).liftoffs >= 1


def test_a_ground_falling_faster_than_gravity_is_flagged_not_followed():
    """g + a_v <= 0: the blocks leave the ground; the model does not follow them and says so."""
    tb = two_block(*_bodies(*STATUE))
    av = np.where(TIMES > 0.5, -1.2 * G, 0.0)
    out = simulate_two_block(tb, _sine(3.0, 0.4), DT, av_ms2=av)
    assert out.status & STATUS_GROUND_FLIGHT


@pytest.mark.parametrize("n, dt", [(13000, 0.005), (12999, 0.005), (18000, 0.005), (4001, 0.01), (9999, 0.02),
                                   (30001, 0.004)])
def test_a_stack_at_rest_to_the_records_end_stands_without_a_cap(n, dt):
    """A ground below every lift-off bound to the record's end, on records whose last sample's time the run reaches
    by adding pieces (64.99 + 0.005 is not 12999 x 0.005 in floating point: the run once stood still there): the
    stack stands, nothing opened, no cap met."""
    tb = two_block(*_bodies(*STATUE))
    out = simulate_two_block(tb, 0.01 * np.sin(np.arange(n) * dt), dt)
    assert (out.falls, out.liftoffs, out.status) == (FALLS_NONE, 0, 0)


def test_a_pair_that_cannot_stand_is_a_named_error():
    with pytest.raises(BlockParameterError, match="cannot stand at rest"):
        two_block(*_bodies((0.4, 1.0), (0.3, 1.0), offset=0.4))


def _two_pulses(ap2):
    """A pulse of 2.5 m s-2 and 1 s from 0 s, another of ``ap2`` [m s-2] and 1 s from 2.5 s; 5 s in all."""
    t = np.arange(0.0, 5.0, DT)
    first = np.where(t < 1.0, 2.5 * np.sin(2 * np.pi * t), 0.0)
    return first + np.where((t >= 2.5) & (t < 3.5), ap2 * np.sin(2 * np.pi * (t - 2.5)), 0.0)


@pytest.mark.parametrize("ap2", [0.0, 3.0, 4.0, 5.0, 7.0])
def test_after_the_top_falls_the_lower_block_is_judged_alone(ap2):
    """A slender light top (0.06 x 0.6 m) falls under a first pulse that leaves its 0.6 x 1.6 m plinth at rest; a
    later pulse then meets the plinth alone. The plinth's verdict is the rocking kernel's on the plinth alone over the
    whole record (it cannot have moved before: alone its bound, b1 / h1 g, is above the stack's)."""
    lower, upper = _bodies((0.6, 1.6), (0.06, 0.6))
    a = _two_pulses(ap2)
    verdict = judge_two_block(two_block(lower, upper), a, DT)
    assert verdict.run.falls == FALLS_TOP and verdict.run.peak_phi1_rad == 0.0 and verdict.run.t_fall_s < 2.5
    assert verdict.upper == Verdict.overturns
    alpha, radius = math.atan(0.3 / 0.8), math.hypot(0.3, 0.8)
    alone = rock(a, DT, p=math.sqrt(0.75 * G / radius), alpha=alpha, e=1 - 1.5 * math.sin(alpha) ** 2, R_m=radius)
    assert verdict.lower == (Verdict.overturns if alone.overturned else Verdict.stands)


def test_each_body_has_the_runs_verdict_where_nothing_or_the_stack_falls():
    tb = two_block(*_bodies(*DRUMS))
    assert judge_two_block(tb, _sine(2.0, 0.5), DT)[:2] == (Verdict.stands, Verdict.stands)
    assert judge_two_block(tb, _sine(8.0, 0.8), DT)[:2] == (Verdict.overturns, Verdict.overturns)


def test_a_run_without_a_verdict_leaves_both_bodies_unknown():
    """The ground falling faster than gravity: no body is called standing."""
    av = np.where(TIMES > 0.5, -1.2 * G, 0.0)
    verdict = judge_two_block(two_block(*_bodies(*STATUE)), _sine(3.0, 0.4), DT, av_ms2=av)
    assert (verdict.lower, verdict.upper) == (Verdict.no_verdict, Verdict.no_verdict)


@pytest.mark.parametrize("ap, tp", [(3.0, 0.8), (4.0, 0.8), (5.0, 0.8), (4.0, 1.2), (6.0, 0.6), (3.5, 1.0)])
def test_a_lower_block_rocking_when_the_top_falls_goes_on_as_itself(ap, tp):
    """A top of a millionth of the lower block's mass leaves the lower's motion its own: the top falls while the
    lower rocks (its rate not 0), and the lower's verdict, followed on from that state by the rocking kernel, is the
    kernel's on the lower alone from the start."""
    tb = two_block(StackBody(0.4, 1.6, 1000.0, 0.8), StackBody(0.05, 0.5, 1e-3, 0.8))
    a = _sine(ap, tp)
    verdict = judge_two_block(tb, a, DT)
    assert verdict.run.falls == FALLS_TOP and verdict.run.final.w1 != 0.0
    alpha, radius = math.atan(0.2 / 0.8), math.hypot(0.2, 0.8)
    alone = rock(a, DT, p=math.sqrt(0.75 * G / radius), alpha=alpha, e=1 - 1.5 * math.sin(alpha) ** 2, R_m=radius)
    assert verdict.lower == (Verdict.overturns if alone.overturned else Verdict.stands)


def test_a_free_motion_outlasting_its_cap_stands_where_its_energy_cannot_reach_a_fall():
    """A wide slab on a narrow column (0.12 x 0.985 m under 1.2 x 1.06 m) rocks on after a record for more than the
    60 s followed (the stack's impact keeps most of its rate): the run is capped, and its energy, far below the least
    potential energy on the boundary of the tipping angles' box, gives both bodies a verdict. A state on that boundary
    at rest, or at rest past the stack's tipping angle, is not certified; rest is."""
    rng = np.random.default_rng(1)
    lower, upper = StackBody(0.123, 0.985, 84.8, 0.8), StackBody(1.198, 1.063, 1146.2, 0.8, -0.009)
    tb = two_block(lower, upper)
    capped = None
    for _ in range(40):
        ah = rng.standard_normal(200)
        ah *= 0.253 * G / np.max(np.abs(ah))
        verdict = judge_two_block(tb, ah, 0.01)
        if verdict.run.status == STATUS_TAIL_CAP:
            capped = verdict
            break
    assert capped is not None and capped.run.falls == FALLS_NONE
    assert (capped.lower, capped.upper) == (Verdict.stands, Verdict.stands)
    (a1p, a1m), _ = tipping_angles(tb)
    assert energy_below_barrier(tb, Motion(0.0, 0.0, 0.0, 0.0))
    for a1 in (a1p, -a1m, 1.2 * a1p):
        assert not energy_below_barrier(tb, Motion(a1, a1, 0.0, 0.0))
    assert not energy_below_barrier(tb, Motion(3.0, 3.0, 0.0, 0.0))      # outside the box: low energy proves nothing


def test_a_record_with_a_gap_is_refused_by_name_not_judged():
    """A NaN in the record would leave every lift-off test false (a silent 'stands'): it is refused, naming the
    sample."""
    tb = two_block(*_bodies(*STATUE))
    a = _sine(3.0, 0.4)
    a[37] = np.nan
    with pytest.raises(ParameterError, match="sample 37"):
        simulate_two_block(tb, a, DT)
    with pytest.raises(ParameterError, match="expected 600 as the horizontal"):
        simulate_two_block(tb, _sine(3.0, 0.4), DT, av_ms2=np.zeros(10))


@pytest.mark.parametrize("ap, tp", [(3.0, 0.8), (6.0, 0.6), (8.0, 0.8)])
def test_the_history_is_the_runs_state_at_each_sample(ap, tp):
    """Kept at every sample: its peaks are the run's (the run's are at steps' ends, every sample one of them), it
    starts at rest and stops at a fall."""
    tb = two_block(*_bodies(*STATUE))
    a = _sine(ap, tp)
    hist = np.full((2, a.size), np.nan)
    hist[:, 0] = 0.0
    out = simulate_two_block(tb, a, DT, history=hist)
    kept = np.isfinite(hist[0])
    assert kept[0] and (np.flatnonzero(~kept).size == 0 or out.falls != FALLS_NONE)
    assert np.nanmax(np.abs(hist[0])) <= out.peak_phi1_rad and np.nanmax(np.abs(hist[1])) <= out.peak_psi_rad
    if out.falls == FALLS_NONE:
        assert np.nanmax(np.abs(hist[1])) == pytest.approx(out.peak_psi_rad, rel=0.05, abs=1e-12)
    else:
        assert not kept[int(out.t_fall_s / DT) + 2:].any()


@pytest.mark.parametrize("ap, tp", [(5.0, 0.3), (6.0, 0.6), (8.0, 0.3), (5.0, 0.6), (7.0, 0.4)])
def test_the_ground_joints_friction_demand_is_the_outline_blocks(ap, tp):
    """A 0.05 m slab on a 0.5 x 1.0 m block rocks as the 0.5 x 1.05 m block of their outline: the friction its base
    needs while rocking is the rocking kernel's friction demand on that block (Housner's equation; the demand from
    its own pivot force), where the kernel's block rocks and stands."""
    tb = two_block(*_bodies((0.5, 1.0), (0.5, 0.05)))
    a = _sine(ap, tp)
    out = simulate_two_block(tb, a, DT)
    alpha, radius = math.atan(0.25 / 0.525), math.hypot(0.25, 0.525)
    alone = rock(a, DT, p=math.sqrt(0.75 * G / radius), alpha=alpha, e=1 - 1.5 * math.sin(alpha) ** 2, R_m=radius)
    assert not alone.overturned and alone.friction_demand > 0 and out.falls == FALLS_NONE
    assert out.demand_ground == pytest.approx(alone.friction_demand, rel=1e-4)


@pytest.mark.parametrize("ratio", [0.05, 0.12, 0.2])
def test_at_rest_the_friction_demand_is_the_grounds_ratio(ratio):
    """A stack at rest moves with the ground: each joint carries what is above it at the ground's acceleration, so
    each needs |a_h| / (g + a_v), the largest over the samples (by hand: ``ratio`` g over g - 0.1 g)."""
    tb = two_block(*_bodies(*STATUE))
    a = ratio * G * np.sin(2 * np.pi * TIMES)
    av = np.full(TIMES.size, -0.1 * G)
    out = simulate_two_block(tb, a, DT, av_ms2=av)
    assert out.liftoffs == 0
    expected = ratio * np.max(np.abs(np.sin(2 * np.pi * TIMES))) / 0.9
    assert out.demand_ground == pytest.approx(expected, rel=1e-12) and out.demand_joint == out.demand_ground
