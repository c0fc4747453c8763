"""Velocity pulses against the published MATLAB output, invariants, synthetic truth and hard cases."""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest
from handoff import NO_HANDOFF

from pipeline.cli import main
from pipeline.errors import PulseError
from pipeline.pulses import analyze, classify, dominant_lobe
from pipeline.pulses.along import _head, _strongest_point, extract_along
from pipeline.pulses.cwt import column_coefficients, cwt, cwt_point, cwt_window, scales_for
from pipeline.pulses.shahi_baker import PulseResult, wavelet_on_grid
from pipeline.records.listing import find_records
from pipeline.records.loader import load_record
from pipeline.store import open_results

PROJECT_CONFIGS = __import__("pathlib").Path(__file__).resolve().parents[2] / "configs"


@pytest.fixture(scope="module")
def reference(records_dir):
    with open(records_dir / "pulse-reference" / "matlab_reference_output.csv") as fh:
        return list(csv.DictReader(fh))


@pytest.fixture(scope="module")
def example_velocity(records_dir):
    """The MATLAB input: v = cumsum(a) * dt * 981 cm/s, no filtering."""
    import obspy

    a = [obspy.read(str(records_dir / "pulse-reference" / f"example{k}.AT2"))[0].data for k in (1, 2)]
    return np.vstack([np.cumsum(x) * 0.005 * 981 for x in a]), 0.005


def test_matlab_parity_all_candidates(example_velocity, reference):
    v, dt = example_velocity
    res = classify(v, dt)
    assert len(res.candidates) == 5
    for c, r in zip(res.candidates, reference):
        assert c.column + 1 == int(r["selected_col_1based"])
        assert c.row + 1 == int(r["selected_row_1based"])
        assert c.scale == int(r["pulse_scale"])
        assert c.tp_s == pytest.approx(float(r["tp_s"]), abs=1e-9)
        assert c.angle_rad == pytest.approx(float(r["rot_angle_rad"]), abs=1e-6)
        assert c.pulse_indicator == pytest.approx(float(r["pulse_indicator"]), abs=1e-6)
        assert c.pgv_cms == pytest.approx(float(r["pgv_cms"]), abs=1e-6)
        assert c.pgv_resid_cms == pytest.approx(float(r["pgv_resid_cms"]), abs=1e-6)
        assert c.energy_ratio == pytest.approx(float(r["energy_ratio"]), abs=1e-8)
        assert c.late == bool(int(r["late"])) and c.is_pulse == bool(int(r["is_pulse"]))
        assert [p + 1 for p in c.positions] == [int(x) for x in r["wavelet_cols_1based"].split(";")]
        np.testing.assert_allclose(c.coefficients, [float(x) for x in r["wavelet_coefs"].split(";")],
                                   atol=1e-6)
    assert res.is_pulse and res.tp_s == pytest.approx(4.788, abs=1e-9)  # find_Tp


@pytest.mark.slow
def test_parity_through_screen_command(make_records, blocks_csv, tmp_path, reference):
    root = make_records("pulse-reference/example1.AT2", "pulse-reference/example2.AT2")
    out = tmp_path / "out"
    assert main([*NO_HANDOFF,
                 "--samples", "0", "--records", str(root), "--blocks", str(blocks_csv), "--out", str(out), "-q",
                 "--config", str(PROJECT_CONFIGS / "shahi_baker_2014.toml")]) == 0
    ds = open_results(out / "screening.nc").sel(record="example")
    r = reference[0]
    assert float(ds.pulse_period) == pytest.approx(float(r["tp_s"]), abs=1e-9)
    assert float(ds.pulse_indicator) == pytest.approx(float(r["pulse_indicator"]), abs=1e-6)
    # orientation: component 1 is at 140 deg; the pulse axis is 140 + degrees(theta) mod 180
    assert float(ds.pulse_azimuth) == pytest.approx((140 + float(r["rot_angle_deg"])) % 180, abs=1e-6)
    assert int(ds.is_pulse) == 1


def test_default_processing_moves_tp_by_a_documented_amount(make_records, config, reference):
    """Default config (trapezoid, g = 9.80665) on the same pair: Tp stays within one scale step."""
    root = make_records("pulse-reference/example1.AT2", "pulse-reference/example2.AT2")
    rec = load_record(find_records(root, config=config)[0][0], root=root, config=config)
    p = analyze(rec)
    assert abs(p.result.tp_s - 4.788) <= 1.4 * 0.005 * 43  # one of the 51 scale steps at most


