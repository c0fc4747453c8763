"""What a cylinder's 3D scene costs against the planar scan of the same cylinder (the worst of its rocking planes, as
a blank azimuth is scanned), on the bundled records with two horizontal components.

For each record and each cylinder, both are timed once after a warm-up (compiled kernels loaded): the 3D run
(:func:`pipeline.rocking.solids.solid3d.solid_scene`) and the planar scan
(:func:`pipeline.rocking.orientation.worst_plane` over the pulse axis and the 5-degree grid, 37 planes, with the
cylinder's own p and restitution). Prints each pair and the ratio of the totals.

Usage::

    python benchmarks/cylinder_cost.py [RECORDS_DIR]
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import sys
import time
from pathlib import Path

from pipeline.config import Config
from pipeline.records.loader import iter_records
from pipeline.rocking.block import BlockShape, ShapeKind, dynamics
from pipeline.rocking.orientation import Planes, plane_grid, worst_plane
from pipeline.rocking.solids.solid3d import solid_of, solid_scene

CYLINDERS = (("vase 0.8 x 0.26", 0.8, 0.26, 0.55), ("column 2 x 0.5", 2.0, 0.5, 0.6),
             ("column 6 x 1", 6.0, 1.0, 0.7))


def main(argv: list[str]) -> int:
    root = Path(argv[0]) if argv else Path(__file__).resolve().parents[1] / "records"
    cfg = Config()
    settings = cfg.simulation_settings()
    grid = plane_grid(settings.orientation_step_deg)
    t3, tp = 0.0, 0.0
    n = 0
    for rec in iter_records(root, config=cfg):
        if rec.single_component:
            continue
        planes = Planes(rec.horizontal_ms2, rec.azimuths_deg[0], rec.vertical_ms2, g_ms2=cfg.records.g_ms2)
        for label, height, width, mu in CYLINDERS:
            shape = BlockShape(height_m=height, width_m=width, mu=mu, kind=ShapeKind.cylinder)
            block = dynamics([shape])[0]
            for _warm_then_timed in (True, False):   # the first call of each warms up, the second is timed
                t0 = time.perf_counter()
                solid = solid_of(shape, record_azimuth_deg=float(rec.azimuths_deg[0]), known_azimuth=True)
                assert solid is not None
                res3, _ = solid_scene(rec.horizontal_ms2[0], rec.horizontal_ms2[1], rec.vertical_ms2, rec.dt_s,
                                   float(rec.azimuths_deg[0]), solid, settings=settings)
                t1 = time.perf_counter()
                resp = worst_plane(planes, [0.0, *grid.tolist()], rec.dt_s, settings=settings, block=block,
                                   refine_span_deg=settings.orientation_step_deg,
                                   refine_deg=settings.orientation_refine_deg)
                t2 = time.perf_counter()
            t3 += t1 - t0
            tp += t2 - t1
            n += 1
            print(f"{rec.record_id[:34]:34s} {label:16s} 3D {1e3 * (t1 - t0):8.1f} ms "
                  f"(theta/alpha {res3.scene.theta_max:7.3f}, verdict {res3.scene.verdict:2d})   "
                  f"planar scan {1e3 * (t2 - t1):8.1f} ms ({resp.planes_simulated} planes, theta/alpha "
                  f"{resp.scene.theta_max:7.3f}, verdict {resp.scene.verdict:2d})")
    print(f"{n} scenes: 3D {t3:.2f} s, planar scan {tp:.2f} s, ratio 3D / planar {t3 / max(tp, 1e-12):.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
