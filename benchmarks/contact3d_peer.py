"""The 3D contact model (pipeline.rocking.solids.contact3d) against PyBullet and against the exact 3D models, on the
bundled records with two horizontals of known azimuth, per family of body: square statues and cabinets with an
azimuth, boxes of friction 0.3-0.4, and cylinders. For each scene: the verdict of each (the exact models' none where
they stop at a slide or a lift-off), whether the contact model and PyBullet agree, and each disagreement re-run by
PyBullet with its step halved and the record scaled by 0.98 and 1.02 (robust: the engine's verdict holds in all
three). Prints the counts per family and the time per scene of each model (the median and the worst).

Run: ``python benchmarks/contact3d_peer.py [--families statues,cabinets,boxes,cylinders] [--pga-min 0.2]``
(PyBullet is a test extra: ``pip install pybullet``).
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import dataclasses
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "support"))

from rigid_body_peer import STEP_S, bullet_box_overturns, bullet_cylinder_overturns  # noqa: E402

from pipeline.config import Config  # noqa: E402
from pipeline.constants import G  # noqa: E402
from pipeline.records.loader import iter_records  # noqa: E402
from pipeline.rocking.block import BlockShape, ShapeKind  # noqa: E402
from pipeline.rocking.scene import Guard  # noqa: E402
from pipeline.rocking.solids.contact3d import simulate_contact3d  # noqa: E402
from pipeline.rocking.solids.convex_body import box_body, cylinder_body  # noqa: E402
from pipeline.rocking.solids.solid3d import judge_solid, solid_of  # noqa: E402

#: family -> bodies: (kind, width, depth, height, mu, azimuth of the width [deg])
FAMILIES = {
    "statues": [("box", 0.5, 0.5, 1.5, 0.7, 50.0), ("box", 0.5, 0.5, 2.0, 0.7, 50.0),
                ("box", 0.5, 0.5, 3.0, 0.7, 50.0)],
    "cabinets": [("box", 0.45, 0.9, 1.98, 0.35, 0.0), ("box", 0.6, 1.2, 2.1, 0.35, 90.0)],
    "boxes": [("box", 0.5, 0.5, 1.5, 0.4, 20.0), ("box", 0.6, 0.8, 1.8, 0.3, 70.0)],
    "cylinders": [("cylinder", 0.4, math.nan, 1.6, 0.6, math.nan), ("cylinder", 0.6, math.nan, 1.5, 0.5, math.nan)],
}


def _frame(rec, azimuth_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """The record's horizontals in the body's frame (x along its width, y 90 deg counter-clockwise from above)."""
    x, y = rec.horizontal_ms2[0], -rec.horizontal_ms2[1]            # the record's frame, y counter-clockwise
    phi = math.radians((float(rec.azimuths_deg[0]) - azimuth_deg) % 360.0) if math.isfinite(azimuth_deg) else 0.0
    c, s = math.cos(phi), math.sin(phi)
    return c * x + s * y, -s * x + c * y


def _peer(kind, w, d, h, mu, bx, by, av, dt, *, step_s=STEP_S, scale=1.0) -> bool:
    if kind == "cylinder":
        return bullet_cylinder_overturns(bx, by, av, dt, height_m=h, diameter_m=w, mu=mu, step_s=step_s,
                                         scale=scale)[0]
    return bullet_box_overturns(bx, by, av, dt, width_m=w, depth_m=d, height_m=h, mu=mu, step_s=step_s,
                                scale=scale)[0]


def _compile(rec, settings, handing) -> None:
    """Each model run once on a second of the record (the first call compiles), so the times are the runs'."""
    n = int(round(1.0 / rec.dt_s))
    h1, h2, av = rec.horizontal_ms2[0][:n], rec.horizontal_ms2[1][:n], rec.vertical_ms2[:n]
    for kind, w, d, h, mu, az in (FAMILIES["statues"][0], FAMILIES["cylinders"][0]):
        shape = BlockShape(height_m=h, width_m=w, mu=mu, azimuth_deg=az, depth_m=d,
                           kind=ShapeKind.cylinder if kind == "cylinder" else ShapeKind.box)
        body = cylinder_body(w, h, mu=mu) if kind == "cylinder" else box_body(w, d, h, mu=mu)
        simulate_contact3d(h1, -h2, av, rec.dt_s, body)
        solid = solid_of(shape, record_azimuth_deg=float(rec.azimuths_deg[0]), known_azimuth=True)
        for s in (settings, handing):
            judge_solid(h1, h2, av, rec.dt_s, solid, settings=s)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--families", default=",".join(FAMILIES))
    ap.add_argument("--pga-min", type=float, default=0.2, help="records below this PGA [g] are left out")
    args = ap.parse_args()
    cfg = Config()
    settings = cfg.simulation_settings()
    handing = dataclasses.replace(settings, contact3d=True)           # [simulation] contact3d = true
    records = [r for r in iter_records(ROOT / "records", config=cfg) if not r.single_component and r.azimuth_known
               and np.max(np.hypot(*r.horizontal_ms2)) >= args.pga_min * G]
    print(f"{len(records)} records with two horizontals of known azimuth and PGA >= {args.pga_min} g")
    _compile(records[0], settings, handing)
    for family in args.families.split(","):
        rows, t_c, t_e, t_p = [], [], [], []
        for kind, w, d, h, mu, az in FAMILIES[family]:
            shape = BlockShape(height_m=h, width_m=w, mu=mu, azimuth_deg=az, depth_m=d,
                               kind=ShapeKind.cylinder if kind == "cylinder" else ShapeKind.box)
            body = cylinder_body(w, h, mu=mu) if kind == "cylinder" else box_body(w, d, h, mu=mu)
            for rec in records:
                bx, by = _frame(rec, az)
                av = rec.vertical_ms2
                t0 = time.perf_counter()
                c3 = simulate_contact3d(bx, by, av, rec.dt_s, body)
                t1 = time.perf_counter()
                solid = solid_of(shape, record_azimuth_deg=float(rec.azimuths_deg[0]), known_azimuth=True)
                exact_scene = judge_solid(rec.horizontal_ms2[0], rec.horizontal_ms2[1], av, rec.dt_s, solid,
                                          settings=settings).scene
                exact = exact_scene.verdict
                t2 = time.perf_counter()
                peer = _peer(kind, w, d, h, mu, bx, by, av, rec.dt_s)
                t3 = time.perf_counter()
                handed = judge_solid(rec.horizontal_ms2[0], rec.horizontal_ms2[1], av, rec.dt_s, solid,
                                     settings=handing).scene.verdict
                t_c.append(t1 - t0)
                t_e.append(t2 - t1)
                t_p.append(t3 - t2)
                robust = None
                held = exact_scene.guard & (Guard.model_limit | Guard.held_past_alpha)
                handed_held = int(c3.overturned) if held else exact           # held past alpha handed over too
                if c3.overturned != peer or handed != int(peer):
                    again = [_peer(kind, w, d, h, mu, bx, by, av, rec.dt_s, step_s=STEP_S / 2),
                             _peer(kind, w, d, h, mu, bx, by, av, rec.dt_s, scale=0.98),
                             _peer(kind, w, d, h, mu, bx, by, av, rec.dt_s, scale=1.02)]
                    robust = all(a == peer for a in again)
                rows.append((f"{w}x{d}x{h} mu {mu}", rec.record_id, int(c3.overturned), exact, int(peer), robust,
                             c3.capped_steps, handed, handed_held))
        agree = sum(r[2] == r[4] for r in rows)
        exact_agree = sum(r[3] == r[4] for r in rows)
        print(f"\n## {family}: {len(rows)} scenes; the contact model agrees with PyBullet on {agree}, the exact "
              f"models on {exact_agree} (no verdict on {sum(r[3] < 0 for r in rows)}), the exact models handed to "
              f"the contact model where they stop ([simulation] contact3d = true) on "
              f"{sum(r[7] == r[4] for r in rows)} (no verdict on {sum(r[7] < 0 for r in rows)}), and where they stop "
              f"or hold past alpha on {sum(r[8] == r[4] for r in rows)}")
        print(f"   time per scene [s]: contact model median {np.median(t_c):.3f} worst {max(t_c):.3f}; exact "
              f"models median {np.median(t_e):.3f} worst {max(t_e):.3f}; PyBullet median {np.median(t_p):.3f} "
              f"worst {max(t_p):.3f}")
        for body_name, rid, c, e, p, robust, capped, handed, _ in rows:
            if c != p or handed != p:
                print(f"   differ: {body_name} x {rid}: contact {c}, exact {e}, handed {handed}, PyBullet {p} "
                      f"({'robust' if robust else 'not robust'} in the engine); capped steps {capped}")


if __name__ == "__main__":
    main()
