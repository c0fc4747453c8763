"""The margin's upward scan (:mod:`pipeline.bodies.factor_sweep`) against the plain scan in 1 % steps over the whole
range (the reference): identical up to x1.5, where a margin changes a recommendation; above, within one fine step
of the first overturning the scan can see, with far fewer runs; and what it can miss there, stated."""

from __future__ import annotations

import math

import pytest

from pipeline.bodies.factor_sweep import factor_sweep, scan_factors
from pipeline.risk import RELOCATE_BELOW_SCALE
from pipeline.rocking.settings import SimulationConfig

SETTINGS = SimulationConfig()


def _plain_factors(lift, step=SETTINGS.margin_step, top=SETTINGS.margin_max_factor):
    """The reference grid: every factor from ``lift`` to 1 and from 1 to ``top`` in steps of ``step``."""
    x = lift
    while x < 1.0:
        yield x
        x *= 1.0 + step
    yield 1.0
    x = 1.0 + step
    while x <= top:
        yield x
        x *= 1.0 + step


def _plain(lift, verdict_at):
    """The reference scan: the first factor of :func:`_plain_factors` that does not stand, and the runs."""
    factors = list(_plain_factors(lift))
    for runs, f in enumerate(factors, start=1):
        v = verdict_at(f)
        if v != 0:
            return (f if v == 1 else math.nan), runs
    return math.inf, len(factors)


def _window(lo, hi=math.inf):
    return lambda f: 1 if lo <= f < hi else 0


def test_the_fine_range_covers_every_margin_that_changes_a_recommendation():
    assert SETTINGS.margin_fine_to >= RELOCATE_BELOW_SCALE


def test_the_factors_are_the_fine_grid_up_to_the_fine_range_then_grow_to_the_coarse_step():
    factors = list(scan_factors(0.5, settings=SETTINGS))
    fine = [f for f in factors if f <= SETTINGS.margin_fine_to]
    plain = [f for f in _plain_factors(0.5) if f <= SETTINGS.margin_fine_to]
    assert fine == plain and 1.0 in factors
    ratios = [b / a for a, b in zip(factors, factors[1:])]
    assert all(r > 1.0 for r in ratios) and max(ratios) == pytest.approx(1.0 + SETTINGS.margin_coarse_step)
    assert factors[-1] == SETTINGS.margin_max_factor
    assert len(factors) < len(list(_plain_factors(0.5))) - 150         # 1.5 to 10: 23 factors instead of 191


@pytest.mark.parametrize("threshold", [0.31, 0.77, 1.0, 1.003, 1.25, 1.49])
def test_up_to_the_fine_range_the_margin_is_the_plain_scans(threshold):
    verdict = _window(threshold)
    assert factor_sweep(0.3, verdict, settings=SETTINGS) == _plain(0.3, verdict)


@pytest.mark.parametrize("threshold", [1.52, 1.8, 2.345, 4.0, 7.77, 9.9])
def test_above_it_the_margin_overturns_and_the_factor_one_step_below_stands(threshold):
    """A monotonic threshold above x1.5: the margin found overturns and the factor 1 % below it stands, so it lies
    within one fine step above the threshold, as the plain scan's does; with fewer runs."""
    verdict = _window(threshold)
    margin, runs = factor_sweep(0.3, verdict, settings=SETTINGS)
    plain, plain_runs = _plain(0.3, verdict)
    assert verdict(margin) == 1 and verdict(margin / (1.0 + SETTINGS.margin_step)) == 0
    for found in (margin, plain):
        assert threshold <= found < threshold * (1.0 + SETTINGS.margin_step)
    assert runs <= plain_runs and (threshold < 2.0 or runs < plain_runs - 20)


def test_nothing_overturns_up_to_the_limit():
    assert factor_sweep(0.3, lambda f: 0, settings=SETTINGS) == (math.inf, len(list(scan_factors(0.3,
                                                                                                  settings=SETTINGS))))


def test_a_window_wider_than_the_step_is_found_and_a_narrower_one_above_the_fine_range_can_be_missed():
    """Overturning is not monotonic in amplitude. A window of overturning below x1.5 one fine step wide is found, as
    by the plain scan; above x1.5 a window wider than the step there is found (its first factor within one fine
    step), and one narrower than it can be missed: the stated resolution."""
    below = _window(1.201, 1.215)
    assert factor_sweep(0.3, below, settings=SETTINGS) == _plain(0.3, below)
    wide = _window(3.1, 3.5)                              # steps of 10 % there
    margin, _ = factor_sweep(0.3, wide, settings=SETTINGS)
    assert 3.1 <= margin < 3.1 * (1.0 + SETTINGS.margin_step)
    factors = list(scan_factors(0.3, settings=SETTINGS))
    gap = next((a, b) for a, b in zip(factors, factors[1:]) if a > 3.0)
    narrow = _window(gap[0] * 1.01, gap[1] * 0.99)        # between two coarse factors
    assert math.isfinite(_plain(0.3, narrow)[0]) and factor_sweep(0.3, narrow, settings=SETTINGS)[0] == math.inf


def test_no_verdict_found_while_bisecting_is_no_margin():
    """Above x1.5, a factor with no verdict (-1) before any overturning gives NaN, as in the plain scan."""
    def verdict(f):
        return -1 if f >= 2.0 else 0

    assert math.isnan(factor_sweep(0.3, verdict, settings=SETTINGS)[0])
    assert math.isnan(_plain(0.3, verdict)[0])


def test_a_certificate_decides_the_factors_below_it():
    """Factors below ``stands_below`` stand without a run; the margin is unchanged."""
    verdict = _window(2.345)
    with_cert = factor_sweep(0.3, verdict, settings=SETTINGS, stands_below=2.0)
    without = factor_sweep(0.3, verdict, settings=SETTINGS)
    assert with_cert[0] == without[0] and with_cert[1] < without[1]
    assert 2.345 <= with_cert[0] < 2.345 * (1.0 + SETTINGS.margin_step)
