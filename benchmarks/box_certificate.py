"""The other-axis certificate of a box (pipeline.rocking.solids.box_planar) against the 3D model, draw by draw, on the
bundled records: for every record with two horizontals of known azimuth, every box of configs/blocks.csv with a
depth and an azimuth, and the first DRAWS draws of the declared uncertainty (the screening's own draws), the draw's
planar scene and certificate, and the 3D model's run. Prints how many draws were certified, how many of those the 3D
model judges otherwise, and for each such draw whether each verdict holds with the record x0.98 and x1.02 (the
chaos check), with the time each model took.

Run: ``python benchmarks/box_certificate.py [--draws 40]``.
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import time
from pathlib import Path

import numpy as np

from pipeline.blocks import read_inventory
from pipeline.config import Config
from pipeline.records.loader import iter_records
from pipeline.rocking.solids.box3d import Box
from pipeline.rocking.solids.box_planar import planar_box_scene
from pipeline.rocking.solids.solid3d import drawn, run, scene_of, solid_of
from pipeline.uncertainty.sampling import common_normals, sample_block

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--draws", type=int, default=40)
    args = ap.parse_args()
    cfg = Config()
    st = cfg.simulation_settings()
    inv = read_inventory(ROOT / "configs" / "blocks.csv", default_mu=cfg.blocks.default_mu)
    z = common_normals(cfg.uncertainty.seed, args.draws)
    n = certified = differ = 0
    t_planar = t_3d = 0.0
    rows = []
    for rec in iter_records(ROOT / "records", config=cfg):
        if rec.single_component or not rec.azimuth_known:
            continue
        h1, h2, v, dt = rec.horizontal_ms2[0], rec.horizontal_ms2[1], rec.vertical_ms2, rec.dt_s
        for j in range(len(inv)):
            shape = inv.shape(j)
            solid = solid_of(shape, record_azimuth_deg=float(rec.azimuths_deg[0]), known_azimuth=True)
            if solid is None or not isinstance(solid.body, Box):
                continue
            sb = sample_block(z, shape, settings=cfg.uncertainty, g_ms2=cfg.records.g_ms2)
            for r in range(args.draws):
                az = None if np.isnan(sb.azimuth_deg[r]) else float(sb.azimuth_deg[r])
                body = drawn(solid, R_m=float(sb.R_m[r]), alpha=float(sb.alpha[r]), mu=float(sb.mu[r]),
                             restitution=float(sb.e[r]), azimuth_deg=az,
                             record_azimuth_deg=float(rec.azimuths_deg[0]))
                amp = float(sb.amplitude[r])
                n += 1
                t0 = time.perf_counter()
                cs = planar_box_scene(h1, h2, v, dt, body.body, body.azimuth_deg, settings=st, amplitude=amp)
                t1 = time.perf_counter()
                if not cs.other_axis.certified or cs.scene is None:
                    continue
                out = run(h1, h2, v, dt, body, settings=st, amplitude=amp)
                t_3d += time.perf_counter() - t1
                t_planar += t1 - t0
                certified += 1
                v3 = scene_of(out, body).verdict
                if v3 == cs.scene.verdict:
                    continue
                differ += 1
                chaos = []
                for f in (0.98, 1.02):
                    p = planar_box_scene(h1, h2, v, dt, body.body, body.azimuth_deg, settings=st, amplitude=amp * f)
                    o = run(h1, h2, v, dt, body, settings=st, amplitude=amp * f)
                    chaos.append((p.scene.verdict if p.scene is not None else "not run",
                                  scene_of(o, body).verdict))
                rows.append(f"  {rec.record_id} x {inv.ids[j]} draw {r}: planar {cs.scene.verdict} (theta_max "
                            f"{cs.scene.theta_max:.3f} alpha, {cs.scene.n_impacts} impacts), 3D {v3}; x0.98 / x1.02: "
                            f"planar {chaos[0][0]} / {chaos[1][0]}, 3D {chaos[0][1]} / {chaos[1][1]}; e "
                            f"{float(sb.e[r]):.3f}")
    print(f"{n} draws of boxes with a depth and an azimuth; {certified} certified; the 3D model judges {differ} of "
          f"those otherwise (verdict 1 overturns, 0 stands, -1 none)")
    print("\n".join(rows))
    print(f"time on the certified draws: planar {t_planar:.2f} s, 3D {t_3d:.2f} s "
          f"({t_3d / max(t_planar, 1e-9):.1f}x)")


if __name__ == "__main__":
    main()
