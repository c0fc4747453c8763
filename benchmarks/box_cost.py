"""What a box's 3D run costs against the planar run of the same box at the same azimuth, on the bundled records with
two horizontal components.

For each record and each box (width along x), both are timed once after a warm-up (compiled kernels loaded): the 3D
run (:func:`pipeline.rocking.solids.box3d.simulate_box` on both horizontals and the vertical) and the planar run of the
plane of its width (:func:`pipeline.rocking.simulate.rock` on the x component and the vertical, Housner's
restitution). Prints each pair, the 3D outcome, and the ratio of the totals.

Usage::

    python benchmarks/box_cost.py [RECORDS_DIR]
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import math
import sys
import time
from pathlib import Path

from pipeline.config import Config
from pipeline.records.loader import iter_records
from pipeline.rocking.simulate import rock
from pipeline.rocking.solids.box3d import Box, housner_e_box, simulate_box

G = 9.80665
#: (label, width [m], depth [m], height [m], mu)
BOXES = (("square h/w 3", 0.5, 0.5, 1.5, 0.7), ("square h/w 4.5", 0.4, 0.4, 1.8, 0.7),
         ("square h/w 6", 0.3, 0.3, 1.8, 0.7), ("cabinet d = 2w", 0.6, 1.2, 2.0, 0.7))


def main(argv: list[str]) -> int:
    root = Path(argv[0]) if argv else Path(__file__).resolve().parents[1] / "records"
    t3, tp, n = 0.0, 0.0, 0
    for rec in iter_records(root, config=Config()):
        if rec.single_component:
            continue
        h1, h2 = rec.horizontal_ms2
        for label, w, d, h, mu in BOXES:
            box = Box(w / 2, d / 2, h / 2, mu=mu)
            big_r, alpha = math.hypot(w / 2, h / 2), math.atan2(w, h)
            for _warm_then_timed in (True, False):   # the first call of each warms up, the second is timed
                t0 = time.perf_counter()
                out = simulate_box(h1, h2, rec.vertical_ms2, rec.dt_s, box)
                t1 = time.perf_counter()
                res = rock(h1, rec.dt_s, p=math.sqrt(0.75 * G / big_r), alpha=alpha, e=housner_e_box(w / 2, h / 2),
                           R_m=big_r, av_ms2=rec.vertical_ms2)
                t2 = time.perf_counter()
            t3 += t1 - t0
            tp += t2 - t1
            n += 1
            print(f"{rec.record_id[:30]:30s} {label:15s} 3D {1e3 * (t1 - t0):7.1f} ms (overturned {out.overturned!s:5s}"
                  f" flag {out.flag}, on a corner {out.corner_s:5.2f} s)   planar {1e3 * (t2 - t1):6.1f} ms "
                  f"(overturned {res.overturned!s:5s})")
    print(f"{n} scenes: 3D {t3:.2f} s, planar {tp:.2f} s, ratio 3D / planar {t3 / max(tp, 1e-12):.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
