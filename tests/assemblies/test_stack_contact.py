"""The stack's contact model (pipeline.assemblies.stack_contact): against the exact n-block model where no joint
slides (a second algorithm and impact law), against closed forms (Coulomb sliding, a free flight's height), its
geometry against the n-block model's (the state it starts from, the offsets it hands back), and the verdicts it
gives where the ground falls faster than gravity."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.assemblies import n_block as nbm
from pipeline.assemblies import two_block as tbm
from pipeline.assemblies.n_block_run import FALLS_NONE, simulate_n_block
from pipeline.assemblies.n_block_verdicts import judge_n_block
from pipeline.assemblies.stack import StackBody
from pipeline.assemblies.stack_contact import simulate_stack_contact
from pipeline.assemblies.stack_pose import bodies_of, handback, shifted, state_of
from pipeline.assemblies.stack_scene import judge
from pipeline.rocking.codes import STATUS_GROUND_FLIGHT, STATUS_STEP_CAP, Verdict

DT = 0.005
G = 9.80665
TIMES = np.arange(0.0, 4.0, DT)
N = nbm.MAX_BODIES
#: friction high enough that no joint slides: the n-block model's assumption
STICKY = 50.0
DRUMS = [StackBody(0.5, 0.8, 2.0, STICKY), StackBody(0.48, 0.7, 1.6, STICKY, 0.01),
         StackBody(0.46, 0.6, 1.3, STICKY, -0.02), StackBody(0.44, 0.5, 1.0, STICKY), StackBody(0.6, 0.25, 0.9, STICKY)]
STATUE = [StackBody(0.7, 1.0, 1890.0, STICKY), StackBody(0.45, 1.7, 2065.5, STICKY)]


def _sine(ap, tp):
    """One cycle of a sine pulse [m s-2] of period ``tp`` [s]."""
    return np.where(TIMES < tp, ap * np.sin(2 * np.pi * TIMES / tp), 0.0)


def _mu(bodies):
    return tuple(b.mu for b in bodies)


@pytest.mark.parametrize("bodies, joints", [(DRUMS[:1], 1), (STATUE, 2), (DRUMS[:3], 1)], ids=["1", "statue", "3"])
@pytest.mark.parametrize("ap, tp", [(3.0, 0.5), (4.5, 0.5), (6.0, 0.8), (9.0, 0.4), (2.5, 1.0), (3.5, 1.0)])
def test_where_no_joint_slides_it_follows_the_exact_model(bodies, joints, ap, tp):
    """Ample friction, a pulse: the same blocks fall as in the n-block model (event-driven, its own impact law), and
    the peak rotation of the lowest ``joints`` joints agrees within 3 % of their smaller tipping angle (time stepping
    at 0.25 ms). Above the lowest joint of three drums the two impact laws part (docs/validation.md: Moreau's lets a
    shut joint open in an impact, the n-block model's keeps it shut), and so do the upper peaks."""
    nb = nbm.n_block(bodies)
    exact = simulate_n_block(nb, _sine(ap, tp), DT)
    got = simulate_stack_contact(nb, _mu(bodies), _sine(ap, tp), DT, hand_back=False)
    falls = exact.falls if exact.falls != FALLS_NONE else nb.n
    assert got.standing == falls
    tips = [min(t) for t in nbm.tipping_angles(nb)]
    for k in range(min(falls, joints)):
        assert abs(got.peak_rad[k] - exact.peak_psi_rad[k]) <= 0.03 * tips[k], k
    assert got.unconverged <= 0.01 * got.steps
    assert bool(got.status & STATUS_STEP_CAP) == (got.unconverged > 0)      # a capped step flags the run, no other


def test_a_block_slides_on_the_block_under_it_as_coulomb_says():
    """A squat block (mu 0.2) on a squat base held by its ground's friction, under a constant 0.3 g for 1 s: it
    slides on the base with the relative acceleration (0.3 - 0.2) g (Newmark's sliding block), within 0.5 %."""
    t = np.arange(0.0, 1.0 + DT / 2, DT)
    bodies = [StackBody(2.0, 0.4, 5.0, STICKY), StackBody(1.0, 0.2, 1.0, 0.2)]
    out = simulate_stack_contact(nbm.n_block(bodies), _mu(bodies), np.full(t.size, 0.3 * G), DT,
                                 hand_back=False)
    expected = 0.5 * 0.1 * G * 1.0 ** 2 + 0.1 * G * 1.0 * (0.1 * G * 1.0) / (2 * 0.2 * G)   # speeding, then braking
    assert out.peak_slide_m[1] == pytest.approx(expected, rel=5e-3)
    assert out.peak_rad[0] < 1e-6 and out.peak_rad[1] < 1e-6


def test_a_stack_thrown_up_flies_its_parabola_and_lands():
    """A ground falling at 2 g for 0.1 s, then still (linear between its samples): the stack, intact, rises above it
    as z'' = -(g + a_v) says while z > 0 (integrated here on a 1 us grid), within 1 %; it lands, and stands."""
    t = np.arange(0.0, 2.0, DT)
    av = np.where(t < 0.1 - DT / 2, -2.0 * G, 0.0)
    nb = nbm.n_block(DRUMS[:3])
    out = simulate_stack_contact(nb, _mu(DRUMS[:3]), np.zeros(t.size), DT, av_ms2=av, hand_back=False)
    fine = np.arange(0.0, 0.5, 1e-6)
    rate = np.cumsum(-(G + np.interp(fine, t, av))) * 1e-6
    height = np.cumsum(rate) * 1e-6
    assert out.status & STATUS_GROUND_FLIGHT
    assert out.peak_lift_m == pytest.approx(height.max(), rel=1e-2)
    assert out.standing == 3 and out.rested and max(out.peak_rad[:3]) < 1e-6


@pytest.mark.parametrize("bodies", [DRUMS[:2], DRUMS[:3], DRUMS[:5], STATUE])
def test_the_state_it_starts_from_is_the_exact_models(bodies):
    """From an n-block state (random psi and rates, each joint on its corner): every upper block's pivot corner lies
    on the lower block's top face at the corner the exact model turns it about, and the centres' velocities are the
    derivatives of the centres' positions (a central difference along the state's rates)."""
    nb = nbm.n_block(bodies)
    rng = np.random.default_rng(3)
    for _ in range(10):
        psi = rng.normal(0.0, 0.05, nb.n)
        rate = rng.normal(0.0, 0.3, nb.n)
        y = tuple(psi) + (0.0,) * (N - nb.n) + tuple(rate) + (0.0,) * (N - nb.n)
        q, v = state_of(nb, y)
        eps = 1e-7
        ahead = tuple(psi + eps * rate) + (0.0,) * (N - nb.n) + y[N:]
        back = tuple(psi - eps * rate) + (0.0,) * (N - nb.n) + y[N:]
        dq = (state_of(nb, ahead)[0] - state_of(nb, back)[0]) / (2 * eps)
        np.testing.assert_allclose(v, dq, atol=1e-6)
        for k in range(1, nb.n):
            corner = nb.hi[k] if psi[k] > 0 else nb.lo[k]
            c, s = math.cos(q[2, k]), math.sin(q[2, k])
            px, pz = q[0, k] + c * corner - s * nb.h[k], q[1, k] - s * corner - c * nb.h[k]
            c1, s1 = math.cos(q[2, k - 1]), math.sin(q[2, k - 1])
            dx, dz = px - q[0, k - 1], pz - q[1, k - 1]
            assert c1 * dx - s1 * dz == pytest.approx(corner + nb.off[k], abs=1e-12)
            assert s1 * dx + c1 * dz == pytest.approx(nb.h[k - 1], abs=1e-12)


def test_the_stack_it_hands_back_is_the_stack_of_those_offsets():
    """:func:`shifted` with a stack's own offsets is the stack; with others, the stack the inventory would build with
    them (a second construction, :func:`pipeline.assemblies.n_block.n_block`); a block pushed off its support is
    None."""
    nb = nbm.n_block(DRUMS[:4])
    same = shifted(nb, nb.off, 4)
    assert same is not None
    for a, b in zip(same, nb):
        np.testing.assert_allclose(np.asarray(a, dtype=float), np.asarray(b, dtype=float), atol=1e-15)
    moved = (0.0, 0.03, -0.01, 0.02)
    again = nbm.n_block([b._replace(offset_m=o) for b, o in zip(DRUMS[:4], moved)])
    got = shifted(nb, moved + (0.0,), 4)
    assert got is not None
    for a, b in zip(got, again):
        np.testing.assert_allclose(np.asarray(a, dtype=float), np.asarray(b, dtype=float), atol=1e-12)
    assert shifted(nb, (0.0, 0.9, 0.0, 0.0, 0.0), 4) is None


def _flight_ground(ap=4.0, t_flight=0.35, width=0.07):
    """A pulse, and a vertical that falls faster than gravity (1.5 g) for ``width`` [s] from ``t_flight`` [s] while
    the stack rocks (and, by default, 1.3 g for 0.03 s at 0.6 s)."""
    ah = _sine(ap, 0.8) + _sine(2.0, 0.3)
    av = np.where((TIMES > t_flight) & (TIMES < t_flight + width), -1.5 * G, 0.0)
    if width == 0.07:
        av = av + np.where((TIMES > 0.6) & (TIMES < 0.63), -1.3 * G, 0.0)
    return ah, av


@pytest.mark.parametrize("bodies", [DRUMS[:2], DRUMS[:3], DRUMS[:5], STATUE])
def test_a_ground_falling_faster_than_gravity_gives_every_body_a_verdict(bodies):
    """With the bodies' friction the flight is followed: every body has a verdict and the flight is flagged."""
    nb = nbm.n_block(bodies)
    ah, av = _flight_ground()
    got = judge_n_block(nb, ah, DT, av_ms2=av, mu=_mu(bodies))
    assert got.status & STATUS_GROUND_FLIGHT
    assert all(v != Verdict.no_verdict for v in got.verdicts)


@pytest.mark.parametrize("bodies", [DRUMS[:2], DRUMS[:3], STATUE], ids=["2", "3", "statue"])
@pytest.mark.parametrize("mu", [STICKY, 0.6])
@pytest.mark.parametrize("ap, t_flight", [(3.0, 0.35), (4.0, 0.35), (5.0, 0.35), (3.0, 0.6), (4.0, 0.6), (5.0, 0.6)])
def test_handing_back_to_the_exact_model_keeps_the_contact_models_verdicts(bodies, mu, ap, t_flight):
    """Handed back to the n-block model once every joint is shut or turns on a sticking corner, the verdicts are
    those of the contact model run to the end (two and three drums, the statue; friction 50 and 0.6; a 1.5 g flight
    of 0.05 s at two instants of three pulses). For five drums the two impact laws part (docs/validation.md)."""
    bodies = [b._replace(mu=mu) for b in bodies]
    nb = nbm.n_block(bodies)
    ah, av = _flight_ground(ap, t_flight, 0.05)
    got = judge_n_block(nb, ah, DT, av_ms2=av, mu=_mu(bodies))
    whole = simulate_stack_contact(nb, _mu(bodies), ah, DT, av_ms2=av, hand_back=False)
    assert tuple(int(Verdict.overturns if not math.isnan(t) else Verdict.stands)
                 for t in whole.t_fall_s[:nb.n]) == tuple(got.verdicts)


def test_two_blocks_in_flight_are_judged_as_the_n_block_stack():
    """Two blocks: the two-block model stops at the flight; the stack's judge follows it as the n-block stack of the
    same blocks."""
    tb, nb = tbm.two_block(*STATUE), nbm.n_block(STATUE)
    ah, av = _flight_ground()
    got = judge(tb, ah, DT, av_ms2=av, bodies=tuple(STATUE))
    assert got == judge_n_block(nb, ah, DT, av_ms2=av, mu=_mu(STATUE))
    assert all(v != Verdict.no_verdict for v in got.verdicts)


@pytest.mark.parametrize("bodies", [DRUMS[:2], DRUMS[:3], DRUMS[:5], STATUE,
                                    [StackBody(0.4, 1.0, 1.0, STICKY), StackBody(0.7, 0.3, 1.0, STICKY, 0.1)]])
def test_the_state_it_hands_back_is_the_one_it_started_from(bodies):
    """Round trip: an n-block state (random psi of random signs, a shut joint among them, random rates) made into the
    blocks' positions and back (:func:`state_of`, then the hand-back's offsets and state) is that state and the
    stack's own offsets, to 1e-12 (a wide top on a narrow block turns on the lower's corner)."""
    nb = nbm.n_block(bodies)
    rng = np.random.default_rng(11)
    for _ in range(10):
        psi = rng.normal(0.0, 0.05, nb.n) * (rng.random(nb.n) > 0.3)
        rate = rng.normal(0.0, 0.3, nb.n) * (psi != 0)
        y = tuple(psi) + (0.0,) * (N - nb.n) + tuple(rate) + (0.0,) * (N - nb.n)
        q, v = state_of(nb, y)
        modes = np.zeros(N, dtype=np.int64)
        modes[:nb.n] = np.sign(psi)
        offsets, back = handback(bodies_of(nb, _mu(bodies)), q, v, modes, nb.n)
        np.testing.assert_allclose(back, y, atol=1e-12)
        np.testing.assert_allclose(offsets[1:nb.n], nb.off[1:nb.n], atol=1e-12)


def test_a_stack_in_motion_is_handed_back_while_the_ground_asks_more_than_its_least_friction():
    """The friction clause of the hand-back is a resting stack's: two drums rocking together on the lower one's
    corner, their joint sticking, under 0.45 g held (above the joint's 0.4) are handed back within a few steps, still
    rocking, and the exact model then follows the joint's demand (the rule before this one held them until the ground
    asked for less)."""
    nb = nbm.n_block([StackBody(0.6, 1.5, 2250.0, 0.9), StackBody(0.55, 1.2, 1650.0, 0.4)])
    start = [0.0] * (2 * N)
    start[0], start[N] = 0.02, 0.2                       # the lower drum's rotation [rad] and rate [rad/s]
    out = simulate_stack_contact(nb, (0.9, 0.4), np.full(60, 0.45 * G), DT, start=tuple(start))
    assert out.rested and out.standing == 2
    assert out.t_end_s < 0.01                           # the record runs to 0.295 s
    assert out.handback[0] > 0.02 and out.handback[N] > 0.0     # rocking on, the joint shut (its psi 0)
    assert out.handback[1] == 0.0
