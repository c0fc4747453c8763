"""``screen bench`` rows of the inventory's cylinders: the 3D model's scenes against the planar scan of the same
cylinders (every rocking plane, the worst kept, with the cylinder's own p and restitution), on the records with two
horizontal components: what each costs, and where their verdicts differ (the 3D model taken as the reference; its
scenes without a verdict left out of the comparison and counted)."""

from __future__ import annotations

import math
import time

import numpy as np

from ..blocks import Inventory
from ..config import Config
from ..rocking.cylinder_scene import cylinder_scene
from ..rocking.orientation import Planes, plane_grid, worst_plane

SECTION = "cylinders"


def cylinder_rows(scenes, inventory: Inventory, config: Config) -> list[dict]:
    """The two rows (3D, planar scan) of the inventory's cylinders on the two-component records of ``scenes``
    (the bench's loaded records); none without a cylinder."""
    cyl = np.flatnonzero(inventory.cylinders())
    records = [s.record for s in scenes if not s.record.single_component]
    if cyl.size == 0 or not records:
        return []
    settings = config.simulation_settings()
    grid = [0.0, *plane_grid(settings.orientation_step_deg).tolist()]
    blocks = inventory.rocking_blocks(g_ms2=config.records.g_ms2)
    t3 = tp = 0.0
    v3, vp = [], []
    for rec in records:
        planes = Planes(rec.horizontal_ms2, rec.azimuths_deg[0], rec.vertical_ms2, g_ms2=config.records.g_ms2)
        for j in cyl.tolist():
            t0 = time.perf_counter()
            res = cylinder_scene(rec.horizontal_ms2[0], rec.horizontal_ms2[1], rec.vertical_ms2, rec.dt_s,
                                 float(rec.azimuths_deg[0]), inventory.shape(j), settings=settings,
                                 g_ms2=config.records.g_ms2)
            t1 = time.perf_counter()
            flat = worst_plane(planes, grid, rec.dt_s, settings=settings, block=blocks[j],
                               refine_span_deg=settings.orientation_step_deg,
                               refine_deg=settings.orientation_refine_deg)
            tp += time.perf_counter() - t1
            t3 += t1 - t0
            v3.append(res.scene.verdict)
            vp.append(flat.scene.verdict)
    n = len(v3)
    ref, plane = np.array(v3), np.array(vp)
    judged = ref >= 0
    return [{"section": SECTION, "setting": "3D model (one run, no orientation scan)", "value": int(cyl.size),
             "time_s": t3, "time_per_scene_us": 1e6 * t3 / n, "scenes": n,
             "scenes_simulated": int(np.sum(judged))},
            {"section": SECTION, "setting": "planar scan of the same cylinders (worst plane; vs the 3D verdicts)",
             "value": int(cyl.size), "time_s": tp, "time_per_scene_us": 1e6 * tp / n, "scenes": n,
             "misses": int(np.sum(judged & (ref == 1) & (plane != 1))),
             "false_alarms": int(np.sum(judged & (ref == 0) & (plane == 1))),
             "theta_error_median": math.nan}]
