"""One step's frictional contact problem (:mod:`pipeline.rocking.solids.contact_problem`): its Delassus matrix against
J M^-1 J^T built from the rigid body's kinematics, its generalized Jacobian against finite differences, and its
solutions against Coulomb's law and Signorini's condition checked contact by contact (not through the natural map
the solver iterates)."""

from __future__ import annotations

import numpy as np
import pytest

from pipeline.rocking.solids import contact_problem as cp

#: A 0.5 x 0.5 x 3 m statue (the slender case whose edge took 380 sweeps a step) and a 0.45 x 0.9 x 1.98 m cabinet:
#: half sizes [m].
BODIES = {"statue": (0.25, 0.25, 1.5), "cabinet": (0.225, 0.45, 0.99)}
SCALE = 9.80665 * 5e-4          # the step's weight impulse g h [m s-1]


def _inertia(b, d, h):
    return np.array([(d * d + h * h) / 3.0, (b * b + h * h) / 3.0, (b * b + d * d) / 3.0])


def _corners(b, d, h, n_c):
    return np.array([[b, d, -h], [b, -d, -h], [-b, d, -h], [-b, -d, -h]])[:n_c].copy()


def _skew(r):
    return np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])


def _jacobian_of_contacts(arms):
    """u_c = v + w x r_c = [1, -[r_c]x] (v, w): the contacts' velocity Jacobian."""
    return np.vstack([np.hstack([np.eye(3), -_skew(r)]) for r in arms])


def _tilted(arms, rng):
    """The arms turned by a random small rotation (the body leaning), as the stepping gives them."""
    a = rng.normal(size=3) * 0.2
    k = _skew(a / np.linalg.norm(a))
    rot = np.eye(3) + np.sin(np.linalg.norm(a)) * k + (1 - np.cos(np.linalg.norm(a))) * k @ k
    return arms @ rot.T


@pytest.mark.parametrize("n_c", [1, 2, 4])
@pytest.mark.parametrize("body", sorted(BODIES))
def test_the_delassus_matrix_is_j_m_inverse_j_transposed(body, n_c):
    rng = np.random.default_rng(n_c)
    inertia = _inertia(*BODIES[body])
    arms = _tilted(_corners(*BODIES[body], n_c), rng)
    inv_i = np.diag(1.0 / inertia)
    j = _jacobian_of_contacts(arms)
    expected = j @ np.diag(np.r_[1.0, 1.0, 1.0, 1.0 / inertia]) @ j.T
    got = np.empty((3 * n_c, 3 * n_c))
    cp.delassus(inv_i, arms, n_c, got, np.empty((3, 3)))
    np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("seed", range(6))
def test_the_natural_maps_jacobian_is_its_derivative(seed):
    """At a point where the map is smooth (every contact's trial impulse away from the cone's edges), the Jacobian
    equals central differences."""
    rng = np.random.default_rng(seed)
    n_c, mu = 2, 0.5
    inertia = _inertia(*BODIES["cabinet"])
    arms = _tilted(_corners(*BODIES["cabinet"], n_c), rng)
    m = 3 * n_c
    big = np.empty((m, m))
    cp.delassus(np.diag(1.0 / inertia), arms, n_c, big, np.empty((3, 3)))
    q, pv = rng.normal(size=m) * 0.1, np.abs(rng.normal(size=m)) * 0.1
    rho = np.full(n_c, 0.2)
    f, jac, dp = np.empty(m), np.empty((m, m)), np.empty((3, 3))
    cp._natural_map(big, q, pv, rho, mu, n_c, f, jac, dp, True)
    fd = np.empty((m, m))
    for k in range(m):
        up, down = pv.copy(), pv.copy()
        up[k] += 1e-7
        down[k] -= 1e-7
        f_up, f_down = np.empty(m), np.empty(m)
        cp._natural_map(big, q, up, rho, mu, n_c, f_up, jac.copy(), dp, False)
        cp._natural_map(big, q, down, rho, mu, n_c, f_down, jac.copy(), dp, False)
        fd[:, k] = (f_up - f_down) / 2e-7
    np.testing.assert_allclose(jac, fd, atol=1e-6)


def _problem(rng, body, n_c):
    """A step's contact problem: the body leaning on ``n_c`` of its base corners, approaching the ground, moving
    sideways and turning."""
    inertia = _inertia(*BODIES[body])
    arms = _tilted(_corners(*BODIES[body], n_c), rng) if n_c < 4 else _corners(*BODIES[body], n_c)
    v = rng.normal(size=3) * 0.02
    v[2] = -abs(v[2]) - 0.005
    w = rng.normal(size=3) * 0.02
    return inertia, arms, v, w


