"""Issue 20: fragility by multiple-stripe analysis, IM ranking, the hazard integral.

Independent truth: the overturning of every scaled half-sine record by the independent solver
(``solve_ivp``, :func:`rock_reference`); a maximum-likelihood fit of those counts by a general
optimizer (Nelder-Mead on the binomial likelihood), not the scoring iterations under test; a
numerical integration of the fitted curve over the hazard curve on a dense grid; Sa against
``scipy.signal.lsim``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid
from scipy.optimize import minimize
from scipy.stats import binom, norm

from pipeline.blocks import Inventory
from pipeline.config import Config
from pipeline.errors import HazardError, UsageError
from pipeline.levels import parse_levels
from pipeline.records.record import Record
from pipeline.rocking.references.excitation import pulse
from pipeline.rocking.references.reference import rock_reference
from pipeline.run.fragility_assembly import assemble_fragility, stripe_warnings
from pipeline.run.fragility_stripes import judge_record
from pipeline.run.screening import Context
from pipeline.uncertainty.fragility import FitStatus, fit_stripes
from pipeline.uncertainty.hazard import HazardCurve, annual_rate
from pipeline.uncertainty.hazard_files import read_hazard

G = 9.80665
PERIODS = np.geomspace(0.3, 3.0, 16)
LEVELS = np.array([0.2, 0.3, 0.45, 0.65, 0.9, 1.3, 2.0]) * G
BLOCK = dict(height_m=2.0, width_m=0.3, mu=2.0)          # mu = 2: the block rocks, never slides


def _record(k: int, period: float) -> Record:
    """A one-component half-sine of unit amplitude [m s-2], then 3 s of rest."""
    a, dt = pulse("half-sine", amplitude_ms2=1.0, period_s=period, samples_per_period=200)
    a = np.concatenate([a, np.zeros(int(3.0 / dt))])
    h = a[None, :]
    return Record(f"HS{k:02d}", dt, h, (0.0,), False, None, (), (), ("H1",), "corrected",
                  velocity_ms=cumulative_trapezoid(h, dx=dt, axis=1, initial=0.0))


@pytest.fixture(scope="module")
def suite():
    """The 16 records, judged by the pipeline (nominal verdicts) and by the independent solver (112 solve_ivp runs,
    25-29 s: the tests on it are marked slow)."""
    inv = Inventory.single(**BLOCK, block_id="B")
    cfg = Config().with_uncertainty(samples=0)
    ctx = Context("", cfg, inv, {})
    recs = [_record(k, T) for k, T in enumerate(PERIODS)]
    results = [judge_record(r, ctx, "pga", LEVELS) for r in recs]
    geo = inv.geometry(g_ms2=G)
    p, alpha, e = float(geo.p[0]), float(geo.alpha[0]), float(geo.e_housner[0])
    independent = np.array([[rock_reference(level * r.horizontal_ms2[0], r.dt_s, p=p, alpha=alpha, e=e,
                                            g=G).overturned for level in LEVELS] for r in recs], dtype=float)
    ds = assemble_fragility(results, inv, cfg, im="pga", levels=LEVELS, bootstrap=100)
    return ds, independent, results


@pytest.mark.slow
def test_stripe_counts_agree_with_the_independent_solver(suite):
    ds, independent, _ = suite
    counts = ds["overturned_sum"].values[0]
    assert np.all(ds["n_records"].values[0] == 16)
    assert np.all(np.abs(counts - independent.sum(axis=0)) <= 1), (counts, independent.sum(axis=0))
    assert 0 < independent.sum() < independent.size          # the suite spans standing and overturning


@pytest.mark.slow
def test_fit_agrees_with_a_general_maximum_likelihood_fit(suite):
    ds, independent, _ = suite
    z, n = independent.sum(axis=0), np.full(len(LEVELS), 16.0)

    def nll(q):
        return -np.sum(binom.logpmf(z, n, np.clip(norm.cdf((np.log(LEVELS) - q[0]) / math.exp(q[1])),
                                                   1e-12, 1 - 1e-12)))

    best = minimize(nll, [math.log(np.median(LEVELS)), math.log(0.5)], method="Nelder-Mead",
                    options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 10000})
    theta, beta = math.exp(best.x[0]), math.exp(best.x[1])
    assert int(ds["fit_status"].values[0]) == FitStatus.ok
    assert float(ds["median"].values[0]) == pytest.approx(theta, rel=0.05)
    assert float(ds["beta"].values[0]) == pytest.approx(beta, rel=0.15)
    assert ds["median_low"].values[0] < ds["median"].values[0] < ds["median_high"].values[0]


@pytest.mark.slow
def test_hazard_integral_agrees_with_a_dense_numerical_integration(suite, tmp_path):
    ds, _, _ = suite
    theta, beta = float(ds["median"].values[0]), float(ds["beta"].values[0])
    path = tmp_path / "hazard.csv"
    pga_g = np.array([0.05, 0.1, 0.2, 0.4, 0.8, 1.6])
    rate = np.array([2e-2, 8e-3, 2e-3, 4e-4, 5e-5, 4e-6])
    path.write_text("pga_g,annual_rate\n" + "\n".join(f"{a},{r}" for a, r in zip(pga_g, rate)) + "\n")
    curve = read_hazard(path, im="pga")
    got = annual_rate(curve, theta, beta)
    x = np.geomspace(curve.levels[0], curve.levels[-1], 200001)
    lam = np.exp(np.interp(np.log(x), np.log(curve.levels), np.log(curve.rates)))
    frag = norm.cdf(np.log(x / theta) / beta)
    dense = float(np.sum(0.5 * (frag[1:] + frag[:-1]) * -np.diff(lam))) + frag[-1] * lam[-1]
    assert got == pytest.approx(dense, rel=0.05)
    assert got == pytest.approx(dense, rel=1e-4)           # far better than asked: Gauss-Legendre per segment


def test_fit_statuses_and_a_second_fit_path():
    lv = np.array([0.1, 0.2, 0.4, 0.8])
    n = np.full(4, 10.0)
    assert FitStatus(int(fit_stripes(lv, np.zeros(4), n).status)) == FitStatus.none_overturn
    assert FitStatus(int(fit_stripes(lv, n, n).status)) == FitStatus.all_overturn
    sep = fit_stripes(lv, np.array([0, 0, 10, 10.0]), n)
    assert FitStatus(int(sep.status)) == FitStatus.separated
    assert float(sep.theta) == pytest.approx(math.sqrt(0.2 * 0.4))


@pytest.mark.slow
def test_im_ranking_and_sufficiency_are_reported(suite):
    ds, _, _ = suite
    ims = ds["im"].values.tolist()
    beta = dict(zip(ims, ds["beta_im"].values[0]))
    # records scaled to PGA: PGA's own dispersion is the stripes' (same points); Sa and Arias are computed
    assert beta["pga"] == pytest.approx(float(ds["beta"].values[0]), rel=0.05)
    assert np.isfinite(beta["sa"]) and np.isfinite(beta["arias"])
    assert sorted(ds["im_rank"].values[0].tolist()) == list(range(1, len(ims) + 1))


@pytest.mark.parametrize("text, im, message", [
    ("0.2,0.1", "pga", "does not increase"), ("0.1,-0.2", "pga", "positive"), ("0.1,x", "pga", "not a number"),
    ("0.1g", "pgv", "unit 'g' is not one pgv takes"), ("0.1", "tp", "not scalable"),
])
def test_bad_levels_are_usage_errors(text, im, message):
    with pytest.raises(UsageError, match=message):
        parse_levels(text, im)


def test_a_unit_suffix_applies_to_every_level():
    np.testing.assert_allclose(parse_levels("0.1g, 2.0", "pga"), [0.1 * G, 2.0 * G])
    np.testing.assert_allclose(parse_levels("0.1,0.2,0.3g", "pga"), [0.1 * G, 0.2 * G, 0.3 * G])
    np.testing.assert_allclose(parse_levels("10,20cms", "pgv"), [0.1, 0.2])
    np.testing.assert_allclose(parse_levels("0.5,1.5", "pga"), [0.5, 1.5])
    with pytest.raises(UsageError, match="several units"):
        parse_levels("0.1g,20gal", "pga")


@pytest.mark.parametrize("body, message", [
    ("pga_g\n0.1\n", "header"), ("pgv_g,annual_rate\n0.1,1e-2\n", "header"),
    ("pga_g,annual_rate\n0.1,1e-2\n0.2,2e-2\n", "line 3: annual_rate = 2e-2 increases"),
    ("pga_g,annual_rate\n0.1,1e-2\n-0.2,1e-3\n", "line 3: pga_g = '-0.2'; expected a positive number"),
    ("pga_g,annual_rate\n0.1,-1e-2\n", "line 2: annual_rate = '-1e-2'; expected a number >= 0"),
    ("pga_g,annual_rate\n0.1,1e-2\n0.2,0\n", "1 usable point(s)"),
    ("pga_g,annual_rate\n0.1,1e-2\n0.05,1e-3\n", "does not increase"),
    ("pga_g,annual_rate\n0.1,abc\n", "line 2: annual_rate = 'abc' is not a number"),
])
def test_bad_hazard_curves_name_the_file_line_and_value(tmp_path, body, message):
    path = tmp_path / "h.csv"
    path.write_text(body)
    with pytest.raises(HazardError) as err:
        read_hazard(path, im="pga")
    assert str(path) in str(err.value) and message in str(err.value)


@pytest.mark.slow
def test_an_unscalable_record_is_reported(suite):
    """ap is undefined where no pulse was extracted: the record cannot be scaled, and the run says why."""
    ds, _, results = suite
    inv = Inventory.single(**BLOCK, block_id="B")
    bad = dict(results[0])
    bad["factor"] = np.full_like(bad["factor"], np.nan)
    cfg = Config().with_uncertainty(samples=0)
    ds2 = assemble_fragility([bad, *results[1:]], inv, cfg, im="pga", levels=LEVELS, bootstrap=0)
    assert ds2["n_records"].values[0, 0] == 15
    assert any("cannot be scaled" in w and "HS00" in w for w in stripe_warnings(ds2))


@pytest.mark.slow
def test_cli_resumes_and_is_identical_on_dask(make_records, tmp_path):
    """screen fragility end to end: a second run reuses every record; Dask gives the same numbers."""
    pytest.importorskip("distributed")
    from pipeline.cli import main
    from pipeline.store import open_results

    records = make_records("peer-at2/RSN1176_KOCAELI_YPT060.AT2", "peer-at2/RSN1176_KOCAELI_YPT150.AT2",
                           "peer-at2/RSN4040_BAM_BAM-L.AT2", "peer-at2/RSN4040_BAM_BAM-T.AT2")
    blocks = tmp_path / "b.csv"
    blocks.write_text("id,height_m,width_m,mu\nTOMB,1.1,0.2,0.65\nCOL,2.0,0.5,0.7\n")
    hazard = tmp_path / "hz.csv"
    hazard.write_text("# Hazard at the museum, mean, 2026 model\npga_g_rotd100,annual_rate\n0.05,2e-2\n0.2,2e-3\n"
                      "0.8,5e-5\n1.6,4e-6\n")
    (tmp_path / "a").mkdir()
    (tmp_path / "a" / "assets.csv").write_text("screen's own table\n")   # screen fragility into screen's output
    args = ["fragility", "--records", str(records), "--blocks", str(blocks), "--im", "pga",
            "--levels", "0.1g,0.3g,0.6g", "--hazard", str(hazard), "--samples", "0", "--bootstrap", "20", "-q"]
    assert main([*args, "--out", str(tmp_path / "a")]) == 0
    first = open_results(tmp_path / "a" / "fragility.nc")
    assert main([*args, "--out", str(tmp_path / "a"), "-v"]) == 0     # resumed: nothing new to compute
    again = open_results(tmp_path / "a" / "fragility.nc")
    assert main([*args, "--out", str(tmp_path / "d"), "--scheduler", "local", "-n", "2"]) == 0
    dask = open_results(tmp_path / "d" / "fragility.nc")
    for other in (again, dask):
        for name in ("fraction_overturned", "median", "beta", "annual_rate_overturn", "beta_im"):
            np.testing.assert_array_equal(first[name].values, other[name].values, err_msg=name)
    assert np.all(first["annual_rate_overturn"].values >= 0)
    rates = [float(x) for x in first["annual_rate_overturn"].values]
    html = (tmp_path / "a" / "fragility.html").read_text()
    assert "by annual rate of overturning" in html
    assert "which its file titles &ldquo;Hazard at the museum, mean, 2026 model&rdquo;" in html
    assert "labelled synthetic" not in html and "site's hazard curve" not in html
    import re
    cells = re.findall(r"<td[^>]*>(.*?)</td>", html, flags=re.S)
    assert not [c for c in cells if re.match(r"-1 \(|.*\(\)|.*\bnan\b", c)], cells
    assert (tmp_path / "a" / "assets.csv").read_text() == "screen's own table\n"
    lines = (tmp_path / "a" / "fragility_assets.csv").read_text().splitlines()
    assert lines[0].startswith("rank,block,im,im_component,orientation,median_pga_g,median_low_pga_g") \
        and len(lines) == 3
    assert lines[1].split(",")[2:4] == ["pga", "rotd100"]
    median_g = float(lines[1].split(",")[5])
    block = lines[1].split(",")[1]
    j = [str(b) for b in first["block"].values].index(block)
    assert median_g == pytest.approx(float(first["median"].values[j]) / G, rel=1e-9)
    ranked = [float(line.split(",")[ASSET_RATE]) for line in lines[1:]]
    assert ranked == sorted(rates, reverse=True)


ASSET_RATE = 12     # column of annual_rate_overturn in fragility_assets.csv


def test_a_hazard_curve_labelled_synthetic_says_so_on_the_page(tmp_path):

    curve = read_hazard(Path(__file__).resolve().parents[2] / "configs" / "hazard-example.csv", im="pga")
    assert curve.synthetic and curve.title.startswith("SYNTHETIC hazard curve") and curve.units == "g"


def test_degenerate_fits_give_the_closed_form_rates():
    """Nothing overturns: no rate. Everything overturns at every level: the rate of exceeding the curve's
    first level (the integral of |d lambda| from there, tail included)."""
    c = HazardCurve("pga", np.array([1.0, 2.0, 4.0]), np.array([1e-2, 1e-3, 1e-4]), "x")
    assert annual_rate(c, math.inf, math.nan) == 0.0
    assert annual_rate(c, 0.0, math.nan) == pytest.approx(1e-2, rel=1e-12)


@pytest.mark.parametrize("counts", [[0, 0, 0.1], [0, 0, 0, 14]])
def test_stripes_that_do_not_bracket_half_are_not_bounded(counts):
    """The issue's two cases: 0 / 0 / 0.003 (STAT-02 on PGA) and 0 / 0 / 0 / 0.4 (CAB-03 on PGV) of 35 records: a
    median beyond the levels is never labelled ok."""
    lv = np.geomspace(0.1, 0.4, len(counts))
    fit = fit_stripes(lv, np.array(counts, dtype=float), np.full(len(counts), 35.0))
    assert FitStatus(int(fit.status)) == FitStatus.not_bounded
    assert float(fit.theta) > lv.max()


def test_a_bracketed_median_within_the_levels_is_ok_and_one_outside_is_extrapolated():
    lv = np.array([1.0, 2.0, 4.0])
    n = np.full(3, 100.0)
    assert FitStatus(int(fit_stripes(lv, np.array([10.0, 50.0, 90.0]), n).status)) == FitStatus.ok
    # 5 %, 5 % and 51 %: the stripes bracket one half (barely), but the fitted median lies above the top level
    out = fit_stripes(lv, np.array([5.0, 5.0, 51.0]), n)
    assert float(out.theta) > lv.max() and FitStatus(int(out.status)) == FitStatus.extrapolated


def test_the_interval_of_a_median_beyond_the_levels_is_open():
    from pipeline.uncertainty.fragility import bootstrap_stripes, open_interval

    lv = np.array([0.1, 0.2, 0.4])
    outcomes = np.zeros((35, 3))
    outcomes[0, 2] = 1.0                                  # one record of 35 overturns, at the top level only
    theta_ci, _ = bootstrap_stripes(lv, outcomes, draws=200, seed=1)
    assert theta_ci[1] == math.inf                        # many resamples hold no overturning at all
    assert open_interval(np.array([0, 0, 1 / 35]), np.array([0.5, 0.7]))[1] == math.inf
    assert open_interval(np.array([0.6, 0.8, 1.0]), np.array([0.05, 0.09]))[0] == 0.0


def test_nothing_overturned_gives_no_rate_but_the_hazards_rate_above_the_top_level():
    """The issue's TRAF-01 case: a block that can rock and overturned at no level gets no rate (never 0), and an
    upper bound equal to the hazard's rate of exceeding the top level (log-log interpolation, closed form)."""
    from pipeline.uncertainty.hazard import annual_rate_upper, exceedance_rate

    c = HazardCurve("pga", np.array([1.0, 2.0, 4.0]), np.array([1e-2, 1e-3, 1e-4]), "x")
    top = 3.0
    closed = 1e-3 * (top / 2.0) ** (math.log(1e-4 / 1e-3) / math.log(2.0))
    assert exceedance_rate(c, top) == pytest.approx(closed, rel=1e-12)
    assert annual_rate_upper(c, math.inf, math.nan, top) == pytest.approx(closed, rel=1e-12)
    # for a finite fit the bound is the fit's rate below the top level plus the rate above it: >= the rate
    assert annual_rate_upper(c, 2.5, 0.4, top) >= annual_rate(c, 2.5, 0.4)
    assert annual_rate_upper(c, 2.5, 0.4, 10.0) == pytest.approx(annual_rate(c, 2.5, 0.4) + 0.0, rel=0.2)


