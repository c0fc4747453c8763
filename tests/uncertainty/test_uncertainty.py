"""Issue 19: the probability of overturning under declared uncertainty.

Truth here is independent of the sampler: the overturning threshold of a half-sine pulse
from the independent solver (``solve_ivp``, :func:`rock_reference`) with the lognormal
closed form P = Phi(ln(A / A*) / s); the exact at-rest certificate; the nominal simulator
(``worst_plane``) for unit factors; and the executors against each other.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.stats import norm

from pipeline.blocks import geometry
from pipeline.config import Config, config_from_dict
from pipeline.errors import ConfigError
from pipeline.rocking.block import Block, BlockShape
from pipeline.rocking.orientation import Planes, plane_grid, worst_plane
from pipeline.rocking.references.excitation import pulse
from pipeline.rocking.references.reference import rock_reference
from pipeline.rocking.simulate import rock
from pipeline.uncertainty.robust import Robustness
from pipeline.uncertainty.sampling import common_normals, lognormal_factor
from pipeline.uncertainty.scenes import motion, scene_probability
from pipeline.uncertainty.settings import UncertaintyConfig

G = 9.80665
#: a slender block (2 m x 0.3 m) that cannot slide (mu = 2), Housner's restitution
HEIGHT, WIDTH, MU = 2.0, 0.3, 2.0
AMPLITUDE_ONLY = UncertaintyConfig(samples=4000, batch=4000, amplitude_cov=0.05, restitution_cov=0.0,
                                   friction_cov=0.0, size_cov=0.0, azimuth_sd_deg=0.0, seed=7)


def _block():
    geo = geometry(HEIGHT, WIDTH, g_ms2=G)
    return float(geo.p), float(geo.alpha), float(geo.e_housner), float(geo.R)


def _halfsine(amplitude_ms2: float, omega_over_p: float = 3.0):
    p, *_ = _block()
    return pulse("half-sine", amplitude_ms2=amplitude_ms2, period_s=2 * math.pi / (omega_over_p * p),
                 samples_per_period=1000)


@pytest.fixture(scope="module")
def halfsine_threshold() -> float:
    """Smallest overturning amplitude of the half-sine [m s-2], by bisection on the independent solver."""
    p, alpha, e, _ = _block()
    lo, hi = G * math.tan(alpha), 20 * G * math.tan(alpha)

    def over(a):
        ah, dt = _halfsine(a)
        return rock_reference(ah, dt, p=p, alpha=alpha, e=e, g=G).overturned

    assert not over(lo) and over(hi)
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if over(mid) else (mid, hi)
    return hi


def test_overturning_is_monotonic_in_amplitude_around_the_threshold(halfsine_threshold):
    """The premise of the closed form: below A* the block stands, above it overturns (project simulator)."""
    p, alpha, e, R = _block()
    for f in np.linspace(0.8, 1.25, 46):
        ah, dt = _halfsine(f * halfsine_threshold)
        assert rock(ah, dt, p=p, alpha=alpha, e=e, R_m=R).overturned == (f > 1.0 + 1e-9), f


@pytest.mark.parametrize("log_offset, expected", [(0.0, 0.5), (0.05, float(norm.cdf(0.05 / math.sqrt(math.log1p(
    0.05 ** 2)))))])
def test_amplitude_uncertainty_matches_the_lognormal_closed_form(halfsine_threshold, log_offset, expected):
    """P(overturn) = Phi(ln(A / A*) / s): 0.5 at A*, Phi(1) = 0.84 at A* e^0.05 (cov 0.05)."""
    ah, dt = _halfsine(halfsine_threshold * math.exp(log_offset))
    m = motion(ah[None, :], 0.0, None, dt)
    prob = scene_probability(m, common_normals(AMPLITUDE_ONLY.seed, AMPLITUDE_ONLY.samples), BlockShape(height_m=HEIGHT,
                             width_m=WIDTH, mu=MU, restitution=math.nan, azimuth_deg=math.nan),
                             settings=AMPLITUDE_ONLY, g_ms2=G)
    assert prob.drawn == 4000
    se = math.sqrt(expected * (1 - expected) / prob.drawn)
    assert prob.p == pytest.approx(expected, abs=4 * se)
    assert prob.low < expected < prob.high


@pytest.mark.parametrize("samples, p_halfwidth", [(40, 0.1), (120, 0.1), (40, 0.5)])
def test_a_sensitive_scene_is_sampled_to_the_stated_precision(halfsine_threshold, samples, p_halfwidth):
    """At the threshold amplitude (closed form p = 0.5) the scene is sensitive: it is sampled until half its
    90 % Wilson interval is at most p_halfwidth or the samples run out (at p = 0.5 that takes about 65);
    p_halfwidth = 0.5 stops as soon as the class is decided, as the rule did before the target."""
    ah, dt = _halfsine(halfsine_threshold)
    cfg = dataclasses.replace(AMPLITUDE_ONLY, samples=samples, batch=5, p_halfwidth=p_halfwidth)
    prob = scene_probability(motion(ah[None, :], 0.0, None, dt), common_normals(cfg.seed, cfg.samples),
                             BlockShape(height_m=HEIGHT, width_m=WIDTH, mu=MU),
                             settings=cfg, g_ms2=G)
    assert prob.robustness == Robustness.sensitive
    half = (prob.high - prob.low) / 2
    if p_halfwidth >= 0.5:
        assert prob.drawn < 40                              # stopped once sensitive was decided
    elif prob.drawn < samples:
        assert half <= p_halfwidth                          # stopped on the precision target
        assert prob.drawn >= 55                             # which at p near 0.5 needs about 65 samples
    else:
        assert samples == 40 and half > p_halfwidth        # the samples ran out first
    assert prob.low < 0.5 < prob.high


def test_record_below_uplift_gives_zero_without_integration():
    """Every sample below the uplift threshold: p = 0 exactly, nothing integrated."""
    _, alpha, _, _ = _block()
    ah, dt = _halfsine(0.5 * G * math.tan(alpha))
    cfg = UncertaintyConfig(samples=40)
    prob = scene_probability(motion(ah[None, :], 0.0, None, dt), common_normals(cfg.seed, cfg.samples),
                             BlockShape(height_m=HEIGHT, width_m=WIDTH, mu=MU),
                             settings=cfg, g_ms2=G)
    assert prob.p == 0.0 and prob.simulations == 0
    assert prob.robustness == Robustness.robust_stand
    assert prob.high < cfg.robust_below


def test_harmonic_near_its_chaotic_threshold_is_sensitive():
    """A 25-cycle harmonic at the smallest overturning amplitude on a fine grid: 0 < p < 1."""
    p, alpha, e, R = _block()
    period = 2 * math.pi / (2.0 * p)

    def over(a):
        ah, dt = pulse("harmonic", amplitude_ms2=a, period_s=period, cycles=25, samples_per_period=200)
        return rock(ah, dt, p=p, alpha=alpha, e=e, R_m=R).overturned

    grid = G * math.tan(alpha) * np.linspace(1.0, 3.0, 201)
    outcomes = np.array([over(a) for a in grid])
    first = int(np.argmax(outcomes))
    assert outcomes[first] and not outcomes[:first].any()
    ah, dt = pulse("harmonic", amplitude_ms2=grid[first], period_s=period, cycles=25, samples_per_period=200)
    cfg = UncertaintyConfig(samples=200, batch=200, seed=3)
    prob = scene_probability(motion(ah[None, :], 0.0, None, dt), common_normals(cfg.seed, cfg.samples),
                             BlockShape(height_m=HEIGHT, width_m=WIDTH, mu=MU),
                             settings=cfg, g_ms2=G)
    assert 0.0 < prob.p < 1.0
    assert prob.robustness == Robustness.sensitive


def test_unit_factors_reproduce_the_nominal_orientation_scan(records_dir, config):
    """With every spread 0, each sample is the nominal block: its verdict is worst_plane's on the grid."""
    from pipeline.records.listing import list_directory
    from pipeline.run.screening import Context

    scanned = list_directory(records_dir / "peer-at2", config=config)
    zero = UncertaintyConfig(samples=5, batch=5, amplitude_cov=0.0, restitution_cov=0.0, friction_cov=0.0,
                             size_cov=0.0, azimuth_sd_deg=0.0)
    ctx = Context(str(records_dir / "peer-at2"), config, None, {}, None)
    checked = 0
    for src in scanned.sources[:6]:
        rec = ctx.load(src)
        planes = Planes(rec.horizontal_ms2, rec.azimuths_deg[0], rec.vertical_ms2, g_ms2=G)
        grid = [0.0, *plane_grid(5.0).tolist()]
        for height, width in ((1.1, 0.2), (2.0, 0.5), (3.0, 0.3)):
            geo = geometry(height, width, g_ms2=G)
            nominal = worst_plane(planes, grid, rec.dt_s, block=Block(p=float(geo.p), alpha=float(geo.alpha),
                                                                     e=float(geo.e_housner), R_m=float(geo.R),
                                                                     mu=0.7, g_ms2=G))
            m = motion(rec.horizontal_ms2, rec.azimuths_deg[0], rec.vertical_ms2, rec.dt_s, planes_deg=grid)
            prob = scene_probability(m, common_normals(1, 5), BlockShape(height_m=height, width_m=width, mu=0.7,
                                     restitution=math.nan, azimuth_deg=math.nan), settings=zero, g_ms2=G)
            expected = nominal.scene.verdict
            if expected == -1:
                assert prob.without_verdict == prob.drawn
            else:
                assert prob.p == float(expected), (src.record_id, height, width)
            checked += 1
    assert checked == 18


