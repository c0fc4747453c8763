"""The rocking simulator against published benchmarks and closed forms (Housner 1963; Makris & Roussos 2000;
Zhang & Makris 2001)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.blocks import geometry
from pipeline.closed_forms import housner_rectangle_duration, makris_roussos_halfsine
from pipeline.rocking.planner import Physics, plan
from pipeline.rocking.references.excitation import pulse
from pipeline.rocking.simulate import rock, slide

G81 = 9.81      # the published benchmarks use g = 9.81


def block(height, width):
    geo = geometry(height, width, g_ms2=G81)
    return dict(p=float(geo.p), alpha=float(geo.alpha), R_m=float(geo.R), e=float(geo.e_housner), g_ms2=G81)


def p_block(p, alpha, e):
    """A block given by p and alpha (R from p^2 = 3 g / (4 R))."""
    return dict(p=p, alpha=alpha, R_m=3 * G81 / (4 * p * p), e=e, g_ms2=G81)


def free(b, phi0, *, linear, t_end=30.0, log=400):
    return rock(np.zeros(2), 1.0, theta0=phi0 * b["alpha"], t_end_s=t_end, tail="integrate", linear=linear,
                log_impacts=log, **b)


@pytest.mark.parametrize("alpha, e_expected", [(math.atan(1 / 3), 0.85), (0.25, 0.9082)])
def test_restitution_energy_ratio_at_every_impact(alpha, e_expected):
    b = p_block(2.5, alpha, 1 - 1.5 * math.sin(alpha) ** 2)
    assert b["e"] == pytest.approx(e_expected, abs=1e-4)
    res = free(b, 0.6, linear=False, log=50)
    ke = res.impacts[:, 2] ** 2 / res.impacts[:, 1] ** 2
    assert len(ke) == 50 and np.all(np.abs(ke - b["e"] ** 2) < 1e-12)
    assert np.all(np.sign(res.impacts[:, 1]) == np.sign(res.impacts[:, 2]))
    # between impacts the free motion conserves energy, so the speed arriving at an impact is the speed the
    # previous one left (the first from the release: omega^2 = 2 p^2 (cos(alpha - theta0) - cos(alpha)))
    p, a = b["p"], alpha
    first = math.sqrt(2 * p * p * (math.cos(a - 0.6 * a) - math.cos(a)))
    assert abs(res.impacts[0, 1]) == pytest.approx(first, rel=1e-7)
    np.testing.assert_allclose(np.abs(res.impacts[1:, 1]), np.abs(res.impacts[:-1, 2]), rtol=1e-6)


@pytest.mark.parametrize("phi0, lin, nonlin", [(0.1, 0.173918, 0.174394), (0.5, 0.490304, 0.490864),
                                               (0.9, 1.114377, 1.114705)])
def test_free_rocking_quarter_period(phi0, lin, nonlin):
    b = block(2.0, 0.4)                                   # b = 0.2 m, h = 1.0 m
    p = b["p"]
    closed = math.acosh(1 / (1 - phi0)) / p               # Housner eqs. 2-3, linear
    t_lin = free(b, phi0, linear=True).t_first_impact
    assert t_lin == pytest.approx(closed, abs=1e-9)
    assert t_lin == pytest.approx(lin, abs=1e-6)
    assert free(b, phi0, linear=False).t_first_impact == pytest.approx(nonlin, abs=1e-6)


def test_amplitude_decay_recurrences():
    b = block(2.0, 0.4)
    p, a, e = b["p"], b["alpha"], b["e"]
    r = e * e
    nl = free(b, 0.5, linear=False, log=5).impacts[:, 2]
    # nonlinear energy: cos(alpha - theta_n) = cos(alpha) + r^n [cos(alpha - theta_0) - cos(alpha)]
    theta_n = a - np.arccos(np.cos(a) + nl ** 2 / (2 * p * p))
    expected = a - np.arccos(np.cos(a) + r ** np.arange(1, 6) * (np.cos(a / 2) - np.cos(a)))
    np.testing.assert_allclose(theta_n, expected, atol=1e-8 * a)
    np.testing.assert_allclose(theta_n / a, [0.422193, 0.360968, 0.311127, 0.269701, 0.234782], atol=1e-6)
    li = free(b, 0.5, linear=True, log=5).impacts[:, 2]
    phi_lin = 1 - np.sqrt(1 - li ** 2 / (p * a) ** 2)     # linear energy at theta = 0 -> peak
    housner = 1 - np.sqrt(1 - r ** np.arange(1, 6) * (1 - (1 - 0.5) ** 2))
    np.testing.assert_allclose(phi_lin, housner, atol=1e-8)


def test_zeno_cascade_reaches_rest_in_finite_time():
    b = block(2.0, 0.4)
    res = free(b, 0.5, linear=True, t_end=40.0, log=10000)
    assert res.mode_end == 0 and not res.chatter
    assert res.impacts[-1, 0] == pytest.approx(12.198, abs=1e-3)
    assert res.n_impacts < 400


@pytest.mark.parametrize("nu", [1.1, 1.5, 2.0, 5.0])
def test_housner_rectangular_pulse_threshold(nu):
    b = block(2.0, 0.4)
    t1 = float(housner_rectangle_duration(nu)) / b["p"]
    a = nu * b["alpha"] * G81
    for factor, overturns in ((1 - 2e-6, False), (1 + 2e-6, True)):
        n = 4001
        acc = np.full(n, a)                               # exact rectangle: ground still after the last sample
        res = rock(acc, factor * t1 / (n - 1), linear=True, **b)
        assert res.overturned is overturns


@pytest.mark.parametrize("k", [0.5, 1.0, 2.0, 4.0])
def test_half_sine_matches_makris_roussos_eq27(k):
    b = block(1.2, 0.4)
    T = 2 * math.pi / (k * b["p"])
    a_min = float(makris_roussos_halfsine(k)) * b["alpha"] * G81
    safe = rock(*pulse("half-sine", amplitude_ms2=a_min * (1 - 1e-3), period_s=T), linear=True, **b)
    over = rock(*pulse("half-sine", amplitude_ms2=a_min * (1 + 1e-3), period_s=T), linear=True, **b)
    assert not safe.overturned and over.overturned and over.n_impacts == 0


def test_makris_roussos_fig2_and_fig9():
    hs = dict(block(1.2, 0.4), e=0.85)
    for a_g, overturns in ((0.5535, False), (0.5550, True)):
        res = rock(*pulse("half-sine", amplitude_ms2=a_g * G81, period_s=1.0), linear=True, **hs)
        assert res.overturned is overturns and res.n_impacts == 0
    one = dict(block(3.0, 1.0), e=0.85)
    safe = rock(*pulse("one-sine", amplitude_ms2=4.426, period_s=1.0), linear=True, **one)
    over = rock(*pulse("one-sine", amplitude_ms2=4.433, period_s=1.0), linear=True, **one)
    assert not safe.overturned and over.overturned and over.n_impacts == 1


@pytest.mark.parametrize("ratio, overturns, impacts", [(3.00, False, None), (3.03, True, 1), (6.30, True, 1),
                                                       (6.33, False, None), (7.10, False, None), (7.19, True, 0)])
def test_zhang_makris_two_modes(ratio, overturns, impacts):
    b = p_block(2.14, 0.25, 0.9)
    res = rock(*pulse("one-sine", amplitude_ms2=ratio * 0.25 * G81, period_s=2 * math.pi / (5 * 2.14)),
               linear=True, **b)
    assert res.overturned is overturns
    if impacts is not None:
        assert res.n_impacts == impacts


def _first_overturn(b, *, linear, lo_g, hi_g, step_g, shape="one-sine", T=2 * math.pi / 15.7):
    x = lo_g
    while x <= hi_g:
        res = rock(*pulse(shape, amplitude_ms2=x * G81, period_s=T), linear=linear, **b)
        if res.overturned:
            return x, res
        x += step_g
    return None, None


def test_linear_and_nonlinear_differ_zhang_makris_fig10():
    b = p_block(2.14, 0.25, 0.9)
    a_nl, res_nl = _first_overturn(b, linear=False, lo_g=2.15, hi_g=2.4, step_g=0.002)
    a_li, res_li = _first_overturn(b, linear=True, lo_g=3.15, hi_g=3.4, step_g=0.002)
    assert a_nl == pytest.approx(2.22, rel=5e-3) and res_nl.n_impacts == 1      # mode 1
    assert a_li == pytest.approx(3.24, rel=5e-3) and res_li.n_impacts == 0      # mode 2


@pytest.mark.parametrize("a_g, overturns, impacts", [(0.3150, False, None), (0.3151, True, 4), (0.32, True, 4),
                                                     (0.33, False, None), (0.34, True, 2), (0.35, False, None),
                                                     (0.36, True, 1)])
def test_non_monotonic_one_cosine_wsh20(a_g, overturns, impacts):
    alpha = math.radians(15)
    b = p_block(2.0, alpha, 1 - 1.5 * math.sin(alpha) ** 2)
    res = rock(*pulse("one-cosine", amplitude_ms2=a_g * G81, period_s=2.0), **b)
    assert res.overturned is overturns
    if impacts is not None:
        assert res.n_impacts == impacts
    if a_g == 0.35:
        assert res.theta_max > 1.0            # passes alpha and comes back: never flag at |theta| = alpha


def test_uplift_threshold_with_and_without_vertical():
    b = block(2.0, 0.4)
    thr = G81 * math.tan(b["alpha"])
    t = np.arange(0, 2, 0.005)
    shape = np.sin(2 * math.pi * t)
    assert rock(thr * shape, 0.005, **b).n_uplifts == 0                        # exactly at g tan(alpha)
    assert rock(1.01 * thr * shape, 0.005, **b).n_uplifts >= 1
    up = 0.06 * G81 * np.ones_like(t)                                           # ground accelerating upward
    assert rock(1.03 * thr * shape, 0.005, av_ms2=up, **b).n_uplifts == 0       # (g + a_v) tan(alpha) not reached
    assert rock(1.03 * thr * shape, 0.005, av_ms2=-up, **b).n_uplifts >= 1
    assert plan(1.03 * thr * shape, up, alpha=b["alpha"], mu=0.6, g_ms2=G81) == Physics.none
    assert plan(1.03 * thr * shape, -up, alpha=b["alpha"], mu=0.6, g_ms2=G81) == Physics.rocking_vertical
    # the vertical is simulated whenever the record has one, unless the approximation is asked for
    assert plan(1.03 * thr * shape, 0.01 * up, alpha=b["alpha"], mu=0.6, g_ms2=G81) == Physics.rocking_vertical
    assert plan(1.03 * thr * shape, 0.01 * up, alpha=b["alpha"], mu=0.6, g_ms2=G81,
                vertical_fraction=0.05) == Physics.rocking
    # ... but never from the decision that nothing moves: 0.99 g tan(alpha) lifts once a_v < -1 % g
    assert plan(0.99 * thr * shape, -0.3 * up, alpha=b["alpha"], mu=0.6, g_ms2=G81,
                vertical_fraction=0.05) != Physics.none


def test_friction_demand_of_the_locomotive_case():
    b = p_block(2.14, 0.25, 0.9)
    res = rock(*pulse("one-sine", amplitude_ms2=2.21 * G81, period_s=2 * math.pi / 15.7), **b)
    assert not res.overturned
    assert res.friction_demand == pytest.approx(2.5 * math.tan(0.25), rel=0.2)          # Z&M Fig. 9


def test_similarity_theta_over_alpha_in_pt():
    base = p_block(2.0, 0.2, 0.9)
    k = 9.0
    big = dict(base, p=base["p"] / math.sqrt(k), R_m=base["R_m"] * k)
    acc, dt = pulse("one-sine", amplitude_ms2=1.1 * G81 * math.tan(0.2), period_s=2.0, samples_per_period=400)
    a = rock(acc, dt, t_end_s=8.0, tail="integrate", history=True, **base)
    b = rock(acc, dt * math.sqrt(k), t_end_s=8.0 * math.sqrt(k), tail="integrate", history=True, **big)
    assert a.n_impacts == b.n_impacts > 0
    np.testing.assert_allclose(a.theta, b.theta, atol=1e-6 * 0.2, equal_nan=True)


def test_minimum_overturning_grows_with_omega_over_p():
    """Housner's scale effect (section 6.13): the first overturning a_p/(g tan a) does not decrease with w_p/p."""
    b = p_block(2.14, 0.25, 0.9)
    mins = []
    for ratio in (0.5, 1.0, 2.0, 3.0):
        T = 2 * math.pi / (ratio * 2.14)
        x, _ = _first_overturn(b, linear=False, lo_g=math.tan(0.25), hi_g=1.0, step_g=0.001, shape="half-sine", T=T)
        mins.append(x / math.tan(0.25))
    assert all(np.diff(mins) > 0)
    step = 0.001 / math.tan(0.25)             # the scan finds the first overturning within one step above it
    computed = np.array([1.108, 1.321, 1.801, 2.297])                         # computed CSV, nonlinear
    assert np.all(mins >= computed - 1e-3) and np.all(mins <= computed + step + 1e-3)


def test_sliding_step_pulse_closed_form():
    mu, a, T, dt = 0.3, 0.5 * G81, 0.4, 1e-5
    n = int(round(T / dt))
    acc = np.concatenate([np.full(n + 1, a), np.zeros(int(0.6 / dt))])
    res = slide(acc, dt, mu=mu, g_ms2=G81)
    # accelerate at a - mu g for T, then decelerate at mu g: |u| = (a - mu g) T^2 a / (2 mu g)
    expected = (a - mu * G81) * T * T * a / (2 * mu * G81)
    assert res.sliding_max_m == pytest.approx(expected, rel=1e-4)
    assert res.n_slips == 1 and res.sliding_end_m == pytest.approx(-expected, rel=1e-4)
    assert slide(np.full(100, 0.29 * G81), 0.01, mu=0.3, g_ms2=G81).sliding_max_m == 0.0