def test_the_fragility_run_never_reports_a_rate_of_zero_for_a_block_that_can_rock(tmp_path):
    """Planted: one block that rocks and one that cannot (it slides), both with no overturning at any level."""
    from pipeline.blocks import read_inventory
    from pipeline.store.exports import left_out, openquake_nrml

    csv = tmp_path / "inv.csv"
    csv.write_text("id,height_m,width_m,mu\nROCKS,2.0,0.3,2.0\nSLIDES,1.0,0.8,0.3\n")
    inv = read_inventory(csv, default_mu=0.6)
    cfg = Config().with_uncertainty(samples=0)
    ctx = Context("", cfg, inv, {})
    levels = np.array([0.01, 0.02])                        # far below any uplift: nothing overturns
    results = [judge_record(_record(k, T), ctx, "pga", levels) for k, T in enumerate(PERIODS[:4])]
    curve = HazardCurve("pga", np.array([0.005, 0.05, 0.5]), np.array([1e-1, 1e-2, 1e-4]), "x")
    from pipeline.uncertainty.hazard import HazardSet, exceedance_rate
    ds = assemble_fragility(results, inv, cfg, im="pga", levels=levels, bootstrap=0, hazard=HazardSet((curve,)))
    status = [FitStatus(int(s)) for s in ds["fit_status"].values]
    assert status == [FitStatus.none_overturn, FitStatus.none_overturn]
    rate, upper = ds["annual_rate_overturn"].values, ds["annual_rate_overturn_upper"].values
    assert math.isnan(rate[0]) and upper[0] == pytest.approx(exceedance_rate(curve, 0.02), rel=1e-12)
    assert rate[1] == 0.0 and upper[1] == 0.0              # cannot rock: cannot overturn at any level
    ds.attrs.setdefault("im_component", "rotd100")
    assert "ROCKS: nothing overturns at any level tested (raise the levels)" in left_out(ds)
    assert "no curve for ROCKS: nothing overturns" in openquake_nrml(ds)
    # advice that matches the physics: higher levels cannot overturn a block that only slides
    assert ds["can_rock"].values.tolist() == [1, 0]
    slides = [line for line in left_out(ds) if line.startswith("SLIDES")]
    assert slides == ["SLIDES: it cannot rock (it slides or stands: mu <= tan alpha, or alpha >= 54.7 deg), so no "
                      "level overturns it; its risk is sliding (see the screening's recommendation)"]
    # the page and the table say it in words: no raw "inf" or "nan" (the medians are inf, the betas NaN)
    import re

    from pipeline.report.fragility_html import build_fragility_report

    html, table = build_fragility_report(ds, tmp_path)
    text = re.sub(r"<[^>]+>", " ", re.sub(r"data:image/[^\"]+", "", html.read_text()))
    assert not re.findall(r"\b(?:nan|inf)\b", text, flags=re.I)
    cells = [c for line in table.read_text().splitlines() for c in line.split(",")]
    assert not [c for c in cells if c.strip().lower() in ("nan", "inf", "-inf")] and "" in cells


