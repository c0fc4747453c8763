"""How a box with a depth but a blank azimuth is judged, measured against its 3D model at every orientation.

A box whose orientation is unknown is judged by the planar scan (every rocking plane k x the scan step, refined
around the worst standing one, the worst kept) of its width's plane, as every blank-azimuth block is. This script
measures what that misses: on each bundled record with two horizontals of known azimuth, for the four boxes of the
PyBullet comparison (square bases 0.5 x 0.5 x 1.5, 0.4 x 0.4 x 1.8, 0.3 x 0.3 x 1.8 m; a cabinet 0.6 x 1.2 x 2.0 m
with its width the narrow side; mu 0.7), the scan's verdict against the 3D model's at AZIMUTHS orientations (0 to
165 deg in 15 deg steps: a box is symmetric under a half turn). Prints, per box, the scenes where some orientation
overturns in 3D while the scan stands (a false reassurance), where the scan overturns while no orientation does,
and the time each takes.

Run: ``python benchmarks/box_blank_azimuth.py``.
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import time
from pathlib import Path

import numpy as np

from pipeline.config import Config
from pipeline.records.loader import iter_records
from pipeline.rocking.orientation import Planes, plane_grid, worst_plane
from pipeline.rocking.solids.box3d import Box
from pipeline.rocking.solids.box_planar import width_block
from pipeline.rocking.solids.solid3d import Solid, judge_solid

ROOT = Path(__file__).resolve().parents[1]
MU = 0.7
BOXES = (("square 0.5", 0.5, 0.5, 1.5), ("square 0.4", 0.4, 0.4, 1.8), ("square 0.3", 0.3, 0.3, 1.8),
         ("cabinet", 0.6, 1.2, 2.0))
AZIMUTHS = np.arange(0.0, 180.0, 15.0)


def main() -> None:
    cfg = Config()
    st = cfg.simulation_settings()
    step, refine = st.orientation_step_deg, st.orientation_refine_deg
    grid = plane_grid(step).tolist()
    tally = {label: {"scenes": 0, "false_reassurance": [], "scan_only": [], "some_3d_none": 0, "t_scan": 0.0,
                     "t_3d": 0.0} for label, *_ in BOXES}
    for rec in iter_records(ROOT / "records", config=cfg):
        if rec.single_component or not rec.azimuth_known:
            continue
        h1, h2, v, dt = rec.horizontal_ms2[0], rec.horizontal_ms2[1], rec.vertical_ms2, rec.dt_s
        planes = Planes(rec.horizontal_ms2, rec.azimuths_deg[0], v, g_ms2=cfg.records.g_ms2)
        for label, w, d, h in BOXES:
            box = Box(half_width_m=w / 2, half_depth_m=d / 2, half_height_m=h / 2, mu=MU)
            t = tally[label]
            t0 = time.perf_counter()
            scan = worst_plane(planes, grid, dt, settings=st, refine_span_deg=step, refine_deg=refine,
                               block=width_block(box)).scene.verdict
            t1 = time.perf_counter()
            verdicts = [judge_solid(h1, h2, v, dt, Solid(box, float(az), width_block(box).alpha),
                                    settings=st).scene.verdict for az in AZIMUTHS]
            t["t_scan"] += t1 - t0
            t["t_3d"] += time.perf_counter() - t1
            t["scenes"] += 1
            t["some_3d_none"] += int(any(x < 0 for x in verdicts))
            falls = [float(az) for az, x in zip(AZIMUTHS, verdicts) if x == 1]
            if falls and scan != 1:
                t["false_reassurance"].append(f"{rec.record_id} (scan {scan}; overturns in 3D at {falls} deg)")
            if scan == 1 and not falls:
                t["scan_only"].append(f"{rec.record_id} (3D verdicts {verdicts})")
    for label, t in tally.items():
        print(f"{label}: {t['scenes']} scenes; the scan stands (or has no verdict) where some orientation overturns "
              f"in 3D: {len(t['false_reassurance'])}; the scan overturns where no orientation does: "
              f"{len(t['scan_only'])}; scenes with an orientation without a 3D verdict: {t['some_3d_none']}; time "
              f"scan {t['t_scan']:.2f} s, 3D at {AZIMUTHS.size} orientations {t['t_3d']:.2f} s")
        for line in t["false_reassurance"]:
            print(f"  false reassurance: {line}")
        for line in t["scan_only"]:
            print(f"  scan only: {line}")


if __name__ == "__main__":
    main()
