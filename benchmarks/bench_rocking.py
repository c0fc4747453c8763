"""Rocking kernel vs an event-driven scipy solve_ivp implementation, on the bundled real records.

For every (record, block) scene of the sample inventory that the planner sends
to the rocking model (first horizontal component, horizontal motion only, so
both solvers see the same physics), times the compiled kernel at the default
settings and the reference (``pipeline.rocking.references.reference``, DOP853 at
rtol 1e-8) and compares verdicts, impacts and theta_max/alpha. Prints measured
figures only. The kernel is compiled (and a warm-up scene run) before timing.

Run: python benchmarks/bench_rocking.py [--limit N]
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import time
from pathlib import Path

import numpy as np

from pipeline.blocks import read_inventory
from pipeline.config import Config
from pipeline.records.loader import iter_records
from pipeline.rocking.planner import Physics, plan
from pipeline.rocking.references.reference import rock_reference
from pipeline.rocking.simulate import rock

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--limit", type=int, default=0, help="stop after N scenes (0: all)")
    args = ap.parse_args()
    cfg = Config()
    inv = read_inventory(ROOT / "configs" / "blocks.csv", default_mu=cfg.blocks.default_mu)
    geo = inv.geometry()
    rock(np.array([0.0, 5.0, 0.0]), 0.01, p=2.0, alpha=0.1, e=0.9, R_m=1.0)         # compile / load cache
    rows = []
    for rec in iter_records(ROOT / "records", config=cfg):
        ah = rec.horizontal_ms2[0]
        for j in range(len(inv)):
            alpha, p, e = float(geo.alpha[j]), float(geo.p[j]), max(float(geo.e_housner[j]), 0.0)
            if plan(ah, None, alpha=alpha, mu=float(inv.mu[j])) != Physics.rocking:
                continue
            t0 = time.perf_counter()
            res = rock(ah, rec.dt_s, p=p, alpha=alpha, e=e, R_m=float(geo.R[j]), settings=cfg.simulation)
            t1 = time.perf_counter()
            ref = rock_reference(ah, rec.dt_s, p=p, alpha=alpha, e=e, rtol=1e-8)
            t2 = time.perf_counter()
            rows.append((rec.record_id, inv.ids[j], t1 - t0, t2 - t1, res.overturned, ref.overturned,
                         res.theta_max, ref.theta_max_ratio, res.n_impacts, ref.n_impacts))
            if args.limit and len(rows) >= args.limit:
                break
        if args.limit and len(rows) >= args.limit:
            break
    tk = np.array([r[2] for r in rows])
    tr = np.array([r[3] for r in rows])
    ratio = tr / tk
    same = sum(r[4] == r[5] for r in rows)
    dtheta = np.array([abs(r[6] - r[7]) for r in rows if not r[4] and not r[5]])
    print(f"scenes: {len(rows)} (records x blocks sent to rocking by the planner)")
    print(f"kernel: {tk.sum():.3f} s total, {len(rows) / tk.sum():.0f} scenes/s, median {1e3 * np.median(tk):.2f} ms")
    print(f"solve_ivp reference (DOP853, rtol 1e-8): {tr.sum():.1f} s total, median {1e3 * np.median(tr):.0f} ms")
    print(f"speed-up: total {tr.sum() / tk.sum():.0f}x; per scene median {np.median(ratio):.0f}x, "
          f"min {ratio.min():.0f}x, max {ratio.max():.0f}x")
    print(f"verdicts identical: {same}/{len(rows)}")
    for r in rows:
        if r[4] != r[5]:
            print(f"  {r[0]} x {r[1]}: kernel overturned={r[4]} (theta_max {r[6]:.4f}, {r[8]} impacts), "
                  f"reference overturned={r[5]} ({r[7]:.4f}, {r[9]} impacts)")
    if dtheta.size:
        within = int(np.sum(dtheta < 1e-3))
        print(f"theta_max/alpha (scenes standing in both): {within}/{dtheta.size} within 1e-3, "
              f"max difference {dtheta.max():.2e}")
        for r in rows:
            if not r[4] and not r[5] and abs(r[6] - r[7]) >= 1e-3:
                print(f"  {r[0]} x {r[1]}: {r[6]:.5f} vs {r[7]:.5f} ({r[8]} vs {r[9]} impacts)")


if __name__ == "__main__":
    main()
