"""Hypothesis property tests: the record's vector quiet table (:func:`ground.vector_quiet_table`), scaled by a draw's
factor, holds for that draw's plane: no chunk it passes over holds a sample at which a block at rest could lift in
the scaled projection (the kernel's own per-sample test, written out here); and the sampled kernels give the same
verdicts and integrated planes with the table as without it (every sample tested)."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from pipeline.constants import G
from pipeline.rocking.numerics import ground
from pipeline.rocking.planar.sampled import SampledBlocks, SampledMotion, kernels, sample_rules
from pipeline.rocking.settings import SimulationConfig

accel = st.floats(min_value=-30.0, max_value=30.0, allow_nan=False, allow_subnormal=True)
factors = st.floats(min_value=1e-3, max_value=20.0) | st.sampled_from([0.5, 1.0, 1.05, 2.0])
thresholds = st.floats(min_value=1e-3, max_value=2.0) | st.sampled_from([0.1, 0.25, 1.0])


def _liftable(a: np.ndarray, av_s: np.ndarray | None, thr: float) -> np.ndarray:
    """Where a block at rest can lift (or the ground falls faster than gravity): the rocking kernel's test of a
    sample, |a| > (g + a_v) thr or g + a_v <= 0."""
    gv = G + (av_s if av_s is not None else 0.0)
    return (np.abs(a) > gv * thr) | (gv <= 0.0)


@settings(max_examples=300, deadline=None)
@given(st.integers(min_value=1, max_value=400).flatmap(
    lambda n: st.tuples(arrays(np.float64, n, elements=accel), arrays(np.float64, n, elements=accel),
                        arrays(np.float64, n, elements=accel))), factors, st.floats(min_value=0.0, max_value=360.0),
    thresholds, st.booleans())
def test_a_chunk_the_scaled_table_passes_over_cannot_lift_the_block(series, factor, azimuth_deg, thr, with_vertical):
    h1, h2, av = series
    c, s = math.cos(math.radians(azimuth_deg)), math.sin(math.radians(azimuth_deg))
    table = ground.vector_quiet_table(h1, h2, av if with_vertical else None)
    scaled = ground.scaled_quiet_table(table, factor)
    a = factor * (c * h1 + s * h2)                          # the draw's projection, as the sampled kernels make it
    av_s = factor * av if with_vertical else None
    loud = _liftable(a, av_s, thr)
    for chunk in range(table.peak_ah_ms2.size):
        if ground.chunk_quiet(scaled, chunk, G, thr, with_vertical):
            assert not loud[chunk * ground.QUIET_CHUNK:(chunk + 1) * ground.QUIET_CHUNK].any()


@settings(max_examples=40, deadline=None)
@given(st.integers(min_value=0, max_value=2**31 - 1), st.booleans(), st.integers(min_value=1, max_value=3))
def test_the_sampled_kernels_judge_the_same_with_the_table_as_without(seed, with_vertical, n_planes):
    rng = np.random.default_rng(seed)
    n, dt = 1500, 0.01
    t = np.arange(n) * dt
    pulse = np.exp(-((t - 6.0) / rng.uniform(0.5, 2.0)) ** 2)     # quiet, a strong pulse, quiet again
    h1 = rng.uniform(1.0, 6.0) * pulse * np.sin(2 * np.pi * rng.uniform(0.3, 2.0) * t) + 0.05 * rng.standard_normal(n)
    h2 = rng.uniform(0.0, 4.0) * pulse * np.cos(2 * np.pi * rng.uniform(0.3, 2.0) * t) + 0.05 * rng.standard_normal(n)
    av = rng.uniform(0.0, 3.0) * pulse * np.sin(2 * np.pi * 4.0 * t) if with_vertical else np.zeros(0)
    k = 8
    alpha = rng.uniform(0.1, 0.4, k)
    R = rng.uniform(0.3, 3.0, k)
    blocks = SampledBlocks(rng.uniform(0.8, 1.3, k), np.sqrt(3 * G / (4 * R)), alpha,
                           1.0 - 1.5 * np.sin(alpha) ** 2, R, rng.uniform(0.2, 0.9, k))
    phi = rng.uniform(0.0, np.pi, (k, n_planes))
    cosines, sines = np.ascontiguousarray(np.cos(phi)), np.ascontiguousarray(np.sin(phi))
    table = ground.vector_quiet_table(h1, h2, av if with_vertical else None)
    rules = sample_rules(SimulationConfig(), G)
    results = []
    for motion in (SampledMotion(h1, h2, av, dt),
                   SampledMotion(h1, h2, av, dt, table.peak_ah_ms2, table.least_av_ms2)):
        verdicts, planes = np.zeros(k, dtype=np.int64), np.zeros(k, dtype=np.int64)
        outcomes, plane_counts = np.zeros((k, n_planes), dtype=np.int8), np.zeros(k, dtype=np.int64)
        kernels().sample_verdicts(motion, cosines, sines, blocks, rules, verdicts, planes)
        kernels().sample_plane_outcomes(motion, cosines, sines, blocks, rules, outcomes, plane_counts)
        results.append((verdicts, planes, outcomes, plane_counts))
    for without, with_table in zip(*results):
        np.testing.assert_array_equal(with_table, without)