def test_common_random_numbers_are_shared_and_extend():
    z10, z40 = common_normals(5, 10), common_normals(5, 40)
    np.testing.assert_array_equal(z10, z40[:10])
    f = lognormal_factor(np.array([0.0, 1.0]), 0.05)
    assert f[0] == 1.0 and f[1] == pytest.approx(math.exp(math.sqrt(math.log1p(0.0025))))


def test_impossible_samples_are_handled_not_crashed():
    """A squat block whose sampled sizes pass 54.7 deg is simulated as sliding; restitution stays in [0, 1]."""
    from pipeline.uncertainty.sampling import sample_block

    cfg = UncertaintyConfig(size_cov=0.9, restitution_cov=0.9)
    sb = sample_block(common_normals(1, 500), BlockShape(height_m=1.0, width_m=1.35, mu=0.6, restitution=math.nan,
                      azimuth_deg=math.nan), settings=cfg)
    assert np.all((sb.e >= 0) & (sb.e <= 1))
    assert np.any(sb.alpha > math.asin(math.sqrt(2 / 3)))
    ah, dt = pulse("half-sine", amplitude_ms2=8.0, period_s=1.0)
    prob = scene_probability(motion(ah[None, :], 0.0, None, dt), common_normals(1, 40), BlockShape(height_m=1.0,
                             width_m=1.35, mu=0.6, restitution=math.nan, azimuth_deg=math.nan), settings=cfg)
    assert prob.drawn > 0 and 0.0 <= prob.p <= 1.0