def check_coulomb(inertia, arms, v0, w0, p, v, w, mu, *, tol, inv_i=None):
    """Each contact of the solution, checked on its own: the impulses are what moved the body from (v0, w0) to
    (v, w); P_n >= 0 and u_n >= 0, one of them 0; |P_t| <= mu P_n; a contact that slips is pushed by the largest
    friction straight against its slip; one inside the cone does not slip. ``inv_i``: the inverse inertia as a
    matrix (default: of the principal moments ``inertia``)."""
    j = _jacobian_of_contacts(arms)
    inverse = np.eye(6)
    inverse[3:, 3:] = np.diag(1.0 / inertia) if inv_i is None else inv_i
    moved = np.r_[v0, w0] + inverse @ j.T @ p[: len(arms)].ravel()
    np.testing.assert_allclose(np.r_[v, w], moved, atol=tol)
    u = (j @ np.r_[v, w]).reshape(-1, 3)
    for pc, uc in zip(p[: len(arms)], u):
        slip, push = np.hypot(uc[0], uc[1]), np.hypot(pc[0], pc[1])
        assert pc[2] >= -tol and uc[2] >= -tol and min(pc[2], abs(uc[2])) <= tol
        assert push <= mu * pc[2] + tol
        if slip > 100 * tol:
            np.testing.assert_allclose(pc[:2], -mu * pc[2] * uc[:2] / slip, atol=10 * tol)
        elif push < mu * pc[2] - 100 * tol:
            assert slip <= 100 * tol


@pytest.mark.parametrize("n_c", [1, 2, 4])
@pytest.mark.parametrize("body", sorted(BODIES))
@pytest.mark.parametrize("mu", [0.3, 0.7])
def test_a_solved_step_obeys_coulomb_and_signorini_at_every_contact(body, n_c, mu):
    """20 random steps each: every converged one obeys the law; a step flagged at the cap is one the sweeps alone,
    from no impulse and without a cap, also take more than MAX_SWEEPS to converge."""
    rng = np.random.default_rng(7 * n_c + int(10 * mu))
    for _ in range(20):
        inertia, arms, v0, w0 = _problem(rng, body, n_c)
        inv_i, u_before = np.diag(1.0 / inertia), np.full(n_c, -0.01)
        v, w, p = v0.copy(), w0.copy(), np.zeros((n_c, 3))
        taken = cp.solve_contacts(v, w, inv_i, arms, n_c, u_before, mu, 0.0, SCALE, p, cp.workspace(n_c))
        if taken > 0:
            check_coulomb(inertia, arms, v0, w0, p, v, w, mu, tol=1e-7 * SCALE * 10)
            continue
        work = cp.workspace(n_c)
        cp._step_sizes(inv_i, arms, n_c, work.block, work.cone, work.rho)
        alone = cp.sweep_contacts(v0.copy(), w0.copy(), inv_i, arms, n_c, u_before, mu, 0.0, SCALE,
                                  np.zeros((n_c, 3)), work, 100 * cp.MAX_SWEEPS)
        assert alone < 0 or alone > cp.MAX_SWEEPS


def test_newtons_start_leaves_the_sweeps_almost_nothing_on_a_slender_edge():
    """The statue leaning 0.05 rad on one base edge (two contacts, the Delassus matrix's nonzero eigenvalues 0.04
    to 12), rocking about it and sliding toward it: from Newton's start the sweeps converge at once, where from no
    impulse they take over a thousand; both end at the same velocity."""
    b, d, h = BODIES["statue"]
    inertia = _inertia(b, d, h)
    inv_i = np.diag(1.0 / inertia)
    tilt = 0.05
    turn = np.array([[np.cos(tilt), 0.0, np.sin(tilt)], [0.0, 1.0, 0.0], [-np.sin(tilt), 0.0, np.cos(tilt)]])
    arms = np.array([[b, d, -h], [b, -d, -h]]) @ turn.T
    v0, w0, u_before = np.array([0.01, 0.0, -0.005]), np.array([0.0, 0.02, 0.003]), np.full(2, -0.01)
    v, w, p = v0.copy(), w0.copy(), np.zeros((2, 3))
    assert cp.solve_contacts(v, w, inv_i, arms, 2, u_before, 0.7, 0.0, SCALE, p, cp.workspace(2)) == 1
    work = cp.workspace(2)
    cp._step_sizes(inv_i, arms, 2, work.block, work.cone, work.rho)
    plain_v, plain_w = v0.copy(), w0.copy()
    sweeps = cp.sweep_contacts(plain_v, plain_w, inv_i, arms, 2, u_before, 0.7, 0.0, SCALE, np.zeros((2, 3)), work,
                               100 * cp.MAX_SWEEPS)
    assert sweeps > 1000
    np.testing.assert_allclose(np.r_[v, w], np.r_[plain_v, plain_w], atol=1e-8)
    check_coulomb(inertia, arms, v0, w0, p, v, w, 0.7, tol=1e-7 * SCALE * 10)


