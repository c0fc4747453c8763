"""The random orientation's stratified mean and its successive-difference interval, against closed forms and
Monte Carlo truth (Bernoulli draws of known per-plane probabilities)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.uncertainty.robust import normal_quantile
from pipeline.uncertainty.stratified import successive_difference_interval

Z90 = normal_quantile(0.95)


def test_a_plateau_of_planes_has_the_closed_form_interval():
    """10 of 36 planes overturn, one draw each: two changes between neighbours (cyclic), so the variance is
    2 (1/36)^2 / 2 and the half-width z / 36."""
    fractions = np.array([1.0] * 10 + [0.0] * 26)
    got = successive_difference_interval(fractions, np.ones(36))
    assert got.mean == pytest.approx(10 / 36, abs=1e-15)
    assert (got.high - got.low) / 2 == pytest.approx(Z90 / 36, rel=1e-12)


def test_equal_planes_give_a_point_and_the_bounds_stay_in_the_unit_interval():
    got = successive_difference_interval(np.zeros(36), np.ones(36))
    assert got == (0.0, 0.0, 0.0)
    got = successive_difference_interval(np.array([1.0, 0.0] * 18), np.ones(36))    # alternating: the widest
    assert 0.0 <= got.low < got.mean < got.high <= 1.0


def test_the_weights_are_the_draws_counts():
    """Planes drawn twice weigh twice: the mean is the plain mean of the draws."""
    got = successive_difference_interval(np.array([1.0, 0.5, 0.0, 0.0]), np.array([2, 2, 1, 1]))
    assert got.mean == pytest.approx((2 + 1) / 6, abs=1e-15)


@pytest.mark.parametrize("bad", [(np.array([0.5]), np.array([1])), (np.array([0.5, 0.5]), np.array([1, 0]))])
def test_fewer_than_two_planes_or_an_undrawn_plane_is_refused(bad):
    with pytest.raises(ValueError, match="two or more planes"):
        successive_difference_interval(*bad)


def _coverage(p_planes: np.ndarray, cycles: int, trials: int, seed: int) -> tuple[float, float, float]:
    """Over ``trials`` samples of ``cycles`` draws a plane: the interval's coverage of the true mean, the mean of
    the variance estimate and the variance of the mean (the truth it estimates)."""
    rng = np.random.default_rng(seed)
    truth = float(p_planes.mean())
    covered, estimates, means = 0, [], []
    for _ in range(trials):
        fractions = rng.binomial(cycles, p_planes) / cycles
        got = successive_difference_interval(fractions, np.full(p_planes.size, cycles))
        covered += got.low <= truth <= got.high
        estimates.append(((got.high - got.low) / (2 * Z90)) ** 2 if 0.0 < got.low and got.high < 1.0 else math.nan)
        means.append(got.mean)
    return covered / trials, float(np.nanmean(estimates)), float(np.var(means))


def test_on_independent_planes_the_variance_is_the_binomials_on_average():
    """Every plane at p = 0.5: neighbours differ only by chance, and the estimate is unbiased (the binomial
    variance 0.25 / n, the mean of 4,000 estimates within 5 %) with about the stated coverage."""
    coverage, estimate, truth = _coverage(np.full(36, 0.5), cycles=2, trials=4000, seed=1)
    assert truth == pytest.approx(0.25 / 72, rel=0.1)
    assert estimate == pytest.approx(0.25 / 72, rel=0.05)
    assert 0.86 <= coverage <= 0.94


def test_where_the_probability_changes_smoothly_with_the_plane_the_interval_is_conservative():
    """p from 0 to 1 and back around the grid (a bad window of orientations): the estimate is at least the true
    variance of the mean on average, far below the binomial's; the interval covers the true mean nearly as often
    as stated (0.87 of 4,000 samples of one draw a plane, 0.89 of three: the estimate of a few neighbours'
    differences is noisy, and a small one gives a short interval)."""
    angle = np.arange(36) * 5.0
    p_planes = np.clip(1.5 * np.cos(np.radians(angle - 30.0)) ** 2 - 0.4, 0.0, 1.0)
    coverage, estimate, truth = _coverage(p_planes, cycles=1, trials=4000, seed=2)
    mean = float(p_planes.mean())
    assert estimate >= truth
    assert estimate < 0.5 * mean * (1 - mean) / 36
    assert coverage >= 0.85
