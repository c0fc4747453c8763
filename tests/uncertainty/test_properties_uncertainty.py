"""Properties of the binomial interval and the sequential stopping rule (issue 19).

The rule's error rates are measured on Bernoulli streams of known p, replaying exactly
the loop of :func:`pipeline.uncertainty.scenes.scene_probability` (batches, test after each).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.stats import beta as beta_dist

from pipeline.uncertainty.robust import Robustness, classify, final_class, wilson_interval
from pipeline.uncertainty.settings import UncertaintyConfig


@given(n=st.integers(1, 2000), data=st.data(), conf=st.sampled_from([0.8, 0.9, 0.95]))
def test_wilson_interval_brackets_the_estimate(n, data, conf):
    k = data.draw(st.integers(0, n))
    lo, hi = wilson_interval(k, n, confidence=conf)
    assert 0.0 <= lo <= k / n <= hi <= 1.0
    wider_lo, wider_hi = wilson_interval(k, n, confidence=0.99)
    assert wider_lo <= lo + 1e-12 and wider_hi >= hi - 1e-12


@given(n=st.integers(5, 500), data=st.data())
def test_wilson_is_close_to_clopper_pearson(n, data):
    """A second method: Wilson's bounds lie within 0.1 of the exact (Clopper-Pearson) ones."""
    k = data.draw(st.integers(0, n))
    lo, hi = wilson_interval(k, n, confidence=0.9)
    cp_lo = beta_dist.ppf(0.05, k, n - k + 1) if k > 0 else 0.0
    cp_hi = beta_dist.ppf(0.95, k + 1, n - k) if k < n else 1.0
    assert abs(lo - cp_lo) < 0.1 and abs(hi - cp_hi) < 0.1
    assert lo >= cp_lo - 1e-9 or k == 0            # Wilson is never wider than the exact interval here
    assert hi <= cp_hi + 1e-9 or k == n


def test_no_sample_gives_no_interval():
    lo, hi = wilson_interval(0, 0)
    assert np.isnan(lo) and np.isnan(hi)
    assert final_class(float(lo), float(hi), below=0.1, above=0.9) == -1


def _sequential(p: float, rng: np.random.Generator, cfg: UncertaintyConfig) -> tuple[int, int]:
    """The scene loop on a Bernoulli(p) stream: (final class, samples drawn)."""
    k = n = 0
    lo = hi = float("nan")
    while n < cfg.samples:
        m = min(cfg.batch, cfg.samples - n)
        k += int(rng.binomial(m, p))
        n += m
        lo, hi = (float(x) for x in wilson_interval(k, n, confidence=cfg.confidence))
        if classify(lo, hi, below=cfg.robust_below, above=cfg.robust_above) is not None:
            break
    return final_class(lo, hi, below=cfg.robust_below, above=cfg.robust_above), n


@pytest.mark.parametrize("p, wrong, limit", [
    # a scene that overturns in 30 % of samples is never called robust_stand more than 5 % of the time
    (0.30, Robustness.robust_stand, 0.05), (0.70, Robustness.robust_overturn, 0.05),
    # scenes beyond the thresholds are rarely called robust on the other side
    (0.20, Robustness.robust_overturn, 0.0), (0.80, Robustness.robust_stand, 0.0),
])
def test_sequential_rule_error_rates(p, wrong, limit):
    cfg = UncertaintyConfig()
    rng = np.random.default_rng(11)
    classes = np.array([_sequential(p, rng, cfg)[0] for _ in range(4000)])
    assert np.mean(classes == wrong) <= limit


@pytest.mark.parametrize("p, right, at_least", [(0.0, Robustness.robust_stand, 1.0),
                                                (1.0, Robustness.robust_overturn, 1.0),
                                                (0.5, Robustness.sensitive, 1.0),
                                                (0.01, Robustness.robust_stand, 0.75)])
