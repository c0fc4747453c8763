"""Hard cases: the slowest scenes of a boundary set, as numbers.

Draws N scenes on the simulator's boundaries (the tie rules of ``pipeline/rocking/rules.py``: mu = tan(alpha)
and a double either side, demands exactly at a threshold, verticals reaching exactly -g, slenderness up to the
54.7 deg limit, blocks from 2 cm to 30 m, records of 2 to 800 samples), runs each through the nominal path and
prints the time of the slowest and of the median scene, and the same for the tie blocks under the bundled Rinaldi
record (RSN1063) in every 5-degree plane. Run: ``python benchmarks/bench_boundaries.py [--scenes N]``.
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "tests" / "support"), str(ROOT / "tests" / "rocking")]   # the scenes the tests draw

from boundary_scenes import block, mu_ties, run_scene  # noqa: E402
from test_boundaries_fuzz import _draws  # noqa: E402

from pipeline.bodies.warmup import compile_kernels  # noqa: E402
from pipeline.config import Config  # noqa: E402
from pipeline.records.loader import iter_records  # noqa: E402
from pipeline.rocking.orientation import Planes, plane_grid  # noqa: E402
from pipeline.rocking.planner import simulate_scene  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", type=int, default=20000)
    args = ap.parse_args()
    compile_kernels()
    draws = _draws(np.random.default_rng(1))
    times = []
    for _ in range(args.scenes):
        blk, m = next(draws)
        times.append((run_scene(m, blk).seconds, m.name, m.ah.size, blk.alpha, blk.mu))
    times.sort(reverse=True)
    t = np.array([x[0] for x in times])
    print(f"boundary set: {args.scenes} scenes in {t.sum():.2f} s; median {1e3 * np.median(t):.3f} ms, slowest "
          f"{1e3 * t[0]:.1f} ms ({t[0] / np.median(t):.0f}x the median)")
    for s, name, n, alpha, mu in times[:3]:
        print(f"  {1e3 * s:.1f} ms: {name}, {n} samples, alpha {math.degrees(alpha):.3f} deg, mu {mu!r}")
    rec = next(r for r in iter_records(ROOT / "records", config=Config()) if r.record_id == "RSN1063_NORTHR_RRS")
    planes = Planes(rec.horizontal_ms2, rec.azimuths_deg[0], rec.vertical_ms2, g_ms2=9.80665)
    rows = []
    alpha = math.atan2(0.75, 1.5)
    for name, mu in {**mu_ties(alpha), "0.49": 0.49, "0.51": 0.51}.items():
        blk = block(3.0, alpha, mu)
        t0 = time.perf_counter()
        for az in plane_grid(5.0):
            simulate_scene(planes.along(float(az)), planes.vertical, rec.dt_s, block=blk)
        rows.append((name, mu, time.perf_counter() - t0))
    print("Rinaldi (RSN1063) x a 3 m x 1.5 m block, 36 planes with the vertical:")
    for name, mu, s in rows:
        print(f"  mu {name:>8} = {mu!r}: {1e3 * s:.1f} ms")


if __name__ == "__main__":
    main()
