"""A missing verdict is unknown, never safe: in every probability, robustness class, asset row, recommendation,
fragility stripe and event level; and a scan's weakest plane is always among the planes judged."""

from __future__ import annotations

import math
from statistics import NormalDist

import numpy as np
import pytest

from pipeline.rocking.codes import Verdict
from pipeline.uncertainty.robust import Robustness
from pipeline.uncertainty.scenes import sample_until_decided
from pipeline.uncertainty.settings import UncertaintyConfig


def _judge_fixed(codes: np.ndarray):
    """A judge that gives the draws fixed verdicts (a stand-in for the simulator, so that the counting is tested
    against numbers fixed in advance)."""
    def judge(rows: slice, verdicts: np.ndarray, simulations: np.ndarray) -> None:
        verdicts[rows] = codes[rows]
        simulations[rows] = 1
    return judge


@pytest.mark.parametrize("overturned, unknown", [(0, 15), (3, 12), (0, 1), (10, 30)])
def test_the_interval_spans_the_draws_without_a_verdict(overturned, unknown):
    n = 40
    codes = np.full(n, Verdict.stands, dtype=np.int64)
    codes[:overturned] = Verdict.overturns
    codes[overturned:overturned + unknown] = Verdict.no_verdict
    rng = np.random.default_rng(1)
    rng.shuffle(codes)
    settings = UncertaintyConfig(samples=n, batch=n)           # one batch: the counts are the whole draw
    prob = sample_until_decided(n, _judge_fixed(codes), settings=settings)
    assert (prob.drawn, prob.overturned, prob.without_verdict) == (n, overturned, unknown)
    # the bounds are Wilson's (1927) on the two readings of the unknown draws, written out here
    z = NormalDist().inv_cdf(0.5 + settings.confidence / 2.0)

    def wilson(k: int, sign: float) -> float:
        if (sign < 0 and k == 0) or (sign > 0 and k == n):
            return 0.0 if sign < 0 else 1.0
        centre = (k + z * z / 2.0) / (n + z * z)
        return centre + sign * z * math.sqrt(k * (n - k) / n + z * z / 4.0) / (n + z * z)

    assert prob.low == pytest.approx(wilson(overturned, -1.0)) and prob.high == pytest.approx(
        wilson(overturned + unknown, +1.0))
    assert prob.high >= (overturned + unknown) / n >= prob.p * (n - unknown) / n
    assert prob.p == pytest.approx(overturned / (n - unknown))
    assert prob.robustness != Robustness.robust_stand


def test_robust_stand_needs_fewer_than_one_unknown_draw_in_ten():
    """With a lenient threshold the interval alone would call 5 unknown draws of 40 robust_stand; 1 of 40 is."""
    settings = UncertaintyConfig(samples=40, batch=40, robust_below=0.5)
    for unknown, expected in ((5, Robustness.sensitive), (1, Robustness.robust_stand)):
        codes = np.full(40, Verdict.stands, dtype=np.int64)
        codes[:unknown] = Verdict.no_verdict
        assert sample_until_decided(40, _judge_fixed(codes), settings=settings).robustness == expected


def test_a_scene_with_no_verdict_at_all_is_not_standing():
    codes = np.full(40, Verdict.no_verdict, dtype=np.int64)
    prob = sample_until_decided(40, _judge_fixed(codes), settings=UncertaintyConfig(samples=40, batch=10))
    assert math.isnan(prob.p) and prob.low == 0.0 and prob.high == 1.0
    assert prob.robustness == Robustness.sensitive and prob.without_verdict == prob.drawn == 10


@pytest.mark.parametrize("kwargs", [
    # the cabinet of the finding: 15 of 31 stations without a verdict, its governing scene slides
    {"undecided": 15, "stations": (0, 31), "response": 1, "slide_m": 0.0},
    # samples without a verdict that could lift p to 0.53
    {"unknown_draws": (15, 40), "p_with_unknown": 0.53, "stations": (0, 31), "response": 2},
])
def test_an_asset_not_judged_is_at_risk_never_no_action_nor_a_sliding_of_zero(kwargs):
    from pipeline.risk import recommendation

    text = recommendation(sim_scale=math.inf, crit_overturns=False, p_max=0.0, p_record="R", governing="G",
                          **kwargs)
    assert text.startswith("at risk until judged:"), text
    assert "no action" not in text and "slides 0 m" not in text


