"""The closed-form flights of an impact cascade (pipeline.rocking.planar.chatter) against stepped flights and
solve_ivp."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pipeline.rocking.planar.chatter import flight, flight_peak
from pipeline.rocking.references.reference import rock_reference
from pipeline.rocking.settings import SimulationConfig
from pipeline.rocking.simulate import rock

G81 = 9.81
CLOSED = SimulationConfig()
STEPPED = dataclasses.replace(SimulationConfig(), closed_form_chatter=False)


def p_block(p, alpha, e):
    """A block given by p and alpha (R from p^2 = 3 g / (4 R))."""
    return dict(p=p, alpha=alpha, R_m=3 * G81 / (4 * p * p), e=e, g_ms2=G81)


@pytest.mark.parametrize("w, g0, g1, k", [(1e-3, 2.0, 0.0, 0.0), (1e-3, 2.0, 40.0, 0.0), (1e-3, 2.0, -40.0, 5.0),
                                          (2e-5, 0.3, 5.0, 20.0), (5e-2, 8.0, -300.0, 60.0), (1e-2, 1.0, 3.0, 1e-12)])
def test_flight_matches_an_integrated_flight(w, g0, g1, k):
    """Return time, return speed and peak of u'' = -(g0 + g1 t) + k u from (0, w), against solve_ivp's events."""
    def returns(t, y):
        return y[0]

    def turns(t, y):
        return y[1]

    returns.terminal, returns.direction = True, -1.0
    sol = solve_ivp(lambda t, y: [y[1], -(g0 + g1 * t) + k * y[0]], (0.0, 10.0), [0.0, w], method="DOP853",
                    rtol=1e-13, atol=1e-18, events=[returns, turns], first_step=1e-9 * w / g0)
    fl = flight(w, g0, g1, k, 10.0)
    tau = float(sol.t_events[0][0])
    assert fl.tau == pytest.approx(tau, rel=1e-10)
    assert fl.w_return == pytest.approx(-float(sol.y_events[0][0][1]), rel=1e-9)
    assert flight_peak(w, g0, g1, k, fl.tau) == pytest.approx(float(sol.y_events[1][0][0]), rel=1e-10)
    assert flight(w, g0, g1, k, 0.5 * tau).tau < 0          # it does not return within half its time


def test_a_flight_that_does_not_return_is_refused():
    """A deceleration that turns into a push before the block comes back: no flight."""
    assert flight(1.0, 1.0, -1.0, 0.0, 100.0).tau < 0


def _ground_then_still(kind, n=4001, dt=0.005):
    """A one-sine pulse that sets the block rocking (166 impacts, the last at 13.1 s), then a tail the cascade
    plays out in."""
    t = np.arange(n) * dt
    pulse = t < 0.8
    a = np.where(pulse, 0.3 * G81 * np.sin(2 * np.pi * t / 0.8), 0.0)
    if kind == "constant tail":
        a[~pulse] = 0.01 * G81
    elif kind == "noisy tail":
        a[~pulse] = 0.03 * G81 * np.random.default_rng(3).standard_normal(int((~pulse).sum()))
    return a, dt


@pytest.mark.parametrize("kind", ["still tail", "constant tail", "noisy tail"])
@pytest.mark.parametrize("linear", [False, True])
def test_closed_form_cascade_matches_stepped_flights(kind, linear):
    """Stepped flights and Newton-located impacts (the reference tier's way) are the second algorithm: the same
    impacts, the same rest, the same history to within the integration tolerance."""
    a, dt = _ground_then_still(kind)
    b = p_block(2.2, 0.2, 0.92)
    closed = rock(a, dt, linear=linear, history=True, log_impacts=5000, settings=CLOSED, **b)
    stepped = rock(a, dt, linear=linear, history=True, log_impacts=5000, settings=STEPPED, **b)
    assert closed.n_impacts > 20                        # a real cascade
    assert not np.array_equal(closed.impacts, stepped.impacts)  # the closed form took part
    assert closed.overturned == stepped.overturned
    assert abs(closed.n_impacts - stepped.n_impacts) <= 1
    assert closed.mode_end == stepped.mode_end
    n = min(closed.n_impacts, stepped.n_impacts)
    np.testing.assert_allclose(closed.impacts[:n, 0], stepped.impacts[:n, 0], rtol=0, atol=1e-6)
    assert closed.theta_max == pytest.approx(stepped.theta_max, rel=1e-6)
    np.testing.assert_allclose(closed.theta, stepped.theta, rtol=0, atol=1e-6 * b["alpha"])


