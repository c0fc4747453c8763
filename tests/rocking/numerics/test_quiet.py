"""A plane's quiet table (:func:`pipeline.rocking.numerics.ground.quiet_table`) changes nothing the rocking kernel
returns: the same outcome, bit for bit, with and without it, on real records with their verticals, on a vertical
that reaches g + a_v <= 0, for the linear model and on a table of another series' length (ignored)."""

from __future__ import annotations

import math

import numpy as np
import obspy
import pytest

from pipeline.constants import G
from pipeline.rocking.numerics.ground import QUIET_CHUNK, chunk_quiet, quiet_table
from pipeline.rocking.simulate import rock

STATIONS = [("RSN1063_NORTHR_RRS228", "RSN1063_NORTHR_RRS-UP"), ("RSN1503_CHICHI_TCU065-E", "RSN1503_CHICHI_TCU065-V"),
            ("RSN1176_KOCAELI_YPT060", "RSN1176_KOCAELI_YPT-UP")]


def _accel(records_dir, name: str) -> tuple[np.ndarray, float]:
    tr = obspy.read(str(records_dir / "peer-at2" / f"{name}.AT2"))[0]
    return np.ascontiguousarray(tr.data, dtype=np.float64) * G, float(tr.stats.delta)


def _fields(r) -> tuple:
    """Every field as its bytes (NaN equal to NaN)."""
    return tuple(np.asarray(v).tobytes()
                 for v in (r.overturned, r.t_overturn, r.theta_max, r.n_impacts, r.friction_demand, r.status, r.t_stop,
                           r.theta_end, r.omega_end, r.mode_end, r.n_uplifts, r.t_first_impact, r.theta))


def _same(ah, av, dt, table, **kw) -> None:
    assert _fields(rock(ah, dt, av_ms2=av, quiet=table, **kw)) == _fields(rock(ah, dt, av_ms2=av, **kw))


@pytest.mark.parametrize("horizontal, vertical", STATIONS)
@pytest.mark.parametrize("with_vertical", [True, False])
def test_same_outcome_with_the_table_on_real_records(records_dir, horizontal, vertical, with_vertical):
    ah, dt = _accel(records_dir, horizontal)
    av, _ = _accel(records_dir, vertical)
    n = min(ah.size, av.size)
    ah, av = ah[:n], av[:n] if with_vertical else None
    table = quiet_table(ah, av)
    rng = np.random.default_rng(n)
    for _ in range(30):
        alpha, R = rng.uniform(0.05, 0.6), rng.uniform(0.2, 3.0)
        p = math.sqrt(3.0 * G / (4.0 * R))
        _same(ah, av, dt, table, p=p, alpha=alpha, e=1.0 - 1.5 * math.sin(alpha) ** 2, R_m=R,
              history=bool(rng.integers(2)), linear=bool(rng.integers(2)))


def test_a_vertical_below_minus_g_ends_the_scene_as_without_the_table():
    dt, n = 0.01, 3000
    t = np.arange(n) * dt
    ah = 1.5 * np.sin(2.0 * np.pi * 0.7 * t) * (t > 5.0)
    av = -11.0 * np.exp(-((t - 20.0) / 0.3) ** 2)            # g + a_v < 0 near t = 20 s
    for alpha in (0.1, 0.2, 0.4):
        _same(ah, av, dt, quiet_table(ah, av), p=2.0, alpha=alpha, e=0.9, R_m=1.0)


def test_a_table_of_another_length_is_not_read():
    dt, n = 0.01, 2000
    ah = 2.0 * np.sin(np.arange(n) * dt * 3.0)
    other = quiet_table(np.zeros(n + QUIET_CHUNK), None)      # says every chunk is quiet
    _same(ah, None, dt, other, p=2.0, alpha=0.15, e=0.9, R_m=1.0)


@pytest.mark.parametrize("n", [1, 63, 64, 65, 1000])
def test_a_quiet_chunk_holds_no_sample_that_lifts(n):
    """The table's test against the per-sample test, chunk by chunk, at thresholds on either side of each
    chunk's bound."""
    rng = np.random.default_rng(n)
    ah, av = rng.normal(0.0, 3.0, n), rng.normal(0.0, 4.0, n)
    table = quiet_table(ah, av)
    for c in range(table.peak_ah_ms2.size):
        s = slice(c * QUIET_CHUNK, min((c + 1) * QUIET_CHUNK, n))
        bound = np.max(np.abs(ah[s]) / (G + av[s]))
        for thr in (0.5 * bound, bound * (1 - 1e-12), bound, 2.0 * bound):
            lifts = np.any((np.abs(ah[s]) > (G + av[s]) * thr) | (G + av[s] <= 0.0))
            if chunk_quiet(table, c, G, thr, True):
                assert not lifts
        assert chunk_quiet(table, c, G, 1e3, True) == bool(np.all(G + av[s] > 0.0))