def test_levels_auto_start_at_the_uplift_and_extend_until_every_block_brackets():
    """--levels auto on the 16 half-sine records: the ladder starts at the block's uplift acceleration g tan(alpha)
    (closed form), doubles, and is extended until the stripes go from at most 10 % to at least 90 % overturning;
    the stripes are the same as a run given those levels."""
    from pipeline.run.fragility_levels import AUTO_BRACKET, auto_stripes, capacities

    inv = Inventory.single(**BLOCK, block_id="B")
    cfg = Config().with_uncertainty(samples=0)
    ctx = Context("", cfg, inv, {})
    recs = [_record(k, T) for k, T in enumerate(PERIODS)]
    alpha = math.atan2(BLOCK["width_m"], BLOCK["height_m"])
    assert float(capacities(inv, "pga", g_ms2=G)[0]) == pytest.approx(G * math.tan(alpha), rel=1e-12)

    def run(levels):
        return [judge_record(r, ctx, "pga", levels) for r in recs], [], {"records_computed": len(recs),
                                                                         "records_reused": 0, "records_failed": 0,
                                                                         "wall_time_s": 0.0}

    levels, results, _, _ = auto_stripes(run, inv, cfg, "pga")
    assert levels[0] == pytest.approx(G * math.tan(alpha), rel=1e-12) and np.all(np.diff(levels) > 0)
    np.testing.assert_allclose(levels[1:] / levels[:-1], 2.0)
    frac = np.mean(np.stack([r["verdict"] for r in results]) == 1, axis=0)[:, 0]
    assert frac[0] <= AUTO_BRACKET[0] and frac[-1] >= AUTO_BRACKET[1]
    again = [judge_record(r, ctx, "pga", levels) for r in recs]
    assert all(np.array_equal(a["verdict"], b["verdict"]) for a, b in zip(again, results))


