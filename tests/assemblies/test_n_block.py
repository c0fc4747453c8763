"""n stacked blocks rocking (pipeline.assemblies.n_block*): for two blocks against the two-block model (its
equations, impacts, lift-off tests and runs, written out for two blocks), for one block against Housner's equation
solved by the rocking kernel, for three to five against Lagrange's equations of their energy
(tests/support/n_block_reference.py), and the invariants (energy never gained at an impact, mirror symmetry)."""

from __future__ import annotations

import itertools
import math

import n_block_reference as ref
import numpy as np
import pytest

from pipeline.assemblies import n_block as nbm
from pipeline.assemblies import two_block as tbm
from pipeline.assemblies.n_block_run import FALLS_NONE, REST_RATIO, simulate_n_block
from pipeline.assemblies.n_block_verdicts import judge_n_block
from pipeline.assemblies.stack import StackBody
from pipeline.assemblies.two_block_run import FALLS_STACK, FALLS_TOP, simulate_two_block
from pipeline.errors import BlockParameterError
from pipeline.rocking.codes import Verdict
from pipeline.rocking.settings import SimulationConfig
from pipeline.rocking.simulate import rock

DT = 0.005
G = 9.80665
TIMES = np.arange(0.0, 3.0, DT)
N = nbm.MAX_BODIES
PAIRS = [(StackBody(0.6, 1.2, 3.0, 0.6), StackBody(0.4, 0.9, 1.0, 0.6, 0.05)),
         (StackBody(0.3, 1.0, 2.0, 0.6), StackBody(0.3, 1.0, 2.0, 0.6)),
         (StackBody(1.0, 0.5, 5.0, 0.6), StackBody(0.2, 1.0, 0.5, 0.6))]
DRUMS = [StackBody(0.5, 0.8, 2.0, 0.6), StackBody(0.48, 0.7, 1.6, 0.6, 0.01), StackBody(0.46, 0.6, 1.3, 0.6, -0.02),
         StackBody(0.44, 0.5, 1.0, 0.6), StackBody(0.6, 0.25, 0.9, 0.6)]


def _sine(ap, tp, phase=0.0):
    """One cycle of a sine (phase 0) or cosine (phase pi/2) pulse [m s-2] of period ``tp`` [s]."""
    return np.where(TIMES < tp, ap * np.sin(2 * np.pi * TIMES / tp + phase), 0.0)


def _state(psi, rates):
    return tuple(psi) + (0.0,) * (N - len(psi)) + tuple(rates) + (0.0,) * (N - len(rates))


def _modes(n):
    return [tuple(m) + (0,) * (N - n) for m in itertools.product((-1, 0, 1), repeat=n)]