@pytest.mark.parametrize("key, value, message", [
    ("amplitude_cov", 1.0, "[0, 1)"), ("friction_cov", -0.1, "non-negative"), ("samples", 2.5, "integer"),
    ("samples", -1, "non-negative integer"), ("size_cov", 3.0, "[0, 1)"), ("azimuth_sd_deg", 90.0, "[0, 45]"),
])
def test_bad_spreads_are_config_errors_naming_the_key(key, value, message):
    with pytest.raises(ConfigError) as err:
        config_from_dict({"uncertainty": {key: value}}, where="x.toml")
    assert key in str(err.value) and message in str(err.value)


def test_cli_overrides_are_checked():
    cfg = Config().with_uncertainty(samples=0, seed=4)
    assert cfg.uncertainty.samples == 0 and cfg.uncertainty.seed == 4
    with pytest.raises(ConfigError, match="samples"):
        Config().with_uncertainty(samples=-3)


@pytest.mark.slow
def test_probabilities_identical_serial_and_dask(make_records, blocks_csv, tmp_path):
    """The same seed gives the same p_overturn serial, on processes and on Dask."""
    pytest.importorskip("distributed")
    from pipeline.blocks import read_inventory
    from pipeline.run import batch
    from pipeline.run.executors import make_executor

    records = make_records("peer-at2/RSN1176_KOCAELI_YPT060.AT2", "peer-at2/RSN1176_KOCAELI_YPT150.AT2",
                           "peer-at2/RSN1176_KOCAELI_YPT-UP.AT2", "sac/20190706031952.CJ.T001230.HNE.sac",
                           "sac/20190706031952.CJ.T001230.HNN.sac", "sac/20190706031952.CJ.T001230.HNZ.sac")
    cfg = dataclasses.replace(Config(), uncertainty=UncertaintyConfig(samples=20))
    inv = read_inventory(blocks_csv, default_mu=cfg.blocks.default_mu)
    results = {}
    for name, kwargs in (("serial", {"n_workers": 1}), ("processes", {"n_workers": 2}),
                         ("dask", {"n_workers": 2, "scheduler": "local"})):
        with make_executor(**kwargs) as ex:
            results[name] = batch.run(records, inv, cfg, executor=ex).results
    names = ("p_overturn", "p_overturn_low", "p_overturn_high", "robustness", "samples_drawn", "sample_simulations")
    assert np.isfinite(results["serial"]["p_overturn"].values).any()
    for other in ("processes", "dask"):
        for n in names:
            np.testing.assert_array_equal(results["serial"][n].values, results[other][n].values, err_msg=n)