def test_a_pivot_passing_to_the_next_rim_point_is_solved_from_another_start():
    """A 0.26 x 0.8 m cylinder (its rim as 32 points) leaning between two neighbours 2.5 cm apart, its weight on the
    first at the last step (the warm start): the solution carries it on the second alone, the first lifting. Newton
    from the warm start stalls and the sweeps take 4,785 to get there; Newton from the weight on the second contact
    converges: the step ends converged (before: at the cap, its velocity and rate up to 2.6e-4 off), at the
    sweeps' own velocity, obeying Coulomb's law and Signorini's condition at both contacts."""
    r, hh, mu = 0.13, 0.4, 0.55
    inertia = np.array([(3 * r * r + 4 * hh * hh) / 12, (3 * r * r + 4 * hh * hh) / 12, r * r / 2])
    inv_i = np.diag(1.0 / inertia)
    angle = np.radians([45.0, 45.0 + 360.0 / 32])
    arms = np.c_[r * np.cos(angle), r * np.sin(angle), np.full(2, -hh)]
    v0, w0 = np.array([0.004549, 0.005938, -0.002107]), np.array([-0.01164, 0.009242, -0.0006043])
    warm = np.array([[-0.0009385, -0.0009940, 0.004052], [0.0, 0.0, 0.0]])
    u_before = np.full(2, -0.01)
    v, w, p = v0.copy(), w0.copy(), warm.copy()
    taken = cp.solve_contacts(v, w, inv_i, arms, 2, u_before, mu, 0.0, SCALE, p, cp.workspace(2))
    assert 0 < taken <= (cp.NEWTON_ROUNDS + 2) * cp.SWEEPS_PER_ROUND
    work = cp.workspace(2)
    cp._step_sizes(inv_i, arms, 2, work.block, work.cone, work.rho)
    plain_v, plain_w = v0.copy(), w0.copy()
    sweeps = cp.sweep_contacts(plain_v, plain_w, inv_i, arms, 2, u_before, mu, 0.0, SCALE, warm.copy(), work,
                               100 * cp.MAX_SWEEPS)
    assert sweeps > cp.MAX_SWEEPS
    np.testing.assert_allclose(np.r_[v, w], np.r_[plain_v, plain_w], atol=1e-8)
    assert not p[0].any() and p[1, 2] > 0.0
    check_coulomb(inertia, arms, v0, w0, p, v, w, mu, tol=1e-7 * SCALE * 10)


def _stored_steps(path):
    with np.load(path) as z:
        return {k: z[k] for k in z.files}


@pytest.fixture(scope="module")
def flat_base_steps(data_dir):
    return _stored_steps(data_dir / "contact" / "flat_base_steps.npz")


@pytest.fixture(scope="module")
def rim_arc_steps(data_dir):
    return _stored_steps(data_dir / "contact" / "rim_arc_steps.npz")


def _solve_stored(z, k):
    """Solve stored step ``k`` from its warm start; check it converged and obeys Coulomb's law and Signorini's
    condition at every contact."""
    n_c, mu, e_n, scale = int(z["n_contacts"][k]), float(z["mu"][k]), float(z["e_n"][k]), float(z["scale_ms"][k])
    arms = np.ascontiguousarray(z["arms_m"][k, :n_c])
    v0, w0, inv_i = z["v_free_ms"][k], z["w_free_rads"][k], z["inv_inertia"][k]
    v, w, p = v0.copy(), w0.copy(), np.ascontiguousarray(z["warm"][k, :n_c])
    taken = cp.solve_contacts(v, w, inv_i, arms, n_c, np.ascontiguousarray(z["u_before_ms"][k, :n_c]), mu, e_n,
                              scale, p, cp.workspace(n_c))
    assert 0 < taken < cp.MAX_SWEEPS
    check_coulomb(None, arms, v0, w0, p, v, w, mu, tol=1e-7 * scale * 10, inv_i=inv_i)


@pytest.mark.parametrize("k", range(4))
def test_a_base_on_many_rim_points_is_solved_from_the_side_it_tips_toward(flat_base_steps, k):
    """Four steps of cylinders with the base on 18-32 rim points (real runs, tests/data/contact): beyond the
    contacts Newton takes, the sweeps alone ended each at the cap; Newton on the contacts farthest toward the body's
    free horizontal velocity gives a start from which the sweeps converge, and the solution obeys Coulomb's law and
    Signorini's condition at every contact."""
    _solve_stored(flat_base_steps, k)


@pytest.mark.parametrize("k", range(4))
def test_a_cylinder_on_an_arc_of_its_rim_is_solved(rim_arc_steps, k):
    """Four steps of a cylinder barely tilted, on 4, 5, 8 and 15 nearly collinear rim points (a real run,
    tests/data/contact): each ended at the cap when Newton took at most four contacts and ranked them only by the
    free horizontal velocity; with Newton on up to eight contacts together, and on the contacts that approach the
    ground fastest, each converges, and the solution obeys Coulomb's law and Signorini's condition at every
    contact."""
    _solve_stored(rim_arc_steps, k)
