"""``screen bench`` rows of the models that replace the planar model for some blocks (those of the registry with a
:attr:`~pipeline.bodies.contract.BodyModel.versus_planar`), on the records with two horizontal components: each
cylinder in 3D against the planar scan of the same cylinder (every rocking plane, the worst kept, with the
cylinder's own p and restitution), and each box with a depth and an azimuth in 3D against its planar scene in the
plane of its width (the component along its azimuth). What each costs, and where their verdicts differ (the model
taken as the reference; its scenes without a verdict left out of the comparison and counted)."""

from __future__ import annotations

import math
import time
from collections.abc import Sequence

import numpy as np

from ..blocks import Inventory
from ..bodies import registry
from ..bodies.contract import BodyModel, Placement
from ..config import Config
from .screening import on_record


def solid_rows(scenes, inventory: Inventory, config: Config) -> list[dict]:
    """Two rows (the model, the planar model it replaces) per registered model that says how it compares
    (:attr:`~pipeline.bodies.contract.BodyModel.versus_planar`) and claims blocks of the inventory, on the
    two-component records of ``scenes`` (the bench's loaded records)."""
    records = [s.record for s in scenes if not s.record.single_component]
    blocks = inventory.rocking_blocks(g_ms2=config.records.g_ms2)
    ons = [on_record(rec, config, scan=False) for rec in records]        # nominal: no draws; once per record
    rows: list[dict] = []
    for model in registry.BODIES:
        versus = model.versus_planar
        if versus is None:
            continue
        t3 = tp = 0.0
        v3: list[int] = []
        vp: list[int] = []
        for on in ons:
            t3_rec, tp_rec = _record(on, inventory, blocks, model, v3, vp)
            t3, tp = t3 + t3_rec, tp + tp_rec
        n = len(v3)
        if n == 0:
            continue
        ref, plane = np.array(v3), np.array(vp)
        judged = ref >= 0
        count = n // len(records)
        rows += [{"section": versus.section, "setting": versus.setting, "value": count, "time_s": t3,
                  "time_per_scene_us": 1e6 * t3 / n, "scenes": n, "scenes_simulated": int(np.sum(judged))},
                 {"section": versus.section, "setting": versus.setting_planar, "value": count, "time_s": tp,
                  "time_per_scene_us": 1e6 * tp / n, "scenes": n,
                  "misses": int(np.sum(judged & (ref == 1) & (plane != 1))),
                  "false_alarms": int(np.sum(judged & (ref == 0) & (plane == 1))), "theta_error_median": math.nan}]
    return rows


def _record(on, inventory: Inventory, blocks: Sequence, model: BodyModel, v3: list, vp: list) -> tuple[float, float]:
    """The record's scenes of the blocks ``model`` claims and their planar counterparts, timed; verdicts
    appended."""
    assert model.versus_planar is not None
    rec = on.record
    placement = Placement.of(rec)
    t3 = tp = 0.0
    for j in range(len(inventory)):
        shape = inventory.shape(j)
        if registry.body_model(shape, placement, on.setup.settings) is not model:
            continue
        t0 = time.perf_counter()
        res = model.scene(on, shape, blocks[j], 0.0).result
        t1 = time.perf_counter()
        flat = model.versus_planar.planar(on, shape, blocks[j])
        tp += time.perf_counter() - t1
        t3 += t1 - t0
        v3.append(res.scene.verdict)
        vp.append(flat.scene.verdict)
    return t3, tp
