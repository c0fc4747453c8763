"""How the whole ``screen`` command grows with records and blocks: the README's scale table.

For each (records, blocks) of the grid, the real command runs in a fresh process into an empty
output with the default executor (and ``--samples`` when given), and the script prints: wall
time, CPU time (the whole process tree), the screening stage's and the margins stage's own times
(from the command's summary), the rest (imports, writing, report), records/s and scenes/s over the
whole command, and peak memory (the RSS of the largest process and summed over the process tree, and
the tree's summed PSS: its shared pages counted once). Records and blocks are made as in
bench_batch.py (bundled records, then retitled AT2 copies; blocks drawn with a fixed seed,
half with a blank azimuth, so the orientation scan runs for them).

Run: python benchmarks/bench_scale.py [--records 10,100] [--blocks 10,100,1000] [--samples N] [--scheduler local -n N]
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import re
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_batch import make_blocks, make_records, timed_run  # noqa: E402


def stage_times(summary: str) -> tuple[float, float]:
    """Screening and margins wall times [s] from the command's summary lines."""
    screening = re.search(r"wall time ([\d.]+) s", summary)
    margins = re.search(r"margins: .*?; ([\d.]+) s", summary)
    return (float(screening.group(1)) if screening else float("nan"),
            float(margins.group(1)) if margins else float("nan"))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", default="10,100")
    ap.add_argument("--blocks", default="10,100,1000")
    ap.add_argument("--samples", type=int, default=None, help="--samples for every run (default: the config's)")
    ap.add_argument("--scheduler", default=None, help="--scheduler for every run (e.g. local: a Dask LocalCluster)")
    ap.add_argument("-n", type=int, default=None, help="-n for every run (default: the command's)")
    a = ap.parse_args()
    n_records = [int(x) for x in a.records.split(",")]
    n_blocks = [int(x) for x in a.blocks.split(",")]
    extra = [] if a.samples is None else ["--samples", str(a.samples)]
    extra += [] if a.scheduler is None else ["--scheduler", a.scheduler]
    extra += [] if a.n is None else ["-n", str(a.n)]
    with tempfile.TemporaryDirectory(prefix="bench-scale-") as tmp:
        tmp = Path(tmp)
        recs = {n: tmp / f"records-{n}" for n in n_records}
        for n, d in recs.items():
            make_records(d, n)
        blocks = {n: tmp / f"blocks-{n}.csv" for n in n_blocks}
        for n, p in blocks.items():
            make_blocks(p, n)
        make_records(tmp / "records-warm", 2)
        make_blocks(tmp / "blocks-warm.csv", 2)
        # numba's and the imports' caches, on two records x two blocks (not a full run of the first row)
        timed_run(["--records", str(tmp / "records-warm"), "--blocks", str(tmp / "blocks-warm.csv"),
                   "--out", str(tmp / "warm"), *extra])
        print(f"{'records':>7s} {'blocks':>6s} {'wall s':>7s} {'CPU s':>7s} {'screen s':>8s} {'margins s':>9s} "
              f"{'rest s':>6s} {'records/s':>9s} {'scenes/s':>9s} {'peak RSS MB (largest / total)':>30s} "
              f"{'peak PSS MB (total)':>19s}")
        for nr in n_records:
            for nb in n_blocks:
                r = timed_run(["--records", str(recs[nr]), "--blocks", str(blocks[nb]),
                               "--out", str(tmp / f"out-{nr}-{nb}"), *extra])
                screen_s, margins_s = stage_times(r["summary"])
                rest = r["wall_s"] - screen_s - margins_s
                print(f"{nr:7d} {nb:6d} {r['wall_s']:7.1f} {r['cpu_s']:7.1f} {screen_s:8.1f} {margins_s:9.1f} "
                      f"{rest:6.1f} "
                      f"{nr / r['wall_s']:9.2f} {nr * nb / r['wall_s']:9.0f} "
                      f"{r['peak_one_mb']:16.0f} / {r['peak_sum_mb']:<11.0f} {r['peak_pss_mb']:19.0f}", flush=True)


if __name__ == "__main__":
    main()