@pytest.mark.parametrize("pair", PAIRS)
def test_two_blocks_have_the_two_block_models_equations(pair):
    """Accelerations, contact demands, energies, lift-off and the impact law of two blocks, in every mode and for
    every mode after, at random states: the same as the two-block model's to rounding."""
    rng = np.random.default_rng(7)
    tb, nb, wk = tbm.two_block(*pair), nbm.n_block(pair), nbm.work()
    for _ in range(20):
        p1, p2 = rng.normal(0, 0.05, 2)
        w1, w2 = rng.normal(0, 0.3, 2)
        ah, av = rng.normal(0, 3, 2)
        for js in _modes(2):
            j1, j2 = js[:2]
            psi = (p1 if j1 else 0.0, p2 if j2 else 0.0)
            rate = (w1 if j1 else 0.0, w2 if j2 else 0.0)
            y2 = tbm.Motion(psi[0], psi[0] + psi[1], rate[0], rate[0] + rate[1])
            y = _state(psi, rate)
            nbm.accelerations(nb, y, js, ah, av, wk)
            np.testing.assert_allclose(wk.qdd[:2], tbm.accelerations(tb, y2, j1, j2, ah, av), rtol=1e-12, atol=1e-12)
            nbm.demands(nb, y, js, ah, av, wk)
            np.testing.assert_allclose(wk.d[:2], tbm.demands(tb, y2, j1, j2, ah, av), rtol=1e-10)
            assert nbm.kinetic_energy(nb, y, js, wk) == pytest.approx(tbm.kinetic_energy(tb, y2, j1, j2), abs=1e-12)
            assert nbm.potential_energy(nb, y, js, wk) == pytest.approx(tbm.potential_energy(tb, y2, j1, j2),
                                                                        abs=1e-12)
            joint, corner = nbm.opening(nb, y, js, ah, av, wk)
            assert (joint + 1, corner) == tbm.opening(tb, y2, j1, j2, ah, av)
            for after in _modes(2):
                nbm.projected_rates(nb, y, js, after, wk)
                np.testing.assert_allclose(wk.qdd[:2], tbm.projected_rates(tb, y2, (j1, j2), after[:2]),
                                           rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("pair", PAIRS)
@pytest.mark.parametrize("ap, tp", [(4.0, 0.3), (6.0, 0.6), (9.0, 1.0), (6.0, 0.3)])
def test_two_blocks_run_as_the_two_block_run(pair, ap, tp):
    """The n-block run of two blocks: the same fall, impacts and peaks as the two-block run."""
    ah = _sine(ap, tp)
    a = simulate_two_block(tbm.two_block(*pair), ah, DT)
    b = simulate_n_block(nbm.n_block(pair), ah, DT)
    assert b.falls == {0: FALLS_NONE, FALLS_TOP: 1, FALLS_STACK: 0}[a.falls]
    assert (b.impacts, b.liftoffs, b.status) == (a.impacts, a.liftoffs, a.status)
    assert b.peak_psi_rad[:2] == pytest.approx((a.peak_phi1_rad, a.peak_psi_rad), abs=1e-9)


@pytest.mark.parametrize("ap, tp, phase", [(3.0, 0.5, 0.0), (4.0, 1.0, 0.0), (4.0, 0.8, math.pi / 2), (2.5, 2.0, 0)])
def test_one_block_is_housners(ap, tp, phase):
    """One block: the rocking kernel's verdict and peak rotation (Housner's equation and impact), to 1e-4 alpha."""
    body = StackBody(0.4, 2.0, 1.0, 0.6)
    ah = _sine(ap, tp, phase)
    run = simulate_n_block(nbm.n_block([body]), ah, DT)
    alpha, radius = math.atan(0.2), math.hypot(0.2, 1.0)
    alone = rock(ah, DT, p=math.sqrt(0.75 * G / radius), alpha=alpha, e=1 - 1.5 * math.sin(alpha) ** 2, R_m=radius,
                 settings=SimulationConfig())
    assert (run.falls == 0) == bool(alone.overturned)
    if not alone.overturned:
        assert run.peak_psi_rad[0] / alpha == pytest.approx(alone.theta_max, abs=1e-4)


@pytest.mark.parametrize("n", [3, 4, 5])
def test_three_to_five_blocks_follow_lagranges_equations(n):
    """At random states in every mode, the accelerations equal those of Lagrange's equations of the stack's energy
    formed independently (finite differences of the positions and the energy, tests/support/n_block_reference.py)."""
    rng = np.random.default_rng(n)
    bodies = DRUMS[:n]
    nb, wk = nbm.n_block(bodies), nbm.work()
    stack = ref.Stack([x.width_m / 2 for x in bodies], [x.height_m / 2 for x in bodies],
                      [x.mass_kg for x in bodies], [0.0] + [x.offset_m for x in bodies[1:]])
    modes = _modes(n)
    for js in [modes[k] for k in rng.choice(len(modes), 12, replace=False)]:
        psi = [rng.normal(0, 0.05) if js[k] else 0.0 for k in range(n)]
        rate = [rng.normal(0, 0.3) if js[k] else 0.0 for k in range(n)]
        ah, av = rng.normal(0, 3, 2)
        nbm.accelerations(nb, _state(psi, rate), js, ah, av, wk)
        expected = ref.accelerations(stack, js[:n], np.array(psi), np.array(rate), ah, av)
        np.testing.assert_allclose(wk.qdd[:n], expected, rtol=1e-5, atol=1e-5 * np.abs(expected).max())


@pytest.mark.parametrize("n", [3, 4, 5])
def test_an_impact_never_gains_energy(n):
    """At random states, every impact and every stop at any joint leaves the kinetic energy at most what it was."""
    rng = np.random.default_rng(10 + n)
    nb, wk = nbm.n_block(DRUMS[:n]), nbm.work()
    for _ in range(40):
        js = tuple(int(v) for v in rng.choice([-1, 1], n)) + (0,) * (N - n)
        psi = [abs(rng.normal(0, 0.05)) * js[k] for k in range(n)]
        rate = list(rng.normal(0, 0.5, n))
        k = int(rng.integers(n))
        psi[k] = 0.0
        y = _state(psi, rate)
        before = nbm.kinetic_energy(nb, y, js, wk)
        for after in (nbm.tuple_set(js, k, -js[k]), nbm.tuple_set(js, k, 0)):
            nbm.projected_rates(nb, y, js, after, wk)
            qd = wk.qdd[:n].copy()
            rel = np.diff(np.concatenate([[0.0], qd]))
            after_energy = nbm.kinetic_energy(nb, _state(psi, rel), after, wk)
            assert after_energy <= before * (1 + 1e-12) + 1e-15


@pytest.mark.parametrize("ap, tp", [(5.0, 0.5), (8.0, 0.8), (12.0, 0.4)])
def test_a_mirrored_ground_mirrors_a_symmetric_stack(ap, tp):
    """Centred drums (a stack symmetric about its axis): the ground reversed gives the same falls and peaks."""
    bodies = [b._replace(offset_m=0.0) for b in DRUMS[:3]]
    nb = nbm.n_block(bodies)
    a, b = judge_n_block(nb, _sine(ap, tp), DT), judge_n_block(nb, -_sine(ap, tp), DT)
    assert a.verdicts == b.verdicts
    assert a.peak_psi_rad == pytest.approx(b.peak_psi_rad, rel=1e-6, abs=1e-9)


def test_every_drum_has_a_verdict_and_a_fall_takes_what_stands_on_it():
    """A three-drum column under growing pulses: every drum judged; a drum overturns only with every drum above it;
    the drums under a fall keep rocking to a verdict of their own."""
    nb = nbm.n_block(DRUMS[:3])
    seen = set()
    for ap in np.linspace(2.0, 14.0, 13):
        for tp in (0.3, 0.6, 1.2):
            got = judge_n_block(nb, _sine(ap, tp), DT)
            assert all(v in (Verdict.stands, Verdict.overturns) for v in got.verdicts)
            falls = [v == Verdict.overturns for v in got.verdicts]
            assert falls == sorted(falls), "a drum fell with one under it standing"
            seen.add(sum(falls))
    assert seen >= {0, 3} and len(seen) >= 3, seen


def test_more_than_five_bodies_is_a_named_error():
    with pytest.raises(BlockParameterError, match="at most 5"):
        nbm.n_block(DRUMS + [DRUMS[0]])


@pytest.mark.slow
@pytest.mark.parametrize("tp, phase", [(0.2, 0.0), (0.2, math.pi / 2), (0.3, 0.0), (0.3, math.pi / 2)])
def test_three_drums_run_as_lagranges_equations_solved_by_scipy(tp, phase):
    """Three drums under a 4 m s-2 sine or cosine pulse, to 0.3 s after it: the run against Lagrange's equations
    solved by scipy's DOP853 with its event location (tests/support/n_block_reference.py; its lift-offs, impacts and
    stops by the same rules, its own code): the same verdicts, each joint's peak within 1 % or 1e-4 of its tipping
    angle. (The reference takes 5-40 s a pulse; stronger pulses, with their impacts, take it minutes.)"""
    bodies = DRUMS[:3]
    nb = nbm.n_block(bodies)
    sc = nbm.scales(nb)
    stack = ref.Stack([x.width_m / 2 for x in bodies], [x.height_m / 2 for x in bodies],
                      [x.mass_kg for x in bodies], [0.0] + [x.offset_m for x in bodies[1:]])
    times = np.arange(0.0, 1.0, DT)
    ah = np.where(times < tp, 4.0 * np.sin(2 * np.pi * times / tp + phase), 0.0)
    expected = ref.simulate(stack, ah, DT, rest=[REST_RATIO * a * p for a, p in zip(sc.alpha, sc.p)], tail_s=0.3)
    got = simulate_n_block(nb, ah, DT)
    assert got.falls == expected.falls
    tips = [min(t) for t in nbm.tipping_angles(nb)]
    for k in range(3):
        assert got.peak_psi_rad[k] == pytest.approx(expected.peaks[k], rel=0.01, abs=1e-4 * tips[k])
    assert expected.peaks[0] > 0.02 * tips[0] and expected.peaks[1] > 0.0, "the pulse leaves the joints shut"


@pytest.mark.parametrize("n", [3, 5])
@pytest.mark.parametrize("ap, tp, phase", [(5.0, 0.3, 0.0), (6.0, 0.6, 0.0), (6.0, 1.0, 0.0), (8.0, 0.3, 0.0),
                                           (5.0, 0.6, math.pi / 2), (9.0, 0.4, math.pi / 2)])
def test_thin_slabs_on_a_block_rock_as_the_block_of_their_outline(n, ap, tp, phase):
    """n - 1 slabs 0.025 m thick on a 0.5 x 1.0 m block, all of its width and density: no joint above the ground
    opens (tan alpha of a slab 10 and more) and the stack is the block of their outline, the same mass about the
    same corner, its impact Housner's. The rocking kernel on that block: the same verdict, peaks within 1e-4 alpha."""
    slab = 0.025
    bodies = [StackBody(0.5, 1.0, 2500.0 * 0.5, 0.6)] + [StackBody(0.5, slab, 2500.0 * 0.5 * slab, 0.6)] * (n - 1)
    out = simulate_n_block(nbm.n_block(bodies), _sine(ap, tp, phase), DT)
    b, h = 0.25, 0.5 + 0.5 * slab * (n - 1)
    alpha, radius = math.atan(b / h), math.hypot(b, h)
    single = rock(_sine(ap, tp, phase), DT, p=math.sqrt(0.75 * G / radius), alpha=alpha,
                  e=1 - 1.5 * math.sin(alpha) ** 2, R_m=radius, settings=SimulationConfig(rtol=1e-10, atol=1e-12),
                  tail="integrate", t_end_s=TIMES[-1] + 60)
    assert (out.falls == 0) == single.overturned
    if not single.overturned:
        assert out.peak_psi_rad[0] / alpha == pytest.approx(single.theta_max, abs=1e-4)
        assert out.peak_psi_rad[1:n] == (0.0,) * (n - 1) and out.modes == 1


@pytest.mark.parametrize("bodies", [DRUMS[:3], DRUMS[:5], [StackBody(0.8, 1.0, 2.0, 0.6), StackBody(0.3, 1.2, 0.5, 0.6),
                                                           StackBody(0.3, 0.2, 0.1, 0.6, 0.05)]])
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_at_rest_a_joint_opens_only_above_its_bound(bodies, sign):
    """A ground held at the stack's first lift-off bound does not move it; a rounding above it does (tie rule 2:
    motion only where the demand exceeds). The bound is the statics of each interface (the part above tips where the
    ground's a_h / g passes (x_G - support end) / z_G: `stack.uplift_ratios`), not the model's equations."""
    from pipeline.assemblies.stack import interfaces, uplift_ratios

    low, high = zip(*(uplift_ratios(face) for face in interfaces(bodies)))
    ratio = max(low) if sign < 0 else min(high)
    nb = nbm.n_block(bodies)
    held = np.full(400, ratio * G)
    assert simulate_n_block(nb, held, DT).liftoffs == 0
    assert simulate_n_block(nb, held * (1 + 1e-9), DT).liftoffs >= 1


def test_a_ground_falling_faster_than_gravity_is_flagged_not_followed():
    """g + a_v <= 0: the blocks leave the ground; the model does not follow them, says so, and no body stands."""
    from pipeline.rocking.codes import STATUS_GROUND_FLIGHT

    nb = nbm.n_block(DRUMS[:3])
    av = np.where(TIMES > 0.5, -1.2 * G, 0.0)
    out = simulate_n_block(nb, _sine(3.0, 0.4), DT, av_ms2=av)
    assert out.status & STATUS_GROUND_FLIGHT
    got = judge_n_block(nb, _sine(3.0, 0.4), DT, av_ms2=av)
    assert all(v == Verdict.no_verdict for v in got.verdicts)


@pytest.mark.parametrize("n, dt", [(13000, 0.005), (12999, 0.005), (4001, 0.01), (30001, 0.004)])
def test_a_stack_at_rest_to_the_records_end_stands_without_a_cap(n, dt):
    """A ground below every lift-off bound to the record's end (the run reaches the last sample's time by adding
    pieces): every drum stands, nothing opened, no cap met."""
    out = simulate_n_block(nbm.n_block(DRUMS[:3]), 0.01 * np.sin(np.arange(n) * dt), dt)
    assert (out.falls, out.liftoffs, out.status) == (FALLS_NONE, 0, 0)


@pytest.mark.parametrize("n", [1, 2, 3, 5])
def test_at_rest_the_statics_bound_is_the_released_joints_acceleration(n):
    """At rest the run opens a joint by the statics of its interface (`n_block_run.rest_lift`); releasing the joint
    on that corner in the equations of motion accelerates it that way exactly where the statics say so (grounds
    away from the bound by more than 1e-9 of g)."""
    from pipeline.assemblies.n_block_run import rest_lift

    nb, wk = nbm.n_block(DRUMS[:n]), nbm.work()
    ch, cg = rest_lift(nb)
    rest = (0.0,) * (2 * N)
    rng = np.random.default_rng(n)
    for ah, av in rng.normal(0.0, 4.0, (200, 2)):
        for k in range(n):
            for c, s in enumerate((1, -1)):
                condition = ch[2 * k + c] * ah + cg[2 * k + c] * (G + av)
                nbm.accelerations(nb, rest, nbm.tuple_set((0,) * N, k, s), ah, av, wk)
                nbm.relative(wk.qdd, n, wk)
                if abs(condition) > 1e-9 * G:
                    assert (s * wk.rel[k] > 0) == (condition > 0), (k, s, ah, av)
