"""``screen bench`` rows of the inventory's 3D scenes (:mod:`pipeline.rocking.solids.solid3d`) against the planar models
they replace, on the records with two horizontal components: each cylinder against the planar scan of the same
cylinder (every rocking plane, the worst kept, with the cylinder's own p and restitution), and each box with a
depth and an azimuth against its planar scene in the plane of its width (the component along its azimuth). What
each costs, and where their verdicts differ (the 3D model taken as the reference; its scenes without a verdict
left out of the comparison and counted)."""

from __future__ import annotations

import math
import time

import numpy as np

from ..blocks import Inventory
from ..config import Config
from ..rocking.orientation import Planes, plane_grid, worst_plane
from ..rocking.scene import Physics
from ..rocking.solids.solid3d import Solid, solid_of, solid_scene

#: (section, the 3D row's setting, the planar row's setting, cylinders: True / boxes: False)
SECTIONS = (("cylinders", "3D model (one run, no orientation scan)",
             "planar scan of the same cylinders (worst plane; vs the 3D verdicts)", True),
            ("boxes in 3D", "3D model (one run at the box's azimuth, both horizontals)",
             "planar scene in the plane of the width (vs the 3D verdicts)", False))


def solid_rows(scenes, inventory: Inventory, config: Config) -> list[dict]:
    """Two rows (3D, planar) per section with scenes: the inventory's cylinders, and its boxes with a depth and an
    azimuth, on the two-component records of ``scenes`` (the bench's loaded records)."""
    records = [s.record for s in scenes if not s.record.single_component]
    rows: list[dict] = []
    for section, setting_3d, setting_planar, cylinders in SECTIONS:
        t3 = tp = 0.0
        v3: list[int] = []
        vp: list[int] = []
        for rec in records:
            t3_rec, tp_rec = _record(rec, inventory, config, cylinders, v3, vp)
            t3, tp = t3 + t3_rec, tp + tp_rec
        n = len(v3)
        if n == 0:
            continue
        ref, plane = np.array(v3), np.array(vp)
        judged = ref >= 0
        count = n // len(records)
        rows += [{"section": section, "setting": setting_3d, "value": count, "time_s": t3,
                  "time_per_scene_us": 1e6 * t3 / n, "scenes": n, "scenes_simulated": int(np.sum(judged))},
                 {"section": section, "setting": setting_planar, "value": count, "time_s": tp,
                  "time_per_scene_us": 1e6 * tp / n, "scenes": n,
                  "misses": int(np.sum(judged & (ref == 1) & (plane != 1))),
                  "false_alarms": int(np.sum(judged & (ref == 0) & (plane == 1))), "theta_error_median": math.nan}]
    return rows


def _record(rec, inventory: Inventory, config: Config, cylinders: bool, v3: list, vp: list) -> tuple[float, float]:
    """The record's 3D scenes of one kind and their planar counterparts, timed; verdicts appended."""
    settings = config.simulation_settings()
    g = config.records.g_ms2
    blocks = inventory.rocking_blocks(g_ms2=g)
    planes = Planes(rec.horizontal_ms2, rec.azimuths_deg[0], rec.vertical_ms2, g_ms2=g)
    grid = [0.0, *plane_grid(settings.orientation_step_deg).tolist()]
    t3 = tp = 0.0
    for j in range(len(inventory)):
        shape = inventory.shape(j)
        solid: Solid | None = solid_of(shape, record_azimuth_deg=float(rec.azimuths_deg[0]),
                                       known_azimuth=bool(rec.azimuth_known))
        if solid is None or (solid.physics == Physics.wobbling) != cylinders:
            continue
        t0 = time.perf_counter()
        res, _certified = solid_scene(rec.horizontal_ms2[0], rec.horizontal_ms2[1], rec.vertical_ms2, rec.dt_s,
                                      float(rec.azimuths_deg[0]), solid, settings=settings, g_ms2=g)
        t1 = time.perf_counter()
        flat = worst_plane(planes, grid if cylinders else [float(shape.azimuth_deg)], rec.dt_s, settings=settings,
                           block=blocks[j], refine_span_deg=settings.orientation_step_deg if cylinders else 0.0,
                           refine_deg=settings.orientation_refine_deg)
        tp += time.perf_counter() - t1
        t3 += t1 - t0
        v3.append(res.scene.verdict)
        vp.append(flat.scene.verdict)
    return t3, tp