@pytest.mark.parametrize("angle_deg", [17.0, 45.0, 123.0])
def test_rotation_invariance(example_velocity, angle_deg):
    v, dt = example_velocity
    a = math.radians(angle_deg)
    # rotate the pair: new first axis at +angle clockwise from the old first axis
    rot = np.vstack([math.cos(a) * v[0] + math.sin(a) * v[1], -math.sin(a) * v[0] + math.cos(a) * v[1]])
    base, turned = classify(v, dt), classify(rot, dt)
    assert turned.tp_s == pytest.approx(base.tp_s, abs=1e-9)
    for c0, c1 in zip(base.candidates, turned.candidates):
        assert c1.pulse_indicator == pytest.approx(c0.pulse_indicator, abs=1e-6)
        shift = (math.degrees(c1.angle_rad) + angle_deg - math.degrees(c0.angle_rad)) % 180
        assert min(shift, 180 - shift) == pytest.approx(0, abs=1e-6)


@pytest.mark.parametrize("rel", ["peer-at2/RSN1063_NORTHR_RRS228.AT2", "peer-at2/RSN879_LANDERS_LCN260.AT2",
                                 "peer-at2/RSN1086_NORTHR_SYL360.AT2", "peer-at2/RSN292_ITALY_A-STU270.AT2"])
def test_tp_is_integer_multiple_of_1p4_dt(make_records, config, rel):
    root = make_records(rel)
    rec = load_record(find_records(root, config=config)[0][0], root=root, config=config)
    for c in analyze(rec).result.candidates:
        q = c.tp_s / (1.4 * rec.dt_s)
        assert q == pytest.approx(round(q), abs=1e-9)


@pytest.mark.parametrize("scale", [120, 300, 517])
def test_inserted_db4_wavelet_comes_back_at_its_scale(scale):
    dt, n = 0.01, 8000
    v = wavelet_on_grid(3000.0, scale, 3000, n) + np.random.default_rng(scale).normal(0, 0.05, n)
    res = classify(v[None, :], dt)
    assert abs(res.candidates[0].scale - scale) <= 1


def test_cwt_window_equals_full_transform():
    x = np.random.default_rng(0).normal(size=3000)
    full = cwt(x, [57])[0]
    np.testing.assert_allclose(cwt_window(x, 57, 1000, 1200), full[1000:1201], rtol=1e-10, atol=1e-10)


@pytest.mark.parametrize("n, scale, position", [(3000, 57, 1500), (3000, 57, 30), (3000, 57, 2990),
                                                 (20000, 700, 9000), (20000, 1500, 2000), (20000, 1500, 10000),
                                                 (5000, 3, 2500)])
def test_a_wavelets_window_response_is_its_own_transform(n, scale, position):
    """The extraction's iterations subtract each wavelet's coefficients from the residual's over the search window
    (the transform is linear): the shifted unit response, or for a wavelet cut by the record's ends or a window
    wider than the search's its own FFT transform, against a second algorithm, the wavelet's coefficients as
    direct dot products (:func:`cwt_point`), over windows that hold its position."""
    from pipeline.pulses.shahi_baker import WINDOW_FRACTION, _window_response

    half = int(np.ceil(WINDOW_FRACTION * scale))
    wavelet = wavelet_on_grid(-1234.5, scale, position, n)
    for start, width in ((position - 2 * half, 2 * half), (position - half, 2 * half), (position, 2 * half),
                         (position - 2 * half, 4 * half)):
        lo, hi = max(0, start), min(n - 1, start + width)
        expected = np.array([cwt_point(wavelet, scale, col) for col in range(lo, hi + 1)])
        np.testing.assert_allclose(_window_response(-1234.5, scale, position, lo, hi, n), expected,
                                   rtol=0, atol=1e-9 * np.max(np.abs(expected)))


