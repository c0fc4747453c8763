"""The stack's contact problem solved by its contacts' modes (pipeline.assemblies.stack_direct) against its laws
(Signorini's condition and Coulomb's friction at every contact) and against the second algorithm, projected
Gauss-Seidel (pipeline.assemblies.stack_contact._sweeps), on the contact problems of stacks that stand, rock on a
corner, slide at a joint and land."""

from __future__ import annotations

import numpy as np
import pytest
from stack_problems import friction, problem, velocities

from pipeline.assemblies import stack_contact as sc
from pipeline.assemblies.stack_direct import solve_direct

TOL = sc.SWEEP_TOL_MS

#: (family, psi, rates, push, mu on the ground, mu at the joints, a_h): stacks at rest, rocking, sliding, landing
AT_REST = ("statue", (0.0, 0.0), (0.0, 0.0), (0.0,) * 6, 0.6, 0.36, 1.0)
CASES = {
    "statue, its joint pushed to slide": ("statue", (0.0, 0.0), (0.0, 0.0), (0, 0, 0, 0.3, 0, 0), 0.6, 0.25, 3.0),
    "plinth rocking, statue shut on it": ("statue", (0.02, 0.0), (0.3, 0.0), (0.0,) * 6, 0.6, 0.36, 4.0),
    "plinth rocking, statue sliding": ("two", (0.01, 0.0), (0.2, 0.0), (0, 0, 0, 0.2, 0, 0), 0.5, 0.25, 4.0),
    "upper drum rocking on the lower": ("two", (0.0, 0.03), (0.0, 0.4), (0.0,) * 6, 0.5, 0.25, -3.0),
    "upper drum landing on the lower": ("two", (0.0, 1e-7), (0.0, -0.5), (0.0,) * 6, 0.5, 0.25, 0.0),
    "both drums rocking": ("two", (-0.02, 0.015), (-0.2, 0.35), (0.0,) * 6, 0.5, 0.25, 2.0),
    "three drums, the top sliding": ("three", (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0, 0, 0, 0, 0, 0, 0.3, 0, 0),
                                     0.6, 0.2, 1.5),
    "three drums, the base landing": ("three", (1e-7, 0.0, 0.0), (-0.4, 0.0, 0.0), (0.0,) * 9, 0.6, 0.36, 0.5),
}


def check_laws(bd, count, wk) -> None:
    """Signorini's condition and Coulomb's friction at every contact, to the sweeps' tolerance."""
    u, mu = velocities(count, wk), friction(bd, count, wk)
    for i in range(count):
        pn, pt, un, ut = wk.p[2 * i], wk.p[2 * i + 1], u[2 * i], u[2 * i + 1]
        assert pn >= 0.0 and abs(pt) <= mu[i] * pn                      # exactly: the cone's bounds are set
        assert un >= -TOL                                               # no approach
        assert pn * wk.w[2 * i, 2 * i] <= TOL or abs(un) <= TOL         # an impulse only where it touches
        if abs(ut) > TOL:                                               # slipping: friction full and against it
            assert abs(pt) >= mu[i] * pn * (1 - 1e-9) and pt * ut <= 0.0


def _direct(bd, count, wk) -> bool:
    return solve_direct(count, wk.w, wk.rhs, wk.kept, wk.slot, wk.body, np.asarray(bd.mu), wk.direct, wk.p, TOL)


def _swept(bd, count, wk) -> tuple[np.ndarray, np.ndarray]:
    """The sweeps' impulses and velocities, each contact's impulse also kept in its slot as the step before's."""
    assert sc._sweeps(bd, count, wk)
    check_laws(bd, count, wk)
    for i in range(count):
        wk.kept[2 * wk.slot[i]], wk.kept[2 * wk.slot[i] + 1] = wk.p[2 * i], wk.p[2 * i + 1]
    return wk.p[:2 * count].copy(), velocities(count, wk)


@pytest.mark.parametrize("name", list(CASES))
def test_with_the_modes_of_the_step_before_it_solves_at_once_as_the_sweeps_do(name):
    """The case it is for: contacts in the modes they had a step before. It keeps every law and gives the sweeps'
    velocities; the impulses of a shut face's ends may be shared out differently, not their sum."""
    bd, count, wk = problem(*CASES[name])
    assert count > 0
    swept_p, swept_u = _swept(bd, count, wk)
    assert _direct(bd, count, wk), name
    check_laws(bd, count, wk)
    np.testing.assert_allclose(velocities(count, wk), swept_u, atol=1e-7)
    # impulses compared by the velocity they give (the sweeps stop at a change of 1e-9 m/s, not of impulse)
    scale = np.diag(wk.w)[:2 * count].max()
    np.testing.assert_allclose(wk.p[:2 * count].reshape(count, 2).sum(axis=0) * scale,
                               swept_p.reshape(count, 2).sum(axis=0) * scale, rtol=0, atol=1e-7)


@pytest.mark.parametrize("name", list(CASES))
def test_from_no_impulse_it_solves_as_the_sweeps_do_or_hands_the_step_to_them(name):
    """New contacts guessed sticking, modes changed where a law breaks, at most TRIES solves: where it answers, the
    laws hold and the velocities are the sweeps'; where it does not, the sweeps take the step."""
    bd, count, wk = problem(*CASES[name])
    if _direct(bd, count, wk):
        check_laws(bd, count, wk)
        direct_u = velocities(count, wk)
        wk.kept[:] = 0.0
        np.testing.assert_allclose(direct_u, _swept(bd, count, wk)[1], atol=1e-7)
    wk.kept[:] = 0.0
    assert sc._solve(bd, count, wk)
    check_laws(bd, count, wk)


@pytest.mark.parametrize("name", ["plinth rocking, statue shut on it", "plinth rocking, statue sliding",
                                  "upper drum rocking on the lower", "both drums rocking",
                                  "three drums, the base landing"])
def test_a_guess_from_the_step_before_that_is_wrong_is_mended(name):
    """Every contact guessed sliding, the ends of a face opposite ways: the modes that break their laws are changed
    and the system solved again, to the laws and the sweeps' velocities."""
    bd, count, wk = problem(*CASES[name])
    for i in range(count):
        wk.kept[2 * wk.slot[i]], wk.kept[2 * wk.slot[i] + 1] = 1.0, 1.0 * (1 if i % 2 else -1)
    assert _direct(bd, count, wk)
    check_laws(bd, count, wk)
    direct_u = velocities(count, wk)
    wk.kept[:] = 0.0
    np.testing.assert_allclose(direct_u, _swept(bd, count, wk)[1], atol=1e-7)


def test_the_ends_of_a_shut_face_that_sticks_share_its_friction_in_proportion_to_their_normal_impulses():
    """A stack at rest: each face's two ends press and stick, and how they share the face's friction is not
    determined by the laws; the solve gives each the same share of its cone and the velocities the sweeps give."""
    bd, count, wk = problem(*AT_REST)
    assert count == 4
    swept_u = _swept(bd, count, wk)[1]
    assert _direct(bd, count, wk)
    check_laws(bd, count, wk)
    np.testing.assert_allclose(velocities(count, wk), swept_u, atol=1e-7)
    ratio = wk.p[1:2 * count:2] / wk.p[0:2 * count:2]
    np.testing.assert_allclose(ratio[0], ratio[1], rtol=1e-12)             # the ground's ends
    np.testing.assert_allclose(ratio[2], ratio[3], rtol=1e-12)             # the joint's ends
