"""What the planar margin's upward scan costs per scaled scene, side by side with the same scan planned on the scaled
series themselves.

On every bundled record with two horizontals and a vertical, in two planes (0 and 65 deg from its first component),
for a fixed set of blocks that rock (seeded, heights 0.5-5 m, mu above tan alpha): the product's scan
(:func:`pipeline.bodies.planar.overturn_scale_simulated`: each factor judged by the sampled kernel, one draw at that
amplitude, the series checked once, the factors below the one that first lifts the block not judged: they stand) and
the scan whose every factor's scene is planned on ``f a_h`` and ``f a_v`` (:func:`~pipeline.rocking.planner.
simulate_scene` computing the ratio and checking both series itself, the factors below the lift included). Prints
each way's scaled scenes judged, its best of ``--passes`` timed passes (after one pass that loads the compiled
kernels, the two ways alternating), the time per block's scan, the share of it spent inside compiled calls (the
rocking kernel and the general contact model's hand-off where planned; the sampled kernel in the product's), and
whether the margins are the same.

Usage::

    python benchmarks/margin_scan_cost.py [--passes 3] [--blocks 12]
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import math
import time
from pathlib import Path

import numpy as np

from pipeline.bodies.factor_sweep import factor_sweep
from pipeline.bodies.planar import lift_factor, overturn_scale_simulated
from pipeline.config import Config
from pipeline.records.loader import iter_records
from pipeline.rocking.block import BlockShape, dynamics
from pipeline.rocking.planar import handoff, kernel, sampled
from pipeline.rocking.planner import rocks, simulate_scene
from pipeline.rocking.settings import SimulationConfig

ROOT = Path(__file__).resolve().parents[1]
SETTINGS = SimulationConfig()
PLANES_DEG = (0.0, 65.0)


def planned_on_scaled(ah, av, dt_s, block):
    """The scan with each factor's scene planned on the scaled series (its ratio and checks from them), the factors
    below the lift included."""
    if not rocks(block.alpha, block.mu):
        return math.nan, 0
    return factor_sweep(lift_factor(ah, av, alpha=block.alpha, g_ms2=block.g_ms2),
                        lambda f: simulate_scene(f * ah, None if av is None else f * av, dt_s, block=block,
                                                 settings=SETTINGS).verdict, settings=SETTINGS)


def blocks(n: int):
    """``n`` blocks that rock, drawn with a fixed seed."""
    rng = np.random.default_rng(20261207)
    shapes = []
    while len(shapes) < n:
        h, w, mu = rng.uniform(0.5, 5.0), rng.uniform(0.15, 0.6), rng.uniform(0.3, 0.9)
        if w < mu:                                      # width / height below mu: tan alpha < mu, it rocks
            shapes.append(BlockShape(height_m=h, width_m=w * h, mu=mu))
    return dynamics(shapes)


def scenes():
    """(ah, av, dt) of each bundled record with two horizontals and a vertical, in each plane."""
    for rec in iter_records(ROOT / "records", config=Config()):
        if rec.horizontal_ms2.shape[0] == 2 and rec.vertical_ms2 is not None:
            for az in PLANES_DEG:
                yield np.ascontiguousarray(rec.along(rec.azimuths_deg[0] + az)), rec.vertical_ms2, rec.dt_s


#: The compiled entry points the two scans call from Python: (module, name).
COMPILED_CALLS = ((kernel, "rock"), (handoff, "continue_rocking"), (sampled, "sample_verdicts"))


class KernelClock:
    """The compiled entry points (:data:`COMPILED_CALLS`) wrapped to sum the seconds spent in them."""

    def __init__(self):
        self.seconds, self._saved = 0.0, [getattr(m, name) for m, name in COMPILED_CALLS]

    def __enter__(self):
        for (module, name), compiled in zip(COMPILED_CALLS, self._saved):
            setattr(module, name, self._timed(compiled))
        return self

    def _timed(self, compiled):
        def timed(*args):
            t0 = time.perf_counter()
            try:
                return compiled(*args)
            finally:
                self.seconds += time.perf_counter() - t0
        return timed

    def __exit__(self, *exc):
        for (module, name), compiled in zip(COMPILED_CALLS, self._saved):
            setattr(module, name, compiled)


def one_pass(scan, cases, bs):
    """Every scan of ``bs`` on ``cases``: the results, the wall time and the compiled calls' part of it [s]."""
    with KernelClock() as clock:
        t0 = time.perf_counter()
        out = [scan(ah, av, dt, b) for ah, av, dt in cases for b in bs]
        return out, time.perf_counter() - t0, clock.seconds


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--passes", type=int, default=3)
    ap.add_argument("--blocks", type=int, default=12)
    a = ap.parse_args()
    cases, bs = list(scenes()), blocks(a.blocks)
    ways = {"product": lambda ah, av, dt, b: overturn_scale_simulated(ah, av, dt, block=b, settings=SETTINGS),
            "planned on the scaled series": planned_on_scaled}
    best = {name: (math.inf, 0.0) for name in ways}
    results = {}
    for k in range(a.passes + 1):                       # the first pass loads the kernels and is not timed
        for name, scan in ways.items():
            results[name], wall, in_kernel = one_pass(scan, cases, bs)
            if k and wall < best[name][0]:
                best[name] = (wall, in_kernel)
    scans = len(cases) * len(bs)
    print(f"{len(cases)} record planes x {len(bs)} blocks: {scans} scans, best of {a.passes} passes")
    for name, (wall, in_kernel) in best.items():
        runs = sum(r for _, r in results[name])
        print(f"  {name:30s} {runs:6d} scaled scenes  {wall:7.2f} s  {wall / scans * 1e3:6.2f} ms a scan, compiled "
              f"calls {in_kernel / wall:.0%} of it")
    same = [m for m, _ in results["product"]] == [m for m, _ in results["planned on the scaled series"]]
    print(f"  ratio {best['planned on the scaled series'][0] / best['product'][0]:.2f}x; margins the same: {same}")


if __name__ == "__main__":
    main()
