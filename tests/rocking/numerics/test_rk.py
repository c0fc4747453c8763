"""The one Runge-Kutta step (pipeline.rocking.numerics.rk) against independent truth: the order of the method on an
equation with a closed form, and the planar kernel's unrolled step against the generic step, double for double."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.compiled import jit
from pipeline.rocking.numerics.dopri import accel_nonlinear, dopri_step
from pipeline.rocking.numerics.rk import DOPRI54, rk_step
from pipeline.rocking.structures import GroundPiece


@jit
def _oscillator(t, y, args, out):
    """y'' = -w^2 y + a t (args: w, a)."""
    w, a = args
    out[0] = y[1]
    out[1] = -w * w * y[0] + a * t
    return 0.0


@jit
def _plane(t, y, args, out):
    """The rocking equation of a plane as dopri.rocking_accel writes it, its sin and cos returned."""
    pc, s, p2, alpha, g, linear = args
    ah, av = pc.a0 + pc.sa * (t - pc.t0), pc.v0 + pc.sv * (t - pc.t0)
    phi = alpha * s - y[0]
    sin_phi, cos_phi = math.sin(phi), math.cos(phi)
    out[0] = y[1]
    out[1] = -p2 * ((1.0 + av / g) * phi + ah / g) if linear else accel_nonlinear(sin_phi, cos_phi, ah, av, p2, g)
    return sin_phi, cos_phi


def _step(fun, args, t, y, h):
    k = np.zeros((DOPRI54.b.size, y.size))
    fun(t, y, args, k[0])
    y_new, err = np.empty(y.size), np.empty(y.size)
    kept = rk_step(fun, args, t, y, h, k, np.empty(y.size), y_new, err, DOPRI54)
    return y_new, err, k, kept


def test_the_tableau_is_consistent_and_of_order_five():
    """Row sums equal the nodes, the weights sum to 1 and the error's to 0 (Hairer et al. 1993, II.1); and on
    y'' = -y (y = cos t) halving the step divides the error at t = 2 (the larger of y's and y''s) by about 2^5."""
    assert np.allclose(DOPRI54.rows.sum(axis=1), DOPRI54.nodes, rtol=0, atol=1e-15)
    assert DOPRI54.b.sum() == pytest.approx(1.0, abs=1e-15)
    assert DOPRI54.e.sum() == pytest.approx(0.0, abs=1e-15)
    errors = []
    for h in (0.1, 0.05):
        y = np.array([1.0, 0.0])
        for i in range(int(round(2.0 / h))):
            y, _err, _k, _ = _step(_oscillator, (1.0, 0.0), i * h, y, h)
        errors.append(max(abs(y[0] - math.cos(2.0)), abs(y[1] + math.sin(2.0))))
    assert 2 ** 4.5 < errors[0] / errors[1] < 2 ** 5.5


@pytest.mark.parametrize("linear", [False, True])
def test_the_planar_unrolled_step_is_the_generic_step_double_for_double(linear):
    """dopri_step (the planar kernel's, unrolled over theta and omega) gives the same doubles as rk_step with
    DOPRI54 on the same equation, on random states (tilts down to 1e-6 rad, where a stage summed in another order
    rounds differently), steps and ground pieces."""
    rng = np.random.default_rng(7)
    for _ in range(2000):
        t0 = rng.uniform(0, 10)
        t = t0 + rng.uniform(0, 0.01)
        pc = GroundPiece(0, t0, t0 + 0.01, *rng.normal(0, 3, 4), *rng.normal(0, 50, 2))
        th, om, h = rng.uniform(-0.3, 0.3) * 10 ** rng.uniform(-5, 0), rng.normal(0, 1), rng.uniform(1e-5, 1e-2)
        s, p2, alpha, g = float(rng.choice([-1.0, 1.0])), rng.uniform(1, 20), rng.uniform(0.05, 0.4), 9.80665
        got = dopri_step(t, th, om, h, pc, s, p2, alpha, g, linear)
        y_new, err, k, (sin1, cos1) = _step(_plane, (pc, s, p2, alpha, g, linear), t, np.array([th, om]), h)
        assert got == (y_new[0], y_new[1], err[0], err[1], k[-1, 1], sin1, cos1)