@pytest.mark.slow       # 33 s since five bundled boxes are judged in 3D (their sampled margins are 3D scans)
def test_default_screen_is_probabilistic_end_to_end(make_records, blocks_csv, tmp_path, capsys):
    """The default command samples every scene; screening.nc, assets.csv and the report carry p_overturn."""
    import csv

    from pipeline.cli import main
    from pipeline.schema import check
    from pipeline.store import open_results

    records = make_records("peer-at2/RSN1176_KOCAELI_YPT060.AT2", "peer-at2/RSN1176_KOCAELI_YPT150.AT2",
                           "peer-at2/RSN1176_KOCAELI_YPT-UP.AT2")
    out = tmp_path / "out"
    cfg = tmp_path / "margins.toml"
    cfg.write_text("[uncertainty]\nmargin_samples = 5\n")           # the default run plus sampled margins
    assert main(["--records", str(records), "--blocks", str(blocks_csv), "--out", str(out), "-q",
                 "--config", str(cfg)]) == 0
    ds = open_results(out / "screening.nc")
    assert check(ds) == []
    p, lo, hi = (ds[n].values for n in ("p_overturn", "p_overturn_low", "p_overturn_high"))
    drawn = ds["samples_drawn"].values
    assert np.all(drawn > 0) and np.all(drawn <= UncertaintyConfig().samples)
    judged = np.isfinite(p)
    assert np.all((lo[judged] <= p[judged]) & (p[judged] <= hi[judged]))
    # a nominal verdict and the probability sit side by side; proven-at-rest scenes cost no simulation
    rest = ds["physics"].values == 0
    assert np.all(ds["overturn"].values[rest] == 0)
    assert ds.attrs["uncertainty_samples"] == UncertaintyConfig().samples
    # per asset: p on the governing record, and the median of the sampled margins
    rec_index = {r: i for i, r in enumerate(ds["record"].values.tolist())}
    for j, gov in enumerate(ds["governing_record"].values.tolist()):
        if gov:
            i = rec_index[gov]
            assert ds["p_overturn_governing"].values[j] == pytest.approx(ds["p_overturn"].values[i, j], nan_ok=True)
    margin, median = ds["overturn_scale_simulated"].values, ds["overturn_scale_median"].values
    finite = np.isfinite(margin) & np.isfinite(median)
    assert finite.any()
    # the sampled margins scatter around the nominal one by the declared spreads, not by orders of magnitude
    assert np.all((median[finite] > 0.5 * margin[finite]) & (median[finite] < 2.0 * margin[finite]))
    with open(out / "assets.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    # ranked by probability first, the samples without a verdict counted as overturning (unknown is never safe)
    ps = [float(np.fmax(float(r["p_overturn"] or "nan"), float(r["p_overturn_with_unknown"] or "nan"))) for r in rows]
    assert ps == sorted(ps, reverse=True)
    assert all(r["robustness"] in ("robust_stand", "sensitive", "robust_overturn", "unknown") for r in rows)
    assert all(r["robustness"] != "robust_stand" for r in rows if int(r["draws_without_verdict"]) > 0)
    html = (out / "report.html").read_text()
    assert "Sensitive</b> means" in html and "p overturn (90 % interval)" in html
    # the closing summary counts the robustness classes (a re-run: everything from the cache)
    capsys.readouterr()
    assert main(["--records", str(records), "--blocks", str(blocks_csv), "--out", str(out),
                 "--config", str(cfg)]) == 0
    line = next(x for x in capsys.readouterr().err.splitlines() if x.startswith("under the declared uncertainty"))
    counts = {m.name: int((ds["robustness"].values == m.value).sum()) for m in Robustness}
    assert all(f"{k} {v}" in line for k, v in counts.items())
