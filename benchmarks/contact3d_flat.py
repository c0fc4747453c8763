"""The flat slide against every step solved: the 3D contact model (:mod:`pipeline.rocking.solids.contact3d`) with a
body flat on its base stepped as a translation (:mod:`pipeline.rocking.solids.flat_slide`, the default) and with
every step's contact problem solved (``flat_slides=False``), on the same scenes, one process.

The scenes: the bundled records with two horizontals (and the vertical where there is one) x objects that stick,
slide and rock on their base: the bundled inventory's boxes and cylinder at their given friction and at 0.6 of it,
and the three sliding objects of ``benchmarks/contact3d_sliding.py``; each run from rest by the contact model alone.
Printed: verdicts that differ, and where both stand the largest differences of the peak tilt (over alpha) and of the
largest slide; the steps and time of each. A verdict that differs is run again at 0.98 and 1.02 of the record with
every step solved (robust or not there).

Run: ``python benchmarks/contact3d_flat.py [--records N]``.
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import math
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

from pipeline.config import Config  # noqa: E402
from pipeline.records.loader import iter_records  # noqa: E402
from pipeline.rocking.solids.contact3d import simulate_contact3d  # noqa: E402
from pipeline.rocking.solids.convex_body import box_body, cylinder_body  # noqa: E402

#: name -> (kind, width, depth, height, mu, yaw of the width from the record's first horizontal [deg])
OBJECTS = {"STAT-02": ("box", 0.24, 0.24, 0.62, 0.5, 0.0),
           "STAT-03": ("cylinder", 0.26, math.nan, 0.80, 0.55, 0.0),
           "TOMB-01": ("box", 0.20, 0.60, 1.10, 0.65, 45.0),
           "CAB-01": ("box", 0.45, 0.90, 1.98, 0.35, 0.0),
           "CAB-02": ("box", 0.60, 1.20, 2.10, 0.35, 90.0),
           "TRAF-01": ("box", 1.40, 2.00, 3.40, 0.50, 0.0),
           "CRATE-01": ("box", 1.20, 0.80, 0.60, 0.25, 0.0),
           "vase": ("cylinder", 0.4, math.nan, 1.2, 0.12, 0.0),
           "cabinet": ("box", 0.45, 0.9, 1.8, 0.15, 30.0),
           "box": ("box", 0.5, 0.5, 1.5, 0.3, 20.0)}
FRICTION_FACTORS = (1.0, 0.6)


def _body(kind, w, d, h, mu):
    return cylinder_body(w, h, mu=mu) if kind == "cylinder" else box_body(w, d, h, mu=mu)


def _alpha(kind, w, d, h) -> float:
    return math.atan(min(w, d if math.isfinite(d) else w) / h)


def _run(body, bx, by, av, dt, yaw, flat, scale=1.0):
    t0 = time.perf_counter()
    out = simulate_contact3d(scale * bx, scale * by, None if av is None else scale * av, dt, body, yaw_deg=yaw,
                             flat_slides=flat)
    return out, time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", type=int, default=0, help="the first N records with two horizontals (0: all)")
    args = ap.parse_args()
    records = [r for r in iter_records(ROOT / "records", config=Config()) if r.horizontal_ms2.shape[0] > 1]
    records = records[:args.records] if args.records else records
    warm = records[0]
    n = int(round(1.0 / warm.dt_s))
    for flat in (True, False):                          # compiled before any time is taken
        simulate_contact3d(warm.horizontal_ms2[0][:n], -warm.horizontal_ms2[1][:n], None, warm.dt_s,
                           box_body(0.4, 0.4, 1.2, mu=0.3), flat_slides=flat)
    scenes = differ = 0
    d_tilt, d_slide, t_flat, t_full, s_flat, s_full = [], [], 0.0, 0.0, 0, 0
    for rec in records:
        bx, by = rec.horizontal_ms2[0], -rec.horizontal_ms2[1]
        av = rec.vertical_ms2
        for name, (kind, w, d, h, mu, yaw) in OBJECTS.items():
            for f in FRICTION_FACTORS:
                body = _body(kind, w, d, h, f * mu)
                a, ta = _run(body, bx, by, av, rec.dt_s, yaw, True)
                b, tb = _run(body, bx, by, av, rec.dt_s, yaw, False)
                scenes, t_flat, t_full = scenes + 1, t_flat + ta, t_full + tb
                s_flat, s_full = s_flat + a.integrated_steps, s_full + b.integrated_steps
                if a.overturned != b.overturned:
                    differ += 1
                    near = [_run(body, bx, by, av, rec.dt_s, yaw, False, s)[0].overturned for s in (0.98, 1.02)]
                    print(f"differs: {rec.record_id} x {name} (mu {f * mu:.3f}): flat slides {a.overturned}, "
                          f"every step solved {b.overturned}; every step solved at 0.98 / 1.02 of the record: "
                          f"{near[0]} / {near[1]}")
                elif not a.overturned:
                    d_tilt.append(abs(a.tilt_max_rad - b.tilt_max_rad) / _alpha(kind, w, d, h))
                    d_slide.append(abs(a.slide_max_m - b.slide_max_m))
    d_tilt_a, d_slide_a = np.asarray(d_tilt), np.asarray(d_slide)
    print(f"{len(records)} records x {len(OBJECTS)} objects x {len(FRICTION_FACTORS)} frictions: {scenes} scenes, "
          f"verdicts differ in {differ}")
    if d_tilt_a.size:
        print(f"standing in both ({d_tilt_a.size}): peak tilt differs by more than 1e-3 alpha in "
              f"{int(np.sum(d_tilt_a > 1e-3))} (largest {d_tilt_a.max():.2g} alpha), largest slide by more than 1 mm "
              f"in {int(np.sum(d_slide_a > 1e-3))} (largest {d_slide_a.max():.3g} m)")
    print(f"integrated steps: flat slides {s_flat:,}, every step solved {s_full:,}; time {t_flat:.1f} s against "
          f"{t_full:.1f} s ({t_full / t_flat:.2f}x)")


if __name__ == "__main__":
    main()