def test_levels_auto_refuses_an_inventory_that_cannot_rock_and_an_im_without_a_capacity():
    from pipeline.run.fragility_levels import auto_ladder, capacities

    inv = Inventory.single(height_m=0.5, width_m=2.0, mu=0.3, block_id="SLAB")
    with pytest.raises(UsageError, match="no block of the inventory can rock"):
        auto_ladder(capacities(inv, "pga", g_ms2=G))
    with pytest.raises(UsageError, match="arias has no capacity"):
        capacities(inv, "arias", g_ms2=G)


def test_a_change_of_component_definition_says_why_every_scene_is_new(tmp_path, caplog):
    import logging
    import types

    import xarray as xr

    from pipeline.run.fragility import _say_why_all_is_new
    from pipeline.uncertainty.hazard import Component

    xr.Dataset(attrs={"im": "pga", "im_component": "rotd100"}).to_netcdf(tmp_path / "fragility.nc")
    with caplog.at_level(logging.WARNING):
        _say_why_all_is_new(tmp_path, types.SimpleNamespace(im="pga", component=Component.rotd50))
    assert "fitted pga as rotd100, this one as rotd50" in caplog.text and "--im-component rotd100" in caplog.text
    caplog.clear()
    with caplog.at_level(logging.WARNING):
        _say_why_all_is_new(tmp_path, types.SimpleNamespace(im="pga", component=Component.rotd100))
    assert caplog.text == ""


def test_levels_auto_brackets_the_outcome_the_fit_uses():
    """With sampling, the fit uses each scaled scene's probability: the ladder is extended on it, not on the
    nominal verdicts (planted: verdicts that bracket, probabilities that do not reach 0.9 at the top)."""
    from pipeline.run.fragility_levels import extension

    levels = np.array([1.0, 2.0, 4.0])
    cap = np.array([1.0])
    verdict = np.array([[[0], [1], [1]]] * 5, dtype="i1")                   # 5 records: 0, 1, 1 over the levels
    p = np.array([[[0.0], [0.5], [0.6]]] * 5)
    results = [{"verdict": v, "p_random": q} for v, q in zip(verdict, p)]
    assert extension(levels, results, cap) == []
    assert extension(levels, results, cap, outcome="p_random") == [8.0]