def test_the_criterion_tier_never_writes_no_action():
    from pipeline.risk import recommendation

    for response in (0, 1, 2):
        text = recommendation(sim_scale=math.nan, crit_overturns=False, response=response, stations=(0, 31),
                              criterion_only=True)
        assert text.startswith("check by simulation:") and "no action" not in text, text


@pytest.mark.parametrize("sim, undecided, unknown", [(0, 11, 0), (0, 0, 3), (-1, 15, 0)])
def test_the_simulated_verdict_never_reads_stands_where_something_was_not_judged(sim, undecided, unknown):
    from pipeline.risk import _verdict_words

    words = _verdict_words(sim, 2, math.nan, undecided, 35, unknown)
    assert words.startswith("unknown:") and words != "stands", words


def test_fragility_stripes_bounded_both_ways_by_the_records_without_a_verdict():
    from pipeline.run.fragility_assembly import _unjudged
    from pipeline.uncertainty.fragility import fit_stripes

    levels = np.array([0.5, 1.0, 2.0, 4.0])
    rng = np.random.default_rng(3)
    n_rec = 30
    # a lognormal truth (median 1.5, beta 0.5); 8 records go without a verdict at the top two levels (the strong
    # levels are where a 3D model stops)
    capacity = 1.5 * np.exp(0.5 * rng.standard_normal(n_rec))
    truth = (levels[None, :] >= capacity[:, None]).astype(float)[:, :, None]
    outcome = truth.copy()
    outcome[:8, 2:, 0] = np.nan
    factor = np.ones_like(outcome)
    results = [{"slides": np.full((4, 1), -1)} for _ in range(n_rec)]
    u = _unjudged(results, outcome, factor, sampled=False, shape=(4, 1))
    np.testing.assert_array_equal(u.count[:, 0], [0, 0, 8, 8])
    n = np.sum(np.isfinite(outcome), axis=0)[:, 0]
    z = np.nansum(outcome, axis=0)[:, 0]
    judged = fit_stripes(levels, z, n)
    over = fit_stripes(levels, z + u.overturn_add[:, 0], np.full(4, n_rec))
    stand = fit_stripes(levels, z + u.stand_add[:, 0], np.full(4, n_rec))
    # the fit of the whole truth (no record unknown) lies between the two readings of the unknown records
    whole = fit_stripes(levels, truth.sum(axis=0)[:, 0], np.full(4, n_rec))
    assert float(over.theta) <= float(whole.theta) <= float(stand.theta)
    assert float(over.theta) < float(stand.theta) and np.isfinite(float(judged.theta))


def test_a_sampled_scene_adds_its_unknown_fraction_to_the_bounds():
    from pipeline.run.fragility_assembly import _unjudged

    outcome = np.array([[[0.2]]])                  # p over the judged samples
    results = [{"p_unknown": np.array([[0.25]]), "slides": np.array([[0]])}]
    u = _unjudged(results, outcome, np.ones((1, 1, 1)), sampled=True, shape=(1, 1))
    # k / n = 0.2 x 0.75 = 0.15 counted standing; + 0.25 counted overturning
    assert outcome[0, 0, 0] + u.stand_add[0, 0] == pytest.approx(0.15)
    assert outcome[0, 0, 0] + u.overturn_add[0, 0] == pytest.approx(0.40)
    assert u.count[0, 0] == pytest.approx(0.25)


def test_the_event_never_says_none_where_p_is_unknown_or_the_asset_slides():
    from pipeline.event.assets import Basis, Fragilities, Level, event_risk, levels

    frag = Fragilities(median=np.array([10.0, 10.0, 10.0]), beta=np.array([0.4, 0.4, 0.4]),
                       median_low=np.array([8.0, 8.0, 8.0]), median_high=np.array([12.0, 12.0, 12.0]),
                       status=np.zeros(3, int), level_min=1.0, level_max=20.0, can_rock=np.array([True, True, False]),
                       median_unjudged=np.array([np.nan, 2.0, np.nan]), beta_unjudged=np.array([np.nan, 0.4, np.nan]),
                       slides_from=np.array([np.inf, np.inf, 1.5]))
    risk = event_risk(np.full(3, 2.0), np.full(3, 0.3), frag)
    assert risk.p[0] < 0.01 and risk.p[1] == risk.p[0]          # the judged records alone read safe
    assert risk.p_high[1] > 0.4 and risk.p_rank[1] > 0.4 and risk.basis[1] == Basis.unjudged
    assert risk.p[2] == 0.0 and bool(risk.sliding[2])             # it cannot rock, but it slid at this shaking
    lv = levels(risk.p_rank, (0.05, 0.2, 0.5), at_least_low=risk.sliding)
    assert lv[0] == Level.none and lv[1] != Level.none and lv[2] == Level.low


