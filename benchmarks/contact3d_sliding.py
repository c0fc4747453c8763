"""Objects that slide, side by side: the 3D contact model (:mod:`pipeline.rocking.solids.contact3d`), PyBullet and
MuJoCo on the same scenes, each run in one process: the largest sliding distance of the centre of mass, the largest
turn about the vertical, the verdict, and the time of one run.

The scenes: three objects whose friction is below the tan of their smallest tipping angle (a 1.2 x 0.4 m vase, mu
0.12; a cabinet 1.8 m high, 0.45 x 0.9 m, mu 0.15, azimuth 30 deg; a box 1.5 m high, 0.5 x 0.5 m, mu 0.3, azimuth
20 deg) on four near-field stations of the FEMA P695 set (Rinaldi, Sylmar, Yarimca, El Centro #6; both horizontals
and the vertical, in the object's frame). Both engines take the ground's motion as a time-varying gravity, linear
between samples (the contact model's moving-ground frame): PyBullet as ``tests/support/rigid_body_peer.py`` sets it
(its step 1/4000 s), MuJoCo as ``benchmarks/contact3d_second_engine.py`` does (1e-4 s); each engine is also run at
half its step, which says whether its distance is converged. Times are of one run after a warm-up run (the contact
model's compilation not counted).

Run: ``python benchmarks/contact3d_sliding.py [--stations rinaldi,sylmar] [--no-mujoco]`` (PyBullet and MuJoCo are
test extras: ``pip install pybullet mujoco``).
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "support"))
sys.path.insert(0, str(ROOT / "benchmarks"))

from contact3d_peer import _frame  # noqa: E402
from contact3d_second_engine import mujoco_body, require_mujoco  # noqa: E402
from rigid_body_peer import STEP_S, _free_body, _world, ground_at, pybullet  # noqa: E402

from pipeline.config import Config  # noqa: E402
from pipeline.constants import G  # noqa: E402
from pipeline.records.loader import iter_records  # noqa: E402
from pipeline.rocking.solids.contact3d import simulate_contact3d  # noqa: E402
from pipeline.rocking.solids.convex_body import box_body, cylinder_body  # noqa: E402

STATIONS = {"rinaldi": "RSN1063", "sylmar": "RSN1086", "yarimca": "RSN1176", "el_centro_6": "RSN181_"}
#: name -> (kind, width, depth, height, mu, azimuth of the width [deg])
OBJECTS = {"vase": ("cylinder", 0.4, math.nan, 1.2, 0.12, math.nan),
           "cabinet": ("box", 0.45, 0.9, 1.8, 0.15, 30.0),
           "box": ("box", 0.5, 0.5, 1.5, 0.3, 20.0)}
MUJOCO_STEP_S = 1e-4
TAIL_S = 5.0


class Run:
    """One engine's run: largest slide [m], largest turn about the vertical [deg], overturned, seconds."""

    def __init__(self, slide_m: float, twist_deg: float, overturned: bool, seconds: float):
        self.slide_m, self.twist_deg, self.overturned, self.seconds = slide_m, twist_deg, overturned, seconds


def _yaw(rot9) -> float:
    """The turn about the vertical of a body standing upright [rad] (its x axis seen from above)."""
    return math.atan2(rot9[3], rot9[0])


def rockscreen(kind, w, d, h, mu, ax, ay, az, dt) -> Run:
    body = cylinder_body(w, h, mu=mu) if kind == "cylinder" else box_body(w, d, h, mu=mu)
    t0 = time.perf_counter()
    out = simulate_contact3d(ax, ay, az, dt, body)
    return Run(out.slide_max_m, math.degrees(out.twist_max_rad), out.overturned, time.perf_counter() - t0)


def bullet(kind, w, d, h, mu, ax, ay, az, dt, *, step_s=STEP_S) -> Run:
    pb = pybullet()
    cid = _world(pb, step_s)
    t0 = time.perf_counter()
    try:
        shape = (pb.createCollisionShape(pb.GEOM_CYLINDER, radius=w / 2, height=h, physicsClientId=cid)
                 if kind == "cylinder" else
                 pb.createCollisionShape(pb.GEOM_BOX, halfExtents=[w / 2, d / 2, h / 2], physicsClientId=cid))
        body = pb.createMultiBody(1.0, shape, basePosition=[0, 0, h / 2], physicsClientId=cid)
        _free_body(pb, body, mu, cid)
        n, slide, twist, over = ax.size, 0.0, 0.0, False
        for i in range(int(((n - 1) * dt + TAIL_S) / step_s)):
            g = ground_at((ax, ay, az), i * step_s, dt)
            pb.setGravity(-g[0], -g[1], -(G + g[2]), physicsClientId=cid)
            pb.stepSimulation(physicsClientId=cid)
            if i % 4 == 0:
                pos, q = pb.getBasePositionAndOrientation(body, physicsClientId=cid)
                rot = pb.getMatrixFromQuaternion(q)
                if math.acos(max(-1.0, min(1.0, rot[8]))) >= 0.5 * math.pi - 0.05:
                    over = True
                    break
                slide = max(slide, math.hypot(pos[0], pos[1]))
                twist = max(twist, abs(_yaw(rot)))
        return Run(slide, math.degrees(twist), over, time.perf_counter() - t0)
    finally:
        pb.disconnect(cid)


