"""The hand-back to the box's exact model (pipeline.rocking.solids.alternate) against the contact model alone, on
every box draw and margin run of the bundled default that the contact model decides.

Runs ``screen`` on the bundled records in one process. Each scene the hand-back decides is run again by the contact
model alone from the same start, at its step and at half its step (the contact model's own resolution: how often
its verdict turns with the step). Prints the runs, the verdicts that agree pairwise, and the time of each side.

    python benchmarks/contact3d_handback.py [--records records] [--blocks configs/blocks.csv]

About 3 minutes on 2 cores.
"""

from __future__ import annotations

import argparse
import tempfile
import time

import pipeline.rocking.solids.contact3d as contact3d
from pipeline import cli
from pipeline.rocking.solids.box3d import Box


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", default="records")
    ap.add_argument("--blocks", default="configs/blocks.csv")
    args = ap.parse_args()
    rows: list[tuple[bool, bool, bool, float, float]] = []
    plain = contact3d.simulate_contact3d

    def alone(ax, ay, az, dt_s, box: Box, azimuth_deg, start, g_ms2, step_s):
        kept, contact3d.MAX_STEP_S = contact3d.MAX_STEP_S, step_s
        try:
            return plain(ax, ay, az, dt_s, box.convex(), yaw_deg=azimuth_deg, g_ms2=g_ms2, start=start)
        finally:
            contact3d.MAX_STEP_S = kept

    def both(ax, ay, az, dt_s, box: Box, azimuth_deg, start, **kw):
        t0 = time.perf_counter()
        handed = original(ax, ay, az, dt_s, box, azimuth_deg, start, **kw)
        t1 = time.perf_counter()
        step = contact3d.MAX_STEP_S
        at_h = alone(ax, ay, az, dt_s, box, azimuth_deg, start, kw["g_ms2"], step)
        t2 = time.perf_counter()
        at_half = alone(ax, ay, az, dt_s, box, azimuth_deg, start, kw["g_ms2"], step / 2.0)
        rows.append((handed.overturned, at_h.overturned, at_half.overturned, t1 - t0, t2 - t1))
        return handed

    from pipeline.rocking.solids import box_scene
    original = box_scene.alternate
    box_scene.alternate = both
    with tempfile.TemporaryDirectory() as out:
        try:
            cli.main(["--records", args.records, "--blocks", args.blocks, "--out", out, "--tolerate-failures",
                      "-n", "1", "--quiet"])
        except SystemExit:
            pass
    box_scene.alternate = original
    n = len(rows)

    def agree(i: int, j: int) -> int:
        return sum(r[i] == r[j] for r in rows)

    t_hand, t_alone = sum(r[3] for r in rows), sum(r[4] for r in rows)
    print(f"box runs decided with the hand-back: {n}")
    print(f"verdicts agree: hand-back and the contact model alone {agree(0, 1)} ({agree(0, 1) / n:.1%}); "
          f"the contact model alone at its step and at half of it {agree(1, 2)} ({agree(1, 2) / n:.1%}); "
          f"hand-back and the contact model at half its step {agree(0, 2)} ({agree(0, 2) / n:.1%})")
    print(f"time: hand-back {t_hand:.2f} s, contact model alone {t_alone:.2f} s (ratio {t_alone / t_hand:.2f})")


if __name__ == "__main__":
    main()