def _turned_box(scans_dir, tmp_path, degrees: float):
    """The bundled 0.3 x 3.0 x 1.5 m box mesh turned about the vertical by ``degrees``."""
    src = (scans_dir / "box-0.3x3.0x1.5.obj").read_text().splitlines()
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    out = []
    for line in src:
        if line.startswith("v "):
            x, y, z = (float(t) for t in line.split()[1:4])
            line = f"v {c * x - s * y:.12f} {s * x + c * y:.12f} {z:.12f}"
        out.append(line)
    path = tmp_path / f"box-turned-{degrees}.obj"
    path.write_text("\n".join(out) + "\n")
    return path


@pytest.mark.parametrize("degrees", [0.0, 2.5, 17.0, 44.0])
def test_the_weakest_plane_is_judged_whatever_the_mesh_rotation(scans_dir, tmp_path, degrees):
    from pipeline.rocking.orientation import plane_grid
    from pipeline.rocking.scanned.planes import body_planes
    from pipeline.shapes.plane import footprint_extents
    from pipeline.shapes.scan import read_scan

    shape = read_scan(_turned_box(scans_dir, tmp_path, degrees))
    planes = body_planes(plane_grid(5.0), shape)
    smallest = min(footprint_extents(shape, phi)[0] for phi in planes) / shape.com_height_m
    assert smallest == pytest.approx(0.15 / 0.75, rel=1e-6)      # tan alpha of the slab's thin side, 0.2


def test_a_turned_mesh_overturns_as_the_unturned_one_does(scans_dir, tmp_path):
    """A 1 s one-sine pulse of 0.35 g on one horizontal overturns the slab given as a mesh (tan alpha 0.2); turned by
    2.5 deg, its grid planes alone stand (their smallest tan alpha is 0.287; measured: they stand up to 0.35 g and
    overturn from 0.40 g), and the weakest plane added to them overturns it as the unturned mesh."""
    from pipeline.cli import main

    dt, tp = 0.01, 1.0
    t = np.arange(0.0, 6.0, dt)
    a = np.where((t >= 1.0) & (t < 1.0 + tp), 0.35 * np.sin(2 * math.pi * (t - 1.0) / tp), 0.0)
    records = tmp_path / "records"
    records.mkdir()
    (records / "pulse.txt").write_text("# dt_s=0.01 units=g\n" + "\n".join(f"{x:.8f}" for x in a) + "\n")
    mesh = _turned_box(scans_dir, tmp_path, 2.5)
    flat = _turned_box(scans_dir, tmp_path, 0.0)
    inv = tmp_path / "blocks.csv"
    inv.write_text("id,name,height_m,width_m,mu,azimuth_deg,mesh\n"
                   f"TURNED,slab turned 2.5 deg,,,1.0,,{mesh.name}\nFLAT,slab,,,1.0,,{flat.name}\n")
    out = tmp_path / "out"
    assert main(["--records", str(records), "--blocks", str(inv), "--out", str(out), "--samples", "0"]) == 0
    from pipeline.store import open_results

    ds = open_results(out / "screening.nc")
    assert ds["overturn_simulated"].sel(block="FLAT").values.tolist() == [1]
    assert ds["overturn_simulated"].sel(block="TURNED").values.tolist() == [1]


def test_a_scanned_pivot_that_would_slip_gives_no_verdict(scans_dir):
    """Friction far below the demand of rocking: the rolling model's pivot would slip, which it does not follow; the
    scene has no verdict (never "stands") unless it overturned."""
    from pipeline.rocking.scanned.planes import plane_geometry, plane_scene
    from pipeline.rocking.settings import SimulationConfig
    from pipeline.shapes.scan import read_scan

    shape = read_scan(scans_dir / "leaning-statue.obj")
    dt = 0.005
    t = np.arange(0.0, 4.0, dt)
    exceeded = 0
    for body_deg in (0.0, 90.0, 180.0, 270.0):
        geometry = plane_geometry(shape, body_deg, SimulationConfig())
        for amplitude_g in (0.15, 0.25, 0.4):
            a = np.where(t < 0.6, amplitude_g * 9.80665 * np.sin(2 * math.pi * t / 0.6), 0.0)
            sc = plane_scene(a, None, dt, geometry, restitution=math.nan, mu=0.12, settings=SimulationConfig(),
                             g_ms2=9.80665)
            if sc.friction_exceeded == 1:
                exceeded += 1
                assert sc.overturned or sc.verdict == -1, (body_deg, amplitude_g, sc)
    assert exceeded >= 3


