"""The stacks' contact model's long steps (``long_step_s`` of pipeline.assemblies.stack_contact.simulate_stack_contact,
an option, off by default): where no joint slides they follow the exact n-block model as every step short does, in
fewer steps; the check that no contact is ahead against the corner's height and speed in closed form; the options'
errors. What they cost in verdicts where joints slip is benchmarks/stack_steps.py's (docs/validation.md)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.assemblies import n_block as nbm
from pipeline.assemblies import stack_contact as sc
from pipeline.assemblies.n_block_run import FALLS_NONE, simulate_n_block
from pipeline.assemblies.stack import StackBody
from pipeline.assemblies.stack_pose import bodies_of
from pipeline.errors import ParameterError

DT = 0.005
TIMES = np.arange(0.0, 4.0, DT)
STICKY = 50.0
DRUMS = [StackBody(0.5, 0.8, 2.0, STICKY), StackBody(0.48, 0.7, 1.6, STICKY, 0.01),
         StackBody(0.46, 0.6, 1.3, STICKY, -0.02)]
STATUE = [StackBody(0.7, 1.0, 1890.0, STICKY), StackBody(0.45, 1.7, 2065.5, STICKY)]
LONG_S = 1.25e-3


def _sine(ap, tp):
    """One cycle of a sine pulse [m s-2] of period ``tp`` [s]."""
    return np.where(TIMES < tp, ap * np.sin(2 * np.pi * TIMES / tp), 0.0)


@pytest.mark.parametrize("bodies", [DRUMS[:1], STATUE, DRUMS], ids=["1", "statue", "3"])
@pytest.mark.parametrize("ap, tp", [(3.0, 0.5), (4.5, 0.5), (6.0, 0.8), (2.5, 1.0)])
def test_where_no_joint_slides_long_steps_follow_the_exact_model(bodies, ap, tp):
    """Ample friction, a pulse: with long steps the same blocks fall as in the n-block model (event-driven, its own
    impact law) and the lowest joint's peak rotation agrees within 3 % of its smaller tipping angle, as every step
    short does (tests/assemblies/test_stack_contact.py), in fewer steps."""
    nb = nbm.n_block(bodies)
    mu = tuple(b.mu for b in bodies)
    exact = simulate_n_block(nb, _sine(ap, tp), DT)
    long = sc.simulate_stack_contact(nb, mu, _sine(ap, tp), DT, hand_back=False, long_step_s=LONG_S)
    short = sc.simulate_stack_contact(nb, mu, _sine(ap, tp), DT, hand_back=False)
    assert long.standing == (exact.falls if exact.falls != FALLS_NONE else nb.n)
    if long.standing:
        assert abs(long.peak_rad[0] - exact.peak_psi_rad[0]) <= 0.03 * min(nbm.tipping_angles(nb)[0])
    assert long.steps < short.steps


def _rocking_block(phi_rad, rate_rad_s):
    """A block (half sizes b, h) turning on its right base corner at the origin by ``phi_rad`` at ``rate_rad_s``:
    its state (q, v) as the model holds it (x, z of G, rotation; clockwise positive), and its left base corner's
    height and vertical velocity in closed form."""
    b, h = 0.25, 0.8
    c, s = math.cos(phi_rad), math.sin(phi_rad)
    gx, gz = c * -b + s * h, s * b + c * h                         # G = pivot + R(phi) (-b, h)
    q = np.zeros((3, nbm.MAX_BODIES))
    v = np.zeros((3, nbm.MAX_BODIES))
    q[:, 0] = (gx, gz, phi_rad)
    v[:, 0] = (rate_rad_s * gz, -rate_rad_s * gx, rate_rad_s)       # a turn about the pivot: v_G = w x (G - P)
    left_z = 2.0 * b * s                                             # R(phi) (-2b, 0) from the pivot, its height
    return q, v, left_z, 2.0 * b * c * rate_rad_s, (b, h)


@pytest.mark.parametrize("rate", [-0.8, -0.2, 0.3])
def test_a_landing_corner_keeps_the_steps_short_within_two_long_steps_of_it(rate):
    """One block rocking back onto its left corner: the contact is ahead exactly where the corner's height plus
    twice the long step times its speed towards the ground falls to the ground (the corner's height and speed in
    closed form); a corner rising never is."""
    q, v, z, dz, (b, h) = _rocking_block(0.02, rate)
    bd = bodies_of(nbm.n_block([StackBody(2 * b, 2 * h, 1.0, STICKY)]), (STICKY,))
    cs = np.zeros((2, nbm.MAX_BODIES))
    if dz >= 0.0:
        assert sc._clear_ahead(bd, 1, q, v, cs, 10.0)
        return
    lands_in = z / -dz                                               # [s] at the present speed
    assert sc._clear_ahead(bd, 1, q, v, cs, lands_in / sc.IMPACT_SAFETY * (1.0 - 1e-6))
    assert not sc._clear_ahead(bd, 1, q, v, cs, lands_in / sc.IMPACT_SAFETY * (1.0 + 1e-6))


def test_long_steps_are_whole_divisors_of_a_sampling_interval():
    """The steps merged: the largest divisor of a sampling interval's steps that keeps the long step within its
    bound, so that no long step straddles a sample."""
    assert sc.steps_merged(20, 0.005 / 20, longest_s=1.25e-3) == 5
    assert sc.steps_merged(20, 0.005 / 20, longest_s=1e-3) == 4
    assert sc.steps_merged(40, 0.01 / 40, longest_s=1.25e-3) == 5
    assert sc.steps_merged(1, 2e-4, longest_s=1.25e-3) == 1
    assert sc.steps_merged(20, 0.005 / 20, longest_s=0.0) == 1


@pytest.mark.parametrize("options", [{"step_s": 0.0}, {"step_s": math.nan}, {"long_step_s": -1e-3},
                                     {"long_step_s": math.inf}])
def test_impossible_steps_are_refused_naming_them(options):
    nb = nbm.n_block(DRUMS[:1])
    with pytest.raises(ParameterError, match="step_s"):
        sc.simulate_stack_contact(nb, (STICKY,), _sine(3.0, 0.5), DT, **options)
