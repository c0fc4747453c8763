"""The one Runge-Kutta step (pipeline.rocking.numerics.rk) against independent truth: the order of each method on an
equation with a closed form, the classical method against Kutta's formula written out, and scipy's own
Dormand-Prince step (``scipy.integrate._ivp.rk.rk_step`` with RK45's tableau) on the oscillator and on the rocking
equation the planar kernel steps."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate._ivp import rk as scipy_rk

from pipeline.compiled import jit
from pipeline.rocking.numerics.dopri import accel_nonlinear, dopri_step
from pipeline.rocking.numerics.rk import DOPRI54, RK4, rk_step
from pipeline.rocking.structures import GroundPiece


@jit
def _oscillator(t, y, args):
    """y'' = -w^2 y + a t (args: w, a)."""
    w, a = args
    return (y[1], -w * w * y[0] + a * t), 0.0


@jit
def _step(t, y, h, args, tableau=DOPRI54):
    f, _ = _oscillator(t, y, args)
    return rk_step(_oscillator, args, t, y, f, h, tableau)


def _scipy_step(fun, t, y, h):
    """scipy's step of RK45 (Dormand & Prince's same tableau, its sums as dot products): y_1 and the error."""
    method = scipy_rk.RK45
    k = np.empty((method.n_stages + 1, y.size))
    y_new, _ = scipy_rk.rk_step(fun, t, y, fun(t, y), h, method.A, method.B, method.C, k)
    return y_new, h * (k.T @ method.E)


@pytest.mark.parametrize("tableau, order", [(DOPRI54, 5), (RK4, 4)], ids=["DOPRI54", "RK4"])
def test_each_tableau_is_consistent_and_of_its_order(tableau, order):
    """Row sums equal the nodes, the weights sum to 1 and the error's to 0 (Hairer et al. 1993, II.1); and on
    y'' = -y (y = cos t) halving the step divides the error at t = 2 (the larger of y's and y''s) by about 2^order."""
    for row, node in zip(tableau.rows, tableau.nodes, strict=True):
        assert sum(row) == pytest.approx(node, abs=1e-15)
    assert sum(tableau.b) == pytest.approx(1.0, abs=1e-15)
    assert sum(tableau.e) == pytest.approx(0.0, abs=1e-15)
    errors = []
    for h in (0.1, 0.05):
        y = (1.0, 0.0)
        for i in range(int(round(2.0 / h))):
            y = _step(i * h, y, h, (1.0, 0.0), tableau).y
        errors.append(max(abs(y[0] - math.cos(2.0)), abs(y[1] + math.sin(2.0))))
    assert 2 ** (order - 0.5) < errors[0] / errors[1] < 2 ** (order + 0.5)


def test_the_classical_step_is_kuttas_formula():
    """One RK4 step is Kutta's formula y + h/6 (k1 + 2 k2 + 2 k3 + k4), written out here, to rounding; it has no
    error estimate."""
    rng = np.random.default_rng(11)
    for _ in range(100):
        w, a, t, h = rng.uniform(0.5, 20), rng.normal(0, 5), rng.uniform(0, 10), rng.uniform(1e-4, 0.05)
        y = np.array(rng.normal(0, 1, 2))

        def f(t_, y_, w=w, a=a):
            return np.array([y_[1], -w * w * y_[0] + a * t_])

        k1 = f(t, y)
        k2 = f(t + h / 2, y + h / 2 * k1)
        k3 = f(t + h / 2, y + h / 2 * k2)
        k4 = f(t + h, y + h * k3)
        got = _step(t, tuple(y), h, (w, a), RK4)
        assert np.allclose(got.y, y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4), rtol=1e-14, atol=1e-15)
        assert got.err == (0.0, 0.0)


def test_the_step_is_scipys_on_a_forced_oscillator():
    """The solution, its error estimate and f at the end agree with scipy's RK45 step to rounding (scipy's error
    weights are ours with the opposite sign; the error estimate, a difference of stages, to the rounding of a stage)."""
    rng = np.random.default_rng(3)
    for _ in range(200):
        w, a, t, h = rng.uniform(0.5, 20), rng.normal(0, 5), rng.uniform(0, 10), rng.uniform(1e-4, 0.05)
        y = tuple(rng.normal(0, 1, 2))
        got = _step(t, y, h, (w, a))
        y_ref, err_ref = _scipy_step(lambda t_, y_, wa=(w, a): np.array(_oscillator(t_, y_, wa)[0]), t, np.array(y), h)
        assert np.allclose(got.y, y_ref, rtol=1e-14, atol=1e-15)
        # the error is a difference of stages of size |f| h: its rounding is that size's, not its own
        assert np.allclose(got.err, -err_ref, rtol=0, atol=1e-14 * h * max(map(abs, got.f)))
        assert np.allclose(got.f, _oscillator(t + h, got.y, (w, a))[0], rtol=0, atol=0)


@pytest.mark.parametrize("linear", [False, True])
def test_the_planar_step_is_scipys_on_the_rocking_equation(linear):
    """dopri_step (the planar kernel's) against scipy's RK45 step on the rocking equation written again here
    (Makris & Roussos 2000, eqs. 1-3 and 8-9), on random states (tilts down to 1e-6 rad), steps and ground
    pieces: theta and omega to rounding, the error estimates to the rounding of a stage (1e-14 h |f|), and sin and
    cos of alpha s - theta at the end exactly."""
    rng = np.random.default_rng(7)
    for _ in range(500):
        t0 = rng.uniform(0, 10)
        t = t0 + rng.uniform(0, 0.01)
        pc = GroundPiece(0, t0, t0 + 0.01, *rng.normal(0, 3, 4), *rng.normal(0, 50, 2))
        th, om, h = rng.uniform(-0.3, 0.3) * 10 ** rng.uniform(-5, 0), rng.normal(0, 1), rng.uniform(1e-5, 1e-2)
        s, p2, alpha, g = float(rng.choice([-1.0, 1.0])), rng.uniform(1, 20), rng.uniform(0.05, 0.4), 9.80665

        def plane(t_, y_, pc=pc, s=s, p2=p2, alpha=alpha, g=g):
            ah, av = pc.a0 + pc.sa * (t_ - pc.t0), pc.v0 + pc.sv * (t_ - pc.t0)
            phi = alpha * s - y_[0]
            if linear:
                return np.array([y_[1], -p2 * ((1.0 + av / g) * phi + ah / g)])
            return np.array([y_[1], -p2 * ((1.0 + av / g) * math.sin(phi) + (ah / g) * math.cos(phi))])

        th1, om1, et, eo, acc1, sin1, cos1 = dopri_step(t, th, om, h, pc, s, p2, alpha, g, linear)
        y_ref, err_ref = _scipy_step(plane, t, np.array([th, om]), h)
        assert np.allclose((th1, om1), y_ref, rtol=1e-13, atol=1e-16)
        assert np.allclose((et, eo), -err_ref, rtol=0, atol=1e-14 * h * max(abs(om1), abs(acc1), 1.0))
        assert (sin1, cos1) == (math.sin(alpha * s - th1), math.cos(alpha * s - th1))
        assert acc1 == pytest.approx(plane(t + h, (th1, om1))[1], rel=1e-15, abs=1e-300)
        if not linear:
            assert acc1 == accel_nonlinear(sin1, cos1, pc.a0 + pc.sa * (t + h - pc.t0),
                                           pc.v0 + pc.sv * (t + h - pc.t0), p2, g)
