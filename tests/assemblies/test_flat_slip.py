"""The level stack's slip (pipeline.assemblies.flat_slip): against Coulomb's sliding block solved by the planar
sliding kernel (a second algorithm: one block, a statue on a plinth that never moves, a stack sliding as one), against
the stack's contact model on the same slips of real records (a third), the ground's sign reversed (symmetry), the
exact boundary |a_h| = mu g, and the cases it must leave to the contact model (a joint that would open, a ground in
flight)."""

from __future__ import annotations

import numpy as np
import pytest

from pipeline.assemblies import n_block as nbm
from pipeline.assemblies import n_block_verdicts, stack_scene, two_block
from pipeline.assemblies.flat_slip import UNFINISHED, simulate_flat_slip
from pipeline.assemblies.n_block_verdicts import judge_n_block
from pipeline.assemblies.stack import StackBody, StackPlace, slips_at_rest
from pipeline.assemblies.two_block_verdicts import judge_two_block
from pipeline.config import Config
from pipeline.records.loader import iter_records
from pipeline.rocking.codes import STATUS_GROUND_FLIGHT, Verdict
from pipeline.rocking.simulate import slide

G = 9.80665
DT = 0.005
#: a ground friction no record here reaches: the plinth never slides
STICKY = 5.0
#: a squat statue (it cannot tip below 0.6 g) on a wide, squat plinth
STATUE = StackBody(0.6, 1.0, 1500.0, 0.2)
PLINTH = StackBody(2.0, 0.5, 5000.0, STICKY)


@pytest.fixture(scope="module")
def grounds(records_dir):
    """The first horizontal of eight bundled records of at most 40 s, scaled to 0.45 g [m s-2], and dt [s]."""
    out = []
    for rec in iter_records(records_dir, config=Config()):
        a = rec.horizontal_ms2[0]
        if a.size * rec.dt_s <= 40.0:
            out.append((rec.record_id, a * 0.45 * G / np.abs(a).max(), rec.dt_s))
        if len(out) == 8:
            break
    return out


def _slide_end(ah, dt, mu):
    """The net slip of one block with friction ``mu`` on the ground ``ah`` [m] by the planar sliding kernel, the
    record followed by 10 s of still ground (the stacks' slips are followed after the record to their stop)."""
    return slide(np.concatenate([ah, np.zeros(int(10.0 / dt))]), dt, mu=mu).sliding_end_m


def test_one_block_slides_as_the_sliding_kernel(grounds):
    """One block on the ground, episode after episode from each instant the ground passes mu g: the slip along the
    ground equals the planar sliding kernel's to 1e-9 m + 1e-7 of it."""
    block = StackBody(0.8, 0.5, 400.0, 0.25)
    for rid, ah, dt in grounds:
        verdicts = judge_n_block(nbm.n_block([block]), ah, dt, mu=(block.mu,))
        want = _slide_end(ah, dt, block.mu)
        assert verdicts.verdicts == (int(Verdict.stands),)
        assert abs(verdicts.offset_m[0] - want) <= 1e-9 + 1e-7 * abs(want), rid


def test_a_statue_on_a_plinth_that_holds_slides_as_one_block(grounds):
    """The statue slides on a plinth that neither slides nor tips: its offset on the plinth equals the sliding
    kernel's slip of one block of the statue's friction, and the plinth stays where it stood."""
    for rid, ah, dt in grounds:
        verdicts = judge_n_block(nbm.n_block([PLINTH, STATUE]), ah, dt, mu=(PLINTH.mu, STATUE.mu))
        want = _slide_end(ah, dt, STATUE.mu)
        assert verdicts.verdicts == (int(Verdict.stands),) * 2
        assert verdicts.offset_m[0] == 0.0
        assert abs(verdicts.offset_m[1] - want) <= 1e-9 + 1e-7 * abs(want), rid


