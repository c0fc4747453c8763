"""Blocks of unknown orientation: the sampled probabilities against a reference of many draws per plane.

For every scene of a blank-azimuth block on a two-component record (the bundled records x configs/blocks.csv:
196 scenes), the reference simulates DRAWS draws (default 200) of the declared uncertainty in every plane of the
5-degree grid (36 planes), with the screening's own seed and kernels. Per plane, p is the fraction overturning;
the reference worst orientation is the largest per-plane p (biased upward by the noise of 200 draws: about +0.03
at p = 0.5 among 36 planes), and the reference random orientation is the mean over the grid.

Given the screening.nc of one or more runs (``--compare base.nc new.nc``), it prints per run, over the scenes the
run judged by the planar draws over the grid (orientation ``scanned`` or ``scanned_relative``; a cylinder is judged
in 3D, and a scene at rest has no draws): the class agreement
(the reference's class from its worst-orientation p: below 0.1 robust_stand, above 0.9 robust_overturn, else
sensitive), the error of the worst-orientation p and of the random-orientation p, and how often the random
orientation's 90 % interval covers the reference mean. The reference is cached in ``--cache`` (npz).

Run: ``python benchmarks/bench_orientation_reference.py --compare base/screening.nc new/screening.nc``.
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import dataclasses
import math
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import xarray as xr

from pipeline.blocks import read_inventory
from pipeline.config import Config
from pipeline.records.loader import iter_records
from pipeline.rocking.orientation import Orientation, plane_grid
from pipeline.uncertainty.orientations import _Block, simulate_cells
from pipeline.uncertainty.sampling import common_normals
from pipeline.uncertainty.scenes import motion

ROOT = Path(__file__).resolve().parents[1]


def _scenes(records_dir: Path, blocks_csv: Path, config: Config) -> list[tuple]:
    inv = read_inventory(blocks_csv, default_mu=config.blocks.default_mu)
    blank = [j for j in range(len(inv)) if math.isnan(float(inv.azimuth_deg[j]))]
    out = []
    for rec in iter_records(records_dir, config=config):
        if rec.single_component:
            continue
        for j in blank:
            out.append((rec.record_id, str(inv.ids[j]), rec, dataclasses.replace(inv.shape(j), azimuth_deg=math.nan)))
    return out


def _reference(args) -> tuple[str, str, np.ndarray]:
    rid, bid, rec, shape, draws, config = args
    m = motion(rec.horizontal_ms2, rec.azimuths_deg[0], rec.vertical_ms2, rec.dt_s)
    u = config.uncertainty
    blk = _Block(shape, u, config.simulation_settings(), config.records.g_ms2)
    grid = plane_grid(config.simulation.orientation_step_deg)
    z = common_normals(u.seed, draws)
    return rid, bid, simulate_cells(m, blk.sample(z), np.broadcast_to(grid, (draws, grid.size)), blk)[0]


def reference(records_dir: Path, blocks_csv: Path, draws: int, cache: Path, workers: int) -> dict:
    """(record, block) -> outcomes (draws x 36 planes), computed once and cached."""
    if cache.is_file():
        z = np.load(cache)
        return {tuple(k.split("|")): z[k] for k in z.files}
    config = Config()
    scenes = _scenes(records_dir, blocks_csv, config)
    t0 = time.perf_counter()
    out = {}
    with ProcessPoolExecutor(workers) as pool:
        for k, (rid, bid, outcomes) in enumerate(pool.map(_reference, [(*s, draws, config) for s in scenes])):
            out[(rid, bid)] = outcomes
            if k % 20 == 0:
                print(f"reference: {k + 1}/{len(scenes)} scenes, {time.perf_counter() - t0:.0f} s", flush=True)
    np.savez_compressed(cache, **{f"{r}|{b}": v for (r, b), v in out.items()})
    print(f"reference: {len(out)} scenes x {draws} draws x 36 planes in {time.perf_counter() - t0:.0f} s")
    return out


def _class(p: float) -> int:
    return 0 if p < 0.1 else (2 if p > 0.9 else 1)


def compare(ref: dict, path: Path) -> None:
    ds = xr.open_dataset(path)
    rec, blk = list(ds["record"].values), list(ds["block"].values)
    planar = (Orientation.scanned, Orientation.scanned_relative)   # judged by the planar draws over the grid's planes
    agree = n = cover = n_avg = 0
    err_w, err_a, changed, other = [], [], [], 0
    for (rid, bid), outcomes in ref.items():
        i, j = rec.index(rid), blk.index(bid)
        if int(ds["orientation"].values[i, j]) not in planar:
            other += 1                                  # a cylinder in 3D, or a scene at rest: not this reference's
            continue
        judged = (outcomes >= 0).sum(axis=0)
        per_plane = np.where(judged > 0, (outcomes == 1).sum(axis=0) / np.maximum(judged, 1), np.nan)
        if not np.isfinite(per_plane).any() or not np.isfinite(float(ds["p_overturn"].values[i, j])):
            continue
        ref_worst, ref_avg = float(np.nanmax(per_plane)), float(np.nanmean(per_plane))
        cls = int(ds["robustness"].values[i, j])
        n += 1
        agree += cls == _class(ref_worst)
        if cls != _class(ref_worst):
            p = float(ds["p_overturn"].values[i, j])
            changed.append(f"{rid} x {bid}: {cls} vs reference {_class(ref_worst)} (p {p:.2f} vs {ref_worst:.2f})")
        err_w.append(float(ds["p_overturn"].values[i, j]) - ref_worst)
        lo, hi = float(ds["p_overturn_random_orientation_low"].values[i, j]), \
            float(ds["p_overturn_random_orientation_high"].values[i, j])
        if np.isfinite(lo):
            n_avg += 1
            cover += lo - 1e-12 <= ref_avg <= hi + 1e-12
            err_a.append(float(ds["p_overturn_random_orientation"].values[i, j]) - ref_avg)
    err_w, err_a = np.abs(err_w), np.abs(err_a)
    sims = ds["sample_simulations"].values
    scanned = np.isin(ds["orientation"].values, planar)
    print(f"{path}: {other} of the reference's {len(ref)} scenes judged by another model (3D, or at rest) left out")
    print(f"{path}: classes agree with the reference in {agree} of {n} scenes; worst-orientation p error: median "
          f"{np.median(err_w):.3f}, 90th percentile {np.quantile(err_w, 0.9):.3f}, max {err_w.max():.3f}; "
          f"random orientation: error median {np.median(err_a):.3f}, max {err_a.max():.3f}, its 90 % interval "
          f"covers the reference in {cover} of {n_avg} ({100 * cover / max(n_avg, 1):.1f} %); sampled planes in "
          f"scanned scenes {int(sims[scanned & (sims > 0)].sum())}")
    for line in changed:
        print(f"  class differs: {line}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", type=Path, default=ROOT / "records")
    ap.add_argument("--blocks", type=Path, default=ROOT / "configs" / "blocks.csv")
    ap.add_argument("--draws", type=int, default=200)
    ap.add_argument("--cache", type=Path, default=ROOT / "results" / "orientation_reference.npz")
    ap.add_argument("-n", type=int, default=2, help="worker processes")
    ap.add_argument("--compare", type=Path, nargs="*", default=[])
    args = ap.parse_args()
    args.cache.parent.mkdir(parents=True, exist_ok=True)
    ref = reference(args.records, args.blocks, args.draws, args.cache, args.n)
    for path in args.compare:
        compare(ref, path)


if __name__ == "__main__":
    main()
