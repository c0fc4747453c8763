"""``screen fragility`` at growing size: scenes per second and how the cost grows with each factor.

A base configuration (records, blocks, levels, samples) is run, then each factor is doubled
(or, for samples, switched from nominal verdicts to sampling) with the others kept. Every run is
the real command in a fresh process into an empty output, on the default executor; the script
prints wall time, scaled scenes (records x levels x blocks) and scenes per second, and each
run's time over the base run's. Records are the bundled AT2 records (retitled copies when more
are needed, as in bench_batch.py); blocks are drawn as in bench_batch.py.

Run: python benchmarks/bench_fragility.py [--records 16] [--blocks 16] [--levels 6] [--samples 20]
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_batch import make_blocks, make_records  # noqa: E402


def run(records: Path, blocks: Path, levels: int, samples: int, out: Path) -> float:
    lv = ",".join(f"{x:.3g}g" for x in np.geomspace(0.1, 1.2, levels))
    cmd = [sys.executable, "-m", "pipeline", "fragility", "--records", str(records), "--blocks", str(blocks),
           "--im", "pga", "--levels", lv, "--samples", str(samples), "--bootstrap", "50", "--out", str(out), "-q"]
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode not in (0, 1):
        raise SystemExit(f"screen fragility failed ({proc.returncode}):\n{proc.stderr}")
    return time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", type=int, default=16)
    ap.add_argument("--blocks", type=int, default=16)
    ap.add_argument("--levels", type=int, default=6)
    ap.add_argument("--samples", type=int, default=20)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="bench-fragility-") as tmp:
        tmp = Path(tmp)
        recs = {n: tmp / f"records-{n}" for n in (a.records, 2 * a.records)}
        for n, d in recs.items():
            make_records(d, n)
        blocks = {n: tmp / f"blocks-{n}.csv" for n in (a.blocks, 2 * a.blocks)}
        for n, p in blocks.items():
            make_blocks(p, n)
        run(recs[a.records], blocks[a.blocks], 2, 0, tmp / "warm")        # numba and import caches
        cases = [("base", a.records, a.blocks, a.levels, 0), ("records x2", 2 * a.records, a.blocks, a.levels, 0),
                 ("blocks x2", a.records, 2 * a.blocks, a.levels, 0),
                 ("levels x2", a.records, a.blocks, 2 * a.levels, 0),
                 (f"samples {a.samples}", a.records, a.blocks, a.levels, a.samples)]
        print(f"{'case':14s} {'records':>7s} {'blocks':>6s} {'levels':>6s} {'samples':>7s} {'wall s':>7s} "
              f"{'scenes':>7s} {'scenes/s':>9s} {'x base':>7s}")
        base = None
        for k, (name, nr, nb, nl, ns) in enumerate(cases):
            t = run(recs[nr], blocks[nb], nl, ns, tmp / f"out-{k}")
            base = base or t
            scenes = nr * nb * nl
            print(f"{name:14s} {nr:7d} {nb:6d} {nl:6d} {ns:7d} {t:7.1f} {scenes:7d} {scenes / t:9.1f} "
                  f"{t / base:7.2f}")


if __name__ == "__main__":
    main()
