"""The pulse along any orientation (:mod:`pipeline.pulses.along`, the scale refinement in one compiled loop) against
the extraction with the refinement's coefficients taken one by one (:func:`pipeline.pulses.cwt.cwt_point`)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.pulses import analyze
from pipeline.pulses.along import extract_along
from pipeline.pulses.shahi_baker import classify, wavelet_on_grid
from pipeline.records.listing import find_records
from pipeline.records.loader import load_record

TWO_HORIZONTALS = [
    ("peer-at2/RSN1063_NORTHR_RRS228.AT2", "peer-at2/RSN1063_NORTHR_RRS318.AT2"),   # Rinaldi: a strong pulse
    # 12 s of the one-by-one reference: in make test-slow, so that make test stays under 5 min
    pytest.param(("peer-at2/RSN1492_CHICHI_TCU052-N.AT2", "peer-at2/RSN1492_CHICHI_TCU052-E.AT2"),
                 marks=pytest.mark.slow),
    ("knet/AOM0170806140843.NS", "knet/AOM0170806140843.EW"),                          # no pulse
]


def _same_pulse(res, deg: float) -> None:
    v1, p1 = extract_along(res, math.radians(deg))
    v2, p2 = extract_along(res, math.radians(deg), compiled=False)
    np.testing.assert_array_equal(v1, v2)
    scale = np.abs(p2).max()
    np.testing.assert_allclose(p1, p2, rtol=0, atol=1e-9 * scale, err_msg=f"azimuth {deg} deg")


@pytest.mark.parametrize("files", TWO_HORIZONTALS, ids=lambda f: f[0].split("/")[-1])
def test_compiled_refinement_equals_the_one_by_one_at_every_degree(make_records, config, files):
    root = make_records(*files)
    rec = load_record(find_records(root, config=config)[0][0], root=root, config=config)
    res = analyze(rec).result
    for deg in np.arange(0.0, 180.0, 1.0):
        _same_pulse(res, float(deg))


@pytest.mark.parametrize("position", [300, 2500, 4700])
def test_wavelets_cut_by_the_records_ends(position):
    """A pulse near either end: its wavelets and the refinement's kernels reach past the record."""
    rng = np.random.default_rng(position)
    n, scale = 5000, 260
    base = wavelet_on_grid(4000.0, scale, position, n)
    v = np.vstack([base + rng.normal(0, 2.0, n), 0.6 * base + rng.normal(0, 2.0, n)])
    res = classify(v, 0.01)
    for deg in (0.0, 17.0, 45.0, 90.0, 133.0, 179.0):
        _same_pulse(res, deg)
