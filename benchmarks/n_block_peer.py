"""The planar n-block model (pipeline.assemblies.n_block_run) against PyBullet on the bundled records: columns of three
and five drums, each record's first horizontal in the column's plane scaled to a PGA, no vertical, friction high
enough that no joint slides (mu 2 in both engines' sense). PyBullet holds deep boxes stacked on its floor, the
ground's motion as a time-varying gravity (tests/support/rigid_body_peer.py). For each scene the lowest drum that has
fallen at the first fall (none; the top; a middle drum with those above it; the whole column), and each disagreement
re-run by PyBullet at half its step and at 0.98 and 1.02 of the record (robust: the engine's verdict holds in all
three). Prints the counts, the agreement, and the time per scene of each engine, and of the 3D box model on the box
of the column's outline with a square base (the single body a 3D scene of the column is measured against).

Run: ``python benchmarks/n_block_peer.py [--pga 0.5] [--records 21] [--cost-only]`` (the first records of at most
60 s; PyBullet is a test extra; ``--cost-only`` leaves it out).
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import collections
import statistics
import sys
import time
from functools import partial
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "support"))
sys.path.insert(0, str(ROOT / "tests" / "assemblies"))

from rigid_body_peer import bullet_first_fall, perturbed_verdicts, short_records  # noqa: E402
from test_n_block_peer import COLUMNS, MU, RHO  # noqa: E402

from pipeline.assemblies.n_block import n_block  # noqa: E402
from pipeline.assemblies.n_block_run import simulate_n_block  # noqa: E402
from pipeline.assemblies.stack import StackBody  # noqa: E402
from pipeline.constants import G  # noqa: E402
from pipeline.rocking.solids.box3d import Box, simulate_box  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pga", type=float, default=0.5, help="each record scaled to this PGA [g]")
    ap.add_argument("--records", type=int, default=21, help="the first N bundled records of at most 60 s")
    ap.add_argument("--cost-only", action="store_true", help="time rockscreen and the 3D box only (no PyBullet)")
    args = ap.parse_args()
    records = short_records(ROOT / "records")[:args.records]
    for family, boxes in COLUMNS.items():
        nb = n_block([StackBody(w, h, RHO * w * h, MU) for w, h in boxes])
        simulate_n_block(nb, records[0].horizontal_ms2[0], records[0].dt_s)       # compiled before timing
        width, height = max(w for w, _ in boxes), sum(h for _, h in boxes)
        outline = Box(width / 2, width / 2, height / 2, mu=MU)
        simulate_box(records[0].horizontal_ms2[0][:8], records[0].horizontal_ms2[0][:8] * 0, None, 0.01, outline)
        ours_s, engine_s, box_s, counts, differ = [], [], [], collections.Counter(), []
        for rec in records:
            a = rec.horizontal_ms2[0] * (args.pga * G / abs(rec.horizontal_ms2[0]).max())
            t0 = time.perf_counter()
            ours = simulate_n_block(nb, a, rec.dt_s).falls
            t1 = time.perf_counter()
            simulate_box(a, a * 0.0, None, rec.dt_s, outline)
            box_s.append(time.perf_counter() - t1)
            ours_s.append(t1 - t0)
            if args.cost_only:
                continue
            t1 = time.perf_counter()
            engine = bullet_first_fall(a, rec.dt_s, boxes, mu=MU, density=RHO)
            t2 = time.perf_counter()
            engine_s.append(t2 - t1)
            counts[(ours, engine)] += 1
            if ours != engine:
                checks = perturbed_verdicts(partial(bullet_first_fall, a, rec.dt_s, boxes, mu=MU, density=RHO))
                differ.append((rec.record_id, ours, engine, sorted(checks), "robust" if checks == {engine}
                               else "not robust"))
            print(f"  {family}, {rec.record_id}: rockscreen {ours}, PyBullet {engine}", flush=True)
        ratios = [o / b for o, b in zip(ours_s, box_s)]
        print(f"{family}: a scene, rockscreen / the 3D box of its outline: median {statistics.median(ratios):.2f}, "
              f"worst {max(ratios):.1f} (rockscreen median {1e3 * statistics.median(ours_s):.1f} ms, the box "
              f"{1e3 * statistics.median(box_s):.1f} ms)")
        if args.cost_only:
            continue
        agree = sum(v for (o, e), v in counts.items() if o == e)
        print(f"{family} at {args.pga} g: {agree} of {len(records)} agree; first fall (rockscreen, PyBullet) -> "
              f"scenes: {dict(sorted(counts.items()))} (-1 none, k the lowest drum fallen)")
        for d in differ:
            print(f"  differs: {d[0]}: rockscreen {d[1]}, PyBullet {d[2]}; PyBullet at half step and 0.98 / 1.02 of "
                  f"the record: {d[3]} ({d[4]})")
        print(f"  a scene: rockscreen median {1e3 * statistics.median(ours_s):.1f} ms (worst "
              f"{1e3 * max(ours_s):.0f} ms), PyBullet median {statistics.median(engine_s):.2f} s")


if __name__ == "__main__":
    main()
