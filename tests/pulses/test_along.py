"""The pulse along any orientation by superposition (:mod:`pipeline.pulses.along`) against the extraction
repeated on the projected record (:func:`pipeline.pulses.shahi_baker.extract`): a second algorithm."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.pulses import analyze
from pipeline.pulses.along import AlongCache, _inside, _residual_window, extract_along, unit_response
from pipeline.pulses.cwt import cwt_window
from pipeline.pulses.shahi_baker import _add_wavelet, classify, wavelet_on_grid
from pipeline.records.loader import find_records, load_record

TWO_HORIZONTALS = [
    ("peer-at2/RSN1063_NORTHR_RRS228.AT2", "peer-at2/RSN1063_NORTHR_RRS318.AT2"),   # Rinaldi: a strong pulse
    ("peer-at2/RSN1492_CHICHI_TCU052-N.AT2", "peer-at2/RSN1492_CHICHI_TCU052-E.AT2"),
    ("knet/AOM0170806140843.NS", "knet/AOM0170806140843.EW"),                          # no pulse
]


def _same_pulse(res, deg: float) -> None:
    v1, p1 = extract_along(res, math.radians(deg))
    v2, p2 = extract_along(res, math.radians(deg), superpose=False)
    np.testing.assert_array_equal(v1, v2)
    scale = np.abs(p2).max()
    np.testing.assert_allclose(p1, p2, rtol=0, atol=1e-9 * scale, err_msg=f"azimuth {deg} deg")


@pytest.mark.parametrize("files", TWO_HORIZONTALS, ids=lambda f: f[0].split("/")[-1])
def test_superposition_equals_the_repeated_extraction_at_every_degree(make_records, config, files):
    root = make_records(*files)
    rec = load_record(find_records(root, config=config)[0][0], root=root, config=config)
    res = analyze(rec).result
    for deg in np.arange(0.0, 180.0, 1.0):
        _same_pulse(res, float(deg))


@pytest.mark.parametrize("position", [300, 2500, 4700])
def test_wavelets_cut_by_the_records_ends(position):
    """A pulse near either end: its wavelets leave the record, where the shifted unit response does not hold
    and each is transformed on its own."""
    rng = np.random.default_rng(position)
    n, scale = 5000, 260
    base = wavelet_on_grid(4000.0, scale, position, n)
    v = np.vstack([base + rng.normal(0, 2.0, n), 0.6 * base + rng.normal(0, 2.0, n)])
    res = classify(v, 0.01)
    for deg in (0.0, 17.0, 45.0, 90.0, 133.0, 179.0):
        _same_pulse(res, deg)


@pytest.mark.parametrize("scale", [9, 57, 300])
def test_unit_response_is_the_transform_of_a_wavelet_inside_the_record(scale):
    n = 14 * scale + 200
    resp, offset = unit_response(scale)
    for position in (7 * scale // 2 + 40, n // 2, n - 7 * scale // 2 - 40):
        assert _inside(scale, position, n)
        direct = cwt_window(wavelet_on_grid(1.0, scale, position, n), scale, 0, n - 1)
        d = np.arange(n) - position + offset
        ok = (d >= 0) & (d < resp.size)
        shifted = np.zeros(n)
        shifted[ok] = resp[d[ok]]
        np.testing.assert_allclose(shifted, direct, rtol=0, atol=1e-10 * np.abs(direct).max())


def test_residual_window_against_the_transform_of_the_residual():
    rng = np.random.default_rng(3)
    n, scale = 3000, 120
    v = rng.normal(size=(2, n))
    cache = AlongCache(v)
    positions, coefs = [5, 1500, 1530, 2990], [2.0, -1.5, 0.7, 1.1]      # two cut by the ends
    resid = 0.8 * v[0] + 0.6 * v[1]
    for p, c in zip(positions, coefs):
        resid = resid - _add_wavelet(np.zeros(n), c, scale, p)
    w1, w2 = cache.rows(scale)
    lo, hi = 1400, 1650
    got = _residual_window(cache, 0.8 * w1[lo:hi + 1] + 0.6 * w2[lo:hi + 1], scale, lo, hi, positions, coefs)
    want = cwt_window(resid, scale, lo, hi)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-9 * np.abs(want).max())
