"""The hazard constraint of standing fragile rocks, against independent truths.

* Cornell et al. (2002): a lognormal fragility on a power-law hazard curve lambda = k0 x^-k has the rate
  k0 theta^-k exp(k^2 beta^2 / 2): the toppling rate matches it to 0.1 % per branch.
* The integral equals adaptive quadrature of the log-log curve draw by draw; the upper bound with toppling certain
  above the top level tested equals its closed form on a power law (by parts).
* The truncated normal's survival (closed form) equals numerical quadrature of exp(-lambda T) over its density.
* Anderson & Brune (1999): a fragility without dispersion topples exactly when the shaking exceeds its median, so
  the survival is exp(-lambda(theta) T), lambda read from the hazard curve.
* Brute-force Monte Carlo: earthquakes drawn from a branch's hazard curve, each toppling the rock with the
  fragility's probability, give the survival the rate predicts; branches, ages and fragility draws sampled and the
  survivors counted give the posterior weights.
* The weighted mean and fractiles of the shipped OpenQuake example equal OpenQuake's own exported mean and quantile
  curves.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy import integrate
from scipy.stats import norm, truncnorm

from pipeline.constants import G
from pipeline.errors import ConstraintError
from pipeline.uncertainty.ages import normal_age, read_ages, table_age
from pipeline.uncertainty.branch_stats import common_levels, fractile_curve, level_at_rate, mean_curve, rates_on
from pipeline.uncertainty.branches import read_branches
from pipeline.uncertainty.constraint import (
    Combine,
    combine,
    posterior_weights,
    survival_likelihood,
)
from pipeline.uncertainty.hazard import HazardCurve, annual_rates, annual_rates_upper, exceedance_rate
from pipeline.uncertainty.hazard_files import read_hazard

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "constrain" / "openquake"


def power_law(k0: float, k: float, theta: float, beta: float) -> HazardCurve:
    """lambda = k0 x^-k on levels from theta e^-8beta to theta e^+10beta, 400 points [SI]."""
    levels = np.geomspace(theta * math.exp(-8 * beta), theta * math.exp(10 * beta), 400)
    return HazardCurve("pga", levels, k0 * levels ** -k, "power law")


@pytest.mark.parametrize("k0, k, theta, beta", [(1e-4, 2.0, 0.3 * G, 0.3), (3e-5, 3.0, 0.2 * G, 0.4),
                                                (1e-3, 2.5, 0.8 * G, 0.5), (2e-4, 4.0, 0.5 * G, 0.25)])
def test_a_power_law_branch_matches_cornell_s_closed_form(k0, k, theta, beta):
    curve = power_law(k0, k, theta, beta)
    expected = k0 * theta ** -k * math.exp(k * k * beta * beta / 2)          # Cornell et al. (2002), eq. (6)
    assert annual_rates([curve], [theta], [beta])[0, 0] == pytest.approx(expected, rel=1e-3)


def _quadrature_rate(curve: HazardCurve, theta: float, beta: float) -> float:
    """The same integral by adaptive quadrature (scipy's quad) on each log-log segment, plus the tail term."""
    lv, rt = np.log(curve.levels), np.log(curve.rates)
    total = 0.0
    for k in range(lv.size - 1):
        s = -(rt[k + 1] - rt[k]) / (lv[k + 1] - lv[k])

        def integrand(u, k=k, s=s):
            return norm.cdf((u - math.log(theta)) / beta) * s * math.exp(rt[k] - s * (u - lv[k]))

        total += integrate.quad(integrand, lv[k], lv[k + 1], epsabs=0.0, epsrel=1e-12)[0]
    return total + norm.cdf((lv[-1] - math.log(theta)) / beta) * curve.rates[-1]


def test_the_rates_of_many_draws_equal_adaptive_quadrature():
    curve = read_hazard(next(EXAMPLE.glob("hazard_curve-rlz-000-*.csv")), im="pga")
    rng = np.random.default_rng(5)
    theta, beta = rng.uniform(0.05, 1.5, 8) * G, rng.uniform(0.1, 0.8, 8)
    got = annual_rates([curve], theta, beta)[0]
    assert got == pytest.approx([_quadrature_rate(curve, t, b) for t, b in zip(theta, beta)], rel=1e-9)
    edges = annual_rates([curve], [np.inf, 0.0], [np.nan, np.nan])[0]
    assert edges[0] == 0.0 and edges[1] == pytest.approx(float(curve.rates[0]), rel=1e-12)


@pytest.mark.parametrize("top_over_theta", [0.6, 1.0, 2.5])
def test_the_upper_bound_matches_its_closed_form_on_a_power_law(top_over_theta):
    """The fragility below the top level tested and toppling certain above it, on lambda = k0 x^-k: by parts,
    k0 theta^-k exp(k^2 beta^2 / 2) Phi(z + k beta) + lambda(top) (1 - Phi(z)), z = ln(top / theta) / beta."""
    k0, k, theta, beta = 1e-4, 2.5, 0.3 * G, 0.4
    top = top_over_theta * theta
    z = math.log(top / theta) / beta
    expected = (k0 * theta ** -k * math.exp(k * k * beta * beta / 2) * norm.cdf(z + k * beta)
                + k0 * top ** -k * (1 - norm.cdf(z)))
    curves = [power_law(k0, k, theta, beta), read_hazard(next(EXAMPLE.glob("hazard_curve-rlz-000-*.csv")), im="pga")]
    got = annual_rates_upper(curves, theta, beta, top)
    assert got[0] == pytest.approx(expected, rel=1e-6)
    assert got[1] >= annual_rates([curves[1]], [theta], [beta])[0, 0]      # never below the fitted rate
    assert np.isnan(annual_rates_upper(curves, theta, beta, math.inf)).all()


def test_curves_on_other_levels_in_one_call_give_each_curve_s_rate():
    """Curves grouped by their levels: one call on a tree's branches and a curve of other levels gives what each
    curve gives alone."""
    tree = read_branches(EXAMPLE, im="pga")
    curves = [*tree.curves, power_law(1e-4, 2.5, 0.3 * G, 0.4)]
    theta, beta = np.array([0.21, 0.5]) * G, np.array([0.42, 0.3])
    many = annual_rates(curves, theta, beta)
    for b, c in enumerate(curves):
        assert many[b] == pytest.approx(annual_rates([c], theta, beta)[0], rel=1e-13)


@pytest.mark.parametrize("rate, mean, sd", [(1e-4, 10_000, 1_500), (5e-4, 12_000, 4_000), (3e-3, 5_000, 2_500),
                                            (1e-2, 20_000, 3_000), (1e-6, 30_000, 10_000)])
def test_the_survival_over_a_normal_age_is_the_truncated_normal_s_integral(rate, mean, sd):
    a, b = (0 - mean) / sd, np.inf
    pdf = truncnorm(a, b, loc=mean, scale=sd).pdf
    expected, _ = integrate.quad(lambda t: math.exp(-rate * t) * pdf(t), 0, mean + 12 * sd, limit=200,
                                 points=[mean], epsabs=1e-300)
    got = float(normal_age(mean, sd).survival(rate))
    assert got == pytest.approx(expected, rel=1e-6, abs=1e-300)


def test_a_table_age_and_an_exact_age():
    age = table_age([8_000, 12_000, 16_000], [1, 2, 1])
    assert float(age.survival(1e-4)) == pytest.approx(
        (math.exp(-0.8) + 2 * math.exp(-1.2) + math.exp(-1.6)) / 4, rel=1e-12)
    assert age.mean_yr == pytest.approx(12_000)
    assert float(normal_age(10_000, 0).survival(2e-4)) == pytest.approx(math.exp(-2.0), rel=1e-12)


def test_anderson_and_brune_s_rule_is_the_limit_of_no_dispersion():
    """A rock that topples exactly when the shaking exceeds theta survives T years with exp(-lambda(theta) T)."""
    curve = read_hazard(next(EXAMPLE.glob("hazard_curve-rlz-003-*.csv")), im="pga")
    theta = 0.25 * G
    rate = annual_rates([curve], [theta], [1e-4])[0]
    survival = survival_likelihood(rate, normal_age(12_000, 0))
    assert survival == pytest.approx(math.exp(-exceedance_rate(curve, theta) * 12_000), rel=1e-3)


def test_earthquakes_drawn_from_the_curve_topple_the_rock_at_the_integrated_rate():
    """Brute force: shaking events above a floor level drawn as a Poisson process with the curve's rates (log-log),
    each toppling the rock with the fragility's probability; the share of rocks that stood through T equals
    exp(-rate T) to within its sampling error."""
    curve = read_hazard(next(EXAMPLE.glob("hazard_curve-rlz-000-*.csv")), im="pga")
    theta, beta, years = 0.21 * G, 0.42, 8_000.0
    floor = theta * math.exp(-6 * beta)                       # below it P(topple) < 1e-9
    rng = np.random.default_rng(11)
    n = 40_000
    events = rng.poisson(exceedance_rate(curve, floor) * years, n)
    u = rng.uniform(size=int(events.sum()))
    # invert lambda(x) / lambda(floor) = u along the curve (log-log), the tail above the last level at the last level
    lv, rt = np.log(curve.levels), np.log(curve.rates)
    target = math.log(exceedance_rate(curve, floor)) + np.log(u)
    im = np.exp(np.interp(-target, -rt, lv))
    topple = rng.uniform(size=im.size) < norm.cdf(np.log(im / theta) / beta)
    owner = np.repeat(np.arange(n), events)
    stood = 1.0 - np.bincount(owner[topple], minlength=n).clip(max=1).mean()
    expected = math.exp(-annual_rates([curve], [theta], [beta])[0, 0] * years)
    assert abs(stood - expected) < 4 * math.sqrt(expected * (1 - expected) / n)


@pytest.mark.parametrize("rule", list(Combine))
def test_the_posterior_weights_equal_a_monte_carlo_over_branches_ages_and_draws(rule):
    """Sample a branch by its prior weight, each rock's age and fragility draw, topple each rock with a Poisson
    count; the branches of the samples in which the rocks stood (both, or the most constraining one) have the
    posterior weights' frequencies."""
    prior = np.array([0.2, 0.15, 0.15, 0.2, 0.15, 0.15])
    rng = np.random.default_rng(7)
    rates = [rng.uniform(1e-5, 2e-4, (6, 50)), rng.uniform(5e-6, 1e-4, (6, 50))]       # (branch, draw) per rock
    ages = [normal_age(10_000, 1_500), normal_age(14_000, 2_000)]
    lik = np.array([survival_likelihood(r, a) for r, a in zip(rates, ages)])
    joint, chosen = combine(lik, prior, rule)
    post = posterior_weights(prior, joint)
    n = 400_000
    b = rng.choice(6, size=n, p=prior)
    stood = np.ones(n, dtype=bool)
    rocks = [chosen] if rule is Combine.strongest else [0, 1]
    for i in rocks:
        t = truncnorm(-ages[i].mean_yr / ages[i].sd_yr, np.inf, loc=ages[i].mean_yr,
                      scale=ages[i].sd_yr).rvs(size=n, random_state=rng)
        lam = rates[i][b, rng.integers(0, 50, n)]
        stood &= rng.poisson(lam * t) == 0
    freq = np.bincount(b[stood], minlength=6) / stood.sum()
    se = np.sqrt(post * (1 - post) / stood.sum())
    assert np.all(np.abs(freq - post) < 4.5 * se), (freq, post)
    assert chosen == (int(np.argmin(lik @ prior)) if rule is Combine.strongest else -1)


def test_a_likelihood_of_zero_everywhere_is_refused():
    with pytest.raises(ConstraintError, match="could not have stood"):
        posterior_weights(np.array([0.5, 0.5]), np.array([0.0, 0.0]))


def test_the_example_s_mean_and_fractiles_equal_openquake_s_own():
    """OpenQuake averaged the realizations' probabilities in one year and took their weighted quantiles; the rates
    of the branches read back give the same curves (to 0.2 % where the rate is above 1e-7)."""
    tree = read_branches(EXAMPLE, im="pga")
    grid = common_levels(tree.curves)
    rates = np.array([rates_on(c, grid) for c in tree.curves])
    for name, ours in [("hazard_curve-mean", mean_curve(rates, tree.weights))] + [
            (f"quantile_curve-{q:g}", fractile_curve(rates, tree.weights, q)) for q in (0.05, 0.5, 0.95)]:
        theirs = read_hazard(next(EXAMPLE.glob(f"{name}-PGA_*.csv")), im="pga")
        ref = rates_on(theirs, grid)
        keep = np.isfinite(ref) & (ref > 1e-7)
        assert keep.sum() > 30
        assert ours[keep] == pytest.approx(ref[keep], rel=2e-3), name


def test_the_level_at_a_rate_inverts_a_power_law():
    levels = np.geomspace(0.01, 5.0, 60) * G
    rates = 1e-4 * (levels / G) ** -2.5
    for r in (1e-3, 1e-4, 1e-5):
        assert level_at_rate(levels, rates, r) == pytest.approx(G * (r / 1e-4) ** (-1 / 2.5), rel=1e-9)
    assert math.isnan(level_at_rate(levels, rates, 20.0))            # above the first level's rate (10)


def test_the_example_logic_tree_is_read_with_its_weights():
    tree = read_branches(EXAMPLE, im="pga")
    assert tree.ids == tuple(f"rlz-{k:03d}" for k in range(6))
    assert tree.weights.sum() == pytest.approx(1.0, abs=1e-15)
    assert tree.weights == pytest.approx([0.2, 0.15, 0.15, 0.2, 0.15, 0.15], abs=1e-6)
    assert tree.paths[0] == "B~A" and tree.imt == "PGA" and tree.curves[0].investigation_time_yr == 1.0


def _copy_example(tmp_path: Path, *, drop: str | None = None) -> Path:
    folder = tmp_path / "tree"
    folder.mkdir()
    for f in EXAMPLE.glob("*.csv"):
        if drop is None or drop not in f.name:
            (folder / f.name).write_bytes(f.read_bytes())
    return folder


def test_a_realization_without_its_curve_is_named(tmp_path):
    folder = _copy_example(tmp_path, drop="rlz-004")
    with pytest.raises(ConstraintError, match="realization 4 has no PGA curve file"):
        read_branches(folder, im="pga")


def test_weights_that_do_not_sum_to_one_are_refused(tmp_path):
    folder = tmp_path / "plain"
    folder.mkdir()
    for name in ("a.csv", "b.csv"):
        (folder / name).write_text("pga_g_rotd50,annual_rate\n0.1,1e-3\n0.5,1e-5\n")
    (folder / "weights.csv").write_text("file,weight\na.csv,0.6\nb.csv,0.6\n")
    with pytest.raises(ConstraintError, match="sum to 1.2"):
        read_branches(folder, im="pga")
    (folder / "weights.csv").write_text("file,weight\n../a.csv,0.5\nb.csv,0.5\n")
    with pytest.raises(ConstraintError, match="expected the name of a curve file"):
        read_branches(folder, im="pga")
    (folder / "weights.csv").write_text("file,weight\na.csv,0.5\nb.csv,0.5\n")
    assert read_branches(folder, im="pga").weights == pytest.approx([0.5, 0.5])


@pytest.mark.parametrize("text, message", [
    ("rock,age_yr,age_sd_yr\nA,-5,10\n", "positive number of years"),
    ("rock,age_yr,age_sd_yr\nA,unknown,10\n", "an unknown age cannot constrain"),
    ("rock,age_yr,age_sd_yr\nA,100,-1\n", "must be >= 0"),
    ("rock,age_yr\nA,100\n", "neither an age_sd_yr nor a weight"),
    ("rock,age_yr,age_sd_yr\nA,100,1\nA,200,1\n", "given twice"),
])
def test_bad_ages_are_named(tmp_path, text, message):
    path = tmp_path / "ages.csv"
    path.write_text(text)
    with pytest.raises(ConstraintError, match=message):
        read_ages(path)


def test_an_ages_table_per_rock(tmp_path):
    path = tmp_path / "ages.csv"
    path.write_text("rock,age_yr,weight\nA,9000,1\nA,11000,1\nB,5000,2\n")
    ages = read_ages(path)
    assert ages["A"].values_yr == (9000.0, 11000.0) and ages["A"].weights == (0.5, 0.5)
    assert ages["B"].mean_yr == 5000.0
