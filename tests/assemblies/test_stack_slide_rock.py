"""The stack's contact model (pipeline.assemblies.stack_contact) where two blocks rock on a base corner while the
upper one slides on the lower's top face: against the slide-rock equations in closed form (Lagrange's, integrated by
scipy; tests/support/slide_rock_reference.py), which a Newton-Euler solve derives again. This is the motion that makes
a slipping column costly (docs/validation.md: the two drums at mu 0.5)."""

from __future__ import annotations

import numpy as np
import pytest
from slide_rock_reference import G, SlideRock, accelerations, newton_euler, slide_rock

from pipeline.assemblies import n_block as nbm
from pipeline.assemblies.stack import StackBody
from pipeline.assemblies.stack_contact import simulate_stack_contact

DT = 0.005
RHO = 2500.0


def _stack(mu_joint: float) -> SlideRock:
    """A 0.5 x 1.5 m block under a 0.5 x 1.0 m block, friction ``mu_joint`` between them and 0.9 on the floor."""
    return SlideRock(0.25, 0.75, RHO * 0.5 * 1.5, 0.25, 0.5, RHO * 0.5 * 1.0, mu_joint, 0.9)


def test_the_equations_are_newton_eulers():
    """The slide-rock equations' accelerations and joint force equal a Newton-Euler solve's (the contact forces
    unknowns) at random states, stacks and grounds."""
    rng = np.random.default_rng(5)
    for _ in range(200):
        s = SlideRock(*rng.uniform(0.1, 0.5, 1), *rng.uniform(0.3, 1.5, 1), *rng.uniform(100, 2000, 1),
                      *rng.uniform(0.1, 0.5, 1), *rng.uniform(0.3, 1.5, 1), *rng.uniform(100, 2000, 1),
                      *rng.uniform(0.05, 0.8, 1), 0.9)
        state = (rng.choice([-1.0, 1.0]), rng.choice([-1.0, 1.0]), *rng.uniform(-0.3, 0.3, 1),
                 *rng.uniform(-1.0, 1.0, 1), *rng.uniform(-0.2, 0.2, 1), *rng.uniform(-0.5, 0.5, 1),
                 *rng.uniform(-6.0, 6.0, 1), *rng.uniform(-3.0, 3.0, 1))
        lagrange, newton = accelerations(s, *state), newton_euler(s, *state)
        assert np.allclose(lagrange, newton, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("mu_joint, ah_g, t_end_s", [(0.1, 0.6, 0.25), (0.05, 0.7, 0.2), (0.1, -0.6, 0.25)])
def test_where_the_stack_rocks_with_its_joint_sliding_the_contact_model_follows_the_equations(mu_joint, ah_g,
                                                                                             t_end_s):
    """A constant ground acceleration from rest that tips the stack at once while its joint slides (the reference's
    assumptions checked along its whole motion): the contact model's rotation and slip at the end, at its 0.25 ms
    steps, are the equations' within 1e-3 of them, and its joint stays shut; the mirrored ground mirrors the motion."""
    s = _stack(mu_joint)
    direction = -np.sign(ah_g)                   # the ground pushed one way throws the stack the other
    ref = slide_rock(s, ah_g * G, t_end_s, pivot=direction, slip=direction)
    assert ref.holds
    nb = nbm.n_block([StackBody(2 * s.b0, 2 * s.h0, s.m0, s.mu_floor), StackBody(2 * s.b1, 2 * s.h1, s.m1, mu_joint)])
    out = simulate_stack_contact(nb, (s.mu_floor, mu_joint), np.full(int(t_end_s / DT) + 20, ah_g * G), DT,
                                 hand_back=False, until_s=t_end_s)
    assert out.t_end_s == pytest.approx(t_end_s, abs=1e-9)
    assert out.peak_rad[0] == pytest.approx(abs(ref.phi_rad), rel=1e-3)
    assert out.offsets_m[1] == pytest.approx(ref.u_m, rel=1e-3)
    assert out.peak_rad[1] < 1e-5                 # the upper block turned with the lower: the joint stayed shut
