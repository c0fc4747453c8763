"""What the cylinder's settle rule changes (pipeline.rocking.solids.cylinder3d.SETTLE_TILT_ALPHA: a tilt below that x
alpha through a sample interval over which the ground cannot lift the cylinder from rest is set at rest), against the
same
model without it, on the bundled records with two horizontals x three cylinders (a vase 0.8 x 0.26 m, mu 0.55; a
column 2 x 0.5 m, mu 0.6; a column 6 x 1 m, mu 0.7). Prints the time of each, and every scene whose verdict the
rule changes with the chaos check (the record x0.98 and x1.02, with and without the rule) and, where PyBullet is
installed (a test extra), the engine's verdict.

Run: ``python benchmarks/cylinder_settle.py``.
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import math
import sys
import time
from pathlib import Path

from pipeline.config import Config
from pipeline.records.loader import iter_records
from pipeline.rocking.block import BlockShape, ShapeKind
from pipeline.rocking.solids.cylinder3d import SETTLE_TILT_ALPHA, simulate_cylinder
from pipeline.rocking.solids.cylinder_scene import cylinder_of
from pipeline.rocking.solids.solid3d import Solid, scene_of

ROOT = Path(__file__).resolve().parents[1]
CYLINDERS = (("vase 0.8 x 0.26", 0.8, 0.26, 0.55), ("column 2 x 0.5", 2.0, 0.5, 0.6),
             ("column 6 x 1", 6.0, 1.0, 0.7))


def _verdict(rec, c, solid, settle: float, scale: float = 1.0) -> tuple[int, float, float]:
    h1, h2 = rec.horizontal_ms2
    v = None if rec.vertical_ms2 is None else scale * rec.vertical_ms2
    t0 = time.perf_counter()
    out = simulate_cylinder(scale * h1, -scale * h2, v, rec.dt_s, c, settle_tilt_alpha=settle)
    return scene_of(out, solid).verdict, out.theta_max_rad / solid.alpha, time.perf_counter() - t0


def main() -> None:
    sys.path.insert(0, str(ROOT / "tests"))
    try:
        from rigid_body_peer import bullet_cylinder_overturns
    except ImportError:
        bullet_cylinder_overturns = None
    cfg = Config()
    warm = next(r for r in iter_records(ROOT / "records", config=cfg) if not r.single_component)
    c0 = cylinder_of(BlockShape(height_m=1.0, width_m=0.3, mu=0.6, kind=ShapeKind.cylinder))
    for settle in (SETTLE_TILT_ALPHA, 0.0):                  # compiled once before the timing
        _verdict(warm, c0, Solid(c0, 0.0, math.atan2(c0.radius_m, c0.half_height_m)), settle)
    t_on = t_off = 0.0
    n = changed = 0
    lines = []
    for rec in iter_records(ROOT / "records", config=cfg):
        if rec.single_component:
            continue
        for label, height, diameter, mu in CYLINDERS:
            c = cylinder_of(BlockShape(height_m=height, width_m=diameter, mu=mu, kind=ShapeKind.cylinder))
            solid = Solid(c, 0.0, math.atan2(c.radius_m, c.half_height_m))
            v_on, th_on, dt_on = _verdict(rec, c, solid, SETTLE_TILT_ALPHA)
            v_off, th_off, dt_off = _verdict(rec, c, solid, 0.0)
            t_on, t_off, n = t_on + dt_on, t_off + dt_off, n + 1
            if v_on == v_off:
                continue
            changed += 1
            chaos = [(_verdict(rec, c, solid, SETTLE_TILT_ALPHA, f)[0], _verdict(rec, c, solid, 0.0, f)[0])
                     for f in (0.98, 1.02)]
            engine = ""
            if bullet_cylinder_overturns is not None:
                h1, h2 = rec.horizontal_ms2
                fell = bullet_cylinder_overturns(h1, -h2, rec.vertical_ms2, rec.dt_s, height_m=height,
                                                 diameter_m=diameter, mu=mu)[0]
                engine = f"; PyBullet {int(fell)}"
            lines.append(f"  {rec.record_id} x {label}: with the rule {v_on} (theta_max {th_on:.3f} alpha), without "
                         f"{v_off} ({th_off:.3f}); x0.98: {chaos[0][0]} / {chaos[0][1]}, x1.02: {chaos[1][0]} / "
                         f"{chaos[1][1]}{engine}")
    print(f"{n} scenes: with the settle rule {t_on:.2f} s, without {t_off:.2f} s; verdicts changed in {changed} "
          "(1 overturns, 0 stands, -1 no verdict):")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