@pytest.mark.parametrize("n, scale", [(40, 3), (3000, 57), (3000, 700), (20000, 1500)])
def test_cwt_point_equals_the_full_transform(n, scale):
    """The dot-product coefficient against the FFT transform, at both edges and inside."""
    x = np.random.default_rng(n).normal(size=n)
    full = cwt(x, [scale])[0]
    for col in (0, 1, n // 3, n - 2, n - 1):
        assert cwt_point(x, scale, col) == pytest.approx(full[col], rel=1e-9, abs=1e-9 * np.abs(full).max())


def test_strongest_point_along_any_orientation_is_the_brute_force_argmax(example_velocity):
    """The sorted-amplitude search returns MATLAB's column-major argmax of (cos C1 + sin C2)^2."""
    v, dt = example_velocity
    res = classify(v, dt)
    c = res.coeffs
    for deg in np.arange(0.0, 180.0, 2.5):
        ca, sa = math.cos(math.radians(deg)), math.sin(math.radians(deg))
        flat = int(np.argmax(((ca * c[0] + sa * c[1]) ** 2).ravel(order="F")))
        assert _strongest_point(res, ca, sa) == (flat % c.shape[1], flat // c.shape[1]), deg
    # along the first candidate's orientation its point is the maximum (projection <= amplitude <= its
    # amplitude), so the same pulse comes back
    first = res.candidates[0]
    _, pulse = extract_along(res, first.angle_rad)
    np.testing.assert_allclose(pulse, first.pulse_cms, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("rows, cols, k", [(51, 9000, 1024), (51, 9000, 1100), (4, 20000, 64), (1, 9000, 1024),
                                            (51, 3000, 1024), (3, 200, 4096), (5, 40, 199), (5, 40, 200)])
def test_a_head_built_row_by_row_is_the_transforms_k_largest(rows, cols, k):
    """The selection (row by row where the head is a small part of a row, else over the whole) against a sort of
    the whole transform's amplitudes: the same k amplitudes, the largest left out as its bound, and each point's
    C1, C2 and column-major index its own."""
    c = np.random.default_rng(rows * cols + k).normal(size=(2, rows, cols))
    c[:, :, cols // 2] = 3.0                     # ties: one column of equal amplitudes in every row
    amp = (c[0] ** 2 + c[1] ** 2).ravel()
    ordered = np.sort(amp)[::-1]
    c1, c2, f_index, bound = _head(c, k)
    r, col = f_index % rows, f_index // rows
    assert np.array_equal(c1, c[0, r, col]) and np.array_equal(c2, c[1, r, col])
    if k >= amp.size:
        assert bound == -math.inf and np.array_equal(np.sort(f_index), np.arange(amp.size))
    else:
        np.testing.assert_array_equal(np.sort(c1 ** 2 + c2 ** 2)[::-1], ordered[:k])
        assert bound == ordered[k]


def test_the_strongest_point_beyond_the_first_head_is_found():
    """Points of large amplitude across the orientation asked for (more than the first head holds) push the best
    projection out of it: the head grows until the bound proves its maximum, the brute-force argmax."""
    rng = np.random.default_rng(7)
    c = rng.normal(scale=0.1, size=(2, 51, 400))
    c[1, :, :100] = 5.0 + rng.random((51, 100))     # 5,100 points strong along C2 only
    c[0, 20, 300] = 4.0                              # the strongest along C1, weaker than all of them
    res = PulseResult(False, math.nan, [], 0, "shahi_baker_2014", [], None, c, np.arange(51), 0.01)
    for deg in (0.0, 1.0, 90.0, 135.0):
        ca, sa = math.cos(math.radians(deg)), math.sin(math.radians(deg))
        flat = int(np.argmax(((ca * c[0] + sa * c[1]) ** 2).ravel(order="F")))
        assert _strongest_point(res, ca, sa) == (flat % 51, flat // 51), deg
    assert max(res._strongest) > 1024                # the search grew its head


def test_scales_worked_values():
    assert (scales_for(0.005)[[0, 1, -1]] == [35, 78, 2185]).all()
    assert (scales_for(0.01)[[0, 1, -1]] == [17, 39, 1117]).all()
    assert (scales_for(0.02)[[0, 1, -1]] == [8, 19, 558]).all()


PULSE_LIKE = [
    ("peer-at2/RSN1063_NORTHR_RRS228.AT2", "peer-at2/RSN1063_NORTHR_RRS318.AT2"),   # Rinaldi
    ("peer-at2/RSN879_LANDERS_LCN260.AT2",),                                           # Lucerne
    ("peer-at2/RSN1492_CHICHI_TCU052-N.AT2", "peer-at2/RSN1492_CHICHI_TCU052-E.AT2"),  # TCU052
    ("peer-at2/RSN1086_NORTHR_SYL360.AT2", "peer-at2/RSN1086_NORTHR_SYL090.AT2"),      # Sylmar Olive View
    ("peer-at2/RSN181_IMPVALL.H_H-E06140.AT2", "peer-at2/RSN181_IMPVALL.H_H-E06230.AT2"),  # El Centro #6
    ("peer-at2/RSN182_IMPVALL.H_H-E07140.AT2", "peer-at2/RSN182_IMPVALL.H_H-E07230.AT2"),  # El Centro #7
]
NON_PULSE = [("peer-at2/RSN6_IMPVALL.I_I-ELC180.AT2",), ("peer-at2/RSN15_KERN_TAF021.AT2",),
             ("knet/AOM0170806140843.NS", "knet/AOM0170806140843.EW")]


@pytest.mark.parametrize("files,expected", [(f, True) for f in PULSE_LIKE] + [(f, False) for f in NON_PULSE],
                         ids=lambda v: v[0].split("/")[-1] if isinstance(v, tuple) else str(v))
def test_known_classifications(make_records, config, files, expected):
    root = make_records(*files)
    rec = load_record(find_records(root, config=config)[0][0], root=root, config=config)
    assert analyze(rec).result.is_pulse is expected


@pytest.mark.parametrize("shape,beta", [("half-sine", 2 / math.pi), ("step", 1.0), ("linear", 0.5),
                                        ("parabolic", 2 / 3)])
def test_fullness_factor_of_synthetic_pulses(shape, beta):
    dt, tp, ap = 0.0005, 1.0, 3.0
    k = np.arange(-1000, 6000)
    t = k * dt
    inside = (k >= 0) & (k <= 2000)
    u = np.clip(t / tp, 0, 1)
    a = {"half-sine": np.sin(np.pi * u), "step": np.ones_like(u), "linear": 1 - u,
         "parabolic": 4 * u * (1 - u)}[shape] * inside * ap
    if shape in ("step", "linear"):
        a[k == 2000] = 0.0
    lobe = dominant_lobe(a, dt)
    assert lobe.beta == pytest.approx(beta, abs=1e-3)
    assert lobe.tp_s == pytest.approx(tp, rel=1e-3) and lobe.ap_ms2 == pytest.approx(ap, rel=1e-3)
    assert abs(lobe.dv_ms) == pytest.approx(beta * ap * tp, rel=1e-3)


def test_hard_case_all_zero_is_an_error():
    with pytest.raises(PulseError, match="zero everywhere"):
        classify(np.zeros((2, 4000)), 0.01)


def test_hard_case_too_short_is_an_error():
    with pytest.raises(PulseError, match="shorter than the smallest pulse wavelet"):
        classify(np.random.default_rng(0).normal(size=(2, 20)), 0.01)


def test_hard_case_shorter_than_longest_wavelet_is_flagged():
    dt, n = 0.01, 1500   # 15 s record, longest wavelet 7 * 1117 samples
    v = wavelet_on_grid(2000.0, 1000, 750, n)
    res = classify(v[None, :], dt)
    assert np.isfinite(res.best.pulse_indicator)
    assert any("longer than the record" in f for f in res.flags)


@pytest.mark.parametrize("dt", [0.002, 0.005, 0.01, 0.02])
def test_hard_case_sampling_intervals(dt):
    n = int(40 / dt)
    t = np.arange(n) * dt
    v = 80 * np.exp(-((t - 15) / 1.2) ** 2) * np.sin(2 * np.pi * (t - 15) / 2.5)
    res = classify(np.vstack([v, 0.3 * v]), dt)
    assert res.is_pulse and 1.5 < res.tp_s < 4.5


def test_hard_case_single_spike_and_drift():
    dt, n = 0.01, 4000
    spike = np.zeros(n)
    spike[2000] = 50.0
    res = classify(np.vstack([np.cumsum(spike) * dt, np.zeros(n)]), dt)
    assert np.isfinite(res.best.pulse_indicator)
    drift = np.linspace(0, 200, n) + np.random.default_rng(1).normal(0, 1, n)
    res = classify(np.vstack([drift, 0.5 * drift]), dt)
    assert np.isfinite(res.best.pulse_indicator)


def test_pulse_series_file_and_plot(make_records, blocks_csv, tmp_path):
    import xarray as xr

    from pipeline.report.pulse_plot import plot_pulse

    root = make_records("peer-at2/RSN1063_NORTHR_RRS228.AT2", "peer-at2/RSN1063_NORTHR_RRS318.AT2")
    out = tmp_path / "out"
    assert main([*NO_HANDOFF,
                 "--samples", "0", "--records", str(root), "--blocks", str(blocks_csv), "--out", str(out), "-q"]) == 0
    ps = xr.open_dataset(out / "pulses.nc")
    assert ps.featureType == "timeSeries" and int(ps.row_size.sum()) == ps.sizes["sample"]
    n = int(ps.row_size[0])
    v, p = ps.velocity.values[:n], ps.pulse.values[:n]
    # the pulse explains most of the velocity of this strongly pulse-like record
    assert np.max(np.abs(v - p)) < 0.6 * np.max(np.abs(v))
    png = plot_pulse(v, p, float(ps.dt[0]), title="Rinaldi", path=tmp_path / "p.png", tp_s=1.246)
    assert png.stat().st_size > 10_000


@pytest.mark.parametrize("n", [40, 3000, 18000])
def test_column_coefficients_equal_the_dot_product_at_each_scale(n):
    """The compiled loop over a range of scales against :func:`cwt_point` scale by scale, at both edges and
    inside, on ranges from the smallest scales to the largest the search reaches."""
    x = np.random.default_rng(n).normal(size=n)
    for first, last in ((1, 4), (15, 60), (290, 310), (2180, 2186)):
        for col in (0, 1, n // 3, n - 2, n - 1):
            want = np.array([cwt_point(x, a, col) for a in range(first, last + 1)])
            got = column_coefficients(x, first, last, col)
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-10 * max(np.abs(want).max(), 1e-300))