def mujoco_run(kind, w, d, h, mu, ax, ay, az, dt, *, step_s=MUJOCO_STEP_S) -> Run:
    import mujoco

    model, data = mujoco_body(kind, w, d, h, mu, step_s=step_s)
    t0 = time.perf_counter()
    n, slide, twist, over = ax.size, 0.0, 0.0, False
    while data.time < (n - 1) * dt + TAIL_S:
        g = ground_at((ax, ay, az), data.time, dt)
        model.opt.gravity[:] = (-g[0], -g[1], -(G + g[2]))
        mujoco.mj_step(model, data)
        rot = data.xmat[1]
        if math.acos(max(-1.0, min(1.0, rot[8]))) >= 0.5 * math.pi - 0.05:
            over = True
            break
        slide = max(slide, math.hypot(data.xpos[1][0], data.xpos[1][1]))
        twist = max(twist, abs(_yaw(rot)))
    return Run(slide, math.degrees(twist), over, time.perf_counter() - t0)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--stations", default=",".join(STATIONS))
    ap.add_argument("--no-mujoco", action="store_true")
    args = ap.parse_args()
    if not args.no_mujoco:
        require_mujoco(otherwise="run with --no-mujoco")
    unknown = [s for s in args.stations.split(",") if s not in STATIONS]
    if unknown:
        sys.exit(f"--stations: {', '.join(unknown)} unknown; choose from {','.join(STATIONS)}")
    wanted = [STATIONS[s] for s in args.stations.split(",")]
    records = [r for r in iter_records(ROOT / "records", config=Config())
               if not r.single_component and r.azimuth_known and r.record_id[:7] in wanted]
    first = records[0]
    rockscreen("cylinder", 0.4, math.nan, 1.2, 0.12, first.horizontal_ms2[0][:200], first.horizontal_ms2[1][:200],
               None, first.dt_s)                                           # the compilation, not timed
    rows = []
    for name, (kind, w, d, h, mu, az) in OBJECTS.items():
        for rec in records:
            bx, by = _frame(rec, az)
            av = rec.vertical_ms2
            runs = {"rockscreen": rockscreen(kind, w, d, h, mu, bx, by, av, rec.dt_s),
                    "pybullet": bullet(kind, w, d, h, mu, bx, by, av, rec.dt_s),
                    "pybullet/2": bullet(kind, w, d, h, mu, bx, by, av, rec.dt_s, step_s=STEP_S / 2)}
            if not args.no_mujoco:
                runs["mujoco"] = mujoco_run(kind, w, d, h, mu, bx, by, av, rec.dt_s)
                runs["mujoco/2"] = mujoco_run(kind, w, d, h, mu, bx, by, av, rec.dt_s, step_s=MUJOCO_STEP_S / 2)
            rows.append((name, rec.record_id, runs))
            print(f"{name:8s} {rec.record_id[:22]:22s} " + " | ".join(
                f"{k} {r.slide_m:.3f} m {r.twist_deg:6.1f} deg{' OVER' if r.overturned else ''} {r.seconds:.2f} s"
                for k, r in runs.items()), flush=True)
    ours = np.array([r["rockscreen"].seconds for _, _, r in rows])
    peer = np.array([r["pybullet"].seconds for _, _, r in rows])
    print(f"\none run a scene [s]: rockscreen median {np.median(ours):.3f} worst {ours.max():.3f}; PyBullet median "
          f"{np.median(peer):.3f} worst {peer.max():.3f}; rockscreen / PyBullet per scene: median "
          f"{np.median(ours / peer):.3f}, worst {np.max(ours / peer):.3f}")
    agree = sum(r["rockscreen"].overturned == r["pybullet"].overturned for _, _, r in rows)
    print(f"verdicts: rockscreen and PyBullet agree on {agree} of {len(rows)}")


if __name__ == "__main__":
    main()