def test_sequential_rule_decides_clear_cases(p, right, at_least):
    cfg = UncertaintyConfig()
    rng = np.random.default_rng(12)
    runs = [_sequential(p, rng, cfg) for _ in range(2000)]
    assert np.mean([c == right for c, _ in runs]) >= at_least
    if p in (0.0, 1.0):
        assert all(n == 25 for _, n in runs)         # k = 0 of 25: Wilson's upper bound 0.098 < 0.1


@settings(max_examples=50, deadline=None)
@given(cov=st.floats(0.0, 0.99), z=st.floats(-6, 6))
def test_lognormal_factor_has_median_one_and_is_positive(cov, z):
    from pipeline.uncertainty.sampling import lognormal_factor

    assert lognormal_factor(np.array([0.0]), cov)[0] == 1.0
    f = lognormal_factor(np.array([z, -z]), cov)
    assert np.all(f > 0) and f[0] * f[1] == pytest.approx(1.0)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), n=st.integers(1, 130), data=st.data(),
       height=st.floats(0.2, 30.0), slenderness=st.floats(0.03, 1.2), mu=st.floats(0.05, 1.5),
       cylinder=st.booleans(), azimuth=st.one_of(st.just(float("nan")), st.floats(0.0, 180.0)),
       restitution=st.one_of(st.just(float("nan")), st.floats(0.0, 1.0)))
def test_rows_of_the_draws_are_the_draws_of_those_rows(seed, n, data, height, slenderness, mu, cylinder, azimuth,
                                                       restitution):
    """A scene's draws are made once and read by row (SampledBlock.rows): each row's block is, double for double,
    the one sample_block makes from that row of the common random numbers alone (a slice or any rows)."""
    from pipeline.rocking.block import BlockShape, ShapeKind
    from pipeline.uncertainty.sampling import common_normals, sample_block

    shape = BlockShape(height_m=height, width_m=height * np.tan(slenderness), mu=mu, restitution=restitution,
                       azimuth_deg=azimuth, kind=ShapeKind.cylinder if cylinder else ShapeKind.box)
    u = UncertaintyConfig()
    z = common_normals(seed, n)
    whole = sample_block(z, shape, settings=u)
    start = data.draw(st.integers(0, n - 1))
    rows = np.asarray(data.draw(st.lists(st.integers(0, n - 1), min_size=1, max_size=n)))
    for index in (slice(start, n), slice(start, start + 1), rows):
        alone = sample_block(z[index], shape, settings=u)
        picked = whole.rows(index)
        for field in ("amplitude", "p", "alpha", "R_m", "e", "mu", "azimuth_deg"):
            assert np.array_equal(getattr(picked, field), getattr(alone, field), equal_nan=True), field


@settings(max_examples=300, deadline=None)
@given(drawn=st.integers(0, 400), data=st.data(), conf=st.sampled_from([0.8, 0.9, 0.95, 0.99]))
def test_spanning_interval_is_wilsons_double_for_double(drawn, data, conf):
    """The sequential rule's interval for one scene (scalars) is wilson_interval's (arrays), to the double: the lower
    bound of k / drawn and the upper one of (k + unknown) / drawn, NaN where nothing was drawn; and it is Wilson's
    interval as scipy computes it (binomtest's, another implementation) to rounding."""
    from scipy.stats import binomtest

    from pipeline.uncertainty.robust import spanning_interval

    k = data.draw(st.integers(0, drawn))
    unknown = data.draw(st.integers(0, drawn - k))
    low, high = spanning_interval(k, unknown, drawn, confidence=conf)
    low_w, _ = wilson_interval(k, drawn, confidence=conf)
    _, high_w = wilson_interval(k + unknown, drawn, confidence=conf)
    assert np.array_equal([low, high], [float(low_w), float(high_w)], equal_nan=True)
    assert all(isinstance(b, float) for b in (low, high))
    if drawn:
        ref_low = binomtest(k, drawn).proportion_ci(confidence_level=conf, method="wilson").low
        ref_high = binomtest(k + unknown, drawn).proportion_ci(confidence_level=conf, method="wilson").high
        assert (low, high) == (pytest.approx(ref_low, abs=1e-12), pytest.approx(ref_high, abs=1e-12))
