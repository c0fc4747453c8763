"""The pulse along any orientation (:mod:`pipeline.pulses.along`: the scale refinement in one compiled loop, the
iterations from the components' shared transforms) against the extraction with the refinement's coefficients taken
one by one (:func:`pipeline.pulses.cwt.cwt_point`) and the residual transformed itself; the pulse's lobe from its
support against the whole series'."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from pipeline.pulses import analyze
from pipeline.pulses.along import AlongCache, SharedSteps, extract_along
from pipeline.pulses.characterize import dominant_lobe, pulse_lobe
from pipeline.pulses.cwt import cwt_point
from pipeline.pulses.shahi_baker import WINDOW_FRACTION, classify, wavelet_on_grid
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


@pytest.mark.parametrize("n, scale, position", [(3000, 57, 1500), (3000, 57, 30), (3000, 57, 2990),
                                                 (20000, 700, 9000), (20000, 1500, 2000), (20000, 1500, 10000),
                                                 (5000, 3, 2500)])
def test_the_shared_steps_wavelet_response_is_its_own_transform(n, scale, position):
    """:class:`SharedSteps` takes a cut wavelet's coefficients from one transform over every window that can hold
    its position: against a second algorithm, the wavelet's coefficients as direct dot products
    (:func:`cwt_point`), over windows at either side of it and the same windows asked twice."""
    half = int(np.ceil(WINDOW_FRACTION * scale))
    wavelet = wavelet_on_grid(-1234.5, scale, position, n)
    steps = SharedSteps(np.zeros((2, n)), 1.0, 0.0, AlongCache())
    for _ in range(2):
        for start in (position - 2 * half, position - half, position):
            lo, hi = max(0, start), min(n - 1, start + 2 * half)
            expected = np.array([cwt_point(wavelet, scale, col) for col in range(lo, hi + 1)])
            np.testing.assert_allclose(steps.response(-1234.5, scale, position, lo, hi, n), expected,
                                       rtol=0, atol=1e-9 * np.max(np.abs(expected)))


@pytest.mark.parametrize("n, scale, position", [(3000, 57, 1500), (3000, 57, 5), (3000, 57, 2998),
                                                 (2000, 700, 1000), (5000, 3, 2500)])
def test_a_wavelet_added_by_shifting_is_the_wavelet_on_the_grid(n, scale, position):
    """The shared steps add a wavelet as the unit wavelet shifted and cut by the record's ends: the same samples
    as interpolating it at its position (:func:`wavelet_on_grid`), to rounding."""
    pulse = np.zeros(n)
    SharedSteps(np.zeros((2, n)), 1.0, 0.0, AlongCache()).add(pulse, 321.0, scale, position)
    expected = wavelet_on_grid(321.0, scale, position, n)
    np.testing.assert_allclose(pulse, expected, rtol=0, atol=1e-12 * np.max(np.abs(expected)))


@pytest.mark.parametrize("position", [3, 300, 2500, 4700, 4997])
def test_a_pulses_lobe_from_its_support_is_the_whole_series_lobe(position):
    """:func:`pulse_lobe` reads the pulse's support only: the same lobe, value for value, as
    :func:`dominant_lobe` of the whole series' gradient, for pulses inside the record and cut by either end."""
    dt = 0.01
    rng = np.random.default_rng(position)
    pulse = np.zeros(5000)
    for _ in range(4):
        pulse += wavelet_on_grid(float(rng.normal(0, 50)), 120, position + int(rng.integers(-40, 40)), pulse.size)
    whole = dominant_lobe(np.gradient(pulse, dt), dt)
    assert dataclasses.astuple(pulse_lobe(pulse, dt)) == dataclasses.astuple(whole)


@pytest.mark.parametrize("start", [0, 1, 2, 50])
def test_a_lobe_at_the_supports_edge_is_the_whole_series_lobe(start):
    """A velocity 0 -> 4 -> 1 -> 2 -> 0: the first lobe (its start at the support's edge) dominates."""
    dt = 0.01
    pulse = np.zeros(500)
    pulse[start:start + 400] = np.interp(np.arange(400), [0, 99, 199, 299, 399], [0.0, 4.0, 1.0, 2.0, 0.0]) ** 1.5
    whole = dominant_lobe(np.gradient(pulse, dt), dt)
    assert whole.t_start_s <= (start + 1) * dt
    assert dataclasses.astuple(pulse_lobe(pulse, dt)) == dataclasses.astuple(whole)


def test_the_lobe_of_a_zero_pulse_is_the_empty_lobe():
    lobe = pulse_lobe(np.zeros(100), 0.01)
    assert (lobe.ap_ms2, lobe.tp_s, lobe.dv_ms) == (0.0, 0.0, 0.0) and math.isnan(lobe.beta)