def test_a_stack_whose_ground_is_slipperier_slides_as_one(grounds):
    """Less friction on the ground than at the joint: the stack slides as one block on the ground's friction, its
    joint shut where it was."""
    plinth = PLINTH._replace(mu=0.15)
    for rid, ah, dt in grounds:
        verdicts = judge_n_block(nbm.n_block([plinth, STATUE]), ah, dt, mu=(plinth.mu, STATUE.mu))
        want = _slide_end(ah, dt, plinth.mu)
        assert abs(verdicts.offset_m[0] - want) <= 1e-9 + 1e-7 * abs(want), rid
        assert verdicts.offset_m[1] == 0.0


def test_the_ground_reversed_mirrors_the_slip(grounds):
    """The ground's sign reversed: every slip reversed, to rounding."""
    nb = nbm.n_block([PLINTH, STATUE])
    for rid, ah, dt in grounds[:4]:
        plus = judge_n_block(nb, ah, dt, mu=(PLINTH.mu, STATUE.mu))
        minus = judge_n_block(nb, -ah, dt, mu=(PLINTH.mu, STATUE.mu))
        assert minus.offset_m[1] == pytest.approx(-plus.offset_m[1], abs=1e-12), rid
        assert minus.slide_m == pytest.approx(plus.slide_m, abs=1e-12), rid


@pytest.mark.parametrize("family", ["statue", "two-joints"])
def test_the_slips_agree_with_the_contact_model(grounds, family, monkeypatch):
    """The whole record judged with the level stack's slips, and again with the contact model following every slip
    (a second algorithm, time stepping at 0.25 ms): each joint's final offset and largest slip agree within 1 % of
    the largest + 50 um. Four blocks whose two upper joints have less friction than the lower: slips at two joints
    at once."""
    if family == "statue":
        bodies = [PLINTH, STATUE]
    else:
        bodies = [StackBody(1.5, 0.4, 3000.0, STICKY), StackBody(1.2, 0.4, 2000.0, 0.22),
                  StackBody(1.0, 0.4, 1500.0, 0.2), StackBody(0.8, 0.4, 1000.0, 0.25)]
    nb, mu = nbm.n_block(bodies), tuple(b.mu for b in bodies)
    level = [judge_n_block(nb, ah, dt, mu=mu) for _, ah, dt in grounds]
    monkeypatch.setattr(n_block_verdicts, "_level_slip", lambda *args: None)
    contact = [judge_n_block(nb, ah, dt, mu=mu) for _, ah, dt in grounds]
    for (rid, _, _), ours, other in zip(grounds, level, contact):
        assert ours.verdicts == other.verdicts == (int(Verdict.stands),) * nb.n, rid
        tol = 0.01 * max(other.slide_m) + 5e-5
        assert max(other.slide_m) > 1e-3, rid                          # the joints slipped
        assert np.abs(np.subtract(ours.offset_m, other.offset_m)).max() <= tol, rid
        assert np.abs(np.subtract(ours.slide_m, other.slide_m)).max() <= tol, rid


def test_a_ground_exactly_at_mu_g_slips_nothing():
    """A ground whose |a_h| reaches mu g exactly and goes back: no joint slips (|F| = mu N sticks), at no cost of the
    contact model: every offset 0."""
    t = np.arange(0.0, 2.0, DT)
    ah = STATUE.mu * G * np.clip(1.0 - np.abs(t - 0.5) / 0.4, 0.0, None)
    assert np.abs(ah).max() == STATUE.mu * G
    verdicts = judge_n_block(nbm.n_block([PLINTH, STATUE]), ah, DT, mu=(PLINTH.mu, STATUE.mu))
    assert verdicts.offset_m == (0.0, 0.0)
    assert verdicts.slide_m == ()


def test_a_slip_that_would_tip_the_statue_is_left_to_the_contact_model():
    """A slender statue (tan alpha 0.25) on a joint of mu 0.3, started slipping: the friction's moment would tip it
    (the resultant outside its base), so the model stops unfinished at once."""
    slender = StackBody(0.25, 1.0, 600.0, 0.3)
    nb = nbm.n_block([PLINTH, slender])
    t = np.arange(0.0, 1.0, DT)
    ah = np.full(t.shape, 0.4 * G)
    out = simulate_flat_slip(nb, (PLINTH.mu, slender.mu), ah, DT)
    assert out.end == UNFINISHED
    assert out.t_end_s == 0.0