@pytest.mark.parametrize("theta_over_alpha, rate, a_x, a_y", [(0.3, 0.4, 2.0, 1.5), (0.7, -0.8, -1.0, -2.5),
                                                             (0.05, 0.0, 3.0, 0.0)])
def test_the_3d_edge_forces_split_between_the_corners_as_the_balances_say(theta_over_alpha, rate, a_x, a_y):
    """On an edge the kernel's corner forces (normal forces and the second corner's force across the edge, from its
    Euler equation about the pivot) equal the closed form of the two corners' balances about G: the yaw couple
    X_+ - X_- = d a_y / c and the roll N_+ - N_- = -z_G a_y / c (box_planar's module), d and z_G the edge's horizontal
    and vertical distances from G."""
    from pipeline.rocking.solids.box_kernel import EDGE, FORCE_SIZE, _params, derivatives

    g, b, c, h = 9.80665, 0.12, 0.12, 0.31
    prm = _params(g, b, c, h, 0.62, 1.0, 1e-8, 1e-8)
    alpha = math.atan2(b, h)
    theta = theta_over_alpha * alpha
    # tilted about +y by theta on edge 3 (corner 3 (+b, -c) to corner 0 (+b, +c), along +y): the top toward +x
    y = np.array([math.cos(theta / 2), 0.0, math.sin(theta / 2), 0.0, 0.0, rate, 0.0])
    _, f = derivatives(y, -a_x, -a_y, -g, prm, EDGE, 3)
    assert len(f) == FORCE_SIZE
    fx, fy, fz, n_minus, n_plus, across_plus = f
    big_r = math.hypot(b, h)
    d, z = big_r * math.sin(alpha - theta), big_r * math.cos(alpha - theta)
    assert fy == pytest.approx(a_y, abs=1e-9)
    assert n_plus - n_minus == pytest.approx(-z * a_y / c, abs=1e-9)
    # e_z x u = -e_x: the kernel's force across the edge at the + corner is -X_+
    assert -across_plus == pytest.approx((fx + d * a_y / c) / 2.0, abs=1e-9)


def test_a_corner_that_slips_on_an_edge_is_a_slide():
    from pipeline.rocking.solids.box_kernel import edge_ends_hold

    # the total force well inside the cone (0.4 of mu 0.62 at N = 1), the couple pushing one corner past it
    mu = 0.62
    ok = np.array([0.4, 0.0, 1.0, 0.5, 0.5, -0.2, ])    # X_2 = 0.2, X_1 = 0.2 across (u = +y: across is -x)
    assert edge_ends_hold(ok, mu, 0.0, 1.0)
    couple = np.array([0.4, 0.0, 1.0, 0.5, 0.5, -0.55])  # X_2 = 0.55 > mu N_2 = 0.31
    assert not edge_ends_hold(couple, mu, 0.0, 1.0)
    along = np.array([0.0, 0.6, 1.0, 0.5, 0.5, 0.0])     # all along the edge: rooms 0.31 + 0.31 >= 0.6
    assert edge_ends_hold(along, mu, 0.0, 1.0)
    assert not edge_ends_hold(np.array([0.0, 0.63, 1.0, 0.5, 0.5, 0.0]), mu, 0.0, 1.0)