@pytest.mark.parametrize("e", [0.85, *(pytest.param(e, marks=pytest.mark.slow) for e in (0.95, 1.0))])   # 5.5, 7 s
def test_cascade_agrees_with_the_solve_ivp_reference(e):
    """Impacts and peak rotation of a block set rocking by a pulse, against the independent solve_ivp solver
    (DOP853, every flight integrated): the closed-form cascade is as close to it as the stepped one."""
    a, dt = _ground_then_still("noisy tail")
    b = p_block(2.2, 0.2, e)
    closed = rock(a, dt, settings=CLOSED, **b)
    stepped = rock(a, dt, settings=STEPPED, **b)
    ref = rock_reference(a, dt, p=b["p"], alpha=b["alpha"], e=e, g=G81)
    assert closed.overturned == stepped.overturned == ref.overturned
    assert closed.theta_max == pytest.approx(ref.theta_max_ratio, rel=1e-4)
    assert abs(closed.theta_max - ref.theta_max_ratio) <= abs(stepped.theta_max - ref.theta_max_ratio) + 1e-6
    assert abs(closed.n_impacts - ref.n_impacts) <= abs(stepped.n_impacts - ref.n_impacts) + 1


def test_cascade_hands_back_where_the_ground_lifts_the_block_again():
    """A second pulse arrives while the first cascade plays out in closed form: the closed form stops where the
    ground would push the block off its pivot's side, and the stepped kernel goes on; both paths agree."""
    a, dt = _ground_then_still("still tail")
    t = np.arange(a.size) * dt
    second = (t > 12.95) & (t < 13.75)
    a[second] = -0.3 * G81 * np.sin(2 * np.pi * (t[second] - 12.95) / 0.8)
    b = p_block(2.2, 0.2, 0.92)
    closed = rock(a, dt, history=True, log_impacts=5000, settings=CLOSED, **b)
    stepped = rock(a, dt, history=True, log_impacts=5000, settings=STEPPED, **b)
    assert closed.impacts[-1, 0] > 13.75                 # the second pulse set it rocking again
    assert closed.overturned == stepped.overturned
    assert abs(closed.n_impacts - stepped.n_impacts) <= 1
    np.testing.assert_allclose(closed.theta, stepped.theta, rtol=0, atol=1e-6 * b["alpha"])


@pytest.mark.parametrize("stop_mu", [0.17, 0.18])
def test_cascade_keeps_the_friction_check(stop_mu):
    """A block rocking in tiny flights (e = 1: they never die out) under a slowly rising ground: the pivot's
    friction demand climbs to ``stop_mu`` mid-cascade, and the closed form hands over to the stepped kernel,
    which stops there for the contact model, within one flight (2.7e-4 s here) of the stepped path alone."""
    n, dt = 2001, 0.005
    a = 0.15 * G81 * np.arange(n) * dt / 10.0
    b = p_block(2.2, 0.2, 1.0)
    w0 = 3e-4 * b["p"] * b["alpha"]
    closed = rock(a, dt, settings=CLOSED, omega0=w0, stop_mu=stop_mu, **b)
    stepped = rock(a, dt, settings=STEPPED, omega0=w0, stop_mu=stop_mu, **b)
    free = rock(a, dt, settings=CLOSED, omega0=w0, **b)
    assert free.n_impacts > 10000 and free.friction_demand > stop_mu   # the demand is met mid-cascade
    assert 1.0 < closed.t_stop < 9.0
    assert closed.t_stop == pytest.approx(stepped.t_stop, abs=1e-3)
    assert closed.status == stepped.status
    assert closed.friction_demand == pytest.approx(stop_mu, abs=1e-3)


def test_mirrored_ground_mirrors_the_cascade():
    """Symmetry: -a_h gives -theta, impacts and rest alike, with the cascade in closed form."""
    a, dt = _ground_then_still("noisy tail")
    b = p_block(2.2, 0.2, 0.92)
    plus = rock(a, dt, history=True, settings=CLOSED, **b)
    minus = rock(-a, dt, history=True, settings=CLOSED, **b)
    assert plus.n_impacts == minus.n_impacts
    np.testing.assert_allclose(plus.theta, -minus.theta, rtol=0, atol=1e-12)
    assert math.isclose(plus.theta_max, minus.theta_max, rel_tol=1e-12)