def test_a_ground_falling_faster_than_gravity_is_left_to_the_contact_model():
    """The ground's g + a_v reaching 0 during a slip: the model stops unfinished, before that piece."""
    t = np.arange(0.0, 1.0, DT)
    ah = np.full(t.shape, 0.4 * G)
    av = np.where(t > 0.3, -1.2 * G, 0.0)
    out = simulate_flat_slip(nbm.n_block([PLINTH, STATUE]), (PLINTH.mu, STATUE.mu), ah, DT, av_ms2=av)
    assert out.end == UNFINISHED
    assert out.t_end_s <= 0.3 + 1e-12


def test_a_long_record_of_many_slips_keeps_its_verdict():
    """300 s of a 2 Hz, 0.3 g sine: the statue slips 1,200 times from rest, beyond the 1,000 hand-overs a stack is
    allowed regardless of its record's length (one more a sample); it stands, slid as one Coulomb block."""
    dt = 0.01
    t = np.arange(0.0, 300.0, dt)
    ah = np.where(t < t[-1], 0.3 * G * np.sin(2 * np.pi * 2.0 * t), 0.0)
    verdicts = judge_n_block(nbm.n_block([PLINTH, STATUE]), ah, dt, mu=(PLINTH.mu, STATUE.mu))
    want = _slide_end(ah, dt, STATUE.mu)
    assert verdicts.verdicts == (int(Verdict.stands),) * 2
    assert abs(verdicts.offset_m[1] - want) <= 1e-9 + 1e-7 * abs(want)


@pytest.mark.parametrize("joint_mu, at_rest", [(0.2, True), (0.3, False), (0.25, False)])
def test_slips_at_rest_where_the_slip_comes_before_the_lift(joint_mu, at_rest):
    """A statue whose joint opens at 0.25 g (half-width over the height of its centre, Housner's bound, by hand) under
    a ground ramping to 0.3 g: its joint slips first at rest where its mu is below 0.25; at mu 0.3 it lifts first;
    at 0.25 slip and lift start at the same sample, so it is not a slip at rest. A ground falling faster than gravity
    before the slip is not rest either."""
    bodies = (StackBody(1.0, 1.0, 500.0, 0.8), StackBody(0.4, 1.6, 100.0, joint_mu))
    ramp = 0.3 * G * np.linspace(0.0, 1.0, 31)
    assert slips_at_rest(bodies, ramp) is at_rest
    falling = np.where(np.arange(31) == 3, -1.1 * G, 0.0)
    assert slips_at_rest(bodies, ramp, falling) is False


def _two_block_first(bodies, ah, dt):
    """Two bodies judged without the shortcut, written out: the two-block model's verdicts, unless its run meets a
    flight or needs more friction than a joint has, then the n-block path with the bodies' friction."""
    judged = stack_scene.from_two_block(judge_two_block(two_block.two_block(*bodies), ah, dt))
    mu = tuple(b.mu for b in bodies)
    if judged.status & STATUS_GROUND_FLIGHT or any(d > m for d, m in zip(judged.demand, mu)):
        return judge_n_block(nbm.n_block(bodies), ah, dt, mu=mu)
    return judged


def test_two_bodies_that_slip_at_rest_skip_only_a_run_that_would_hand_over(grounds):
    """Where a joint of two bodies slips while the stack is still at rest (`stack.slips_at_rest`), the stack goes to
    the n-block path at once: the verdicts are those of running the two-block model first, which meets the same slip
    and hands the stack over (every field the same). The same statue with ample friction rocks without a slip: there
    the two paths differ (another model), so a shortcut taken there would fail this test."""
    slipping = (StackBody(0.7, 1.0, 1750.0, 0.5), StackBody(0.45, 1.7, 1912.5, 0.25))
    sticking = tuple(b._replace(mu=0.9) for b in slipping)
    for bodies in (slipping, sticking):
        model = stack_scene.stack_blocks(StackPlace(bodies, 1, ("plinth", "statue")))
        for rid, ah, dt in grounds:
            assert stack_scene.judge(model, ah, dt, bodies=bodies) == _two_block_first(bodies, ah, dt), rid
    assert sum(slips_at_rest(slipping, ah) for _, ah, _ in grounds) >= 4