def _corner_demand(ax, ay, dt, *, b, c, h, mu):
    """The worse corner's |X| / N over the planar run of a box rocking in the plane of its width (its kinematics from
    the planar history, the corners by the balances about G), and that run's scene: an independent reading of what
    one end of the edge must carry."""
    from pipeline.rocking.block import BlockShape, dynamics
    from pipeline.rocking.planner import simulate_scene
    from pipeline.rocking.settings import SimulationConfig

    g = 9.80665
    big_r, alpha = math.hypot(b, h), math.atan2(b, h)
    blk = dynamics([BlockShape(height_m=2 * h, width_m=2 * b, mu=mu)])[0]
    sc = simulate_scene(ax, None, dt, block=blk, settings=SimulationConfig(), history=True)
    th = sc.theta_over_alpha * alpha
    rate = np.gradient(th, dt)
    acc = np.gradient(rate, dt)
    worst = 0.0
    lifted = np.abs(th) > 1e-3 * alpha
    # away from impacts and uplifts, where differences of the history do not give the acceleration
    impact = ~lifted | np.r_[np.sign(th[1:]) != np.sign(th[:-1]), False] | np.r_[False, np.sign(th[1:]) != np.sign(
        th[:-1])]
    steady = np.convolve(impact.astype(int), np.ones(7, dtype=int), mode="same") == 0
    for k in np.flatnonzero(steady):
        s, phi = np.sign(th[k]), alpha - abs(th[k])
        dphi, ddphi = -s * rate[k], -s * acc[k]
        fx = -s * (big_r * math.cos(phi) * ddphi - big_r * math.sin(phi) * dphi ** 2) + ax[k]
        n = -big_r * math.sin(phi) * ddphi - big_r * math.cos(phi) * dphi ** 2 + g
        d, z = big_r * math.sin(phi), big_r * math.cos(phi)
        for sign in (1.0, -1.0):        # the end at y = sign c: the yaw couple's sign follows the pivot's side s
            x_i, n_i = (fx + s * sign * d * ay[k] / c) / 2.0, (n - sign * z * ay[k] / c) / 2.0
            worst = max(worst, abs(x_i) / n_i if n_i > 0 else math.inf)
    return worst, sc


@pytest.mark.parametrize("cross_g, slips", [(0.0, False), (0.1, False), (0.34, True)])
def test_an_edge_end_that_would_slip_gives_no_verdict_and_no_certificate(cross_g, slips):
    """A 0.24 x 0.24 x 0.62 m box, mu 0.62, under a 0.3 s one-sine x pulse of 1.45 g tan(alpha) and a cross motion:
    the total force stays inside the friction cone (peak |F_h| / F_z 0.43-0.53), while with 0.34 g across one end of
    the edge needs 4.4 (read here from the planar run by the corners' balances, independently of the 3D kernel).
    There the 3D model flags a slide (no verdict: it does not follow the twist) where it used to say "stands", and
    the planar certificate never certifies a box whose edge end would slip."""
    from pipeline.rocking.solids.box3d import Box, simulate_box
    from pipeline.rocking.solids.box_planar import other_axis_certificate
    from pipeline.rocking.solids.vec3 import FLAG_NONE, FLAG_SLIDE

    b, c, h, mu, g = 0.12, 0.12, 0.31, 0.62, 9.80665
    dt = 0.001
    t = np.arange(0.0, 3.0, dt)
    pulse = np.where(t < 0.3, np.sin(2 * math.pi * t / 0.3), 0.0)
    ax, ay = 1.45 * (b / h) * g * pulse, cross_g * g * pulse
    box = Box(b, c, h, mu)
    demand, sc = _corner_demand(ax, ay, dt, b=b, c=c, h=h, mu=mu)
    assert sc.verdict == 0 and sc.friction_demand < mu
    assert (demand > mu) == slips, demand
    out = simulate_box(ax, ay, None, dt, box)
    assert out.friction_demand < mu                              # the total force: inside the cone throughout
    assert out.flag == (FLAG_SLIDE if slips else FLAG_NONE)
    cert = other_axis_certificate(ax, ay, None, box, theta_max_rad=sc.theta_max * math.atan2(b, h),
                                  friction_demand=sc.friction_demand)
    assert not (cert.certified and demand > mu)
    if cross_g == 0.0:
        assert cert.certified                                    # no cross motion: the planar run is exact


@pytest.fixture(scope="module")
def strong_pair(records_dir, tmp_path_factory):
    """Two strong bundled records (Ridgecrest CI.CLC, Chi-Chi TCU102) under which 3D boxes stop where the base would
    slide, twist or lift off, a cabinet and a transformer of the demo's inventory screened on them, and a
    configuration that leaves such scenes without a verdict (the 3D contact model off), so that the outputs' unknowns
    are exercised."""
    import shutil

    root = tmp_path_factory.mktemp("strong")
    recs = root / "records"
    recs.mkdir()
    for path in [*records_dir.rglob("CICLC.v1"), *records_dir.rglob("RSN1529_CHICHI_TCU102-*.AT2")]:
        shutil.copy(path, recs / path.name)
    inv = root / "blocks.csv"
    inv.write_text("id,name,height_m,width_m,mu,azimuth_deg,shape,depth_m\n"
                   "CAB-01,cabinet,1.98,0.45,0.35,0,box,0.90\n"
                   "TRAF-01,transformer,3.40,1.40,0.50,0,box,2.00\n")
    (root / "off.toml").write_text("[simulation]\ncontact3d = false\n")
    return recs, inv, root


def test_assets_not_judged_say_so_in_every_output(strong_pair):
    import csv

    from pipeline.cli import main

    recs, inv, root = strong_pair
    out = root / "screen"
    assert main(["--records", str(recs), "--blocks", str(inv), "--out", str(out), "-q", "--samples", "12",
                 "--config", str(root / "off.toml")]) == 0
    rows = list(csv.DictReader(open(out / "assets.csv", newline="")))
    unjudged = [r for r in rows if int(r["stations_without_verdict"]) or int(r["draws_without_verdict"])]
    assert unjudged, "the records chosen no longer leave a draw without a verdict: choose stronger ones"
    for r in unjudged:
        assert r["robustness"] != "robust_stand" and r["verdict_simulation"] != "stands", r
        assert not r["recommendation"].startswith(("no action", "limit sliding")), r["recommendation"]
        assert "slides 0 m" not in r["recommendation"]
        if r["p_overturn_high"]:
            assert float(r["p_overturn_high"]) >= float(r["p_overturn_with_unknown"]) - 1e-12
    page = (out / "report.html").read_text()
    assert 'id="not-judged"' in page and "assets not judged on some records" in page
    # the decision before the diagnostics: the asset table comes before the guarded scenes and the free flights
    assert page.index('id="asset-table"') < page.index('id="diagnostics"')


def test_fragility_stripes_count_the_records_without_a_verdict(strong_pair):
    from pipeline.cli import main
    from pipeline.store import open_results

    recs, inv, root = strong_pair
    out = root / "fragility"
    assert main(["fragility", "--records", str(recs), "--blocks", str(inv), "--im", "pga", "--levels",
                 "0.1g,0.3g,0.6g", "--out", str(out), "-q", "--samples", "8", "--bootstrap", "20",
                 "--config", str(root / "off.toml")]) == 0
    ds = open_results(out / "fragility.nc")
    u = ds["n_unjudged"].values
    assert np.all(ds["n_scaled"].values >= ds["n_records"].values)
    assert np.all(u <= ds["n_scaled"].values + 1e-9) and u.sum() > 0
    lo, hi = ds["median_unjudged_overturn"].values, ds["median_unjudged_stand"].values
    has = u.sum(axis=1) > 0
    assert np.all(lo[has] <= hi[has])
    page = (out / "fragility.html").read_text()
    assert "not judged" in page and "records that could be scaled" in page


def test_the_criterion_tier_clears_no_asset(strong_pair):
    import csv

    from pipeline.cli import main

    recs, inv, root = strong_pair
    out = root / "criterion"
    assert main(["--records", str(recs), "--blocks", str(inv), "--out", str(out), "-q", "--fidelity",
                 "criterion"]) == 0
    rows = list(csv.DictReader(open(out / "assets.csv", newline="")))
    assert rows and not any(r["recommendation"].startswith("no action") for r in rows)
    page = (out / "report.html").read_text()
    # said on the first screen: before the summary and the asset table
    assert 'id="criterion-tier"' in page and page.index('id="criterion-tier"') < page.index('id="summary"')


def test_a_few_unknown_samples_that_cannot_change_the_decision_are_named_in_it():
    """1 of 40 samples without a verdict and none overturning: counted as overturning, p is 0.025 < 0.1, so the
    decision stands as the judged samples give it, and the words say what was not judged."""
    from pipeline.risk import P_RELOCATE, recommendation

    assert 1 / 40 < P_RELOCATE
    text = recommendation(sim_scale=math.inf, crit_overturns=False, response=2, p_max=0.0, p_record="R",
                          governing="G", stations=(0, 31), unknown_draws=(1, 40), p_with_unknown=1 / 40)
    assert text.startswith("no action:") and "1 of 40 samples have no verdict" in text, text
    more = recommendation(sim_scale=math.inf, crit_overturns=False, response=2, p_max=0.0, p_record="R",
                          governing="G", stations=(0, 31), unknown_draws=(4, 40), p_with_unknown=4 / 40)
    assert more.startswith("at risk until judged:"), more
